"""Cartesian LIN and CIRC motions: geometry of every sample (by forward kinematics), end points, time law, errors."""

import numpy as np
import pytest

import kinema
from cli import ROOT, cli_json, needs_cli


def rot_xyz(a, b, c):
    """R = Rx(a)·Ry(b)·Rz(c)."""
    ca, sa, cb, sb, cc, sc = np.cos(a), np.sin(a), np.cos(b), np.sin(b), np.cos(c), np.sin(c)
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    rz = np.array([[cc, -sc, 0], [sc, cc, 0], [0, 0, 1]])
    return rx @ ry @ rz


def transform(p, rpy_xyz):
    T = np.eye(4)
    T[:3, :3] = rot_xyz(*rpy_xyz)
    T[:3, 3] = p
    return T


# Seed 004 §VIII-C1: the start pose (rpy in Rx·Ry·Rz) and a goal, as the CLI's test uses them.
START = transform([0.7373, -0.3271, 0.7325], [-0.6595, 1.4584, 1.2113])
GOAL = transform([0.6, -0.6, 0.3], [0.0, 1.5708, 0.0])


@pytest.fixture(scope="module")
def iiwa():
    r = kinema.Robot.builtin("lbr-iiwa-14-r820")
    return r, r.ik(START).q


def rotation_angle(R):
    return np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))


def test_lin_samples_lie_on_the_segment(iiwa):
    r, q0 = iiwa
    tr = r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5)
    assert isinstance(tr, kinema.JointTrajectory) and tr.profile == "trapezoid"
    k = len(tr)
    assert tr.q.shape == tr.qd.shape == tr.qdd.shape == (k, 7) and tr.poses.shape == (k, 4, 4)
    assert tr.t[0] == 0.0 and np.isclose(tr.t[-1], tr.duration) and np.all(np.diff(tr.t) <= 0.01 + 1e-12)
    assert np.allclose(tr.q[0], q0, atol=1e-12)
    F = r.fkine_batch(tr.q)
    # The planned poses are reached, and every position is on the straight segment START → GOAL.
    assert np.abs(F - tr.poses).max() < 1e-9
    a, b = START[:3, 3], GOAL[:3, 3]
    u = (b - a) / np.linalg.norm(b - a)
    d = F[:, :3, 3] - a
    along = d @ u
    off = np.linalg.norm(d - np.outer(along, u), axis=1)
    assert off.max() < 1e-9
    assert along.min() > -1e-9 and along.max() < np.linalg.norm(b - a) + 1e-9 and np.all(np.diff(along) > -1e-9)
    # Ends at the target, position and orientation.
    assert np.linalg.norm(F[-1, :3, 3] - b) < 1e-9 and rotation_angle(F[-1, :3, :3].T @ GOAL[:3, :3]) < 1e-7
    # Tool speed within vmax (finite differences of the reached positions).
    speed = np.linalg.norm(np.diff(F[:, :3, 3], axis=0), axis=1) / np.diff(tr.t)
    assert speed.max() <= 0.2 * (1 + 1e-6)
    # Joint velocities are the derivative of the joint positions.
    fd = np.gradient(tr.q, tr.t, axis=0)
    assert np.abs(fd[2:-2] - tr.qd[2:-2]).max() < 1e-2
    assert tr.segment_starts == [0.0] and tr.blend_times == [] and len(tr.phase_times) == 3


def test_lin_distance_follows_the_time_law(iiwa):
    # With loose angular limits the translation decides: the distance travelled is the time law of the segment.
    r, q0 = iiwa
    for profile in ["trapezoid", "scurve", "quintic"]:
        tr = r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, jmax=2.0, rot_vmax=50, rot_amax=50, rot_jmax=500, profile=profile)
        length = np.linalg.norm(GOAL[:3, 3] - START[:3, 3])
        law = kinema.time_law(profile, length, vmax=0.2, amax=0.5, jmax=2.0)
        assert np.isclose(tr.duration, law.duration, rtol=1e-12)
        assert np.allclose(tr.phase_times, law.phase_times, rtol=1e-12)
        travelled = np.linalg.norm(r.fkine_batch(tr.q)[:, :3, 3] - START[:3, 3], axis=1)
        assert np.allclose(travelled, law.sample(tr.t)[0], atol=1e-9)


