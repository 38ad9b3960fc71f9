"""Inverse kinematics: round trips fkine(ik(T).q) ≈ T on random configurations."""

import numpy as np
import pytest

import kinema
from conftest import ROBOTS, random_q

SOLVERS = {"lbr-iiwa-14-r820": "iiwa", "puma560": "pieper", "scorbot-er-v-plus": "scorbot"}


def position_orientation_error(T_target, T):
    dp = np.linalg.norm(T_target[:3, 3] - T[:3, 3])
    R = T_target[:3, :3] @ T[:3, :3].T
    angle = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    return dp, angle


@pytest.mark.parametrize("name", ROBOTS)
def test_all_solutions_reproduce_target(robots, name):
    r = robots[name]
    rng = np.random.default_rng(30)
    for q in random_q(r, rng, 25):
        T = r.fkine(q)
        sols = r.ik(T, all=True)
        assert isinstance(sols, list) and len(sols) >= 1
        for s in sols:
            assert isinstance(s, kinema.IkSolution)
            assert s.solver == SOLVERS[name]
            assert s.q.shape == (r.n,)
            assert s.residual == (s.position_error, s.orientation_error)
            assert s.iterations is None
            # The reported residual is the pose error of fkine(q) (the
            # 5-joint Scorbot also lists candidates that miss the orientation).
            dp, angle = position_orientation_error(T, r.fkine(s.q))
            assert np.isclose(s.position_error, dp, atol=1e-9)
            assert np.isclose(s.orientation_error, angle, atol=1e-6)
            lo, hi = r.qlim
            assert s.within_limits == bool(np.all((s.q >= lo) & (s.q <= hi)))
            if s.success:
                assert np.allclose(r.fkine(s.q), T, atol=1e-9)
        good = [s for s in sols if s.position_error < 1e-9 and s.orientation_error < 1e-9]
        assert good, "no solution reproduces the target"


@pytest.mark.parametrize("name", ["puma560", "scorbot-er-v-plus"])
def test_single_solution_is_nearest_within_limits(robots, name):
    r = robots[name]
    rng = np.random.default_rng(31)
    for q in random_q(r, rng, 25):
        T = r.fkine(q)
        s = r.ik(T)
        assert s.success and s.within_limits
        assert np.allclose(r.fkine(s.q), T, atol=1e-9)
        # With q0: the solution within limits nearest to q0 (joint-space distance).
        candidates = [c for c in r.ik(T, all=True) if c.within_limits]
        expected = min(candidates, key=lambda c: np.linalg.norm(c.q - q))
        assert np.array_equal(r.ik(T, q0=q).q, expected.q)


@pytest.mark.parametrize("name", ["puma560", "scorbot-er-v-plus"])
def test_q0_recovers_configuration(robots, name):
    """Configurations with every angle in (-π, π] (the solvers' range) come back exactly."""
    r = robots[name]
    rng = np.random.default_rng(36)
    lo, hi = r.qlim
    checked = 0
    for q in random_q(r, rng, 60):
        q = np.angle(np.exp(1j * q))
        if not np.all((q > lo) & (q < hi)):
            continue
        s = r.ik(r.fkine(q), q0=q)
        assert np.abs(s.q - q).max() < 1e-7
        checked += 1
    assert checked >= 10


def test_iiwa_with_q0_recovers_configuration(robots):
    r = robots["lbr-iiwa-14-r820"]
    rng = np.random.default_rng(32)
    for q in random_q(r, rng, 25):
        T = r.fkine(q)
        s = r.ik(T, q0=q)
        assert s.success
        assert np.allclose(r.fkine(s.q), T, atol=1e-9)


def test_iiwa_q3_and_psi(robots):
    r = robots["lbr-iiwa-14-r820"]
    rng = np.random.default_rng(33)
    for q in random_q(r, rng, 10):
        T = r.fkine(q)
        sols = r.ik(T, all=True, q3=q[2])
        assert 1 <= len(sols) <= 8
        assert all(np.isclose(s.q[2], q[2]) for s in sols)
        assert min(np.abs(s.q - q).max() for s in sols) < 1e-7
        for s in r.ik(T, all=True, psi=0.3):
            assert np.allclose(r.fkine(s.q), T, atol=1e-9)


@pytest.mark.parametrize("name", ["lbr-iiwa-14-r820", "panda"])
def test_numeric_solver(robots, name):
    r = robots[name]
    rng = np.random.default_rng(34)
    for q in random_q(r, rng, 5):
        T = r.fkine(q)
        s = r.ik(T, solver="numeric")
        assert s.solver == "numeric" and s.branch == "numeric"
        assert s.success
        assert s.iterations is not None and s.restarts is not None
        assert np.allclose(r.fkine(s.q), T, atol=1e-5)
        # Seeded: the same answer every time.
        assert np.array_equal(r.ik(T, solver="numeric").q, s.q)


def test_auto_uses_numeric_without_analytic_solver(robots):
    r = robots["panda"]
    q = random_q(r, np.random.default_rng(35))
    s = r.ik(r.fkine(q), q0=r.home)
    assert s.solver == "numeric" and s.success


def test_analytic_forced(robots):
    r = robots["puma560"]
    T = r.fkine(r.home)
    assert r.ik(T, solver="analytic").solver == "pieper"


def test_q0_pose_name(robots):
    r = robots["puma560"]
    T = r.fkine(r.home)
    assert np.allclose(r.ik(T, q0="home").q, r.home, atol=1e-9)


def test_repr(robots):
    s = robots["puma560"].ik(robots["puma560"].fkine(robots["puma560"].home))
    assert repr(s).startswith("IkSolution(q=array(")
