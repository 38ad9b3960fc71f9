"""Plots with matplotlib, an optional dependency imported at the first plot:
the robot as a stick figure with its link frames (``Robot.plot``), and the
joint and Cartesian curves ``kinema plot`` draws (``plot_joints``,
``plot_cartesian``). Every number comes from the Rust core (``fkine_all``,
``fkine_batch``, ``jacob0_batch``); this module only draws. Each returns the
matplotlib ``Figure`` and, given ``file``, saves it there too."""

from __future__ import annotations

import numpy as np

from ._errors import InvalidInput

#: How many configurations of a trajectory ``Robot.plot`` draws as stick figures.
FIGURES_PER_TRAJECTORY = 5


def _pyplot():
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError("kinema's plots need matplotlib: pip install matplotlib") from e
    return plt


def _finish(fig, file):
    if file is not None:
        fig.savefig(file)
    return fig


def _configurations(robot, q) -> np.ndarray:
    """``q`` as an (N, n) array: one configuration, a pose name, an (N, n) array or anything with ``.q``."""
    if isinstance(q, str):
        q = robot.pose(q)
    q = np.asarray(getattr(q, "q", q), dtype=float)
    if q.ndim == 1:
        q = q[None, :]
    if q.ndim != 2 or q.shape[1] != robot.n or q.shape[0] == 0:
        raise InvalidInput(f"`q` must be ({robot.n},) or (N, {robot.n}) joint values or a trajectory, got shape {q.shape}")
    return q


def _equal_axes(ax, points: np.ndarray):
    centre = (points.max(axis=0) + points.min(axis=0)) / 2
    half = max(float(np.ptp(points, axis=0).max()) / 2, 1e-3) * 1.1
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(max(0.0, centre[2] - half) if points[:, 2].min() >= 0 else centre[2] - half, centre[2] + half)


def plot_robot(robot, q, *, frames: bool = True, file=None, ax=None):
    """The robot at ``q`` as a stick figure (base, link origins, tool) in 3D,
    with each link frame's x, y, z axes in red, green, blue. ``q``: one
    configuration, a pose name, an (N, n) array or a trajectory; for many, up
    to ``FIGURES_PER_TRAJECTORY`` figures evenly spread (the last drawn
    darkest) and the tool's path. ``ax``: a 3D Axes to draw into."""
    plt = _pyplot()
    qs = _configurations(robot, q)
    if ax is None:
        fig = plt.figure()
        ax = fig.add_subplot(projection="3d")
    else:
        fig = ax.figure
    picks = np.unique(np.linspace(0, len(qs) - 1, min(len(qs), FIGURES_PER_TRAJECTORY)).round().astype(int))
    chains = [robot.fkine_all(qs[k]) for k in picks]
    points = np.concatenate([c[:, :3, 3] for c in chains])
    scale = max(float(np.ptp(points, axis=0).max()) * 0.08, 1e-3)
    for rank, chain in enumerate(chains):
        shade = 0.25 + 0.75 * (rank + 1) / len(chains)
        origins = chain[:, :3, 3]
        ax.plot(*origins.T, "-o", color=(0.1, 0.2, 0.6, shade), markersize=3, linewidth=2)
        if frames and rank == len(chains) - 1:
            for T in chain:
                for axis, colour in zip(range(3), ("r", "g", "b")):
                    tip = T[:3, 3] + scale * T[:3, axis]
                    ax.plot(*np.stack([T[:3, 3], tip]).T, color=colour, linewidth=1)
    if len(qs) > 1:
        path = robot.fkine_batch(qs)[:, :3, 3]
        ax.plot(*path.T, ":", color="0.4", linewidth=1)
        points = np.concatenate([points, path])
    _equal_axes(ax, points)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_title(robot.name)
    return _finish(fig, file)


def _curves(robot, trajectory):
    t = np.asarray(getattr(trajectory, "t", None) if hasattr(trajectory, "t") else [], dtype=float)
    if not hasattr(trajectory, "q") or t.ndim != 1 or len(t) < 2:
        raise InvalidInput("a curve plot needs a trajectory with `t` and `q` of at least two samples (JointTrajectory, Plan)")
    q = _configurations(robot, trajectory)
    if len(q) != len(t):
        raise InvalidInput(f"the trajectory has {len(t)} times and {len(q)} configurations")
    return t, q


def plot_joints(robot, trajectory, *, file=None):
    """Joint positions, velocities and accelerations of ``trajectory`` against
    time (three panels, one curve per joint, SI units), each joint's position
    limits dashed in its colour, as ``kinema plot joints`` draws them."""
    plt = _pyplot()
    t, q = _curves(robot, trajectory)
    series = [q, np.asarray(trajectory.qd, dtype=float), np.asarray(trajectory.qdd, dtype=float)]
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 8))
    qlim = robot.qlim
    for panel, (ax, values, label) in enumerate(zip(axes, series, ("position", "velocity", "acceleration"))):
        for j, name in enumerate(robot.joint_names):
            (line,) = ax.plot(t, values[:, j], label=name)
            if panel == 0:
                for bound in qlim[:, j]:
                    if np.isfinite(bound):
                        ax.axhline(bound, color=line.get_color(), linestyle="--", linewidth=0.8)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[0].legend(loc="upper right", fontsize="small")
    axes[-1].set_xlabel("t [s]")
    fig.suptitle(f"{robot.name}: joint curves (rad or m, per s, per s²)")
    return _finish(fig, file)


def plot_cartesian(robot, trajectory, *, file=None):
    """The tool's position and linear velocity (x, y, z and the norm) along
    ``trajectory`` against time, as ``kinema plot cartesian`` draws them:
    positions by forward kinematics, velocity as J·q̇."""
    plt = _pyplot()
    t, q = _curves(robot, trajectory)
    position = robot.fkine_batch(q)[:, :3, 3]
    velocity = np.einsum("kij,kj->ki", robot.jacob0_batch(q)[:, :3, :], np.asarray(trajectory.qd, dtype=float))
    fig, axes = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
    for ax, values, label in zip(axes, (position, velocity), ("position [m]", "velocity [m/s]")):
        for k, name in enumerate("xyz"):
            ax.plot(t, values[:, k], label=name)
        ax.plot(t, np.linalg.norm(values, axis=1), "k--", label="norm")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[0].legend(loc="upper right", fontsize="small")
    axes[-1].set_xlabel("t [s]")
    fig.suptitle(f"{robot.name}: tool position and velocity")
    return _finish(fig, file)
