#!/usr/bin/env python3
"""kinema's Python dynamics (`rne`, `inertia`, `coriolis`, `gravload`, `accel`) checked against
Corke's Robotics Toolbox (roboticstoolbox-python), a second oracle beside Pinocchio
(benchmarks/run_dyn_peers.sh).

    python benchmarks/dyn_corke.py [--n 200] [--seed 0] [--bound 1e-9]

Run it in a venv where `kinema` (crates/kinema-py), `roboticstoolbox-python` and `pin` are
installed (it reuses benchmarks/ik_peers.py's model building, which imports Pinocchio);
benchmarks/run_ik_peers.sh and benchmarks/run_dyn_corke.sh make such a venv and run it.

Robots: every built-in whose robots/NAME.toml gives every joint a `[joint.inertial]` table. The
script reads the file itself (ik_peers.Description, tomllib) and builds the toolbox's `DHRobot`
of `RevoluteDH`/`RevoluteMDH` links with the same DH rows, offsets, base and tool, and per link the
file's mass m, centre of mass r and inertia I (3x3, about the centre of mass, in the link frame:
the same frame in both, the distal DH frame for standard DH and the proximal one for modified DH),
no motor inertia or friction (Jm = 0, G = 1, B = 0, Tc = [0, 0]), gravity [0, 0, -9.81].

States: `home` and --n seeded random ones per robot, q within kinema's limits, q̇ in [-2, 2] rad/s,
q̈ in [-3, 3] rad/s², τ (for `accel`) in [-20, 20] N·m. Each of kinema's five calls is made once per
state (the one-row path) and once on all states stacked (the batch path), both compared with the
toolbox's call of the same name at the same state. The measure per state is max|kinema - toolbox|
over the result's elements divided by max|toolbox| over them (the result's magnitude). Exits 1 if
any exceeds --bound (default 1e-9), 2 if the toolbox cannot be imported.
"""

from __future__ import annotations

import argparse
import datetime
import math
import platform
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ik_peers import REPO, Description, exit_if_failed, fmt, rtb_model  # noqa: E402

import kinema  # noqa: E402

GRAVITY = np.array([0.0, 0.0, -9.81])
CALLS = ["rne", "inertia", "coriolis", "gravload", "accel"]


def states(robot, rng, n):
    lo, hi = robot.qlim
    lo, hi = np.maximum(lo, -2 * math.pi), np.minimum(hi, 2 * math.pi)
    dof = robot.n
    q = np.vstack([robot.home, rng.uniform(lo, hi, size=(n, dof))])
    qd = rng.uniform(-2, 2, size=q.shape)
    qdd = rng.uniform(-3, 3, size=q.shape)
    tau = rng.uniform(-20, 20, size=q.shape)
    return q, qd, qdd, tau


