"""Point-to-point trajectories: shapes, end points, synchronisation, limits, errors."""

import numpy as np
import pytest

import kinema
from cli import ROOT, cli_json, needs_cli


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


def without_acceleration_limits(name, tmp_path):
    """A built-in robot, loaded from its file with the `acc` lines left out."""
    text = (ROOT / "robots" / f"{name}.toml").read_text(encoding="utf-8")
    path = tmp_path / f"{name}.toml"
    path.write_text("".join(l + "\n" for l in text.splitlines() if not l.startswith("acc =")), encoding="utf-8")
    return kinema.Robot.from_file(path)


def test_ptp_errors(robots, tmp_path):
    r = robots["lbr-iiwa-14-r820"]
    qf = np.array([0.5, 0.4, -0.3, -1.0, 0.2, 0.6, -0.4])
    with pytest.raises(kinema.InvalidInput, match=r"unknown profile `bogus`"):
        r.ptp(r.home, qf, 0.01, profile="bogus")
    with pytest.raises(kinema.InvalidInput, match=r"has 7 joints, but 3 joint values"):
        r.ptp(r.home, [0, 0, 0], 0.01)
    with pytest.raises(kinema.InvalidInput, match=r"has 2 values; 7 expected \(one per joint of `lbr-iiwa-14-r820`, or 1 for every joint\)"):
        r.ptp(r.home, qf, 0.01, vmax=[1.0, 2.0])
    with pytest.raises(kinema.InvalidInput):
        r.ptp(r.home, qf, 0.01, speed=0.0)
    with pytest.raises(kinema.InvalidInput):
        r.ptp(r.home, qf, -1.0)
    bare = without_acceleration_limits("lbr-iiwa-14-r820", tmp_path)
    with pytest.raises(kinema.InvalidInput, match=r"^joint 1 \(`.+`\): no acceleration limit for its motion in the robot model; give one \(`amax`\)"):
        bare.ptp(bare.home, qf, 0.01)
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
    for profile in ("trapezoid", "scurve"):
        with pytest.raises(kinema.InvalidInput, match="lost to rounding"):
            kinema.time_law(profile, 1e308, vmax=1.0, amax=1.0, jmax=1.0)
    # Large but plannable limits: above the PUMA's own, so the check refuses them (the core's
    # tests check that both ends are kept).
    with pytest.raises(kinema.TrajectoryError, match="the trajectory is not emitted"):
        r.ptp("qz", "qr", 0.01, vmax=1e6, amax=1e6)


def test_panda_trapezoid_is_refused_for_its_jerk_limits_and_its_default_is_the_scurve(robots):
    r = kinema.Robot.builtin("panda")
    qf = [0.5, -0.3, 0.2, -2.0, 0.1, 1.8, 0.6]
    with pytest.raises(kinema.InvalidInput, match="jerk limit"):
        r.ptp(r.home, qf, 0.01, profile="trapezoid")
    for tr in [r.ptp(r.home, qf, 0.01, profile="scurve"), r.ptp(r.home, qf, 0.01)]:
        assert tr.profile == "scurve" and np.allclose(tr.q[-1], qf)


def test_every_builtin_plans_a_default_ptp():
    """Issue 34: ``robot.ptp(q0, q1, dt)`` with every default works on every built-in (from the
    registry): from ``home`` to seeded random configurations within the limits and to every named
    pose, the profile the robot's default (trapezoid, or the S-curve where the model has jerk limits)."""
    rng = np.random.default_rng(34)
    names = kinema.Robot.builtins()
    assert len(names) >= 7
    for name in names:
        r = kinema.Robot.builtin(name)
        lo, hi = r.qlim
        targets = list(r.poses.values()) + [rng.uniform(lo, hi) for _ in range(3)]
        for qf in targets:
            tr = r.ptp(r.home, qf, 0.01)
            assert np.allclose(tr.q[-1], qf, atol=1e-12), name
            assert tr.profile == ("scurve" if name == "panda" else "trapezoid"), (name, tr.profile)


VIA = np.array([0.5, 0.8, 0.2, 1.2, -0.4, -1.0, 0.1])
QF = np.array([-0.1090, 1.2417, 0.4463, 1.9156, -0.9695, -1.8728, 0.4876])
W = np.array([0.3, 0.3, 0.3, 0.3, -0.3, -0.3, 0.3])


