"""A Cartesian line with the toolbox's ctraj, joints by IK along it, a
quintic jtraj, and the plots (written next to this script's output dir)."""

import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402

import kinema  # noqa: E402

out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
robot = kinema.Robot.builtin("puma560")
q_start = np.array([0.0, -0.4, 0.3, 0.0, 0.6, 0.0])
T0 = robot.fkine(q_start)
T1 = T0.copy()
T1[:3, 3] += [0.0, 0.3, -0.1]

Ts = kinema.ctraj(T0, T1, 40)  # (40, 4, 4), trapezoidal spacing
Q, success, _ = robot.ik_batch(Ts, q0=robot.home)
print("IK along the line: all found:", success.all())

q, qd, qdd = kinema.jtraj(robot.home, Q[-1], 50)
print("jtraj end velocity:", np.abs(qd[-1]).max())

tr = robot.lin(q_start, T1, 0.02, vmax=0.2, amax=1.0)
robot.plot(tr, file=out / "puma-lin.png")
robot.plot_joints(tr, file=out / "puma-lin-joints.png")
robot.plot_cartesian(tr, file=out / "puma-lin-cartesian.png")
print("plots in", out)
