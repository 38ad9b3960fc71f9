"""The browser viewer from Python: the iiwa at a configuration, then a motion played.

`robot.show` starts `kinema serve` (found as $KINEMA_BIN or on PATH) and opens the page
once; `robot.animate` plays a trajectory on the same page. In Jupyter, the returned
viewer displays inline. The server stops when Python exits.
"""

import sys

import numpy as np

import kinema

robot = kinema.Robot.builtin("lbr-iiwa-14-r820")
q1 = np.array([0.4, 0.6, -0.3, -1.2, 0.2, 0.9, 0.0])

viewer = robot.show(robot.home)
print("viewer at", viewer.url)
motion = robot.ptp(robot.home, q1, 0.01)
same = robot.animate(motion)
shown = viewer.shown()
print(f"request {shown['version']}: {len(shown['t'])} samples over {shown['t'][-1]:.2f} s")
print("on the same server:", same is viewer)

if sys.stdin.isatty():
    input("Enter stops the viewer: ")
