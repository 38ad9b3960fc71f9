"""Point-to-point trajectories: shapes, end points, synchronisation, limits, errors."""

import numpy as np
import pytest

import kinema


@pytest.mark.parametrize("profile", ["trapezoid", "scurve", "cubic", "quintic", "linear"])
def test_ptp_shapes_ends_and_synchronisation(robots, profile):
    r = robots["lbr-iiwa-14-r820"]
    q0 = r.home
    qf = np.array([0.5, 0.4, -0.3, -1.0, 0.2, 0.6, -0.4])
    tr = r.ptp(q0, qf, 0.01, profile=profile, amax=2.0, jmax=20.0)
    assert isinstance(tr, kinema.JointTrajectory) and tr.profile == profile
    k = len(tr)
    assert tr.t.shape == (k,) and tr.q.shape == tr.qd.shape == tr.qdd.shape == (k, 7)
    assert tr.t[0] == 0.0 and np.isclose(tr.t[-1], tr.duration)
    assert np.all(np.diff(tr.t) > 0) and np.all(np.diff(tr.t) <= 0.01 + 1e-12)
    assert np.allclose(tr.q[0], q0, atol=1e-12) and np.allclose(tr.q[-1], qf, atol=1e-12)
    # One shared law s(t): every joint is at the same fraction of its move.
    s = (tr.q - q0) / (qf - q0)
    assert np.allclose(s, s[:, :1], atol=1e-9)
    assert np.all(np.diff(s[:, 0]) >= -1e-12)


def test_ptp_respects_given_limits(robots):
    r = robots["lbr-iiwa-14-r820"]
    qf = np.array([1.0, -0.5, 0.3, -1.5, 0.2, 0.9, -0.4])
    tr = r.ptp("home", qf, 0.002, vmax=0.5, amax=1.0)
    assert np.abs(tr.qd).max() <= 0.5 + 1e-9
    assert np.abs(tr.qdd).max() <= 1.0 + 1e-9
    # Velocities are the derivative of the positions.
    fd = np.gradient(tr.q, tr.t, axis=0)
    assert np.abs(fd[1:-1] - tr.qd[1:-1]).max() < 5e-3
    slow = r.ptp("home", qf, 0.01, vmax=0.5, amax=1.0, speed=0.5)
    assert slow.duration > tr.duration
    stretched = r.ptp("home", qf, 0.01, vmax=0.5, amax=1.0, duration=2 * tr.duration)
    assert np.isclose(stretched.duration, 2 * tr.duration)


def test_ptp_errors(robots):
    r = robots["lbr-iiwa-14-r820"]
    qf = np.array([0.5, 0.4, -0.3, -1.0, 0.2, 0.6, -0.4])
    with pytest.raises(kinema.InvalidInput, match=r"unknown profile `bogus`"):
        r.ptp(r.home, qf, 0.01, profile="bogus")
    with pytest.raises(kinema.InvalidInput, match=r"has 7 joints, but 3 joint values"):
        r.ptp(r.home, [0, 0, 0], 0.01)
    with pytest.raises(kinema.InvalidInput, match=r"2 values given; expected 1 \(every joint\) or 7"):
        r.ptp(r.home, qf, 0.01, vmax=[1.0, 2.0])
    with pytest.raises(kinema.InvalidInput):
        r.ptp(r.home, qf, 0.01, speed=0.0)
    with pytest.raises(kinema.InvalidInput):
        r.ptp(r.home, qf, -1.0)
    with pytest.raises(kinema.InvalidInput, match=r"^invalid `amax`: joint 1 .* has no acceleration limit"):
        r.ptp(r.home, qf, 0.01)
    # Velocity limits above the robot's: planned, then rejected by the check.
    with pytest.raises(kinema.TrajectoryError, match=r"^the trajectory is not emitted: \d+ violation"):
        r.ptp(r.home, qf, 0.01, vmax=100.0, amax=100.0)


def test_extreme_limits_are_refused_on_every_door(robots):
    """``vmax=amax=1e100`` used to give one sample at the target (the start lost);
    a jerk of 1e-300 an infinite duration. Both are errors naming the cause."""
    r = robots["puma560"]
    with pytest.raises(kinema.InvalidInput, match="shorter than"):
        r.ptp("qz", "qr", 0.01, vmax=1e100, amax=1e100)
    with pytest.raises(kinema.InvalidInput, match="overflows"):
        kinema.time_law("scurve", 1.0, vmax=1.0, amax=1.0, jmax=1e-300)
    with pytest.raises(kinema.InvalidInput, match="overflows"):
        kinema.time_law("trapezoid", 1e308, vmax=0.5, amax=1.0)
    tr = r.ptp("qz", "qr", 0.01, vmax=1e6, amax=1e6)
    assert len(tr.t) >= 2 and np.allclose(tr.q[0], r.pose("qz"))


def test_panda_trapezoid_is_refused_for_its_jerk_limits(robots):
    r = kinema.Robot.builtin("panda")
    qf = [0.5, -0.3, 0.2, -2.0, 0.1, 1.8, 0.6]
    with pytest.raises(kinema.InvalidInput, match="jerk limit"):
        r.ptp(r.home, qf, 0.01)
    tr = r.ptp(r.home, qf, 0.01, profile="scurve")
    assert np.allclose(tr.q[-1], qf)
