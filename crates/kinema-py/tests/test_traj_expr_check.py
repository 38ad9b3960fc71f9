"""Robot.expr (`kinema traj expr`) and Robot.check (`kinema traj check`): values against numpy
recomputations over seeded random inputs, the same answers as the command line, and errors."""

import numpy as np
import pytest

import kinema
from cli import cli_json, needs_cli


@pytest.fixture(scope="module")
def rommel():
    return kinema.Robot.builtin("rommel")


@pytest.fixture(scope="module")
def iiwa():
    return kinema.Robot.builtin("lbr-iiwa-14-r820")


def sample_times(duration, dt):
    """0, dt, 2 dt, ... and the end time (what the core samples)."""
    t = np.arange(int(np.floor(duration / dt)) + 1) * dt
    if duration - t[-1] > 1e-12 * max(duration, 1.0):
        t = np.append(t, duration)
    else:
        t[-1] = duration
    return t


def test_seed_001_curve(rommel):
    # Faster than ROMMEL's (estimated) limits: checked against limits given for it.
    with pytest.raises(kinema.TrajectoryError, match=r"joint 1 .*exceeds its limit"):
        rommel.expr({1: "0.5*sin(4*pi*t^2/2)"}, duration=2.0, dt=0.5)
    tr = rommel.expr({1: "0.5*sin(4*pi*t^2/2)"}, duration=2.0, dt=0.5, vmax=20.0, amax=400.0)
    assert isinstance(tr, kinema.JointTrajectory) and tr.profile == "expression"
    assert len(tr) == 5 and tr.duration == 2.0 and tr.poses is None and tr.phase_times == []
    assert abs(tr.q[1, 0] - 0.5 * np.sin(np.pi / 2)) < 1e-12
    assert np.array_equal(tr.q[:, 1:], np.tile(rommel.home[1:], (5, 1)))


def test_random_sines_against_numpy(rommel):
    """q = a·sin(ω t + φ) + c with its derivatives, for random joints and parameters; others hold q0."""
    rng = np.random.default_rng(60)
    lo, hi = rommel.qlim
    for _ in range(40):
        joints = rng.choice(5, size=rng.integers(1, 6), replace=False)
        params = {}
        for j in joints:
            a, w, phi = rng.uniform(0.05, 0.4), rng.uniform(0.2, 2.0), rng.uniform(-np.pi, np.pi)
            c = rng.uniform(lo[j] + 0.5, hi[j] - 0.5)
            params[int(j) + 1] = (a, w, phi, c)
        exprs = {j: f"{a!r}*sin({w!r}*t + ({phi!r})) + ({c!r})" for j, (a, w, phi, c) in params.items()}
        q0 = rng.uniform(lo + 0.1, hi - 0.1)
        duration, dt = rng.uniform(0.5, 3.0), rng.choice([0.01, 0.02, 0.05])
        form = rng.integers(2)
        tr = rommel.expr(exprs if form else list(exprs.items()), duration, dt=dt, q0=q0)
        t = sample_times(duration, dt)
        assert np.allclose(tr.t, t, rtol=0, atol=1e-12)
        for j in range(5):
            if j + 1 in params:
                a, w, phi, c = params[j + 1]
                assert np.allclose(tr.q[:, j], a * np.sin(w * t + phi) + c, atol=1e-12)
                assert np.allclose(tr.qd[:, j], a * w * np.cos(w * t + phi), atol=1e-12)
                assert np.allclose(tr.qdd[:, j], -a * w * w * np.sin(w * t + phi), atol=1e-12)
            else:
                assert np.all(tr.q[:, j] == q0[j]) and np.all(tr.qd[:, j] == 0) and np.all(tr.qdd[:, j] == 0)


