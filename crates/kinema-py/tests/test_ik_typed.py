"""Typed IK targets (Scorbot pitch/roll, ROMMEL approach, SCARA α), position-only targets and
poses as 6 numbers: every returned q is checked by forward kinematics against the target, over
many seeded random targets; bad combinations raise InvalidInput with a useful message."""

import numpy as np
import pytest

import kinema
from cli import cli_json, needs_cli
from conftest import random_q

# Seed 000 eq. 9: flange frame 5 -> the "tool frame" aligned with the base at home.
R_H = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])


def rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def wrap(a):
    return np.angle(np.exp(1j * np.asarray(a)))


@pytest.fixture(scope="module")
def family():
    return {name: kinema.Robot.builtin(name) for name in ["scorbot-er-v-plus", "rommel", "scara5"]}


def test_scorbot_pitch_roll(family):
    """Seed 000 eq. 13: position reached, R·R_h = Rz(yaw)·Ry(β)·Rx(γ), β = −(θ2+θ3+θ4), γ = θ5."""
    r = family["scorbot-er-v-plus"]
    rng = np.random.default_rng(50)
    for q in random_q(r, rng, 200):
        p = r.fkine(q)[:3, 3]
        pitch, roll = -(q[1] + q[2] + q[3]), q[4]
        sols = r.ik(position=p, pitch=pitch, roll=roll, all=True)
        # Up to 4 branches, each with every 2π copy of the wrist roll within its limits.
        assert 1 <= len({tuple(np.round(wrap(s.q), 9)) for s in sols}) <= 4
        for s in sols:
            assert s.solver == "scorbot" and s.iterations is None
            T = r.fkine(s.q)
            assert np.linalg.norm(T[:3, 3] - p) < 1e-9
            assert np.isclose(s.position_error, np.linalg.norm(T[:3, 3] - p), atol=1e-12)
            yaw_only = T[:3, :3] @ R_H @ rx(roll).T @ ry(pitch).T
            assert abs(yaw_only[2, 2] - 1.0) < 1e-9, s
            assert abs(wrap(-(s.q[1] + s.q[2] + s.q[3]) - pitch)) < 1e-9 and abs(wrap(s.q[4] - roll)) < 1e-12
            lo, hi = r.qlim
            assert s.within_limits == bool(np.all((s.q >= lo) & (s.q <= hi)))
        # The configuration the target came from is among them, and is the one picked near it.
        assert any(np.abs(s.q - q).max() < 1e-7 for s in sols)
        one = r.ik(position=p, pitch=pitch, roll=roll, q0=q)
        assert one.success and np.abs(one.q - q).max() < 1e-7


def test_rommel_approach(family):
    """The tool point at the position and the tool z axis along the approach (any length), q5 = 0."""
    r = family["rommel"]
    rng = np.random.default_rng(51)
    for q in random_q(r, rng, 200):
        T = r.fkine(q)
        p, a = T[:3, 3], T[:3, 2] * rng.uniform(0.2, 3.0)
        sols = r.ik(position=p, approach=a, all=True)
        assert 1 <= len(sols) <= 4
        for s in sols:
            assert s.solver == "rommel" and s.q[4] == 0.0
            F = r.fkine(s.q)
            assert np.linalg.norm(F[:3, 3] - p) < 1e-9
            assert np.linalg.norm(F[:3, 2] - a / np.linalg.norm(a)) < 1e-9
        assert any(np.abs(s.q[:4] - q[:4]).max() < 1e-7 for s in sols)
        one = r.ik(position=p, approach=a, q0=q)
        assert one.success and np.abs(one.q[:4] - q[:4]).max() < 1e-7


def test_rommel_approach_it_cannot_take(family):
    with pytest.raises(kinema.Unreachable) as e:
        family["rommel"].ik(position=[0.2, 0.5, 0.1], approach=[0.0, 0.0, 1.0])
    assert e.value.solver == "rommel" and "orientation" in e.value.reason


