"""Writes Pinocchio's dynamics at seeded random states to a CSV that the ignored Rust test
`dynamics_matches_pinocchio` (crates/kinema/tests/dynamics.rs) reads and compares with kinema's.

    python benchmarks/dyn_peers.py OUT.csv [--n N] [--seed S]

Robots: the built-in TOML robots that carry mass properties (standard DH: PUMA 560), built
in Pinocchio joint by joint from the same file; and URDFs from example-robot-data (UR3, UR5, UR10,
Panda, Unitree Z1), loaded by Pinocchio's own URDF parser, with joints off kinema's chain (the Panda's
fingers) locked at 0. Each CSV row: `spec,n,q…,qd…,qdd…,tau…,M… (row-major),tau2…,qdd2…` where
tau = rnea(q, qd, qdd), M = crba(q), qdd2 = aba(q, qd, tau2), gravity [0, 0, -9.81] m/s².
`spec` is `builtin:NAME` or `urdf:PATH:TIP`.
"""

import argparse
import math
import os
import sys
import tomllib

import numpy as np
import pinocchio as pin

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def dh_model(path):
    """A Pinocchio model of a standard-DH TOML robot with `[joint.inertial]` tables."""
    with open(path, "rb") as f:
        desc = tomllib.load(f)
    assert desc["convention"] == "standard", "only standard DH is built here"
    length = {"m": 1.0, "mm": 1e-3}[desc["units"]["length"]]
    angle = {"rad": 1.0, "deg": math.pi / 180}[desc["units"]["angle"]]
    model = pin.Model()
    model.name = desc["name"]
    parent, placement = 0, pin.SE3.Identity()
    for j in desc["joint"]:
        assert j.get("type", "revolute") == "revolute" and j.get("offset", 0) == 0
        jid = model.addJoint(parent, pin.JointModelRZ(), placement, j["name"])
        # Link frame i = joint frame · Tz(d)·Tx(a)·Rx(alpha) (standard DH after the turn).
        d, a, alpha = j.get("d", 0) * length, j["a"] * length, j["alpha"] * angle
        post = pin.SE3(np.eye(3), np.array([0, 0, d])) * pin.SE3(np.eye(3), np.array([a, 0, 0]))
        post = post * pin.SE3(pin.utils.rotate("x", alpha), np.zeros(3))
        b = j["inertial"]
        ixx, iyy, izz, ixy, ixz, iyz = (v * length**2 for v in b["inertia"])
        inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        body = pin.Inertia(b["mass"], np.array(b["com"]) * length, inertia)
        model.appendBodyToJoint(jid, body, post)
        parent, placement = jid, post
    base = desc.get("base")
    assert base is None, "no base transform in the built-in DH robots compared here"
    return model


def urdf_model(path, tip_joints):
    """Pinocchio's model of a URDF, joints not named in tip_joints locked at 0."""
    full = pin.buildModelFromUrdf(path)
    lock = [full.getJointId(n) for n in full.names[1:] if n not in tip_joints]
    return pin.buildReducedModel(full, lock, pin.neutral(full)) if lock else full


def cases(model, rng, n_cases):
    data = model.createData()
    # Within the limits and within [-pi, pi] (a model built in code has limits of +-max float).
    lo = np.maximum(model.lowerPositionLimit, -math.pi)
    hi = np.minimum(model.upperPositionLimit, math.pi)
    for _ in range(n_cases):
        q = rng.uniform(lo, hi)
        qd = rng.uniform(-2, 2, model.nv)
        qdd = rng.uniform(-3, 3, model.nv)
        tau = pin.rnea(model, data, q, qd, qdd).copy()
        m = pin.crba(model, data, q).copy()
        m = np.triu(m) + np.triu(m, 1).T
        tau2 = rng.uniform(-20, 20, model.nv)
        qdd2 = pin.aba(model, data, q, qd, tau2).copy()
        yield np.concatenate([q, qd, qdd, tau, m.ravel(), tau2, qdd2])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--seed", type=int, default=26)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    # The URDFs as installed by the example-robot-data wheel (a cmeel prefix).
    robots = next(
        os.path.join(d, "cmeel.prefix", "share", "example-robot-data", "robots")
        for d in sys.path
        if os.path.isdir(os.path.join(d, "cmeel.prefix", "share", "example-robot-data", "robots"))
    )
    models = [("builtin:puma560", dh_model(os.path.join(REPO, "robots", "puma560.toml")))]
    for rel, tip, joints in [
        ("ur_description/urdf/ur5_robot.urdf", "tool0", None),
        ("ur_description/urdf/ur3_robot.urdf", "tool0", None),
        ("ur_description/urdf/ur10_robot.urdf", "tool0", None),
        ("panda_description/urdf/panda.urdf", "panda_link8", [f"panda_joint{i}" for i in range(1, 8)]),
        ("z1_description/urdf/z1.urdf", None, None),
    ]:
        path = os.path.join(robots, rel)
        full = pin.buildModelFromUrdf(path)
        chain = joints or list(full.names[1:])
        m = urdf_model(path, chain)
        assert m.nq == m.nv, f"{name}: a joint with nq != nv (continuous?)"
        models.append((f"urdf:{path}:{tip or ''}", m))
    with open(args.out, "w") as out:
        for spec, model in models:
            k = 0
            for row in cases(model, rng, args.n):
                out.write(spec + f",{model.nv}," + ",".join(repr(float(v)) for v in row) + "\n")
                k += 1
            print(f"{spec}: {model.nv} joints, {k} states, total mass {sum(i.mass for i in model.inertias):.4f} kg")
    return 0


if __name__ == "__main__":
    sys.exit(main())
