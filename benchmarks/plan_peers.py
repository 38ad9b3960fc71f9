"""Plans the problems of benchmarks/plan/ with kinema (Robot.plan, seed = problem index, 1 s) and
re-checks every returned path with Pinocchio + coal on the same shapes, obstacles and pairs
(benchmarks/plan_peers_geometry.py); with --ompl, also plans them with OMPL's RRT-Connect whose state
validity is kinema's own Robot.collides on the same scene.

    python benchmarks/plan_peers.py [--subset N] [--seed S] [--ompl] [--resolution R]

The re-check samples each straight segment between via points at most 1 mrad apart in every joint
(the planner's paths are straight in joint space between via points), and every sample of the timed
trajectory; any sample coal finds colliding fails the run (exit 1), as does a kinema/coal difference
over 1e-6 m in the distance at a problem's start and goal, a Pinocchio tool pose that differs
from kinema's by over 1e-9, or a straight start-goal segment coal finds free (the set's are blocked). The margin printed is the smallest coal distance along each path.

OMPL gets configuration goals (the problem set's goals are configurations), the same 1 s, its
discrete motion validator at R rad between checks (L2 over the joints; default 0.01), and its own
path simplifier (its time added, as kinema's shortening is in kinema's); its paths are re-checked by coal the same way.
--subset N: N problems drawn with --seed from the 100 (all without it).
"""

import argparse
import csv
import os
import random
import sys
import time

import numpy as np

import kinema
from plan_peers_geometry import Chain, CoalCheck, dense

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
SHORT = {"panda": "panda", "lbr-iiwa-14-r820": "iiwa"}


def problems():
    with open(os.path.join(HERE, "plan", "problems.csv")) as f:
        rows = list(csv.DictReader(f))
    for k, r in enumerate(rows):
        q = lambda s: np.array([float(v) for v in s.split()])  # noqa: E731
        yield k, r["name"], r["robot"], q(r["start"]), q(r["goal"])


def recheck(check, via, samples):
    """(colliding samples, smallest coal distance, its pair, samples checked) along a path."""
    qs = dense(via) + list(samples)
    bad, low, low_pair = 0, np.inf, None
    for q in qs:
        if check.collides(q):
            bad += 1
        d, pair = check.min_distance(q)
        if d < low:
            low, low_pair = d, pair
    return bad, low, low_pair, len(qs)


def same_model(robot, chain, check, scene, qs):
    """Largest tool-pose and distance differences between kinema and Pinocchio + coal at qs."""
    pose_err, dist_err = 0.0, 0.0
    for q in qs:
        tool = (chain.link_frames(q)[-1] * chain.tool).homogeneous
        pose_err = max(pose_err, float(np.max(np.abs(tool - robot.fkine(q)))))
        dist_err = max(dist_err, abs(robot.distance(q, scene) - check.min_distance(q)[0]))
    return pose_err, dist_err


def plan_kinema(robot, scene, start, goal, seed):
    try:
        traj = robot.plan(start, goal, scene=scene, seed=seed, time_limit=1.0)
    except kinema.PlanningError as e:
        return None, None, None, str(e)
    info = traj.to_dict()["plan"]
    return [np.asarray(v) for v in info["via_points"]], traj.q, info["planning_time"], None