def test_scara_alpha_zone_rule(family):
    """Position reached, α = q2 + q3 + q5 and the tool turned by Rz(α); elbow side kept from q0."""
    r = family["scara5"]
    rng = np.random.default_rng(52)
    reached = outside = 0
    for q in random_q(r, rng, 500):
        p = r.fkine(q)[:3, 3]
        alpha = q[1] + q[2] + q[4]
        try:
            s = r.ik(position=p, alpha=alpha, q0=q)
        except kinema.Unreachable as e:
            assert e.solver == "scara" and ("zone" in e.reason or "stroke" in e.reason), e.reason
            outside += 1
            continue
        reached += 1
        assert s.solver == "scara" and s.success
        F = r.fkine(s.q)
        assert np.linalg.norm(F[:3, 3] - p) < 1e-9
        assert abs(wrap(s.q[1] + s.q[2] + s.q[4] - alpha)) < 1e-9
        assert np.abs(F[:3, :3] - rz(alpha)).max() < 1e-9
        assert np.sign(s.q[2]) == np.sign(q[2])
        # all=True gives the same solution, and the wrist's other 2π copies within its ±360°.
        again = r.ik(position=p, alpha=alpha, q0=q, all=True)
        assert any(np.array_equal(a.q, s.q) for a in again)
        for a in again:
            assert np.allclose(a.q[:4], s.q[:4], atol=0) and abs(wrap(a.q[4] - s.q[4])) < 1e-12
    # Reachable targets are never refused: off the zone rule's rail the nearest working rail is taken.
    assert reached == 500 and outside == 0, (reached, outside)


@pytest.mark.parametrize("name", ["puma560", "ur5", "panda", "lbr-iiwa-14-r820", "scorbot-er-v-plus"])
def test_position_only(robots, name):
    """The numeric solver with a position mask reaches the point; the orientation is free."""
    r = robots[name]
    rng = np.random.default_rng(53)
    for q in random_q(r, rng, 30):
        p = r.fkine(q)[:3, 3]
        s = r.ik(position=p, seed=3)
        assert s.solver == "numeric" and s.branch == "numeric" and s.iterations is not None
        d = np.linalg.norm(r.fkine(s.q)[:3, 3] - p)
        assert d < 1e-6 and np.isclose(s.position_error, d, atol=1e-12)
        assert s.success and s.within_limits
        assert np.array_equal(r.ik(position=list(p), seed=3).q, s.q)  # seeded: reproducible
        near = r.ik(position=p, q0=q)  # started at the answer
        assert np.abs(near.q - q).max() < 1e-6


def test_pose_as_six_numbers(robots):
    """T may be x, y, z, roll, pitch, yaw: zyx (default, R = Rz·Ry·Rx) or xyz (Rx·Ry·Rz)."""
    r = robots["puma560"]
    rng = np.random.default_rng(54)
    for q in random_q(r, rng, 50):
        x, y, z = rng.uniform(-0.3, 0.3, 3) + [0.4, 0.1, 0.2]
        a, b, c = rng.uniform(-np.pi, np.pi), rng.uniform(-1.4, 1.4), rng.uniform(-np.pi, np.pi)
        for rpy, R in [("zyx", rz(c) @ ry(b) @ rx(a)), ("xyz", rx(a) @ ry(b) @ rz(c))]:
            T = np.eye(4)
            T[:3, :3], T[:3, 3] = R, [x, y, z]
            try:
                want = r.ik(T, all=True)
            except kinema.Unreachable:
                with pytest.raises(kinema.Unreachable):
                    r.ik([x, y, z, a, b, c], all=True, rpy=rpy)
                continue
            got = r.ik([x, y, z, a, b, c], all=True, rpy=rpy)
            assert [s.branch for s in got] == [s.branch for s in want]
            for g, w in zip(got, want):
                assert np.allclose(g.q, w.q, atol=1e-9)
                assert np.allclose(r.fkine(g.q), T, atol=1e-9) or not g.success