def test_lin_via_points_and_blending(iiwa):
    r, q0 = iiwa
    via = transform([0.65, -0.45, 0.55], [0.0, 1.5708, 0.0])
    stop = r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, via=[via], blend="none")
    assert len(stop.segment_starts) == 2 and stop.blend_times == [0.0] and stop.phase_times == []
    P = r.fkine_batch(stop.q)[:, :3, 3]

    def off_segment(p, a, b):
        u = b - a
        s = np.clip((p - a) @ u / (u @ u), 0, 1)
        return np.linalg.norm(p - (a + np.outer(s, u)), axis=1)

    a, m, b = START[:3, 3], via[:3, 3], GOAL[:3, 3]
    assert np.minimum(off_segment(P, a, m), off_segment(P, m, b)).max() < 1e-9
    assert np.linalg.norm(P[-1] - b) < 1e-9
    blended = r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, via=np.stack([via]), blend="decel")
    assert blended.blend_times[0] > 0 and blended.duration < stop.duration
    assert np.linalg.norm(r.fkine_batch(blended.q)[:, :3, 3] - m, axis=1).min() > 1e-4  # the corner is cut
    for b_arg in (0.2, "0.2", "0.02m"):
        tr = r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, via=via, blend=b_arg)
        assert tr.duration <= stop.duration + 1e-12


def test_lin_options(iiwa):
    r, q0 = iiwa
    # Resampled so that consecutive tool positions are at most 1 cm apart (as `--max-step 0.01`).
    tr = r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, max_step=0.01)
    P = r.fkine_batch(tr.q)[:, :3, 3]
    assert np.linalg.norm(np.diff(P, axis=0), axis=1).max() <= 0.01 + 1e-9
    assert 50 < len(tr) < 80
    # RPY interpolation ends at the same pose; resolved rate follows the line closely.
    # (Rx·Ry·Rz angles pass a wrist singularity on this path; the default Rz·Ry·Rx ones do not.)
    rpy = r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, orientation="rpy", rot_vmax=0.3, rot_amax=0.5)
    F = r.fkine(rpy.q[-1])
    assert np.linalg.norm(F[:3, 3] - GOAL[:3, 3]) < 1e-9 and rotation_angle(F[:3, :3].T @ GOAL[:3, :3]) < 1e-7
    slerp = r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, rot_vmax=0.3, rot_amax=0.5)
    assert not np.allclose(rpy.poses[len(rpy) // 2], slerp.poses[len(slerp) // 2], atol=1e-3)
    rate = r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, method="rate")
    assert np.abs(r.fkine_batch(rate.q)[:, :3, 3] - rate.poses[:, :3, 3]).max() < 1e-3
    # ptp has no Cartesian poses.
    p = r.ptp(q0, rpy.q[-1], 0.01, amax=1.0)
    assert p.poses is None and p.segment_starts == [0.0] and p.blend_times == []


def rot_zyx(roll, pitch, yaw):
    """R = Rz(yaw)·Ry(pitch)·Rx(roll) (the default `rpy`)."""
    return rot_xyz(0, 0, yaw) @ rot_xyz(0, pitch, 0) @ rot_xyz(roll, 0, 0)


def test_poses_as_six_numbers(iiwa):
    """Goals and via poses as x, y, z, roll, pitch, yaw (both conventions) give the 4×4 forms' motions."""
    r, q0 = iiwa
    rng = np.random.default_rng(70)
    done = 0
    for case in range(12):
        xyz = GOAL[:3, 3] + rng.uniform(-0.05, 0.05, 3)
        angles = np.array([0.0, 1.5708, 0.0]) + rng.uniform(-0.2, 0.2, 3)
        rpy = ["xyz", "zyx"][case % 2]
        R = rot_xyz(*angles) if rpy == "xyz" else rot_zyx(*angles)
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = R, xyz
        six = [*xyz, *angles]
        via4 = transform([0.65, -0.45, 0.55], [0.0, 1.5708, 0.0])
        via6 = [0.65, -0.45, 0.55, 0.0, 1.5708, 0.0]
        kw = dict(vmax=0.2, amax=0.5, rot_vmax=0.5, rot_amax=1.0)
        try:
            want = r.lin(q0, T, 0.01, via=via4, **kw)
        except (kinema.Unreachable, kinema.TrajectoryError) as e:
            with pytest.raises(type(e)):
                r.lin(q0, six, 0.01, via=[via6] if rpy == "xyz" else None, rpy=rpy, **kw)
            continue
        if rpy == "xyz":
            got = r.lin(q0, six, 0.01, via=np.array([via6]), rpy="xyz", **kw)  # (V, 6)
        else:
            got = r.lin(q0, six, 0.01, via=via4, **kw)  # the default convention, a 4×4 via
        assert len(got) == len(want) and np.abs(got.q - want.q).max() < 1e-9
        assert np.abs(got.poses - want.poses).max() < 1e-12
        done += 1
        circ4 = r.circ(q0, [0.7, -0.5, 0.6], T, 0.01, vmax=0.2, amax=0.5, rot_vmax=0.5, rot_amax=1.0)
        circ6 = r.circ(q0, [0.7, -0.5, 0.6, 9.0, 9.0, 9.0], six, 0.01, vmax=0.2, amax=0.5, rot_vmax=0.5,
                       rot_amax=1.0, rpy=rpy)
        assert np.abs(circ6.q - circ4.q).max() < 1e-9
    assert done >= 6, done
    with pytest.raises(kinema.InvalidInput, match=r"`T` contains NaN; all values must be finite"):
        r.lin(q0, [0.6, -0.6, 0.3, 0.0, np.nan, 0.0], 0.01, vmax=0.2, amax=0.5)
    with pytest.raises(kinema.InvalidInput, match=r"`via\[1\]` contains inf"):
        r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, via=[[0.6, -0.5, 0.4, 0, 0, 0], [0.6, -0.5, 0.4, 0, np.inf, 0]])
    with pytest.raises(kinema.InvalidInput, match=r"`via` must have shape \(N, 4, 4\) \(homogeneous transforms\) or \(V, 6\)"):
        r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, via=np.zeros((2, 5)))
    with pytest.raises(kinema.InvalidInput, match=r"`T` must have shape \(4, 4\) \(a homogeneous transform\) or \(6,\)"):
        r.circ(q0, [0.7, -0.5, 0.6], [0.6, -0.6, 0.3], 0.01, vmax=0.2, amax=0.5)
    with pytest.raises(kinema.InvalidInput, match=r"unknown rpy convention `zxy`; expected one of: zyx, xyz"):
        r.circ(q0, [0.7, -0.5, 0.6], GOAL, 0.01, vmax=0.2, amax=0.5, rpy="zxy")


