"""IK-Geo's description of a 6R kinema robot (H: unit joint axes, P: offsets between points on
them, at q = 0), read from kinema's own FK and Jacobian. Shared by ik_peers.py and
ik_geo_compare.py."""

import numpy as np


def axes_at_zero(robot):
    """Per joint: unit axis h and a point on it, in the base frame at q = 0, from kinema's jacob0
    (column [v; w] of a revolute joint: v = w x (p_tool - point), so p_tool + w x v is on the axis)."""
    n = robot.n
    T0 = robot.fkine(np.zeros(n))
    J = robot.jacob0(np.zeros(n))
    p = T0[:3, 3]
    hs, pts = [], []
    for i in range(n):
        w, v = J[3:, i], J[:3, i]
        hs.append(w / np.linalg.norm(w))
        pts.append(p + np.cross(hs[-1], v))
    return T0, hs, pts


def line_intersection(a, h, b, k, eps=1e-9):
    """The point where lines (a, h) and (b, k) meet, or None (parallel or skew)."""
    c = np.cross(h, k)
    s = float(np.dot(c, c))
    if s < 1e-18:
        return None
    d = b - a
    t = float(np.dot(np.cross(d, k), c)) / s
    u = float(np.dot(np.cross(d, h), c)) / s
    x, y = a + t * h, b + u * k
    return x if np.linalg.norm(x - y) < eps else None


def geo_hp(robot):
    """IK-Geo's kinematics (H 6x3, P 7x3) of a 6R kinema robot and the tool rotation at q = 0.
    The point chosen on each axis is its intersection with the next axis, else with the previous
    one, else the foot of the perpendicular from the previous point: the zero offsets IK-Geo's
    families (intersecting, spherical wrist) assume come out exactly zero."""
    if robot.n != 6 or robot.joint_types != "RRRRRR":
        raise ValueError("IK-Geo takes 6R arms")
    T0, hs, pts = axes_at_zero(robot)
    o = []
    for i in range(6):
        x = line_intersection(pts[i], hs[i], pts[i + 1], hs[i + 1]) if i < 5 else None
        if x is None and i > 0:
            x = line_intersection(pts[i], hs[i], pts[i - 1], hs[i - 1])
        if x is None:
            prev = o[-1] if o else np.zeros(3)
            x = pts[i] + np.dot(prev - pts[i], hs[i]) * hs[i]
        o.append(x)
    P = [o[0]] + [o[i] - o[i - 1] for i in range(1, 6)] + [T0[:3, 3] - o[5]]
    P = np.array([[0.0 if abs(c) < 1e-12 else c for c in row] for row in P])
    return np.array(hs), P, T0[:3, :3].copy()
