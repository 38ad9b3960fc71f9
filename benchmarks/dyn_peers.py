"""Writes Pinocchio's dynamics at seeded random states to a CSV that the ignored Rust test
`dynamics_matches_pinocchio` (crates/kinema/tests/all/dynamics.rs) reads and compares with kinema's.

    python benchmarks/dyn_peers.py OUT.csv [--n N] [--seed S]

Robots: the built-in TOML robots that carry mass properties (PUMA 560, Panda, UR5, iiwa 14), built
in Pinocchio joint by joint from the same file; the Panda and UR5 built-ins again against Pinocchio's model
of the example-robot-data URDF their inertials were taken from (spec `builtin:NAME@FILE`), after checking
that the URDF moves the same links at the same q; and URDFs from example-robot-data (UR3, UR5, UR10,
Panda, Unitree Z1, UFactory xArm 7, SO-100, SO-101), loaded by Pinocchio's own URDF parser, with joints off kinema's chain (the Panda's
fingers) locked at 0. Each CSV row: `spec,n,q…,qd…,qdd…,tau…,M… (row-major),tau2…,qdd2…,C… (row-major)` where
tau = rnea(q, qd, qdd), M = crba(q), qdd2 = aba(q, qd, tau2), C = computeCoriolisMatrix(q, qd), gravity [0, 0, -9.81] m/s².
`spec` is `builtin:NAME`, `builtin:NAME@FILE` or `urdf:PATH:TIP`.
"""

import argparse
import math
import os
import sys
import tomllib
import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def dh_model(path, massless=False):
    """A Pinocchio model of a DH TOML robot (standard or modified, revolute, no base transform; the
    tool carries no mass) with its `[joint.inertial]` tables, or with no mass if `massless`.
    Returns the model and, per joint, the placement of kinema's link frame in Pinocchio's joint frame."""
    with open(path, "rb") as f:
        desc = tomllib.load(f)
    conv = desc["convention"]
    assert conv in ("standard", "modified"), f"{path}: only DH is built here"
    length = {"m": 1.0, "mm": 1e-3}[desc["units"]["length"]]
    angle = {"rad": 1.0, "deg": math.pi / 180}[desc["units"]["angle"]]
    assert desc.get("base") is None, "no base transform in the built-in DH robots compared here"
    model = pin.Model()
    model.name = desc["name"]
    parent, placement, posts = 0, pin.SE3.Identity(), []
    for j in desc["joint"]:
        assert j.get("type", "revolute") == "revolute" and j.get("offset", 0) == 0
        d, a, alpha = j.get("d", 0) * length, j["a"] * length, j["alpha"] * angle
        tz, tx = pin.SE3(np.eye(3), np.array([0, 0, d])), pin.SE3(np.eye(3), np.array([a, 0, 0]))
        rx = pin.SE3(pin.utils.rotate("x", alpha), np.zeros(3))
        if conv == "standard":
            # Link frame i = joint frame · Tz(d)·Tx(a)·Rx(alpha) (after the turn about z_{i-1}).
            jplace, post = placement, tz * tx * rx
        else:
            # Modified (Craig): link frame i = frame i-1 · Rx(alpha)·Tx(a)·Rz(theta)·Tz(d).
            jplace, post = placement * rx * tx, tz
        jid = model.addJoint(parent, pin.JointModelRZ(), jplace, j["name"])
        if massless:
            body = pin.Inertia.Zero()
        else:
            b = j["inertial"]
            ixx, iyy, izz, ixy, ixz, iyz = (v * length**2 for v in b["inertia"])
            inertia = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
            body = pin.Inertia(b["mass"], np.array(b["com"]) * length, inertia)
        model.appendBodyToJoint(jid, body, post)
        parent, placement = jid, post
        posts.append(post)
    return model, posts


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
        c = pin.computeCoriolisMatrix(model, data, q, qd).copy()
        yield np.concatenate([q, qd, qdd, tau, m.ravel(), tau2, qdd2, c.ravel()])


