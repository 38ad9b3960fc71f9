"""Seeded boundary-state motion problems and Ruckig's durations for them.

Writes one CSV row per problem: kind, case, dof, then per joint
p0 v0 a0 pf vf af vmax amax jmax (jmax = inf: second order), then Ruckig's
result code and duration. kinema reads the file and compares
(crates/kinema/tests/all/traj_boundary.rs, `ruckig_durations`, run by
benchmarks/run_ruckig.sh). Every state is within the limits and its
acceleration does not carry the velocity past vmax, so that Ruckig never
needs its braking pre-phase and both tools solve the same problem.

    python ruckig_cases.py --cases 10000 --seed 25 --out cases.csv
"""

import argparse
import math
import random

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


def joint(rng, jerk):
    v_max, a_max, j_max = limits(rng, jerk)
    p0 = rng.uniform(-3.0, 3.0)
    d = rng.choice([0.0, rng.uniform(-1e-3, 1e-3), rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0)])
    return state(rng, p0, v_max, a_max, j_max) + state(rng, p0 + d, v_max, a_max, j_max) + (v_max, a_max, j_max)


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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", type=int, default=12000)
    ap.add_argument("--seed", type=int, default=25)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    rng = random.Random(args.seed)
    kinds = [("third", 1, True), ("second", 1, False), ("sync3", 3, True), ("sync3-second", 3, False)]
    with open(args.out, "w") as f:
        for case in range(args.cases):
            kind, dof, jerk = kinds[case % len(kinds)]
            joints = [joint(rng, jerk) for _ in range(dof)]
            code, duration = solve(joints)
            values = ",".join(repr(x) for j in joints for x in j)
            f.write(f"{kind},{case},{dof},{values},{code},{duration!r}\n")


if __name__ == "__main__":
    main()
