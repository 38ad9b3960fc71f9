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


def test_ik_batch_is_solved_a_chunk_at_a_time_with_the_same_answers():
    """Issue 35 item 5: ik_batch reads and solves 65 536 targets at a time. Across the chunk
    boundary the answers are those of the halves solved alone, and a bad pose in a later chunk
    is named by its index in the whole batch."""
    r = kinema.Robot.builtin("puma560")
    rng = np.random.default_rng(355)
    T = r.fkine_batch(random_q(r, rng, 70_000))
    Q, ok, reasons = r.ik_batch(T)
    assert Q.shape == (70_000, 6) and ok.all() and len(reasons) == 70_000
    Qa, _, _ = r.ik_batch(T[:35_000])
    Qb, _, _ = r.ik_batch(T[35_000:])
    assert np.array_equal(Q, np.vstack([Qa, Qb]))
    T[66_000, 0, 0] = np.nan
    with pytest.raises(kinema.InvalidInput, match=r"T\[66000\]"):
        r.ik_batch(T)
    Q6, ok6, _ = r.ik_batch(np.hstack([T[:10, :3, 3], np.zeros((10, 3))]))
    assert Q6.shape == (10, 6) and ok6.shape == (10,)
    Q0, ok0, reasons0 = r.ik_batch(np.zeros((0, 6)))
    assert Q0.shape == (0, 6) and ok0.shape == (0,) and reasons0 == []


def test_an_ik_batch_larger_than_memory_raises_memory_error():
    """Issue 35 item 5: 3·10⁷ targets used to kill the interpreter (an allocation failure
    aborts Rust). Under an address-space limit 1 GiB above what the input needs, the answer
    (1.44 GB of joint values) cannot be reserved: MemoryError naming the figure, and the
    interpreter goes on."""
    import subprocess
    import sys

    code = """
import resource, numpy as np, kinema
r = kinema.Robot.builtin("puma560")
p = np.full((30_000_000, 3), 0.5)
size = int(next(l for l in open("/proc/self/status") if l.startswith("VmSize")).split()[1]) * 1024
resource.setrlimit(resource.RLIMIT_AS, (size + (1 << 30), resource.getrlimit(resource.RLIMIT_AS)[1]))
try:
    r.ik_batch(position=p)
except MemoryError as e:
    print("MemoryError:", e)
print("alive")
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert "MemoryError: ik_batch: the joint values of the answer would take 1.44 GB" in done.stdout, done.stdout
    assert done.stdout.strip().endswith("alive")
