#!/usr/bin/env python3
"""kinema's all-solutions analytic IK against IK-Geo's, from Python, on the same targets.

    python benchmarks/ik_geo_compare.py time [--n N] [--passes K] [--seed S]
    python benchmarks/ik_geo_compare.py calls ROBOT WHO N    (for the instruction count)

`time`: the PUMA 560 (IK-Geo `spherical_two_intersecting`) and the UR5
(`three_parallel_two_intersecting`): the median over K interleaved passes of the mean time per
call, kinema `Robot.ik(T, all=True, solver="analytic")` against IK-Geo `get_ik(R, t)`, so that load
drifts on a shared machine hit both alike. Then random general 6R arms (random unit axes and
offsets, a `general` TOML each): kinema's `geo-general` against IK-Geo's `gen_six_dof`, counting
the solutions each returns, how many reach the target within 1e-6 (kinema's FK, which matches
IK-Geo's own to rounding on these arms), and whether the generating configuration is among them.

`calls`: makes N targets and calls one solver (WHO = kinema or ik-geo) on each, nothing else, so
that `run_ik_geo.sh` can read the instructions per call off callgrind's inclusive count of the
extension's method (repeatable, unlike time, on a machine shared with other work).

Needs `kinema` and `ik-geo` importable; `benchmarks/run_ik_geo.sh` makes such a venv.
"""

import argparse
import math
import os
import statistics
import sys
import tempfile
import time

import numpy as np

import ik_geo
import kinema

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from geo_kinematics import geo_hp  # noqa: E402

ARMS = {"puma560": "spherical_two_intersecting", "ur5": "three_parallel_two_intersecting"}
TOL = 1e-6


def targets(robot, n, rng):
    lo, hi = np.array(robot.qlim)
    return [robot.fkine(rng.uniform(lo, hi)) for _ in range(n)]


def geo_inputs(Ts, R0):
    """IK-Geo's bindings read 3x3 matrices column by column, so R is passed transposed; IK-Geo's
    zero pose has the identity tool rotation, so it is given R·R0ᵀ."""
    return [(np.ascontiguousarray((T[:3, :3] @ R0.T).T), np.ascontiguousarray(T[:3, 3])) for T in Ts]


def per_call(fn, items):
    start = time.perf_counter()
    for x in items:
        fn(x)
    return (time.perf_counter() - start) / len(items)


def time_builtins(n, passes, rng):
    print(f"## All-solutions analytic IK per call, median of {passes} interleaved passes over {n} targets")
    print("| robot | kinema ik(T, all=True) µs | IK-Geo get_ik µs (family) | kinema ÷ IK-Geo |")
    print("|---|---:|---:|---:|")
    for name, family in ARMS.items():
        robot = kinema.Robot.builtin(name)
        H, P, R0 = geo_hp(robot)
        geo = getattr(ik_geo.Robot, family)(H, P)
        Ts = targets(robot, n, rng)
        gin = geo_inputs(Ts, R0)
        tk, tg = [], []
        for _ in range(passes):
            tk.append(per_call(lambda T: robot.ik(T, all=True, solver="analytic"), Ts))
            tg.append(per_call(lambda x: geo.get_ik(*x), gin))
        k, g = statistics.median(tk), statistics.median(tg)
        print(f"| {name} | {k * 1e6:.2f} [best {min(tk) * 1e6:.2f}] | {g * 1e6:.2f} [best {min(tg) * 1e6:.2f}] "
              f"({family}) | **{k / g:.2f}** [best {min(tk) / min(tg):.2f}] |")


def random_general_arm(rng, path):
    """A 6R arm with random unit axes and random offsets (σ = 0.3 m), as a `general` TOML."""
    rows = ['name = "random-general-6r"', 'source = "benchmarks/ik_geo_compare.py, random"',
            'convention = "general"', "", "[units]", 'length = "m"', 'angle = "deg"', "",
            "[tool]", "xyz = [0, 0, 0.1]", ""]
    for i in range(6):
        h = rng.normal(size=3)
        h /= np.linalg.norm(h)
        o = rng.normal(size=3) * 0.3 if i else np.zeros(3)
        rows += ["[[joint]]", f'name = "j{i + 1}"', "xyz = [{:.6f}, {:.6f}, {:.6f}]".format(*o),
                 "axis = [{:.6f}, {:.6f}, {:.6f}]".format(*h), "min = -180", "max = 180", ""]
    rows += ["[poses]", "home = [0, 0, 0, 0, 0, 0]"]
    with open(path, "w") as f:
        f.write("\n".join(rows))
    return kinema.Robot.from_file(path)