def percentile(xs, f):
    xs = sorted(xs)
    return xs[round((len(xs) - 1) * f)] if xs else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--subset", type=int, default=0, help="problems drawn from the set (0: all)")
    ap.add_argument("--seed", type=int, default=39)
    ap.add_argument("--ompl", action="store_true", help="also plan with OMPL's RRT-Connect")
    ap.add_argument("--resolution", type=float, default=0.01, help="OMPL's motion check step [rad]")
    args = ap.parse_args()
    chosen = list(problems())
    if args.subset:
        chosen = sorted(random.Random(args.seed).sample(chosen, args.subset))
    if args.ompl:
        import plan_peers_ompl
    failures, rows = [], []
    worst_pose, worst_dist = 0.0, 0.0
    for k, name, robot_name, start, goal in chosen:
        robot = kinema.Robot.builtin(robot_name)
        scene_path = os.path.join(HERE, "plan", "scenes", f"{name}.toml")
        scene = kinema.Scene.from_file(scene_path)
        chain = Chain(os.path.join(REPO, "robots", f"{robot_name}.toml"))
        check = CoalCheck(chain, scene_path)
        pose_err, dist_err = same_model(robot, chain, check, scene, [start, goal])
        worst_pose, worst_dist = max(worst_pose, pose_err), max(worst_dist, dist_err)
        # The set's straight segments all collide: a re-check that passed one would be blind.
        if not any(check.collides(q) for q in dense([start, goal])):
            failures.append(f"{name}: coal finds the straight start-goal segment free; the set says it collides")
        if pose_err > 1e-9 or dist_err > 1e-6:
            failures.append(f"{name}: kinema and coal disagree (tool pose {pose_err:.1e}, distance {dist_err:.1e} m)")
        row = {"name": name, "robot": SHORT[robot_name], "family": name.split("-")[0]}
        via, samples, t, err = plan_kinema(robot, scene, start, goal, k)
        if err:
            print(f"  {name}: kinema found no path: {err}")
        else:
            bad, low, pair, n = recheck(check, via, samples)
            row["kinema"] = (t, low)
            if bad:
                failures.append(f"{name}: coal finds {bad} of {n} samples of kinema's path colliding")
            print(f"  {name}: kinema {t * 1e3:8.2f} ms, {len(via)} via points, {n} samples, margin {low * 1e3:7.2f} mm {pair}")
        if args.ompl:
            found = plan_peers_ompl.plan(robot, scene, start, goal, k, args.resolution)
            if found is None:
                print(f"  {name}: OMPL found no exact path in 1 s")
            else:
                path, t = found
                bad, low, _, n = recheck(check, path, [])
                row["ompl"] = (t, low, bad)
                print(f"  {name}: OMPL   {t * 1e3:8.2f} ms, {len(path)} states, margin {low * 1e3:7.2f} mm, {bad} colliding")
        rows.append(row)
    print(f"kinema against Pinocchio + coal at the starts and goals: tool pose within {worst_pose:.1e}, "
          f"distance within {worst_dist:.1e} m")
    summary(rows, args.ompl)
    for f in failures:
        print("FAIL", f)
    print(f"plan peers: {len(rows)} problems, {len(failures)} failures")
    sys.stdout.flush()
    return 1 if failures else 0


def summary(rows, ompl):
    print(f"{'robot/family':18} {'kinema ok':>9} {'median ms':>9} {'p90 ms':>8}", end="")
    if ompl:
        print(f" {'OMPL ok':>7} {'median ms':>9} {'p90 ms':>8} {'OMPL/kinema':>11} {'OMPL bad':>8}", end="")
    print(f" {'min margin mm':>13}")
    groups = sorted({(r["robot"], r["family"]) for r in rows}) + [("all", "")]
    for robot, family in groups:
        g = [r for r in rows if robot == "all" or (r["robot"], r["family"]) == (robot, family)]
        kt = [r["kinema"][0] * 1e3 for r in g if "kinema" in r]
        margin = min((r["kinema"][1] for r in g if "kinema" in r), default=float("nan"))
        print(f"{robot + '/' + family if family else robot:18} {len(kt):>4}/{len(g):<4} "
              f"{percentile(kt, 0.5):9.2f} {percentile(kt, 0.9):8.2f}", end="")
        if ompl:
            ot = [r["ompl"][0] * 1e3 for r in g if "ompl" in r]
            bad = sum(1 for r in g if "ompl" in r and r["ompl"][2])
            ratio = percentile(ot, 0.5) / percentile(kt, 0.5) if kt and ot else float("nan")
            print(f" {len(ot):>3}/{len(g):<3} {percentile(ot, 0.5):9.2f} {percentile(ot, 0.9):8.2f} {ratio:11.2f} {bad:8}", end="")
        print(f" {margin * 1e3:13.2f}")


if __name__ == "__main__":
    code = main()
    # OMPL's nanobind module reports its leaked singletons at interpreter exit; nothing is left to flush.
    os._exit(code)