@needs_cli
def test_lin_and_circ_equal_the_cli(iiwa):
    """`kinema traj lin|circ --json` (poses as 6 numbers, --rpy xyz) gives the same joint samples."""
    r, q0 = iiwa
    start = ",".join(repr(float(v)) for v in q0)
    common = ["-r", "lbr-iiwa-14-r820", "--from", start, "--rpy", "xyz", "--vmax", "0.2", "--amax", "0.5", "--json"]
    goal = [0.6, -0.6, 0.3, 0.0, 1.5708, 0.0]
    text = ",".join(map(repr, goal))
    via = [0.65, -0.45, 0.55, 0.0, 1.5708, 0.0]
    out = cli_json(["traj", "lin", *common, "--to", text, "--via", ",".join(map(repr, via)), "--blend", "none"])
    tr = r.lin(q0, goal, 0.01, vmax=0.2, amax=0.5, via=[via], blend="none", rpy="xyz")
    rows = np.array(out["rows"])
    assert rows.shape[0] == len(tr) and out["duration"] == tr.duration and out["segment_starts"] == tr.segment_starts
    assert np.abs(rows[:, 0] - tr.t).max() < 1e-15 and np.abs(rows[:, 1:8] - tr.q).max() < 1e-12
    # Seed 004 eq. 40: the written roll-pitch-yaw triples are interpolated on both doors.
    out = cli_json(["traj", "lin", *common, "--to", text, "--orientation", "rpy"])
    tr = r.lin(q0, goal, 0.01, vmax=0.2, amax=0.5, orientation="rpy", rpy="xyz")
    rows = np.array(out["rows"])
    assert rows.shape[0] == len(tr) and abs(tr.duration - 3.260063) < 1e-6
    assert np.abs(rows[:, 1:8] - tr.q).max() < 1e-12
    out = cli_json(["traj", "circ", *common, "--to", text, "--aux", "0.7,-0.5,0.6"])
    tr = r.circ(q0, [0.7, -0.5, 0.6], goal, 0.01, vmax=0.2, amax=0.5, rpy="xyz")
    rows = np.array(out["rows"])
    assert rows.shape[0] == len(tr) and np.abs(rows[:, 1:8] - tr.q).max() < 1e-12


