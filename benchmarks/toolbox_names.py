#!/usr/bin/env python3
"""kinema's toolbox names checked against Corke's Robotics Toolbox (roboticstoolbox-python):
`kinema.Robot.from_dh` against `DHRobot` forward kinematics, `kinema.ctraj` against `ctraj` and
`kinema.jtraj` against `jtraj`.

    python benchmarks/toolbox_names.py [--arms 200] [--seed 0] [--bound 1e-12]

Run it in a venv where `kinema` (crates/kinema-py) and `roboticstoolbox-python` are installed;
benchmarks/run_ik_peers.sh makes one and runs it.

Arms: --arms seeded random DH tables, half standard, half modified, of 1 to 7 links, each link
revolute or (one in three) prismatic, with random d or θ, a, α and offsets, and a random base and
tool; each arm built as `kinema.Robot.from_dh([RevoluteDH(...), PrismaticDH(...)], base=, tool=)`
and as the toolbox's `DHRobot` of the same links, FK compared at 5 random configurations. Then
`ctraj(T0, T1, n)` and `jtraj(q0, q1, n)` at random ends. The measure is max|kinema - toolbox| over
the elements. Exits 1 if any exceeds --bound (default 1e-12), 2 if the toolbox cannot be imported.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

import kinema

try:
    import roboticstoolbox as rtb
    from spatialmath import SE3
except ImportError as e:
    print(f"roboticstoolbox-python is not installed: {e}")
    sys.exit(2)


def fmt(x):
    return f"{x:.1e}" if x else "0"


def random_pose(rng):
    return SE3.Trans(*rng.uniform(-0.5, 0.5, 3)) * SE3.RPY(*rng.uniform(-np.pi, np.pi, 3))


def random_arm(rng, modified):
    """The same random links for both: kinema's and the toolbox's link classes."""
    ours, theirs = [], []
    for _ in range(rng.integers(1, 8)):
        a, alpha, offset, fixed = rng.uniform(-0.6, 0.6), rng.uniform(-np.pi, np.pi), rng.uniform(-1, 1), rng.uniform(-0.6, 0.6)
        if rng.random() < 1 / 3:
            qlim = [-0.5, 0.5]
            ours.append((kinema.PrismaticMDH if modified else kinema.PrismaticDH)(theta=fixed, a=a, alpha=alpha, offset=offset, qlim=qlim))
            theirs.append((rtb.PrismaticMDH if modified else rtb.PrismaticDH)(theta=fixed, a=a, alpha=alpha, offset=offset, qlim=qlim))
        else:
            qlim = [-np.pi, np.pi]
            ours.append((kinema.RevoluteMDH if modified else kinema.RevoluteDH)(d=fixed, a=a, alpha=alpha, offset=offset, qlim=qlim))
            theirs.append((rtb.RevoluteMDH if modified else rtb.RevoluteDH)(d=fixed, a=a, alpha=alpha, offset=offset, qlim=qlim))
    return ours, theirs


def fk_worst(rng, arms):
    worst = {False: 0.0, True: 0.0}
    for k in range(arms):
        modified = k % 2 == 1
        ours, theirs = random_arm(rng, modified)
        base, tool = random_pose(rng), random_pose(rng)
        robot = kinema.Robot.from_dh(ours, name="arm", base=base, tool=tool)
        peer = rtb.DHRobot(theirs, name="arm", base=base, tool=tool)
        for _ in range(5):
            q = rng.uniform(-0.5, 0.5, robot.n)
            worst[modified] = max(worst[modified], float(np.abs(robot.fkine(q) - peer.fkine(q).A).max()))
    return worst


def traj_worst(rng, cases):
    worst = {"ctraj": 0.0, "jtraj q": 0.0, "jtraj qd": 0.0, "jtraj qdd": 0.0}
    for _ in range(cases):
        T0, T1 = random_pose(rng), random_pose(rng)
        n = int(rng.integers(2, 60))
        theirs = rtb.ctraj(T0, T1, n)
        worst["ctraj"] = max(worst["ctraj"], float(np.abs(kinema.ctraj(T0, T1, n) - np.asarray(theirs.A)).max()))
        q0, q1 = rng.uniform(-3, 3, 6), rng.uniform(-3, 3, 6)
        path, peer = kinema.jtraj(q0, q1, n), rtb.jtraj(q0, q1, n)
        for name, ours, other in (("q", path.q, peer.q), ("qd", path.qd, peer.qd), ("qdd", path.qdd, peer.qdd)):
            worst[f"jtraj {name}"] = max(worst[f"jtraj {name}"], float(np.abs(ours - other).max()))
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arms", type=int, default=200)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--bound", type=float, default=1e-12)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    print(f"kinema {kinema.__version__}, roboticstoolbox-python {rtb.__version__}; {args.arms} random arms, seed {args.seed}")
    failures = []
    for modified, worst in fk_worst(rng, args.arms).items():
        label = f"from_dh FK vs DHRobot ({'modified' if modified else 'standard'} DH)"
        print(f"{label:<45} max |diff| {fmt(worst)}")
        if not worst <= args.bound:
            failures.append(f"{label}: {fmt(worst)} > {args.bound:g}")
    for label, worst in traj_worst(rng, args.arms // 4 + 1).items():
        print(f"{label + ' vs the toolbox':<45} max |diff| {fmt(worst)}")
        if not worst <= args.bound:
            failures.append(f"{label}: {fmt(worst)} > {args.bound:g}")
    if failures:
        print("FAILED:\n- " + "\n- ".join(failures))
        sys.exit(1)


if __name__ == "__main__":
    main()