def test_wrong_combinations(robots, family):
    sc, iiwa, puma = family["scorbot-er-v-plus"], robots["lbr-iiwa-14-r820"], robots["puma560"]
    p = sc.fkine(sc.home)[:3, 3]
    T = puma.fkine(puma.home)
    cases = [
        (lambda: puma.ik(), r"give a target: `T` .* or `position`"),
        (lambda: puma.ik(T, position=[0.4, 0.1, 0.2]), r"give `T` or `position`, not both"),
        (lambda: sc.ik(position=p, pitch=0.1), r"invalid `roll`: missing: a `pitch-roll` target"),
        (lambda: sc.ik(position=p, roll=0.1), r"invalid `pitch`: missing: a `pitch-roll` target"),
        (lambda: puma.ik(T, alpha=0.3), r"go with `position`"),
        (lambda: sc.ik(position=p, pitch=0.1, roll=0.0, alpha=0.2), r"`pitch` and `alpha` belong to different typed targets"),
        (lambda: sc.ik(position=p, approach=[0, 0, 1], alpha=0.2), r"`alpha` and `approach` belong to different typed targets"),
        (lambda: sc.ik(position=[0.1, 0.2]), r"`position` must have shape \(3,\)"),
        (lambda: sc.ik(position=[np.nan, 0.2, 0.3]), r"`position` contains NaN; all values must be finite"),
        (lambda: family["rommel"].ik(position=p, approach=[0, 0, 0]), r"invalid `approach`: a direction cannot be the zero vector"),
        (lambda: family["rommel"].ik(position=p, approach=[0, 0]), r"`approach` must have shape \(3,\)"),
        (lambda: sc.ik(position=p, pitch=0.1, roll=0.0, solver="numeric"), r"select an analytic solver"),
        (lambda: iiwa.ik(iiwa.fkine(iiwa.home), q3=0.1, solver="numeric"), r"select an analytic solver"),
        (lambda: iiwa.ik(position=[0.4, 0.1, 0.5], q3=0.1), r"q3 and psi need a full target pose"),
        (lambda: puma.ik(position=[0.4, 0.1, 0.2], pitch=0.1, roll=0.0), r"Scorbot solver needs 5 revolute joints"),
        (lambda: sc.ik(position=p, alpha=0.1), r"SCARA solver needs joints PRRPR"),
        (lambda: sc.ik(position=p, approach=[0, 0, 1]), r"not described by a modified-DH row"),
        (lambda: puma.ik(position=[0.4, 0.1, 0.2], solver="analytic"), r"no analytic solver"),
        (lambda: puma.ik([0.4, 0.1, 0.2, 0.0, 0.0]), r"`T` must have shape \(4, 4\) .* or \(6,\)"),
        (lambda: puma.ik([0.4, 0.1, 0.2, 0.0, np.inf, 0.0]), r"`T` contains inf; all values must be finite"),
        (lambda: puma.ik(T, rpy="yxz"), r"unknown rpy convention `yxz`; expected one of: zyx, xyz"),
        (lambda: sc.ik(position=p, pitch=0.1, roll=0.0, q0=[0.0, 1.0]), r"has 5 joints, but 2 joint values"),
    ]
    for call, message in cases:
        with pytest.raises(kinema.InvalidInput, match=message):
            call()
    with pytest.raises(kinema.Unreachable, match=r"^unreachable target \(scorbot solver\): ") as e:
        sc.ik(position=[2.0, 0.0, 0.3], pitch=0.0, roll=0.0)
    assert e.value.solver == "scorbot"


@needs_cli
def test_typed_targets_equal_the_cli(family, robots):
    """`kinema ik --json` gives the same solutions for the same targets (same solver, branches, q)."""
    rng = np.random.default_rng(55)
    compared = 0
    for name, make in [
        ("scorbot-er-v-plus", lambda r, q, T: dict(position=T[:3, 3], pitch=-(q[1] + q[2] + q[3]), roll=q[4])),
        ("rommel", lambda r, q, T: dict(position=T[:3, 3], approach=T[:3, 2])),
        ("scara5", lambda r, q, T: dict(position=T[:3, 3], alpha=q[1] + q[2] + q[4], q0=q)),
        ("puma560", lambda r, q, T: dict(position=T[:3, 3])),
    ]:
        r = family.get(name) or robots[name]
        for q in random_q(r, rng, 12):
            kw = make(r, q, r.fkine(q))
            args = ["ik", "--robot", name, "--all", "--json"]
            for key, value in kw.items():
                flag = {"q0": "--q0"}.get(key, "--" + key)
                text = ",".join(repr(float(v)) for v in np.atleast_1d(value))
                args += [flag, text]
            try:
                sols = r.ik(all=True, **kw)
            except kinema.Unreachable as e:
                out = cli_json(args, code=2)
                assert out["error"] == "unreachable" and out["solver"] == e.solver and out["reason"] == e.reason
                continue
            out = cli_json(args)
            assert out["solver"] == sols[0].solver
            assert len(out["solutions"]) == len(sols)
            for c, s in zip(out["solutions"], sols):
                assert c["branch"] == s.branch and c["within_limits"] == s.within_limits
                assert np.allclose(c["q"], s.q, rtol=0, atol=1e-12)
                assert np.isclose(c["position_error"], s.position_error, rtol=0, atol=1e-12)
                if list(kw) == ["position"]:
                    # Position only: the CLI reports no orientation error (null).
                    assert c["orientation_error"] is None
                else:
                    assert np.isclose(c["orientation_error"], s.orientation_error, rtol=0, atol=1e-12)
            compared += 1
    assert compared >= 30