def circumcircle(a, b, c):
    ab, ac = b - a, c - a
    n = np.cross(ab, ac)
    centre = a + (ab @ ab * np.cross(ac, n) + ac @ ac * np.cross(n, ab)) / (2 * n @ n)
    return centre, np.linalg.norm(a - centre), n / np.linalg.norm(n)


@pytest.mark.parametrize("profile", ["trapezoid", "scurve"])
def test_circ_samples_lie_on_the_circle(iiwa, profile):
    r, q0 = iiwa
    aux = np.array([0.7, -0.5, 0.6])
    tr = r.circ(q0, aux, GOAL, 0.01, vmax=0.2, amax=0.5, profile=profile, jmax=2.0)
    assert tr.profile == profile and tr.poses.shape == (len(tr), 4, 4)
    F = r.fkine_batch(tr.q)
    assert np.abs(F - tr.poses).max() < 1e-9
    c, radius, n = circumcircle(START[:3, 3], aux, GOAL[:3, 3])
    P = F[:, :3, 3]
    assert np.abs(np.linalg.norm(P - c, axis=1) - radius).max() < 1e-9
    assert np.abs((P - c) @ n).max() < 1e-9
    assert np.linalg.norm(P[0] - START[:3, 3]) < 1e-9 and np.linalg.norm(P[-1] - GOAL[:3, 3]) < 1e-9
    assert rotation_angle(F[-1, :3, :3].T @ GOAL[:3, :3]) < 1e-7
    # It passes through the auxiliary point (within one sample step), turning one way only.
    assert np.linalg.norm(P - aux, axis=1).min() < 0.2 * 0.01 + 1e-9
    e1 = (START[:3, 3] - c) / radius
    e2 = np.cross(n, e1)
    angle = np.unwrap(np.arctan2((P - c) @ e2, (P - c) @ e1))
    assert np.all(np.diff(angle) >= -1e-12)
    # A 4×4 pose as the via point gives its position.
    via = np.eye(4)
    via[:3, 3] = aux
    same = r.circ(q0, via, GOAL, 0.01, vmax=0.2, amax=0.5, profile=profile, jmax=2.0)
    assert np.array_equal(same.q, tr.q)


def test_cartesian_errors(iiwa):
    r, q0 = iiwa
    with pytest.raises(kinema.InvalidInput, match="on one line"):
        mid = (START[:3, 3] + GOAL[:3, 3]) / 2
        r.circ(q0, mid, GOAL, 0.01, vmax=0.2, amax=0.5)
    far = GOAL.copy()
    far[:3, 3] = [2.5, 0.0, 0.3]
    with pytest.raises(kinema.Unreachable, match="at t = "):
        r.lin(q0, far, 0.01, vmax=0.5, amax=1.0)
    with pytest.raises(kinema.TrajectoryError, match=r"^the trajectory is not emitted: \d+ violation"):
        r.lin(q0, GOAL, 0.01, vmax=3.0, amax=30.0)
    bad = GOAL.copy()
    bad[0, 0] = 2.0
    with pytest.raises(kinema.InvalidInput, match="`T` is not a rigid transform"):
        r.lin(q0, bad, 0.01, vmax=0.2, amax=0.5)
    with pytest.raises(kinema.InvalidInput, match=r"`via\[1\]` is not a rigid transform"):
        r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, via=[GOAL, bad])
    with pytest.raises(kinema.InvalidInput, match=r"`T` must have shape \(4, 4\)"):
        r.lin(q0, GOAL[:3], 0.01, vmax=0.2, amax=0.5)
    with pytest.raises(kinema.InvalidInput, match=r"`via` must have shape \(3,\)"):
        r.circ(q0, [0.7, -0.5], GOAL, 0.01, vmax=0.2, amax=0.5)
    with pytest.raises(kinema.InvalidInput, match="has 7 joints, but 2 joint values"):
        r.lin([0.0, 0.0], GOAL, 0.01, vmax=0.2, amax=0.5)
    for kwargs, message in [
        (dict(orientation="euler"), "invalid `orientation`: `euler`"),
        (dict(orientation="rpy", rpy="abc"), "unknown rpy convention `abc`; expected one of: zyx, xyz"),
        (dict(method="jacobian"), "unknown method `jacobian`; expected one of: ik, rate"),
        (dict(blend="soon"), "unknown blend `soon`; expected one of: decel, none"),
        (dict(blend=[1]), "invalid `blend`"),
        (dict(profile="scurve"), "jmax"),
        (dict(profile="bogus"), "unknown profile `bogus`"),
    ]:
        with pytest.raises(kinema.InvalidInput, match=message):
            r.lin(q0, GOAL, 0.01, vmax=0.2, amax=0.5, **kwargs)
    with pytest.raises(kinema.InvalidInput, match="dt"):
        r.lin(q0, GOAL, -0.01, vmax=0.2, amax=0.5)
    with pytest.raises(kinema.InvalidInput, match=r"invalid `vel`: -1; expected a positive finite limit"):
        r.circ(q0, [0.7, -0.5, 0.6], GOAL, 0.01, vmax=-1.0, amax=0.5)
    with pytest.raises(TypeError):
        r.lin(q0, GOAL, 0.01)  # the Cartesian limits have no default