def test_expr_errors(rommel):
    with pytest.raises(kinema.InvalidInput, match=r"column 6"):
        rommel.expr({1: "sin(t"}, 1.0)
    with pytest.raises(kinema.InvalidInput, match=r"invalid `joint`: 9; expected a joint of `rommel`, 1 to 5"):
        rommel.expr({9: "t"}, 1.0)
    with pytest.raises(kinema.InvalidInput, match=r"joint 0: joints are numbered from 1"):
        rommel.expr({0: "t"}, 1.0)
    with pytest.raises(kinema.InvalidInput, match=r"at least one joint expression"):
        rommel.expr({}, 1.0)
    with pytest.raises(kinema.InvalidInput, match=r"must be a dict"):
        rommel.expr("t", 1.0)
    with pytest.raises(kinema.InvalidInput, match=r"the value at t = .* is NaN"):
        rommel.expr({2: "sqrt(t - 0.5)"}, 1.0)
    with pytest.raises(kinema.InvalidInput, match=r"invalid `duration`"):
        rommel.expr({1: "t"}, -1.0)
    with pytest.raises(kinema.InvalidInput, match=r"invalid `dt`"):
        rommel.expr({1: "t"}, 1.0, dt=0.0)
    with pytest.raises(kinema.InvalidInput, match=r"has 5 joints, but 2 joint values"):
        rommel.expr({1: "t"}, 1.0, q0=[0.0, 0.0])
    with pytest.raises(kinema.TrajectoryError, match=r"the trajectory is not emitted: .* joint 1"):
        rommel.expr({1: "10*t"}, 1.0)


RANK = {"position": 1, "velocity": 2, "jump": 3, "acceleration": 4, "inconsistent": 5}


def reference_check(robot, t, q, qd, qdd, vmax, amax, tol=1e-9):
    """An independent numpy version of the documented check: per sample position, velocity,
    jump, acceleration; per step q̇ within A·h/2 of q's secant (5 % slack, rounding) and q's
    second divided difference within A. A list of (kind, sample, joint from 1) in sample,
    joint, kind order, one per (kind, sample, joint)."""
    lo, hi = robot.qlim
    eps = np.finfo(float).eps
    out = []
    for k in range(len(t)):
        for i in range(robot.n):
            pos_tol = tol * (1 + min(max(abs(hi[i]), abs(lo[i])), 1e6))
            if q[k, i] < lo[i] - pos_tol or q[k, i] > hi[i] + pos_tol:
                out.append(("position", k, i + 1))
            if abs(qd[k, i]) > vmax[i] * (1 + tol):
                out.append(("velocity", k, i + 1))
            if k > 0 and abs(q[k, i] - q[k - 1, i]) > vmax[i] * (t[k] - t[k - 1]) * (1 + tol) + 1e-12:
                out.append(("jump", k, i + 1))
            if abs(qdd[k, i]) > amax[i] * (1 + tol):
                out.append(("acceleration", k, i + 1))
    for k in range(1, len(t)):
        h = t[k] - t[k - 1]
        for i in range(robot.n):
            s1 = (q[k, i] - q[k - 1, i]) / h
            e1 = 2 * (2 * eps * max(abs(q[k - 1, i]), abs(q[k, i]))) / h
            allowed = 0.5 * amax[i] * h * 1.05 + e1
            for kk in (k - 1, k):
                if abs(qd[kk, i] - s1) > allowed + tol * abs(qd[kk, i]):
                    out.append(("inconsistent", kk, i + 1))
            if k + 1 < len(t):
                h2 = t[k + 1] - t[k]
                s2 = (q[k + 1, i] - q[k, i]) / h2
                e2 = 2 * (2 * eps * max(abs(q[k, i]), abs(q[k + 1, i]))) / h2
                second = 2 * (s2 - s1) / (h + h2)
                if abs(second) > amax[i] * (1 + tol) + 2 * (e1 + e2) / (h + h2):
                    out.append(("acceleration", k, i + 1))
    out.sort(key=lambda v: (v[1], v[2], RANK[v[0]]))
    return list(dict.fromkeys(out))


