"""The arm angle psi on a URDF iiwa (the geometric solver `geo-srs`): ik(T,
psi=...) gives the DH iiwa solver's configurations at that psi, and lin holds
psi along the path."""

from pathlib import Path

import numpy as np

import kinema
from conftest import random_q

URDF = Path(__file__).resolve().parents[3] / "crates" / "kinema" / "tests" / "data" / "iiwa14.urdf"

# The URDF's fixed mount (its base) and flange offset (its tool); without them
# it moves as the built-in DH iiwa.
BASE = np.array(
    [
        [np.cos(np.pi / 6), -np.sin(np.pi / 6), 0.0, 0.1],
        [np.sin(np.pi / 6), np.cos(np.pi / 6), 0.0, -0.2],
        [0.0, 0.0, 1.0, 0.05],
        [0.0, 0.0, 0.0, 1.0],
    ]
)
TOOL = np.eye(4)
TOOL[2, 3] = 0.045


def wrapped_gap(a, b):
    return float(np.max(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b)))))))


def test_psi_on_a_urdf_iiwa_is_the_dh_iiwa_solvers():
    urdf, dh = kinema.Robot.from_file(str(URDF)), kinema.Robot.builtin("lbr-iiwa-14-r820")
    rng = np.random.default_rng(0x5138)
    q = random_q(urdf, rng)
    T = urdf.fkine(q)
    assert np.allclose(T, BASE @ dh.fkine(q) @ TOOL, atol=1e-12)
    psi = float(rng.uniform(-np.pi, np.pi))
    ours = urdf.ik(T, all=True, psi=psi)
    theirs = dh.ik(np.linalg.inv(BASE) @ T @ np.linalg.inv(TOOL), all=True, psi=psi)
    assert len(ours) == 8 and len(theirs) == 8
    assert all(s.solver == "geo-srs" for s in ours) and all(s.solver == "iiwa" for s in theirs)
    for s in ours:
        assert np.allclose(urdf.fkine(s.q), T, atol=1e-9)
        assert min(wrapped_gap(s.q, t.q) for t in theirs) < 1e-8
    for t in theirs:
        assert min(wrapped_gap(s.q, t.q) for s in ours) < 1e-8


def test_lin_holds_psi_on_a_urdf_iiwa():
    urdf = kinema.Robot.from_file(str(URDF))
    q0 = np.array([0.3, 1.0, 0.4, -0.8, 0.2, 0.9, 0.1])
    T0 = urdf.fkine(q0)
    psi = 0.7
    start = min((s for s in urdf.ik(T0, all=True, psi=psi) if s.within_limits), key=lambda s: np.abs(s.q - q0).max())
    goal = urdf.fkine(start.q)
    goal[:3, 3] += [0.05, 0.1, -0.1]
    tr = urdf.lin(start.q, goal, 0.01, vmax=0.2, amax=1.0, psi=psi)
    assert np.allclose(urdf.fkine(tr.q[-1]), goal, atol=1e-6)
    # Every sample is one of the closed-form configurations at that psi.
    for qk in tr.q[:: max(1, len(tr.q) // 20)]:
        at_psi = urdf.ik(urdf.fkine(qk), all=True, psi=psi)
        assert min(wrapped_gap(qk, s.q) for s in at_psi) < 1e-7
    assert float(np.max(np.abs(tr.q[:, 2] - start.q[2]))) > 1e-4, "q3 moves while psi is held"