def test_q3_and_psi_choose_the_self_motion_as_the_cli_does(robots):
    """q3 held by default and by "hold" or its value; steered by the seed's
    rule; a value the start lacks, both q3 and psi, a bad name, and a
    six-joint arm are InvalidInput (the CLI's --q3/--psi)."""
    r = robots["lbr-iiwa-14-r820"]
    q0 = [0.3, 1.0, 0.4, -0.8, 0.2, 0.9, 0.1]
    goal = [0.50, 0.20, 0.90, 0.6945, 0.8387, 1.3509]

    def drift(**kw):
        tr = r.lin(q0, goal, 0.01, vmax=0.2, amax=1.0, **kw)
        return float(np.max(np.abs(tr.q[:, 2] - 0.4)))

    for kw in [{}, {"q3": "hold"}, {"q3": 0.4}]:
        assert drift(**kw) < 1e-9, kw
    assert drift(q3="manipulability") > 1e-3
    drift(q3="track")
    drift(q3="avoid-limits")
    for kw, says in [
        ({"q3": 0.5}, "q3 = 0.400000"),
        ({"q3": "hold", "psi": 0.1}, "not both"),
        ({"q3": "sideways"}, "sideways"),
        ({"psi": "track"}, "hold"),
        ({"q3": float("nan")}, "finite"),
        ({"q3": "hold", "method": "rate"}, "method"),
    ]:
        with pytest.raises(kinema.InvalidInput, match=says):
            drift(**kw)
    puma = robots["puma560"]
    qn = puma.pose("qn")
    T = puma.fkine(qn)
    T[2, 3] += 0.02
    with pytest.raises(kinema.InvalidInput, match="no self-motion"):
        puma.lin(qn, T, 0.01, vmax=0.2, amax=1.0, q3="hold")


def test_skip_unreachable_leaves_out_waypoints_as_the_cli_does(tmp_path):
    """Seed 003 Fig. 9 on lin: an unreachable via pose is left out (its index
    in .skipped) and the path equals the one written without it; without the
    option it is an error."""
    # The SCARA without its (estimated) joint velocity and acceleration limits, as the CLI's test:
    # the path kinks where the zone rule moves the rail. It starts from the zone rule's
    # configuration for `home`'s tool pose: from `home` itself the first sample is a branch jump.
    text = (ROOT / "robots" / "scara5.toml").read_text(encoding="utf-8")
    path = tmp_path / "scara5.toml"
    path.write_text("".join(l + "\n" for l in text.splitlines() if not l.startswith(("vel =", "acc ="))))
    r = kinema.Robot.from_file(path)
    home = np.array([0.738577, -0.085236, 2.407185, 0.1, -0.227554])
    near, far, goal = [0.3, 0.1, 0.2, 0, 0, 0], [3, 3, 0.2, 0, 0, 0], [0.35, -0.1, 0.2, 0, 0, 0]
    with pytest.raises(kinema.Unreachable):
        r.lin(home, goal, 0.01, vmax=0.2, amax=1.0, via=[near, far])
    tr = r.lin(home, goal, 0.01, vmax=0.2, amax=1.0, via=[near, far], skip_unreachable=True)
    assert tr.skipped == [1]
    ref = r.lin(home, goal, 0.01, vmax=0.2, amax=1.0, via=[near])
    assert ref.skipped == []
    np.testing.assert_array_equal(tr.q, ref.q)