def lagrange_derivatives(t, q):
    """First and second derivatives at every sample from the parabola through the three nearest
    samples (the documented estimate for samples without qd/qdd); the difference quotient for two."""
    k = len(t)
    if k < 3:
        qd = np.zeros_like(q)
        if k == 2:
            qd[:] = (q[1] - q[0]) / (t[1] - t[0])
        return qd, np.zeros_like(q)
    qd, qdd = np.empty_like(q), np.empty_like(q)
    for j in range(k):
        c = min(max(j, 1), k - 2)
        x0, x1, x2, x = t[c - 1], t[c], t[c + 1], t[j]
        d = [(2 * x - x1 - x2) / ((x0 - x1) * (x0 - x2)), (2 * x - x0 - x2) / ((x1 - x0) * (x1 - x2)),
             (2 * x - x0 - x1) / ((x2 - x0) * (x2 - x1))]
        dd = [2 / ((x0 - x1) * (x0 - x2)), 2 / ((x1 - x0) * (x1 - x2)), 2 / ((x2 - x0) * (x2 - x1))]
        qd[j] = d[0] * q[c - 1] + d[1] * q[c] + d[2] * q[c + 1]
        qdd[j] = dd[0] * q[c - 1] + dd[1] * q[c] + dd[2] * q[c + 1]
    return qd, qdd


def test_check_random_trajectories_against_numpy(iiwa):
    rng = np.random.default_rng(61)
    lo, hi = iiwa.qlim
    kinds = set()
    for case in range(80):
        k = int(rng.integers(2, 80))
        t = np.cumsum(rng.uniform(0.005, 0.02, k)) - 0.005
        q = np.clip(iiwa.home + np.cumsum(rng.normal(0, 0.01, (k, 7)), axis=0), lo - 0.05, hi + 0.05)
        if case % 3 == 0:  # a few jumps and samples beyond the limits
            for _ in range(3):
                q[rng.integers(k), rng.integers(7)] += rng.choice([-1, 1]) * rng.uniform(0.3, 3.5)
        vmax = rng.uniform(0.5, 2.0, 7)
        amax = rng.uniform(5.0, 50.0, 7)
        if case % 2 == 0:  # velocities and accelerations estimated from the positions
            report = iiwa.check(t, q, vmax=vmax, amax=amax)
            qd, qdd = lagrange_derivatives(t, q)
            if k > 2:  # np.gradient is the same first derivative, computed another way
                assert np.allclose(np.gradient(q, t, axis=0, edge_order=2), qd, rtol=1e-9, atol=1e-9)
        else:
            qd, qdd = rng.normal(0, 1.0, (k, 7)), rng.normal(0, 20.0, (k, 7))
            report = iiwa.check(t, q, qd, qdd, vmax=vmax, amax=amax)
        assert report.samples == k and report.ok == (not report.violations)
        assert np.allclose(report.peak_velocity, np.abs(qd).max(axis=0), rtol=1e-9, atol=1e-9)
        assert np.allclose(report.peak_acceleration, np.abs(qdd).max(axis=0), rtol=1e-9, atol=1e-9)
        got = [(v["kind"], v["sample"], v["joint"]) for v in report.violations]
        assert got == reference_check(iiwa, t, q, qd, qdd, vmax, amax)
        for v in report.violations:
            kinds.add(v["kind"])
            assert v["t"] == t[v["sample"]] and v["message"].startswith(f"t = {v['t']:.4f} s (sample {v['sample']}): ")
            assert f"joint {v['joint']}" in v["message"]
    assert kinds == {"position", "velocity", "jump", "acceleration", "inconsistent"}, kinds


