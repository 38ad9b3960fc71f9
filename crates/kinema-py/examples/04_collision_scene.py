"""Collision checks of a robot in a scene: the iiwa under the fume hood."""

from pathlib import Path

import numpy as np

import kinema

repo = Path(__file__).resolve().parents[3]
scene = kinema.Scene.from_file(repo / "examples/scenes/fume-hood.toml")
robot = kinema.Robot.builtin("lbr-iiwa-14-r820")
print(scene)

rng = np.random.default_rng(3)
lo, hi = robot.qlim
Q = rng.uniform(lo, hi, (2000, robot.n))
hits = robot.collides_batch(Q, scene=scene)
print(f"{hits.sum()} of {len(Q)} random configurations collide")
print("clearance at home [m]:", robot.distance(robot.home, scene=scene))
