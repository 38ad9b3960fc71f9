"""The toolbox's names: ctraj, jtraj, poses as spatialmath SE3, sequences of SE3 as batches."""

import numpy as np
import pytest
import spatialmath as sm

import kinema


def rotation_angle(R):
    return np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))


@pytest.fixture
def poses():
    rng = np.random.default_rng(38)
    T0 = sm.SE3(*rng.uniform(-1, 1, 3)) * sm.SE3.RPY(*rng.uniform(-1, 1, 3))
    T1 = sm.SE3(*rng.uniform(-1, 1, 3)) * sm.SE3.RPY(*rng.uniform(-1, 1, 3))
    return T0.A, T1.A


def test_ctraj_moves_on_the_line_with_the_trapezoid_thirds(poses):
    T0, T1 = poses
    Ts = kinema.ctraj(T0, T1, 31)
    assert Ts.shape == (31, 4, 4)
    np.testing.assert_allclose(Ts[0], T0, atol=1e-12)
    np.testing.assert_allclose(Ts[-1], T1, atol=1e-12)
    # The fraction of the path at each sample: along the line and along the rotation's geodesic alike.
    s = np.linalg.norm(Ts[:, :3, 3] - T0[:3, 3], axis=1) / np.linalg.norm(T1[:3, 3] - T0[:3, 3])
    total = rotation_angle(T0[:3, :3].T @ T1[:3, :3])
    angle = np.array([rotation_angle(T0[:3, :3].T @ T[:3, :3]) for T in Ts]) / total
    np.testing.assert_allclose(angle, s, atol=1e-9)
    # Trapezoid in thirds over 30 steps: constant acceleration 1/200 per step² for 10 steps, then cruise.
    np.testing.assert_allclose(s[:11], 0.5 * (1 / 200) * np.arange(11) ** 2, atol=1e-12)
    np.testing.assert_allclose(np.diff(s[10:21]), 0.05, atol=1e-12)
    np.testing.assert_allclose(s, 1 - s[::-1], atol=1e-12)


def test_ctraj_takes_fractions_and_gives_se3(poses):
    T0, T1 = poses
    s = np.array([0.0, 0.25, 1.0])
    Ts = kinema.ctraj(sm.SE3(T0, check=False), sm.SE3(T1, check=False), s, as_se3=True)
    assert isinstance(Ts, sm.SE3) and len(Ts) == 3
    mid = T0[:3, 3] + 0.25 * (T1[:3, 3] - T0[:3, 3])
    np.testing.assert_allclose(Ts[1].t, mid, atol=1e-12)
    with pytest.raises(kinema.InvalidInput, match="fractions of the path lie in"):
        kinema.ctraj(T0, T1, [0.0, 1.5])
    with pytest.raises(kinema.InvalidInput, match="`T0` holds 2 poses; ctraj goes from one pose to one pose"):
        kinema.ctraj(sm.SE3([sm.SE3(T0, check=False)] * 2), T1, 5)
    with pytest.raises(kinema.InvalidInput, match="at least 2"):
        kinema.ctraj(T0, T1, 1)


def test_jtraj_is_the_rest_to_rest_quintic():
    q0, q1 = np.array([0.1, -0.5, 2.0]), np.array([1.0, 0.5, -1.0])
    q, qd, qdd = kinema.jtraj(q0, q1, 101)
    path = kinema.jtraj(q0, q1, 101)
    np.testing.assert_allclose(path.t, np.linspace(0, 1, 101), atol=1e-15)
    assert q.shape == qd.shape == qdd.shape == (101, 3)
    np.testing.assert_allclose(q[[0, -1]], [q0, q1], atol=1e-15)
    np.testing.assert_allclose(qd[[0, -1]], 0, atol=1e-15)
    np.testing.assert_allclose(qdd[[0, -1]], 0, atol=1e-15)
    np.testing.assert_allclose(q[50], (q0 + q1) / 2, atol=1e-15)
    np.testing.assert_allclose(qd[50], 1.875 * (q1 - q0), atol=1e-12)  # 15/8 the mean speed
    # qd and qdd are the derivatives of q (central differences), per second of t.
    t = np.linspace(0, 4, 401)
    q, qd, qdd = kinema.jtraj(q0, q1, t)
    np.testing.assert_allclose(np.gradient(q, t, axis=0)[1:-1], qd[1:-1], atol=1e-4)
    np.testing.assert_allclose(np.gradient(qd, t, axis=0)[1:-1], qdd[1:-1], atol=1e-4)
    with pytest.raises(kinema.InvalidInput, match="increasing times from 0"):
        kinema.jtraj(q0, q1, [0.0, 2.0, 1.0])
    with pytest.raises(kinema.InvalidInput, match="1-D of one length"):
        kinema.jtraj(q0, q1[:2], 5)


def test_fkine_gives_se3_when_asked(robots):
    robot = robots["puma560"]
    q = np.random.default_rng(1).uniform(-1, 1, (4, robot.n))
    one = robot.fkine(q[0], as_se3=True)
    assert isinstance(one, sm.SE3) and len(one) == 1
    np.testing.assert_array_equal(one.A, robot.fkine(q[0]))
    many = robot.fkine_batch(q, as_se3=True)
    assert len(many) == 4
    np.testing.assert_array_equal(np.asarray(many.A), robot.fkine_batch(q))


def test_a_sequence_of_se3_is_a_batch_never_its_first(robots):
    robot = robots["puma560"]
    q = np.random.default_rng(2).uniform(-1, 1, (3, robot.n))
    targets = robot.fkine_batch(q, as_se3=True)
    with pytest.raises(kinema.InvalidInput, match=r"got shape \(3, 4, 4\)"):
        robot.ik(targets)
    sol = robot.ik(targets[1])
    np.testing.assert_allclose(robot.fkine(sol.q), targets[1].A, atol=1e-9)
    batch = robot.ik_batch(targets)
    assert len(batch) == 3