def dynamics_calls(robot):
    """{call: f(q, qd, qdd, tau) -> array}: kinema and the toolbox share these names and arguments."""
    return {
        "rne": lambda q, qd, qdd, tau: robot.rne(q, qd, qdd, gravity=GRAVITY),
        "inertia": lambda q, qd, qdd, tau: robot.inertia(q),
        "coriolis": lambda q, qd, qdd, tau: robot.coriolis(q, qd),
        "gravload": lambda q, qd, qdd, tau: robot.gravload(q, gravity=GRAVITY),
        "accel": lambda q, qd, qdd, tau: robot.accel(q, qd, tau, gravity=GRAVITY),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=200, help="random states per robot, besides home (default 200)")
    ap.add_argument("--seed", type=int, default=0, help="numpy Generator seed (default 0)")
    ap.add_argument("--bound", type=float, default=1e-9, help="relative bound (default 1e-9)")
    ap.add_argument("--robots-dir", type=Path, default=REPO / "robots")
    args = ap.parse_args()

    started = datetime.datetime.now().astimezone()
    try:
        import roboticstoolbox as rtb
    except Exception as exc:  # noqa: BLE001
        print(f"roboticstoolbox-python is not importable ({type(exc).__name__}: {exc}): it is this check's oracle")
        sys.exit(2)
    print(f"# kinema's dynamics vs Corke's toolbox — {started:%Y-%m-%d %H:%M %Z}")
    print(f"python {platform.python_version()}, numpy {np.__version__}, kinema {kinema.__version__}, "
          f"roboticstoolbox-python {rtb.__version__}; n={args.n} seed={args.seed} bound={args.bound:.0e} (relative)")

    rng = np.random.default_rng(args.seed)
    rows, failures = [], []
    for name in kinema.Robot.builtins():
        desc = Description(args.robots_dir / f"{name}.toml")
        if not all("inertial" in j for j in desc.joints):
            continue
        robot = kinema.Robot.builtin(name)
        names = [j["name"] for j in desc.joints]
        if names != robot.joint_names:
            sys.exit(f"robots/{name}.toml has joints {names}, kinema's built-in {robot.joint_names}")
        model = rtb_model(desc, rtb, dynamics=True)
        model.gravity = GRAVITY
        cls = type(model.links[0]).__name__
        Q, QD, QDD, TAU = states(robot, rng, args.n)
        kin, tb = dynamics_calls(robot), dynamics_calls(model)
        print(f"{name}  (n={robot.n}, {desc.convention} DH: DHRobot of {cls}, {len(Q)} states)")
        for call in CALLS:
            ref = [np.asarray(tb[call](*s), float) for s in zip(Q, QD, QDD, TAU)]
            one = [np.asarray(kin[call](*s), float) for s in zip(Q, QD, QDD, TAU)]
            batch = np.asarray(kin[call](Q, QD, QDD, TAU), float)
            worst_abs = worst_rel = 0.0
            worst_at = 0
            mag = 0.0
            for path in (one, batch):
                for i, (a, r) in enumerate(zip(path, ref)):
                    d = float(np.abs(a - r).max())
                    m = float(np.abs(r).max())
                    rel = d / m if m > 0 else d
                    mag = max(mag, m)
                    worst_abs = max(worst_abs, d)
                    if rel > worst_rel:
                        worst_rel, worst_at = rel, i
            ok = worst_rel <= args.bound
            print(f"    {call:<9} max|Δ| {fmt(worst_abs):>7}  max|Δ|/max|toolbox| {fmt(worst_rel):>7}  "
                  f"(largest |toolbox| {mag:.3g})  {'ok' if ok else f'OVER {args.bound:.0e} at state {worst_at}'}")
            rows.append((name, robot.n, desc.convention, call, worst_abs, worst_rel, mag, ok))
            if not ok:
                failures.append(f"{name} {call}: {worst_rel:.1e} relative (state {worst_at}: q = "
                                f"{np.array2string(Q[worst_at], precision=17, separator=', ')})")
    if not rows:
        sys.exit("no built-in with inertials found")
    wall = (datetime.datetime.now().astimezone() - started).total_seconds()
    print(f"\nwall time {wall:.0f} s\n\n---\n")
    print(f"kinema's Python dynamics against roboticstoolbox-python {rtb.__version__}'s DHRobot built from the same "
          f"TOML, `home` and {args.n} random states per robot (seed {args.seed}), each call on one row and on all "
          f"rows; worst max|Δ| and worst max|Δ|/max|toolbox| per state (bound {args.bound:.0e}):\n")
    print("| robot | n | DH | call | max abs Δ | max relative Δ | largest magnitude | within bound |")
    print("|---|---:|---|---|---:|---:|---:|---|")
    for name, n, conv, call, da, dr, mag, ok in rows:
        print(f"| {name} | {n} | {conv} | `{call}` | {fmt(da)} | {fmt(dr)} | {mag:.3g} | {'yes' if ok else 'NO'} |")
    print()
    exit_if_failed(failures)
    print(f"PASSED: kinema's rne, inertia, coriolis, gravload and accel equal the toolbox's within {args.bound:.0e} "
          f"(relative) on {len(rows) // len(CALLS)} robots")


if __name__ == "__main__":
    main()
