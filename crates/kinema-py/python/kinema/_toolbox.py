"""The toolbox's trajectory functions under their names: ``ctraj`` and
``jtraj``. The time scaling is kinema's time law (the same thirds the
toolbox's ``trapezoidal`` uses; the quintic of ``jtraj``); the poses are
interpolated by the Rust core."""

from __future__ import annotations

import numpy as np

from ._errors import InvalidInput
from ._kinema import _interpolate_poses, _to_se3, time_law


class JointPath(tuple):
    """What :func:`jtraj` returns: a tuple ``(q, qd, qdd)`` (each (N, n)) as
    the toolbox's unpacks, with the sample times as ``t`` and the arrays as
    ``q``, ``qd``, ``qdd``."""

    def __new__(cls, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, t: np.ndarray):
        path = super().__new__(cls, (q, qd, qdd))
        path.t = t
        return path

    q = property(lambda self: self[0], doc="positions (N, n) [rad or m]")
    qd = property(lambda self: self[1], doc="velocities (N, n) [per second of t]")
    qdd = property(lambda self: self[2], doc="accelerations (N, n) [per second² of t]")


def _times(t, what: str) -> np.ndarray:
    if isinstance(t, (int, np.integer)) and not isinstance(t, bool):
        if t < 2:
            raise InvalidInput(f"`{what}`: {t} points; a trajectory needs at least 2")
        return np.arange(int(t), dtype=float)
    tv = np.asarray(t, dtype=float)
    if tv.ndim != 1 or tv.size < 2 or not np.all(np.isfinite(tv)) or tv[0] != 0 or np.any(np.diff(tv) <= 0):
        raise InvalidInput(f"`{what}` must be a number of points or increasing times from 0")
    return tv


def _one_pose(T, what: str) -> np.ndarray:
    """A single pose: a 4×4 array or an SE3 of one pose (a sequence is refused, not cut to its first)."""
    if hasattr(T, "A") and hasattr(T, "t"):
        if len(T) != 1:
            raise InvalidInput(f"`{what}` holds {len(T)} poses; ctraj goes from one pose to one pose")
        T = T.A
    a = np.asarray(T, dtype=float)
    if a.shape != (4, 4):
        raise InvalidInput(f"`{what}` must be one 4x4 homogeneous transform, got shape {a.shape}")
    return a


def ctraj(T0, T1, t, *, as_se3: bool = False):
    """Cartesian trajectory from pose ``T0`` to ``T1`` (toolbox ``ctraj``).

    ``t``: a number of points N, spaced in time along a trapezoidal speed
    profile (accelerate, cruise and brake each a third of the time, as the
    toolbox's ``trapezoidal``); or an array of fractions of the path in
    [0, 1], as the toolbox's ``s``. Positions move on the straight line,
    rotations by slerp. Returns an (N, 4, 4) array, or with ``as_se3=True``
    a spatialmath ``SE3`` of N poses. ``T0``, ``T1``: 4×4 arrays or ``SE3``.
    """
    A0, A1 = _one_pose(T0, "T0"), _one_pose(T1, "T1")
    if isinstance(t, (int, np.integer)) and not isinstance(t, bool):
        tv = _times(t, "t")
        s = time_law("trapezoid", duration=tv[-1]).sample(tv)[0]
    else:
        s = np.asarray(t, dtype=float)
    poses = _interpolate_poses(A0, A1, s)
    return _to_se3(poses) if as_se3 else poses


def jtraj(q0, q1, t) -> JointPath:
    """Joint-space trajectory from ``q0`` to ``q1`` on a quintic polynomial
    with zero velocity and acceleration at both ends (toolbox ``jtraj``).

    ``t``: a number of points N (time runs from 0 to 1), or increasing times
    from 0 [s]. Returns a :class:`JointPath` that unpacks as ``q, qd, qdd`` as the
    toolbox's does (``.t`` the times): (N, n) arrays of positions, velocities and
    accelerations (per second of ``t``).
    """
    tv = _times(t, "t")
    if isinstance(t, (int, np.integer)):
        tv = tv / tv[-1]
    a, b = np.asarray(q0, dtype=float), np.asarray(q1, dtype=float)
    if a.ndim != 1 or a.shape != b.shape:
        raise InvalidInput(f"`q0` and `q1` must be 1-D of one length, got shapes {a.shape} and {b.shape}")
    s, sd, sdd, _ = time_law("quintic", duration=tv[-1]).sample(tv)
    delta = b - a
    return JointPath(a + np.outer(s, delta), np.outer(sd, delta), np.outer(sdd, delta), tv)
