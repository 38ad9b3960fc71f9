"""Jacobians against finite differences of fkine, and manipulability against numpy."""

import numpy as np
import pytest

from conftest import ROBOTS, random_q, skew_to_vec


def fd_jacobian(robot, q, h=1e-6):
    """Base-frame geometric Jacobian by central differences of fkine."""
    J = np.zeros((6, robot.n))
    for i in range(robot.n):
        dq = np.zeros(robot.n)
        dq[i] = h
        Tp, Tm = robot.fkine(q + dq), robot.fkine(q - dq)
        J[:3, i] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        R = robot.fkine(q)[:3, :3]
        dR = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h)
        J[3:, i] = skew_to_vec(dR @ R.T)
    return J


@pytest.mark.parametrize("name", ROBOTS + ["panda", "ur5"])
def test_jacob0_matches_finite_differences(robots, name):
    r = robots[name]
    rng = np.random.default_rng(10)
    for q in random_q(r, rng, 10):
        J = r.jacob0(q)
        assert J.shape == (6, r.n) and J.dtype == np.float64
        assert np.allclose(J, fd_jacobian(r, q), atol=1e-7)


@pytest.mark.parametrize("name", ROBOTS)
def test_jacobe_is_jacob0_in_tool_axes(robots, name):
    r = robots[name]
    rng = np.random.default_rng(11)
    for q in random_q(r, rng, 10):
        R = r.fkine(q)[:3, :3]
        J0 = r.jacob0(q)
        Je = r.jacobe(q)
        assert np.allclose(Je[:3], R.T @ J0[:3], atol=1e-12)
        assert np.allclose(Je[3:], R.T @ J0[3:], atol=1e-12)


def test_ur5_first_column_at_home(robots):
    J = robots["ur5"].jacob0(robots["ur5"].home)
    assert np.isclose(J[5, 0], 1.0)


@pytest.mark.parametrize("name", ROBOTS)
def test_manipulability_is_sqrt_det(robots, name):
    r = robots[name]
    rng = np.random.default_rng(12)
    for q in random_q(r, rng, 10):
        J = r.jacob0(q)
        for axes, rows in [("all", slice(0, 6)), ("trans", slice(0, 3)), ("rot", slice(3, 6))]:
            Js = J[rows]
            if Js.shape[0] > Js.shape[1]:
                expected = 0.0
            else:
                expected = np.sqrt(max(np.linalg.det(Js @ Js.T), 0.0))
            assert np.isclose(r.manipulability(q, axes=axes), expected, rtol=1e-9, atol=1e-12), axes
        assert r.manipulability(q) == r.manipulability(q, "all")


def test_manipulability_zero_at_iiwa_coupled_singularity(robots):
    # Seed 004 Cuadro III: q2 = ... = q5 = 0.
    q = [np.pi / 6, 0, 0, 0, 0, np.pi / 6, np.pi / 3]
    assert robots["lbr-iiwa-14-r820"].manipulability(q) < 1e-12
