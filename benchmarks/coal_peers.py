"""Writes Pinocchio + coal's self-collision verdicts and distances at seeded random configurations
of example-robot-data's Panda and UR5 (collision meshes, pairs after their SRDFs) to a CSV that the
ignored Rust test `coal::matches_coal` (crates/kinema-geometry/tests/all/coal.rs) compares with
kinema-geometry's; with --timing, also times coal on the Panda.

    python benchmarks/coal_peers.py OUT.csv [--n N] [--seed S] [--timing M]

Joints off kinema's chain (the Panda's fingers) are locked at 0, as kinema carries them. The CSV has,
per robot, a header line `#robot,NAME,URDF,SRDF,PACKAGE_DIR,TIP,A|B,…` naming the checked pairs
(Pinocchio's geometry names, `LINK_i` as kinema names them), then one line per configuration:
`NAME,q…,collision,distance,…` with coal's verdict (0/1) and distance [m] per pair, in header order.
--timing M: per configuration over the first M configurations of the Panda (the ones kinema's bench
`collision` reads from the same CSV), computeCollisions (forward
kinematics, placements, all pairs, stopping at the first collision, as kinema's `collides` does) and
computeDistances (all pairs), printed as `coal TASK: X us per configuration`.
"""

import argparse
import os
import sys
import time

import numpy as np
import pinocchio as pin

ROBOTS = [
    # name, URDF and SRDF (under example-robot-data's robots/), kinema's tip link, joints kept.
    (
        "panda",
        "panda_description/urdf/panda.urdf",
        "panda_description/srdf/panda.srdf",
        "panda_hand",
        [f"panda_joint{i}" for i in range(1, 8)],
    ),
    ("ur5", "ur_description/urdf/ur5_robot.urdf", "ur_description/srdf/ur5.srdf", "tool0", None),
]


def load(robots, urdf, srdf, joints):
    """Pinocchio's model and collision geometry of a URDF, joints not in `joints` locked at 0,
    every pair of bodies checked but those the SRDF disables."""
    share = os.path.dirname(os.path.dirname(robots))  # holds example-robot-data/robots
    path = os.path.join(robots, urdf)
    full = pin.buildModelFromUrdf(path)
    geom = pin.buildGeomFromUrdf(full, path, pin.GeometryType.COLLISION, package_dirs=[share])
    keep = joints or list(full.names[1:])
    lock = [full.getJointId(n) for n in full.names[1:] if n not in keep]
    model, geom = (full, geom) if not lock else pin.buildReducedModel(full, geom, lock, pin.neutral(full))
    geom.addAllCollisionPairs()
    pin.removeCollisionPairs(model, geom, os.path.join(robots, srdf))
    return model, geom, path, share


def configurations(model, rng, n):
    lo, hi = model.lowerPositionLimit, model.upperPositionLimit
    return [lo + (hi - lo) * rng.random(model.nq) for _ in range(n)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out")
    ap.add_argument("--n", type=int, default=10000, help="configurations per robot")
    ap.add_argument("--seed", type=int, default=37)
    ap.add_argument("--timing", type=int, default=0, help="configurations timed on the Panda (0: none)")
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    robots = next(
        os.path.join(d, "cmeel.prefix", "share", "example-robot-data", "robots")
        for d in sys.path
        if os.path.isdir(os.path.join(d, "cmeel.prefix", "share", "example-robot-data", "robots"))
    )
    with open(args.out, "w") as out:
        for name, urdf, srdf, tip, joints in ROBOTS:
            model, geom, path, share = load(robots, urdf, srdf, joints)
            data, gdata = model.createData(), pin.GeometryData(geom)
            names = [
                f"{geom.geometryObjects[p.first].name}|{geom.geometryObjects[p.second].name}"
                for p in geom.collisionPairs
            ]
            out.write(f"#robot,{name},{path},{os.path.join(robots, srdf)},{share},{tip}," + ",".join(names) + "\n")
            hits = 0
            qs = configurations(model, rng, args.n)
            for q in qs:
                pin.computeCollisions(model, data, geom, gdata, q, False)
                pin.computeDistances(model, data, geom, gdata, q)
                cells = []
                for k in range(len(geom.collisionPairs)):
                    hit = gdata.collisionResults[k].isCollision()
                    hits += hit
                    cells.append(f"{int(hit)},{gdata.distanceResults[k].min_distance!r}")
                out.write(name + "," + ",".join(repr(float(v)) for v in q) + "," + ",".join(cells) + "\n")
            print(f"{name}: {len(geom.geometryObjects)} shapes, {len(names)} pairs after the SRDF, {args.n} configurations, {hits} pair collisions")
            if name == "panda" and args.timing:
                timing(model, geom, qs[: args.timing])
    return 0


def timing(model, geom, qs):
    data, gdata = model.createData(), pin.GeometryData(geom)
    for label, call in [
        ("computeCollisions", lambda q: pin.computeCollisions(model, data, geom, gdata, q, True)),
        ("computeDistances", lambda q: pin.computeDistances(model, data, geom, gdata, q)),
    ]:
        best = float("inf")
        for _ in range(3):  # the best of three passes, as Criterion's estimate discounts noise
            t0 = time.perf_counter()
            for q in qs:
                call(q)
            best = min(best, (time.perf_counter() - t0) / len(qs))
        print(f"coal {label}: {best * 1e6:.2f} us per configuration (panda, {len(qs)} configurations)")


if __name__ == "__main__":
    sys.exit(main())
