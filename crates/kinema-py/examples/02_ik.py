"""Inverse kinematics: every analytic solution of a pose, and a numeric one."""

import numpy as np

import kinema

robot = kinema.Robot.builtin("puma560")
q = np.array([0.2, -0.6, 0.4, 0.3, 0.7, -0.2])
T = robot.fkine(q)

sol = robot.ik(T, q0=robot.home)
print(sol)
print("tool error [m]:", np.linalg.norm(robot.fkine(sol.q)[:3, 3] - T[:3, 3]))

for branch in robot.ik(T, all=True):
    print(branch.branch, np.round(branch.q, 3))