def without_links(path, drop, out_dir):
    """A copy of the URDF at `path` without the links named in `drop` and the joints to them."""
    tree = ET.parse(path)
    root = tree.getroot()
    for e in list(root):
        if (e.tag == "link" and e.get("name") in drop) or (e.tag == "joint" and e.find("child").get("link") in drop):
            root.remove(e)
    out = os.path.join(out_dir, os.path.basename(path).replace(".urdf", "-arm.urdf"))
    tree.write(out)
    return out


def same_kinematics(dh, posts, urdf):
    """Checks that the URDF moves the same links as the DH model at the same joint values: each DH
    link frame is fixed in its URDF link (seeded random q), up to a turn of the URDF root about the
    vertical, which changes neither gravity torques nor M(q). Returns that turn in quarter turns."""
    dd, ud = dh.createData(), urdf.createData()
    qs = [np.zeros(dh.nq)] + [np.random.default_rng(k).uniform(-2, 2, dh.nq) for k in range(5)]
    for quarter in range(4):
        turn = pin.SE3(pin.utils.rotate("z", quarter * math.pi / 2), np.zeros(3))
        first, worst = None, 0.0
        for q in qs:
            pin.forwardKinematics(dh, dd, q)
            pin.forwardKinematics(urdf, ud, q)
            rel = [(dd.oMi[i + 1] * posts[i]).inverse() * turn * ud.oMi[i + 1] for i in range(dh.nq)]
            first = first or rel
            worst = max(worst, max(np.abs((a.inverse() * b).homogeneous - np.eye(4)).max() for a, b in zip(first, rel)))
        if worst < 1e-9:
            return quarter
    raise AssertionError(f"{dh.name}: the URDF's kinematics differ from the built-in's")


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
    # The built-ins with mass properties, each against Pinocchio built from its own file.
    models = []
    for name in ["puma560", "panda", "ur5", "lbr-iiwa-14-r820"]:
        models.append((f"builtin:{name}", dh_model(os.path.join(REPO, "robots", f"{name}.toml"))[0]))
    # The built-ins whose inertials come from an example-robot-data URDF, against Pinocchio's model of
    # that URDF at the same q (the Panda's without its hand, which the built-in leaves out).
    tmp = os.path.dirname(os.path.abspath(args.out))  # the arm-only URDF goes beside the CSV
    hand = {"panda_hand", "panda_hand_tcp", "panda_leftfinger", "panda_rightfinger"}
    for name, rel, drop in [
        ("panda", "panda_description/urdf/panda.urdf", hand),
        ("ur5", "ur_description/urdf/ur5_robot.urdf", set()),
    ]:
        path = without_links(os.path.join(robots, rel), drop, tmp)
        urdf = pin.buildModelFromUrdf(path)
        dh, posts = dh_model(os.path.join(REPO, "robots", f"{name}.toml"), massless=True)
        quarter = same_kinematics(dh, posts, urdf)
        print(f"builtin:{name} vs {rel}: same kinematics, URDF root turned {90 * quarter} deg about z")
        models.append((f"builtin:{name}@{os.path.basename(rel)}", urdf))
    for rel, tip, joints in [
        ("ur_description/urdf/ur5_robot.urdf", "tool0", None),
        ("ur_description/urdf/ur3_robot.urdf", "tool0", None),
        ("ur_description/urdf/ur10_robot.urdf", "tool0", None),
        ("panda_description/urdf/panda.urdf", "panda_link8", [f"panda_joint{i}" for i in range(1, 8)]),
        ("z1_description/urdf/z1.urdf", None, None),
        ("xarm_description/urdf/xarm7.urdf", None, None),
        ("so_arm_description/urdf/so100.urdf", None, None),
        ("so_arm_description/urdf/so101.urdf", "moving_jaw_so101_v1_link", None),
    ]:
        path = os.path.join(robots, rel)
        full = pin.buildModelFromUrdf(path)
        chain = joints or list(full.names[1:])
        m = urdf_model(path, chain)
        assert m.nq == m.nv, f"{rel}: a joint with nq != nv (continuous?)"
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
