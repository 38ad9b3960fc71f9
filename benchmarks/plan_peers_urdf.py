"""`kinema plan` on real URDFs (example-robot-data's Panda, UR5 and Kinova Jaco with their SRDFs;
rtbdata's ROS-Industrial KUKA KR 16-2 and ABB IRB 140; collision meshes), each path re-checked with Pinocchio + coal on the same meshes, for
benchmarks/run_plan_peers.sh --urdf.

    python benchmarks/plan_peers_urdf.py KINEMA_BIN [--per-robot N] [--seed S]

Per robot, N seeded problems: a table under the arm's reach and a box on it; start and goal are
random configurations coal finds free whose straight segment coal finds colliding. Pinocchio's pairs
are kinema's: geometries on bodies more than one joint apart, less the SRDF's disabled pairs, and every
geometry on a moving body against each obstacle. A path sample coal finds colliding fails the run.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import coal
import numpy as np
import pinocchio as pin

from plan_peers_geometry import dense

ROBOTS = [
    # name, source (example-robot-data or rtbdata), URDF, SRDF (None: none), tip (None: the only
    # leaf), joints kept (None: all; the others are locked at 0, as off kinema's chain).
    ("panda", "erd", "panda_description/urdf/panda.urdf", "panda_description/srdf/panda.srdf", "panda_hand",
     [f"panda_joint{i}" for i in range(1, 8)]),
    ("ur5", "erd", "ur_description/urdf/ur5_robot.urdf", "ur_description/srdf/ur5.srdf", "tool0", None),
    ("kinova", "erd", "kinova_description/robots/kinova.urdf", "kinova_description/srdf/kinova.srdf",
     "j2s6s200_end_effector", [f"j2s6s200_joint_{i}" for i in range(1, 7)]),
    ("kr16", "rtb", "kuka_description/kuka_kr16/urdf/kr16_2.urdf", None, None, None),
    ("irb140", "rtb", "abb_irb140_description/urdf/irb140.urdf", None, None, None),
]
# rtbdata keeps ROS-Industrial's <robot>_support packages under other folder names.
RTB_PACKAGES = {
    "kuka_kr16_support": "kuka_description/kuka_kr16",
    "abb_irb140_support": "abb_irb140_description",
}


def erd_dirs():
    """example-robot-data's robots/ folder and the folder holding its packages."""
    robots = next(
        os.path.join(d, "cmeel.prefix", "share", "example-robot-data", "robots")
        for d in sys.path
        if os.path.isdir(os.path.join(d, "cmeel.prefix", "share", "example-robot-data", "robots"))
    )
    return robots, os.path.dirname(os.path.dirname(robots))


def rtb_dirs(work):
    """rtbdata's xacro/ folder and a folder of links named as the URDFs' package:// names."""
    import rtbdata

    root = os.path.join(os.path.dirname(rtbdata.__file__), "xacro")
    packages = os.path.join(work, "packages")
    os.makedirs(packages, exist_ok=True)
    for name, folder in RTB_PACKAGES.items():
        os.symlink(os.path.join(root, folder), os.path.join(packages, name))
    return root, packages


def load(path, package_dir, srdf, joints):
    """Pinocchio's model and collision geometry of a URDF, joints not in `joints` locked at 0, every
    pair of bodies but those the SRDF disables."""
    full = pin.buildModelFromUrdf(path)
    geom = pin.buildGeomFromUrdf(full, path, pin.GeometryType.COLLISION, package_dirs=[package_dir])
    keep = joints or list(full.names[1:])
    lock = [full.getJointId(n) for n in full.names[1:] if n not in keep]
    model, geom = (full, geom) if not lock else pin.buildReducedModel(full, geom, lock, pin.neutral(full))
    geom.addAllCollisionPairs()
    if srdf:
        pin.removeCollisionPairs(model, geom, srdf)
    return model, geom


def scene(rng):
    """A table 0.3–0.5 m in front of the base, its top 0.1–0.3 m below the base, and a box on it."""
    x, top = rng.uniform(0.3, 0.5), -rng.uniform(0.1, 0.3)
    bx, by, h = x + rng.uniform(-0.1, 0.1), rng.uniform(-0.3, 0.3), rng.uniform(0.2, 0.5)
    return [
        ("table", [0.6, 1.2, 0.04], [x + 0.3, 0.0, top - 0.02]),
        ("box", [0.15, 0.15, h], [bx, by, top + h / 2]),
    ]


def scene_toml(obstacles):
    return "".join(
        f'[[obstacle]]\nname = "{n}"\nbox = [{", ".join(map(repr, s))}]\npose = [{", ".join(map(repr, p))}, 0, 0, 0]\n\n'
        for n, s, p in obstacles
    )


def with_kinema_pairs(model, geom, obstacles):
    """geom's SRDF-filtered pairs less those on bodies one joint apart, plus the obstacles'."""
    keep = [
        p
        for p in geom.collisionPairs
        if abs(geom.geometryObjects[p.first].parentJoint - geom.geometryObjects[p.second].parentJoint) > 1
    ]
    robot_count = geom.ngeoms
    for n, size, at in obstacles:
        geom.addGeometryObject(pin.GeometryObject("obstacle:" + n, 0, 0, pin.SE3(np.eye(3), np.array(at)), coal.Box(*size)))
    geom.removeAllCollisionPairs()
    for p in keep:
        geom.addCollisionPair(p)
    for g in range(robot_count):
        if geom.geometryObjects[g].parentJoint > 0:
            for o in range(robot_count, geom.ngeoms):
                geom.addCollisionPair(pin.CollisionPair(g, o))
    return geom