def test_check_trajectories_and_plans(iiwa):
    q1 = iiwa.home + 0.3
    tr = iiwa.ptp("home", q1, 0.01, amax=2.0)
    r = iiwa.check(tr)
    assert isinstance(r, kinema.CheckReport) and r.ok and r.samples == len(tr) and r.violations == []
    assert np.allclose(r.peak_velocity, np.abs(tr.qd).max(axis=0), rtol=0, atol=0)
    assert r.min_manipulability is None
    r.raise_if_violations()
    # Tighter limits: violations, reported; raise_if_violations raises the planners' error.
    slow = iiwa.check(tr, vmax=0.1)
    assert not slow.ok and {v["kind"] for v in slow.violations} >= {"velocity"}
    with pytest.raises(kinema.TrajectoryError, match=r"^the trajectory is not emitted: \d+ violation\(s\); the first: t = "):
        slow.raise_if_violations()
    # Near-singular samples (home is the stretched, singular arm): where manipulability < min_manip.
    w = np.array([iiwa.manipulability(q) for q in tr.q])
    m = iiwa.check(tr, min_manip=1e-3)
    t_min, value = m.min_manipulability
    assert t_min == tr.t[np.argmin(w)] and np.isclose(value, w.min(), rtol=1e-12, atol=1e-15)
    near = [v["sample"] for v in m.violations if v["kind"] == "nearsingular"]
    assert near == list(np.flatnonzero(w < 1e-3)) and near and [v["joint"] for v in m.violations] == [None] * len(near)
    plan = kinema.run_program("JACC 90 deg/s^2\nPTP JOINT(30deg, 20deg, 0deg, -60deg, 0deg, 30deg, 0deg)\n", iiwa)
    assert iiwa.check(plan).ok
    # A joint 4 jump in a copy: named with its sample.
    q = tr.q.copy()
    q[40:, 3] += 1.5
    jumpy = iiwa.check(tr.t, q)
    assert any(v["kind"] == "jump" and v["joint"] == 4 and v["sample"] == 40 for v in jumpy.violations)
    assert "joint 4 jumps" in repr([v["message"] for v in jumpy.violations])


def test_check_errors(iiwa):
    tr = iiwa.ptp("home", iiwa.home + 0.1, 0.05, amax=2.0)
    with pytest.raises(kinema.InvalidInput, match=r"`q` is missing"):
        iiwa.check(tr.t)
    with pytest.raises(kinema.InvalidInput, match=r"not both"):
        iiwa.check(tr, tr.q)
    with pytest.raises(kinema.InvalidInput, match=r"`q` must have shape \(\d+, 7\)"):
        iiwa.check(tr.t, tr.q[:, :6])
    with pytest.raises(kinema.InvalidInput, match=r"`qd` must have shape"):
        iiwa.check(tr.t, tr.q, tr.qd[1:])
    with pytest.raises(kinema.InvalidInput, match=r"`t` must have shape \(N,\)"):
        iiwa.check(tr.q, tr.q)
    with pytest.raises(kinema.InvalidInput, match=r"`t` has 0 samples; at least 1 needed"):
        iiwa.check(np.zeros(0), np.zeros((0, 7)))
    with pytest.raises(kinema.InvalidInput, match=r"vmax"):
        iiwa.check(tr, vmax=[1.0, 2.0])
    # Malformed samples are violations, not exceptions.
    q = tr.q.copy()
    q[2, 1] = np.nan
    assert [v["kind"] for v in iiwa.check(tr.t, q, tr.qd, tr.qdd).violations] == ["malformed"]


