"""Shared helpers of the kinema Python tests (seeded, no network, no files outside tmp_path)."""

import numpy as np
import pytest

import kinema

ROBOTS = ["lbr-iiwa-14-r820", "puma560", "scorbot-er-v-plus"]


@pytest.fixture(scope="session")
def robots():
    return {name: kinema.Robot.builtin(name) for name in ROBOTS + ["panda", "ur5"]}


def random_q(robot, rng, count=None, margin=0.02):
    """Uniform configurations strictly inside the joint limits (unbounded joints: ±π)."""
    lo, hi = robot.qlim
    lo = np.where(np.isfinite(lo), lo, -np.pi)
    hi = np.where(np.isfinite(hi), hi, np.pi)
    span = hi - lo
    lo, hi = lo + margin * span, hi - margin * span
    shape = (robot.n,) if count is None else (count, robot.n)
    return rng.uniform(lo, hi, size=shape)


def skew_to_vec(s):
    return np.array([s[2, 1] - s[1, 2], s[0, 2] - s[2, 0], s[1, 0] - s[0, 1]]) / 2.0