def csv(q):
    return ",".join(f"{v:.17g}" for v in q)


def colliding(model, data, geom, gdata, q):
    pin.updateGeometryPlacements(model, data, geom, gdata, q)
    return pin.computeCollisions(geom, gdata, True)


def angle_limits(model):
    """Per joint (lower, upper) [rad], continuous joints (cos, sin in Pinocchio) as [-pi, pi]."""
    lims = []
    for j in model.joints[1:]:
        if j.nq == 2:
            lims.append((-np.pi, np.pi))
        else:
            lims.append((max(model.lowerPositionLimit[j.idx_q], -np.pi), min(model.upperPositionLimit[j.idx_q], np.pi)))
    return np.array(lims).T


def to_pin(model, angles):
    """Joint angles as Pinocchio's q (cos, sin for a continuous joint)."""
    q = np.empty(model.nq)
    for j, a in zip(model.joints[1:], angles):
        if j.nq == 2:
            q[j.idx_q : j.idx_q + 2] = np.cos(a), np.sin(a)
        else:
            q[j.idx_q] = a
    return q


def colliding_at(model, data, geom, gdata, angles):
    return colliding(model, data, geom, gdata, to_pin(model, angles))


def problem(model, data, geom, gdata, rng):
    lo, hi = angle_limits(model)
    free = []
    for _ in range(2000):
        q = lo + (hi - lo) * rng.random(len(lo))
        if not colliding_at(model, data, geom, gdata, q):
            free.append(q)
        if len(free) >= 2:
            a, b = free[-2], free[-1]
            if any(colliding_at(model, data, geom, gdata, q) for q in dense([a, b], 0.01)):
                return a, b
            free.pop(0)
    return None


def plan_with_kinema(kinema, path, srdf, package_dir, tip, scene_path, start, goal, seed, show):
    cmd = [kinema, "plan", "--robot", path, "--package-path", package_dir, "--scene", scene_path,
           "--from", csv(start), "--to", csv(goal), "--seed", str(seed), "--json", "--profile", "linear"]
    cmd += ["--srdf", srdf] if srdf else []
    cmd += ["--tip", tip] if tip else []
    if show:
        print("    " + " ".join(cmd), flush=True)
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    except subprocess.TimeoutExpired:
        return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("kinema")
    ap.add_argument("--per-robot", type=int, default=3)
    ap.add_argument("--seed", type=int, default=39)
    ap.add_argument("--keep", help="write the scenes here (kept) instead of a temporary folder")
    ap.add_argument("--robots", default=",".join(r[0] for r in ROBOTS), help="comma-separated names of ROBOTS")
    args = ap.parse_args()
    work = args.keep or tempfile.mkdtemp()
    os.makedirs(work, exist_ok=True)
    roots = {"erd": erd_dirs(), "rtb": rtb_dirs(work)}
    failures, solved, total = [], 0, 0
    for name, source, urdf, srdf, tip, joints in ROBOTS:
        if name not in args.robots.split(","):
            continue
        root, package_dir = roots[source]
        path, srdf = os.path.join(root, urdf), srdf and os.path.join(root, srdf)
        rng = np.random.default_rng(args.seed)
        model, geom0 = load(path, package_dir, srdf, joints)
        data = model.createData()
        for k in range(args.per_robot):
            obstacles = scene(rng)
            geom = with_kinema_pairs(model, geom0.clone(), obstacles)
            gdata = pin.GeometryData(geom)
            found = problem(model, data, geom, gdata, rng)
            if found is None:
                print(f"  {name}-{k}: no problem found (free start and goal with a blocked segment)")
                continue
            total += 1
            scene_path = os.path.join(work, f"{name}-{k}.toml")
            with open(scene_path, "w") as f:
                f.write(scene_toml(obstacles))
            run = plan_with_kinema(args.kinema, path, srdf, package_dir, tip, scene_path, found[0], found[1], k, bool(args.keep))
            if run is None:
                failures.append(f"{name}-{k}: kinema plan did not return within 120 s (time limit 1 s)")
                print(f"  {name}-{k}: kinema plan did not return within 120 s", flush=True)
                continue
            if run.returncode != 0:
                print(f"  {name}-{k}: kinema plan exit {run.returncode}: {run.stderr.strip()}", flush=True)
                if "no collision-free path" not in run.stderr:
                    failures.append(f"{name}-{k}: kinema plan failed: {run.stderr.strip()}")
                continue
            answer = json.loads(run.stdout)
            via = [np.asarray(v, float) for v in answer["plan"]["via_points"]]
            bad = sum(colliding_at(model, data, geom, gdata, q) for q in dense(via))
            solved += 1
            ms = answer["plan"]["planning_time"] * 1e3
            counts = {c: answer["plan"][c] for c in ("iterations", "segments_checked", "sphere_checks", "exact_checks") if c in answer["plan"]}
            print(f"  {name}-{k}: {ms:.1f} ms, {len(via)} via points, coal: {bad} colliding, {counts}", flush=True)
            if bad:
                failures.append(f"{name}-{k}: coal finds {bad} samples of kinema's path colliding")
    for f in failures:
        print("FAIL", f)
    print(f"plan on URDFs: {solved} of {total} solved, {len(failures)} failures")
    if not args.keep:
        shutil.rmtree(work)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
