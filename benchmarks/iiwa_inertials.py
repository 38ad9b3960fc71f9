#!/usr/bin/env python3
"""The KUKA LBR iiwa 14 built-in's mass properties (robots/lbr-iiwa-14-r820.toml) are Drake's,
moved into its DH link frames: this script redoes the move and checks it.

    python benchmarks/iiwa_inertials.py [--n 200] [--seed 0] [--bound 1e-9]

Run it in a venv with `kinema` (crates/kinema-py) and `pin` (Pinocchio); benchmarks/run_ik_peers.sh
and benchmarks/run_dyn_corke.sh run it after benchmarks/dyn_corke.py.

1. Drake's iiwa 14 chain (joint origins, link masses, centres of mass and inertia tensors, held
   below with their source) is built in Pinocchio joint by joint, as the URDF describes it.
2. Kinematics: with q4 turned the other way (the URDF's joint 4 turns opposite to the DH table's),
   every kinema link frame (`fkine_all`) must be fixed in the URDF link of the same number, up to a
   quarter turn of the root about the vertical. Those fixed placements P_i are measured.
3. The move: each link's centre of mass and inertia taken into its DH frame with P_i (c' = Rᵀ(c - p),
   I' = Rᵀ I R), printed in the TOML's units (mm, kg·mm²) beside the TOML's values.
4. Dynamics: kinema's `rne`, `inertia`, `coriolis`, `gravload` and `accel` of the built-in against
   Pinocchio's `rnea`, `crba`, `computeCoriolisMatrix`, `computeGeneralizedGravity` and `aba` on
   Drake's chain, at `home` and --n seeded random states (τ in [-20, 20] N·m for `accel`; joint 4's
   sign flipped on the way in and out), gravity [0, 0, -9.81]; the measure is
   max|Δ| / max|Pinocchio| per state. Exits 1 if it exceeds --bound or the kinematics differ.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin

import kinema

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ik_peers import exit_if_failed, fmt  # noqa: E402

try:
    import tomllib
except ImportError:  # Python < 3.11
    import tomli as tomllib  # type: ignore[no-redef]

REPO = Path(__file__).resolve().parents[1]
GRAVITY = np.array([0.0, 0.0, -9.81])

# Drake's iiwa 14: RobotLocomotion/drake, manipulation/models/iiwa_description/urdf/iiwa14_no_collision.urdf
# at commit 966464ebfb524ca78d7b360bb7ef50cc3c47b818. Joints iiwa_joint_1…7: origin (xyz m, rpy rad) in the
# parent link, all revolute about their z. Links iiwa_link_1…7: mass kg, centre of mass (xyz m, rpy 0) and
# the diagonal of the inertia about it (ixx, iyy, izz kg·m²; the products are 0). iiwa_link_0 is the fixed
# base: its mass acts on no joint.
DRAKE_SOURCE = ("RobotLocomotion/drake", "manipulation/models/iiwa_description/urdf/iiwa14_no_collision.urdf",
                "966464ebfb524ca78d7b360bb7ef50cc3c47b818")
HALF_PI, PI = 1.570796326794897, 3.141592653589793  # as the file writes them
DRAKE_JOINTS = [
    ((0, 0, 0.1575), (0, 0, 0)),
    ((0, 0, 0.2025), (HALF_PI, 0, PI)),
    ((0, 0.2045, 0), (HALF_PI, 0, PI)),
    ((0, 0, 0.2155), (HALF_PI, 0, 0)),
    ((0, 0.1845, 0), (-HALF_PI, PI, 0)),
    ((0, 0, 0.2155), (HALF_PI, 0, 0)),
    ((0, 0.081, 0), (-HALF_PI, PI, 0)),
]
DRAKE_LINKS = [
    (5.76, (0, -0.03, 0.12), (0.033, 0.0333, 0.0123)),
    (6.35, (0.0003, 0.059, 0.042), (0.0305, 0.0304, 0.011)),
    (3.5, (0, 0.03, 0.13), (0.025, 0.0238, 0.0076)),
    (3.5, (0, 0.067, 0.034), (0.017, 0.0164, 0.006)),
    (3.5, (0.0001, 0.021, 0.076), (0.01, 0.0087, 0.00449)),
    (1.8, (0, 0.0006, 0.0004), (0.0049, 0.0047, 0.0036)),
    (1.2, (0, 0, 0.02), (0.001, 0.001, 0.001)),
]
# the URDF's joint 4 turns the other way: q_urdf = S q_kinema, τ_kinema = S τ_urdf, M_kinema = S M_urdf S
SIGN = np.array([1, 1, 1, -1, 1, 1, 1], float)


def drake_model():
    model, parent = pin.Model(), 0
    for k, ((xyz, rpy), (mass, com, diag)) in enumerate(zip(DRAKE_JOINTS, DRAKE_LINKS), start=1):
        placement = pin.SE3(pin.rpy.rpyToMatrix(*rpy), np.array(xyz, float))
        parent = model.addJoint(parent, pin.JointModelRZ(), placement, f"iiwa_joint_{k}")
        model.appendBodyToJoint(parent, pin.Inertia(mass, np.array(com, float), np.diag(diag)), pin.SE3.Identity())
    model.gravity = pin.Motion(np.r_[GRAVITY, 0, 0, 0])
    return model


def rot_z(angle):
    c, s = math.cos(angle), math.sin(angle)
    T = np.eye(4)
    T[:2, :2] = [[c, -s], [s, c]]
    return T


def placements(robot, model, qs):
    """(quarter turn of the URDF root, [P_i]): kinema's link frame i in URDF link i, the same at all
    qs; None if no quarter turn makes them constant."""
    data = model.createData()
    for quarter in range(4):
        Z = rot_z(quarter * math.pi / 2)
        first, worst = None, 0.0
        for q in qs:
            pin.forwardKinematics(model, data, SIGN * q)
            frames = robot.fkine_all(q)[1 : robot.n + 1]
            P = [np.linalg.inv(Z @ data.oMi[i + 1].homogeneous) @ frames[i] for i in range(robot.n)]
            first = first or P
            worst = max(worst, max(float(np.abs(a - b).max()) for a, b in zip(first, P)))
        if worst < 1e-12:
            return quarter, first, worst
    return None, None, worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=200, help="random states besides home (default 200)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--bound", type=float, default=1e-9)
    args = ap.parse_args()
    repo, path, commit = DRAKE_SOURCE
    print(f"# the iiwa 14 built-in's inertials against Drake's ({repo} {path} @ {commit[:12]})")
    print(f"kinema {kinema.__version__}, pinocchio {pin.__version__}; n={args.n} seed={args.seed} bound={args.bound:.0e}")

    robot = kinema.Robot.builtin("lbr-iiwa-14-r820")
    model = drake_model()
    data = model.createData()
    rng = np.random.default_rng(args.seed)
    lo, hi = robot.qlim
    Q = np.vstack([robot.home, rng.uniform(lo, hi, size=(args.n, robot.n))])
    QD = rng.uniform(-2, 2, size=Q.shape)
    QDD = rng.uniform(-3, 3, size=Q.shape)
    TAU = rng.uniform(-20, 20, size=Q.shape)
    failures = []

    quarter, P, worst = placements(robot, model, Q[:20])
    if quarter is None:
        print(f"KINEMATICS DIFFER: no quarter turn of the URDF root makes kinema's link frames fixed in Drake's "
              f"links (worst drift {worst:.1e})")
        sys.exit(1)
    print(f"\n## kinematics: kinema's link frames fixed in Drake's links (drift {fmt(worst)} over 20 states), "
          f"URDF root turned {90 * quarter} deg about z, q4 reversed")

    # the move, in the TOML's units
    with open(REPO / "robots" / "lbr-iiwa-14-r820.toml", "rb") as f:
        toml = tomllib.load(f)
    assert toml["units"]["length"] == "mm"
    print("\n## Drake's inertials moved into the DH link frames (mm, kg·mm², order ixx iyy izz ixy ixz iyz) "
          "against robots/lbr-iiwa-14-r820.toml")
    worst_com = worst_inertia = 0.0
    for i, ((mass, com, diag), Pi, j) in enumerate(zip(DRAKE_LINKS, P, toml["joint"]), start=1):
        R, p = Pi[:3, :3], Pi[:3, 3]
        c = R.T @ (np.array(com, float) - p) * 1e3
        inertia = R.T @ np.diag(diag) @ R * 1e6
        six = np.array([inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2], inertia[1, 2]])
        six[np.abs(six) < 1e-9] = 0.0  # -0.0 and rounding noise of exact zeros
        c[np.abs(c) < 1e-9] = 0.0
        b = j["inertial"]
        dm = abs(mass - b["mass"])
        dc = float(np.abs(c - np.array(b["com"], float)).max())
        di = float(np.abs(six - np.array(b["inertia"], float)).max())
        worst_com, worst_inertia = max(worst_com, dc), max(worst_inertia, di)
        print(f"  {j['name']}: mass {mass} (TOML {b['mass']}), com {np.round(c, 9).tolist()} (TOML Δ {fmt(dc)} mm), "
              f"inertia {np.round(six, 6).tolist()} (TOML Δ {fmt(di)} kg·mm²)")
        if dm:
            failures.append(f"{j['name']}: mass {b['mass']} in the TOML, {mass} in Drake's file")

    print("\n## dynamics: kinema (the built-in) vs Pinocchio (Drake's chain)")
    rows = []
    SS = np.outer(SIGN, SIGN)
    for call, kin, ref in [
        ("rne", lambda q, qd, qdd, tau: robot.rne(q, qd, qdd, gravity=GRAVITY),
         lambda q, qd, qdd, tau: SIGN * pin.rnea(model, data, SIGN * q, SIGN * qd, SIGN * qdd)),
        ("inertia", lambda q, qd, qdd, tau: robot.inertia(q),
         lambda q, qd, qdd, tau: SS * sym(pin.crba(model, data, SIGN * q))),
        ("coriolis", lambda q, qd, qdd, tau: robot.coriolis(q, qd),
         lambda q, qd, qdd, tau: SS * pin.computeCoriolisMatrix(model, data, SIGN * q, SIGN * qd)),
        ("gravload", lambda q, qd, qdd, tau: robot.gravload(q, gravity=GRAVITY),
         lambda q, qd, qdd, tau: SIGN * pin.computeGeneralizedGravity(model, data, SIGN * q)),
        ("accel", lambda q, qd, qdd, tau: robot.accel(q, qd, tau, gravity=GRAVITY),
         lambda q, qd, qdd, tau: SIGN * pin.aba(model, data, SIGN * q, SIGN * qd, SIGN * tau)),
    ]:
        worst_abs = worst_rel = 0.0
        for s in zip(Q, QD, QDD, TAU):
            a, r = np.asarray(kin(*s), float), np.asarray(ref(*s), float)
            d = float(np.abs(a - r).max())
            worst_abs, worst_rel = max(worst_abs, d), max(worst_rel, d / float(np.abs(r).max()))
        ok = worst_rel <= args.bound
        print(f"  {call:<9} max|Δ| {fmt(worst_abs):>7}  max|Δ|/max|Pinocchio| {fmt(worst_rel):>7}  "
              f"{'ok' if ok else f'OVER {args.bound:.0e}'}")
        rows.append((call, worst_abs, worst_rel))
        if not ok:
            failures.append(f"{call}: {worst_rel:.1e} relative")

    print(f"\nworst |Δ| between the moved Drake values and the TOML: com {fmt(worst_com)} mm, inertia "
          f"{fmt(worst_inertia)} kg·mm²")
    exit_if_failed(failures)
    print(f"PASSED: the built-in's dynamics equal Pinocchio's on Drake's iiwa 14 within {args.bound:.0e} (relative)")


def sym(m):
    """crba fills the upper triangle only."""
    return np.triu(m) + np.triu(m, 1).T


if __name__ == "__main__":
    main()