@pytest.mark.parametrize("profile", ["scurve", "trapezoid"])
def test_ptp_with_boundary_velocities_chains_without_stopping(robots, profile):
    r = robots["lbr-iiwa-14-r820"]
    acc = np.array([0.1, 0.0, -0.2, 0.0, 0.3, 0.0, 0.0]) if profile == "scurve" else np.zeros(7)
    a = r.ptp("home", VIA, 0.005, profile=profile, amax=2.0, jmax=15.0, v1=W, a1=acc)
    b = r.ptp(VIA, QF, 0.005, profile=profile, amax=2.0, jmax=15.0, v0=W, a0=acc)
    assert a.profile == profile and a.phase_times == []
    assert np.allclose(a.q[-1], b.q[0], atol=1e-9) and np.allclose(a.q[-1], VIA, atol=1e-9)
    assert np.allclose(a.qd[-1], W, atol=1e-9) and np.allclose(b.qd[0], W, atol=1e-9)
    assert np.allclose(a.qdd[-1], b.qdd[0], atol=1e-9) and np.allclose(b.q[-1], QF, atol=1e-9)
    assert np.isclose(a.t[-1], a.duration)
    stop = r.ptp("home", VIA, 0.01, profile=profile, amax=2.0, jmax=15.0).duration
    stop += r.ptp(VIA, QF, 0.01, profile=profile, amax=2.0, jmax=15.0).duration
    assert a.duration + b.duration < stop
    # Within the limits, as the check already made sure.
    assert np.all(np.abs(a.qdd) <= 2.0 * (1 + 1e-9))


def test_ptp_with_zero_boundaries_is_todays_straight_line(robots):
    r = robots["lbr-iiwa-14-r820"]
    plain = r.ptp("home", QF, 0.01, profile="scurve", amax=2.0, jmax=15.0)
    zeros = r.ptp("home", QF, 0.01, profile="scurve", amax=2.0, jmax=15.0, v0=np.zeros(7), a1=[0.0] * 7)
    assert zeros.duration == plain.duration and zeros.phase_times == plain.phase_times
    assert np.array_equal(zeros.q, plain.q) and np.array_equal(zeros.qd, plain.qd)


def test_ptp_boundary_errors_name_the_argument(robots):
    r = robots["lbr-iiwa-14-r820"]
    with pytest.raises(kinema.InvalidInput, match="`v1` has 2 values; 7 expected"):
        r.ptp("home", QF, 0.01, profile="scurve", v1=[0.1, 0.2])
    with pytest.raises(kinema.InvalidInput, match=r"`a0\[2\]` is NaN; it must be a finite number"):
        r.ptp("home", QF, 0.01, profile="scurve", a0=[0.0, np.nan, 0, 0, 0, 0, 0])
    with pytest.raises(kinema.InvalidInput, match="only moves rest to rest"):
        r.ptp("home", QF, 0.01, profile="quintic", v0=W)
    with pytest.raises(kinema.InvalidInput, match="needs the jerk-limited scurve"):
        r.ptp("home", QF, 0.01, profile="trapezoid", a1=W)
    # Joint 4 starts near its limit moving towards it: the overshoot is caught.
    q0 = np.array([0, 0, 0, 2.05, 0, 0, 0.0])
    with pytest.raises(kinema.TrajectoryError, match="joint 4"):
        r.ptp(q0, QF, 0.01, profile="scurve", amax=2.0, jmax=15.0, v0=[0, 0, 0, 1.2, 0, 0, 0])


@needs_cli
def test_ptp_boundary_matches_the_command_line(robots):
    r = robots["lbr-iiwa-14-r820"]
    tr = r.ptp("home", VIA, 0.01, profile="scurve", amax=2.0, jmax=15.0, v1=W)
    out = cli_json(
        ["traj", "ptp", "-r", "lbr-iiwa-14-r820", "--from", "home", "--to", ",".join(map(str, VIA)),
         "--profile", "scurve", "--amax", "2", "--jmax", "15", "--v1", ",".join(map(str, W)), "--json"]
    )
    assert out["duration"] == tr.duration
    rows = np.array(out["rows"])
    assert np.allclose(rows[:, 0], tr.t, atol=1e-9) and np.allclose(rows[:, 1:8], tr.q, atol=1e-9)