def meets(robot, q, T):
    Tq = robot.fkine(np.asarray(q, dtype=float))
    return np.linalg.norm(Tq[:3, 3] - T[:3, 3]) <= TOL and np.linalg.norm(Tq[:3, :3] - T[:3, :3]) <= TOL


def has(qs, q):
    return any(np.abs(np.angle(np.exp(1j * (np.asarray(s) - q)))).max() < 1e-6 for s in qs)


def general_arms(n_arms, n_targets, rng):
    print(f"\n## General 6R: {n_arms} random arms × {n_targets} targets")
    stats = {w: {"time": [], "solutions": 0, "meet": 0, "source": 0} for w in ("kinema", "ik-geo")}
    solver = set()
    with tempfile.TemporaryDirectory() as d:
        for a in range(n_arms):
            robot = random_general_arm(rng, os.path.join(d, f"arm{a}.toml"))
            H, P, R0 = geo_hp(robot)
            geo = ik_geo.Robot.gen_six_dof(H, P)
            for _ in range(n_targets):
                q = rng.uniform(-math.pi, math.pi, 6)
                T = robot.fkine(q)
                (gin,) = geo_inputs([T], R0)
                start = time.perf_counter()
                ks = robot.ik(T, all=True, solver="analytic")
                stats["kinema"]["time"].append(time.perf_counter() - start)
                start = time.perf_counter()
                gs = geo.get_ik(*gin)
                stats["ik-geo"]["time"].append(time.perf_counter() - start)
                solver.update(s.solver for s in ks)
                for who, qs in (("kinema", [s.q for s in ks]), ("ik-geo", [g for g, _ in gs])):
                    st = stats[who]
                    st["solutions"] += len(qs)
                    st["meet"] += sum(meets(robot, s, T) for s in qs)
                    st["source"] += has(qs, q)
    n = n_arms * n_targets
    print(f"kinema solver: {', '.join(sorted(solver))}")
    print("| solver | median ms per pose | solutions | within 1e-6 | source configuration found |")
    print("|---|---:|---:|---:|---:|")
    for who, name in (("kinema", "kinema geo-general"), ("ik-geo", "IK-Geo gen_six_dof")):
        st = stats[who]
        print(f"| {name} | {statistics.median(st['time']) * 1e3:.2f} | {st['solutions']} | {st['meet']} | "
              f"{st['source']}/{n} |")
    return stats


def calls(name, who, n):
    robot = kinema.Robot.builtin(name)
    Ts = targets(robot, n, np.random.default_rng(0))
    if who == "kinema":
        for T in Ts:
            robot.ik(T, all=True, solver="analytic")
    else:
        H, P, R0 = geo_hp(robot)
        geo = getattr(ik_geo.Robot, ARMS[name])(H, P)
        for R, t in geo_inputs(Ts, R0):
            geo.get_ik(R, t)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="mode", required=True)
    t = sub.add_parser("time")
    t.add_argument("--n", type=int, default=1000)
    t.add_argument("--passes", type=int, default=9)
    t.add_argument("--arms", type=int, default=10)
    t.add_argument("--arm-targets", type=int, default=20)
    t.add_argument("--seed", type=int, default=0)
    c = sub.add_parser("calls")
    c.add_argument("robot", choices=sorted(ARMS))
    c.add_argument("who", choices=["kinema", "ik-geo"])
    c.add_argument("n", type=int)
    args = ap.parse_args()
    if args.mode == "calls":
        calls(args.robot, args.who, args.n)
        return 0
    rng = np.random.default_rng(args.seed)
    time_builtins(args.n, args.passes, rng)
    stats = general_arms(args.arms, args.arm_targets, rng)
    # kinema's contract: every solution it returns meets the target.
    wrong = stats["kinema"]["solutions"] - stats["kinema"]["meet"]
    print(f"\nkinema solutions missing the target: {wrong}")
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
