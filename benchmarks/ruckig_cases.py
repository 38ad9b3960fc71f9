"""Seeded boundary-state motion problems and Ruckig's durations for them.

Writes one CSV row per problem: kind, case, dof, then per joint
p0 v0 a0 pf vf af vmax amax jmax (jmax = inf: second order), then Ruckig's
result code and duration. kinema reads the file and compares
(crates/kinema/tests/all/traj_boundary.rs, `ruckig_durations`, run by
benchmarks/run_ruckig.sh). Every state is within the limits and its
acceleration does not carry the velocity past vmax, so that Ruckig never
needs its braking pre-phase and both tools solve the same problem —
except the kinds `brake` and `brake-second`, whose start states lie beyond
the limits (|v0| up to 3 vmax, |a0| up to 3 amax) so that both brake first.

    python ruckig_cases.py --cases 10000 --seed 25 --out cases.csv
    python ruckig_cases.py --timing 256 --seed 25 --out sync7.csv

With --timing N it writes N seven-joint jerk-limited problems instead and
prints Ruckig's planning time per problem: `Ruckig(7).calculate(inp, traj)`
from Python (the binding calls the C++ directly), the InputParameter filled
beforehand, the best of 5 passes over all N problems.
"""

import argparse
import math
import random
import time

from ruckig import InputParameter, Result, Ruckig, RuckigError, Trajectory


def log_uniform(rng, lo, hi):
    return math.exp(rng.uniform(math.log(lo), math.log(hi)))


def limits(rng, jerk):
    v, a = log_uniform(rng, 0.1, 10.0), log_uniform(rng, 0.1, 100.0)
    return v, a, (log_uniform(rng, 1.0, 1000.0) if jerk else math.inf)


def state(rng, p, v_max, a_max, j_max):
    v = rng.uniform(-v_max, v_max)
    a = rng.uniform(-a_max, a_max) if math.isfinite(j_max) else 0.0
    kind = rng.randrange(6)
    if kind == 0:
        v = 0.0
    elif kind == 1:
        a = 0.0
    elif kind == 2:
        v, a = 0.0, 0.0
    if math.isfinite(j_max):
        room = math.sqrt(2.0 * j_max * (v_max - abs(v))) * (1.0 - 1e-9)
        a = max(-room, min(room, a))
    return p, v, a


def beyond(rng, p, v_max, a_max, j_max):
    """A start state beyond the limits."""
    v = rng.uniform(-3.0, 3.0) * v_max
    a = rng.uniform(-3.0, 3.0) * a_max if math.isfinite(j_max) else 0.0
    if rng.randrange(3) == 0:
        v = math.copysign(1.01 * v_max + abs(v), v)
    return p, v, a


def joint(rng, jerk, brake=False):
    v_max, a_max, j_max = limits(rng, jerk)
    if brake and jerk:
        # At most 2 s to swing the acceleration across its range.
        j_max = max(j_max, a_max / 2.0)
    p0 = rng.uniform(-3.0, 3.0)
    d = rng.choice([0.0, rng.uniform(-1e-3, 1e-3), rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0)])
    start = (beyond if brake else state)(rng, p0, v_max, a_max, j_max)
    return start + state(rng, p0 + d, v_max, a_max, j_max) + (v_max, a_max, j_max)


def solve(joints):
    n = len(joints)
    inp = InputParameter(n)
    inp.current_position = [j[0] for j in joints]
    inp.current_velocity = [j[1] for j in joints]
    inp.current_acceleration = [j[2] for j in joints]
    inp.target_position = [j[3] for j in joints]
    inp.target_velocity = [j[4] for j in joints]
    inp.target_acceleration = [j[5] for j in joints]
    inp.max_velocity = [j[6] for j in joints]
    inp.max_acceleration = [j[7] for j in joints]
    inp.max_jerk = [j[8] for j in joints]
    traj = Trajectory(n)
    try:
        res = Ruckig(n).calculate(inp, traj)
    except RuckigError:
        return "refused", math.nan
    if res != Result.Working and res != Result.Finished:
        return str(res).split(".")[-1], math.nan
    return "ok", traj.duration


def inputs(joints):
    n = len(joints)
    inp = InputParameter(n)
    for name, k in [("current_position", 0), ("current_velocity", 1), ("current_acceleration", 2),
                    ("target_position", 3), ("target_velocity", 4), ("target_acceleration", 5),
                    ("max_velocity", 6), ("max_acceleration", 7), ("max_jerk", 8)]:
        setattr(inp, name, [j[k] for j in joints])
    return inp


def timing(rng, n, out):
    problems = [[joint(rng, True) for _ in range(7)] for _ in range(n)]
    with open(out, "w") as f:
        for case, joints in enumerate(problems):
            values = ",".join(repr(x) for j in joints for x in j)
            f.write(f"sync7,{case},7,{values},ok,nan\n")
    inps = [inputs(j) for j in problems]
    otg, traj = Ruckig(7), Trajectory(7)
    best = math.inf
    for _ in range(5):
        start = time.perf_counter()
        for inp in inps:
            otg.calculate(inp, traj)
        best = min(best, (time.perf_counter() - start) / n)
    print(f"ruckig sync-7dof-third: {best * 1e6:.2f} us per problem (best of 5 passes over {n})")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", type=int, default=12000)
    ap.add_argument("--seed", type=int, default=25)
    ap.add_argument("--out", required=True)
    ap.add_argument("--timing", type=int, default=0)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    if args.timing:
        timing(rng, args.timing, args.out)
        return
    kinds = [("third", 1, True, False), ("second", 1, False, False), ("sync3", 3, True, False),
             ("sync3-second", 3, False, False), ("brake", 1, True, True), ("brake-second", 1, False, True)]
    with open(args.out, "w") as f:
        for case in range(args.cases):
            kind, dof, jerk, brake = kinds[case % len(kinds)]
            joints = [joint(rng, jerk, brake) for _ in range(dof)]
            code, duration = solve(joints)
            values = ",".join(repr(x) for j in joints for x in j)
            f.write(f"{kind},{case},{dof},{values},{code},{duration!r}\n")


if __name__ == "__main__":
    main()
