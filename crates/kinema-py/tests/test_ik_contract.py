"""The IK contract from Python: every returned solution meets the target on
what it constrains; a full pose a 5-joint arm cannot take raises Unreachable
with the closest configuration; mask= frees components; bad masks and seeds
raise InvalidInput."""

import numpy as np
import pytest

import kinema
from conftest import random_q


def rot_z(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def errors(T_target, T):
    dp = np.linalg.norm(T_target[:3, 3] - T[:3, 3])
    R = T_target[:3, :3] @ T[:3, :3].T
    return dp, np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))


def test_every_listed_scorbot_solution_meets_the_pose():
    r = kinema.Robot.builtin("scorbot-er-v-plus")
    rng = np.random.default_rng(2302)
    for q in random_q(r, rng, 60):
        T = r.fkine(q)
        for s in r.ik(T, all=True) + [r.ik(T, q0=q)]:
            dp, dw = errors(T, r.fkine(s.q))
            assert dp < 1e-6 and dw < 1e-6, (q, s.q, s.branch)


@pytest.mark.parametrize("solver", ["auto", "analytic", "numeric"])
def test_an_orientation_five_joints_cannot_take_is_unreachable(solver):
    r = kinema.Robot.builtin("scorbot-er-v-plus")
    T = np.array([[np.cos(1.2), 0, np.sin(1.2), 0.35], [0, 1, 0, 0], [-np.sin(1.2), 0, np.cos(1.2), 0.3], [0, 0, 0, 1]])
    T[:3, :3] = rot_z(0.5) @ T[:3, :3]
    with pytest.raises(kinema.Unreachable) as e:
        r.ik(T, solver=solver)
    c = e.value.closest
    assert c is not None and len(c["q"]) == 5
    assert c["position_error"] > 1e-6 or c["orientation_error"] > 1e-6
    # Freeing the rotation about the world z axis.
    s = r.ik(T, mask=[1, 1, 1, 1, 1, 0])
    assert np.linalg.norm(r.fkine(s.q)[:3, 3] - T[:3, 3]) < 1e-6


def test_bad_masks_tolerances_and_seeds_are_invalid_input():
    r = kinema.Robot.builtin("ur5")
    T = r.fkine(np.array([0.1, -1.2, 1.4, -0.8, -1.5, 0.3]))
    for mask in ([1, 1, 1], [0] * 6, [1, 1, 1, 0, 0, 2], "abcdef"):
        with pytest.raises(kinema.InvalidInput):
            r.ik(T, mask=mask)
    with pytest.raises(kinema.InvalidInput):
        r.ik(T, tol_position=0.0)
    for seed in (-1, 2**64, 2**70):
        with pytest.raises(kinema.InvalidInput, match="seed"):
            r.ik(T, seed=seed)
        with pytest.raises(kinema.InvalidInput, match="seed"):
            r.ik_batch(T[None], seed=seed)
    with pytest.raises(kinema.InvalidInput):
        r.ik(position=[0.3, 0.1, 0.4], mask=[1] * 6)


def test_ik_batch_rows_are_ik_answers():
    r = kinema.Robot.builtin("ur5")
    rng = np.random.default_rng(2305)
    Q0 = random_q(r, rng, 200)
    T = r.fkine_batch(Q0)
    T[7, 0, 3] += 10.0  # out of reach
    Q, ok, reasons = r.ik_batch(T)
    assert Q.shape == (200, 6) and ok.shape == (200,) and len(reasons) == 200
    assert not ok[7] and np.isnan(Q[7]).all() and "unreachable" in reasons[7]
    for k in np.flatnonzero(ok):
        dp, dw = errors(T[k], r.fkine(Q[k]))
        assert dp < 1e-6 and dw < 1e-6 and reasons[k] == ""
        one = r.ik(T[k])
        assert np.allclose(one.q, Q[k], atol=1e-12)
    assert ok.sum() == 199
    P = T[:, :3, 3]
    Qp, okp, _ = r.ik_batch(position=P)
    assert okp.sum() == 199
    for k in np.flatnonzero(okp):
        assert np.linalg.norm(r.fkine(Qp[k])[:3, 3] - P[k]) < 1e-6
    with pytest.raises(kinema.InvalidInput):
        r.ik_batch()
    with pytest.raises(kinema.InvalidInput):
        r.ik_batch(T, position=P)
    with pytest.raises(kinema.InvalidInput):
        r.ik_batch(position=P[:, :2])
