"""Pinocchio + coal's copy of kinema's collision model for a built-in robot and a scene file, for
benchmarks/plan_peers.py.

kinema's built-in Panda and iiwa carry primitive link shapes (`[[shape]]` in robots/*.toml: capsules
and spheres on the DH link frames); scenes are boxes and cylinders on the world frame. This builds the
same chain as a Pinocchio model (one revolute-z joint per DH row, read from the same robot file), the
same shapes as coal primitives in a GeometryModel, and the same pairs as kinema's check: shapes on
links more than one apart, and every shape on a moving link against every obstacle. Also the dense
sampling of a path that benchmarks/plan_peers_urdf.py shares.
"""

import math
import tomllib

import coal
import numpy as np
import pinocchio as pin

LENGTH_UNITS = {"m": 1.0, "mm": 1e-3}
ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0}


def rpy_pose(xyz, rpy):
    """R = Rz(yaw)·Ry(pitch)·Rx(roll), kinema's roll-pitch-yaw."""
    return pin.SE3(pin.rpy.rpyToMatrix(*rpy), np.array(xyz, dtype=float))


def rot_x(a):
    return pin.SE3(pin.utils.rotate("x", a), np.zeros(3))


def rot_z(a):
    return pin.SE3(pin.utils.rotate("z", a), np.zeros(3))


def trans(x, y, z):
    return pin.SE3(np.eye(3), np.array([x, y, z], dtype=float))


def coal_shape(table, metres):
    """A coal primitive of a `[[shape]]`/`[[obstacle]]` table (full box sizes and lengths, as kinema)."""
    if "box" in table:
        return coal.Box(*[metres * v for v in table["box"]])
    if "sphere" in table:
        return coal.Sphere(metres * table["sphere"]["radius"])
    for kind, make in (("capsule", coal.Capsule), ("cylinder", coal.Cylinder)):
        if kind in table:
            return make(metres * table[kind]["radius"], metres * table[kind]["length"])
    raise ValueError(f"shape {table.get('name')}: no primitive this script knows")


def placement_of(table, metres, radians):
    p = table.get("pose", [0, 0, 0, 0, 0, 0])
    return rpy_pose([metres * v for v in p[:3]], [radians * v for v in p[3:]])


def dense(path, step=1e-3):
    """The path's straight segments sampled at most `step` apart in every joint, ends included."""
    out = [path[0]]
    for a, b in zip(path[:-1], path[1:]):
        n = max(1, int(np.ceil(np.max(np.abs(b - a)) / step)))
        out.extend(a + (b - a) * (i / n) for i in range(1, n + 1))
    return out


class Chain:
    """A DH robot file as a Pinocchio model, its link frames and its link shapes."""

    def __init__(self, path):
        with open(path, "rb") as f:
            doc = tomllib.load(f)
        units = doc.get("units", {})
        self.metres = LENGTH_UNITS[units.get("length", "m")]
        self.radians = ANGLE_UNITS[units.get("angle", "rad")]
        modified = doc["convention"] == "modified"
        self.model = pin.Model()
        parent, before = 0, pin.SE3.Identity()
        # fixed[i]: link i's frame relative to joint i's frame (after the joint's rotation).
        self.fixed = [pin.SE3.Identity()]
        for j in doc["joint"]:
            a, d = self.metres * j["a"], self.metres * j["d"]
            alpha = self.radians * j["alpha"]
            if modified:
                # T = RotX(alpha)·TransX(a)·RotZ(q)·TransZ(d); TransZ commutes with RotZ.
                placement, after = before * rot_x(alpha) * trans(a, 0, 0) * trans(0, 0, d), pin.SE3.Identity()
            else:
                # T = RotZ(q)·TransZ(d)·TransX(a)·RotX(alpha).
                placement, after = before, trans(0, 0, d) * trans(a, 0, 0) * rot_x(alpha)
            parent = self.model.addJoint(
                parent,
                pin.JointModelRZ(),
                placement,
                j["name"],
                np.array([1e3]),
                np.array([1e3]),
                np.array([self.radians * j["min"]]),
                np.array([self.radians * j["max"]]),
            )
            self.fixed.append(after)
            before = after
        tool = doc.get("tool", {})
        # link n's frame to the tool frame
        self.tool = rpy_pose(
            [self.metres * v for v in tool.get("xyz", [0, 0, 0])], [self.radians * v for v in tool.get("rpy", [0, 0, 0])]
        )
        self.shapes = doc.get("shape", [])
        self.data = self.model.createData()

    def link_frames(self, q):
        """world_from_link for links 0..n (the base frame is the world frame: no [base] in these files)."""
        pin.forwardKinematics(self.model, self.data, np.asarray(q, dtype=float))
        return [pin.SE3.Identity()] + [self.data.oMi[i] * self.fixed[i] for i in range(1, self.model.njoints)]


class CoalCheck:
    """A chain's shapes and a scene's obstacles in a GeometryModel, with kinema's pair set."""

    def __init__(self, chain, scene_path):
        with open(scene_path, "rb") as f:
            scene = tomllib.load(f)
        self.chain = chain
        self.geom = pin.GeometryModel()
        links = []
        for s in chain.shapes:
            link = s["link"]
            at = chain.fixed[link] * placement_of(s, chain.metres, chain.radians)
            obj = pin.GeometryObject(s["name"], link, link, at, coal_shape(s, chain.metres))
            self.geom.addGeometryObject(obj)
            links.append(link)
        robot_count = len(links)
        for o in scene.get("obstacle", []):
            obj = pin.GeometryObject("obstacle:" + o["name"], 0, 0, placement_of(o, 1.0, 1.0), coal_shape(o, 1.0))
            self.geom.addGeometryObject(obj)
        for a in range(robot_count):
            for b in range(a + 1, robot_count):
                if abs(links[a] - links[b]) > 1:
                    self.geom.addCollisionPair(pin.CollisionPair(a, b))
            if links[a] > 0:
                for o in range(robot_count, self.geom.ngeoms):
                    self.geom.addCollisionPair(pin.CollisionPair(a, o))
        self.gdata = pin.GeometryData(self.geom)
        for req in self.gdata.collisionRequests:
            req.security_margin = 0.0

    def place(self, q):
        pin.updateGeometryPlacements(self.chain.model, self.chain.data, self.geom, self.gdata, np.asarray(q, float))

    def collides(self, q):
        self.place(q)
        return pin.computeCollisions(self.geom, self.gdata, True)

    def min_distance(self, q):
        """The smallest distance [m] over the pairs (negative: overlap) and the pair's names."""
        self.place(q)
        k = pin.computeDistances(self.geom, self.gdata)
        pair = self.geom.collisionPairs[k]
        names = (self.geom.geometryObjects[pair.first].name, self.geom.geometryObjects[pair.second].name)
        return self.gdata.distanceResults[k].min_distance, names