@needs_cli
def test_expr_and_check_equal_the_cli(rommel, iiwa, tmp_path):
    out = cli_json(["traj", "expr", "-r", "rommel", "--joint", "1", "0.5*sin(4*pi*t^2/2)", "--joint", "3",
                    "0.2*t", "--duration", "1.3", "--dt", "0.05", "--vmax", "20", "--amax", "400", "--json"])
    tr = rommel.expr({1: "0.5*sin(4*pi*t^2/2)", 3: "0.2*t"}, 1.3, dt=0.05, vmax=20.0, amax=400.0)
    rows = np.array(out["rows"])
    n = 5
    assert np.allclose(rows[:, 0], tr.t, rtol=0, atol=1e-15)
    assert np.allclose(rows[:, 1:1 + n], tr.q, rtol=0, atol=1e-15)
    assert np.allclose(rows[:, 1 + n:1 + 2 * n], tr.qd, rtol=0, atol=1e-15)
    assert np.allclose(rows[:, 1 + 2 * n:1 + 3 * n], tr.qdd, rtol=0, atol=1e-15)
    rng = np.random.default_rng(62)
    for case in range(10):
        k = 30
        t = np.cumsum(rng.uniform(0.005, 0.02, k))
        q = iiwa.home + np.cumsum(rng.normal(0, 0.01, (k, 7)), axis=0)
        q[rng.integers(k), rng.integers(7)] += 2.0
        header = ["t"] + [f"q{i}" for i in range(1, 8)]
        data = np.column_stack([t, q])
        with_rates = case % 2 == 1
        if with_rates:
            qd = rng.normal(0, 1.0, (k, 7))
            header += [f"qd{i}" for i in range(1, 8)]
            data = np.column_stack([data, qd])
        path = tmp_path / f"traj{case}.csv"
        np.savetxt(path, data, delimiter=",", header=",".join(header), comments="", fmt="%.17g")
        out = cli_json(["traj", "check", "-r", "lbr-iiwa-14-r820", str(path), "--vmax", "1.5", "--json"], code=1)
        f = np.genfromtxt(path, delimiter=",", names=True)
        qs = np.column_stack([f[f"q{i}"] for i in range(1, 8)])
        rep = iiwa.check(f["t"], qs, np.column_stack([f[f"qd{i}"] for i in range(1, 8)]) if with_rates else None,
                         vmax=1.5)
        assert out["ok"] == rep.ok and out["samples"] == rep.samples
        assert np.allclose(out["peak_velocity"], rep.peak_velocity, rtol=0, atol=1e-12)
        assert np.allclose(out["peak_acceleration"], rep.peak_acceleration, rtol=0, atol=1e-9)
        assert [v["message"] for v in out["violations"]] == [v["message"] for v in rep.violations]
        assert [v["kind"] for v in out["violations"]] == [v["kind"] for v in rep.violations]


def test_check_reads_q_itself_and_warns_of_singular_passages(iiwa):
    """The CLI's cases: a 7.4 mrad glitch in q with the derivative columns untouched is
    found; a passage through the stretched elbow is one warning; jerk is measured."""
    q_obj = [-0.1090, 1.2417, 0.4463, 1.9156, -0.9695, -1.8728, 0.4876]
    tr = iiwa.ptp("home", q_obj, 0.01, profile="scurve", amax=2.0, jmax=15.0)
    clean = iiwa.check(tr, amax=2.0, jmax=15.0)
    assert clean.ok and clean.peak_jerk.shape == (7,) and clean.peak_jerk.max() <= 15.0 * (1 + 1e-9)
    q = tr.q.copy()
    k = len(q) // 3
    q[k, 1] += 0.0074
    r = iiwa.check(tr.t, q, tr.qd, tr.qdd, amax=2.0)
    assert not r.ok and "inconsistent" in {v["kind"] for v in r.violations}
    assert all(abs(v["sample"] - k) <= 1 and v["joint"] == 2 for v in r.violations)
    through = iiwa.ptp([0.2, 0.5, 0.1, -0.5, 0.3, 0.8, 0], [0.2, 0.5, 0.1, 0.5, 0.3, 0.8, 0], 0.001,
                       profile="quintic", amax=2.0)
    r = iiwa.check(through)
    assert r.ok and [w["kind"] for w in r.warnings] == ["singular"]
    assert iiwa.check(through, singular=0).warnings == []
