"""kinema — kinematics of serial robot arms, from Python.

A thin binding of the Rust library ``kinema``: every number is computed by the
Rust core; this package converts arguments and returns numpy arrays.

Example::

    import numpy as np
    import kinema

    robot = kinema.Robot.builtin("puma560")
    T = robot.fkine(robot.home)               # 4x4 ndarray
    J = robot.jacob0(robot.home)              # 6xn, rows vx vy vz wx wy wz
    sol = robot.ik(T)                         # IkSolution; also ik(position=[x, y, z])
    Ts = robot.fkine_batch(np.zeros((1000, robot.n)))  # (1000, 4, 4), GIL released
    tr = robot.ptp(robot.home, q1, 0.01)      # JointTrajectory; also lin, circ, expr
    report = robot.check(tr)                  # CheckReport, as `kinema traj check`
    law = kinema.time_law("scurve", 0.5, vmax=1.0, amax=2.0, jmax=20.0)  # TimeLaw
    plan = kinema.run_program(program_text, robot)  # Plan: t, q, qd, qdd like `kinema run`
    cell = kinema.Cell(dt=0.01).add("a", robot, tr).add("b", robot, tr, base=[1, 0, 0, 0, 0, 3.14])
    report = cell.run()                       # CellReport like `kinema cell`: distances, closest, checks
    scene = kinema.Scene.from_file("examples/scenes/fume-hood.toml")
    robot.collides(q, scene=scene)            # also distance, collide_dict, collides_batch; ik/check(scene=)
    arm = kinema.Robot.from_dh([kinema.RevoluteDH(a=1.0), kinema.RevoluteDH(a=0.8)], name="planar2")
    Ts = kinema.ctraj(T0, T1, 50)             # (50, 4, 4); as_se3=True for a spatialmath SE3
    q, qd, qdd = kinema.jtraj(q0, q1, 50)     # quintic, as the toolbox's jtraj
    robot.plot(tr, file="arm.png")            # matplotlib Figure; also plot_joints, plot_cartesian
    robot.show(q); robot.animate(tr)          # the browser viewer (kinema serve); inline in Jupyter

Units are SI (metres, radians). Errors derive from :class:`KinemaError`;
bad input also derives from ``ValueError``.
"""

from ._errors import (
    DescriptionError,
    InvalidInput,
    KinemaError,
    PlanningError,
    ProgramError,
    RobotFileError,
    TrajectoryError,
    UnknownRobot,
    Unreachable,
)
from ._dh import PrismaticDH, PrismaticMDH, RevoluteDH, RevoluteMDH
from ._kinema import (
    Cell,
    CellReport,
    CheckReport,
    IkSolution,
    JointTrajectory,
    Plan,
    Robot,
    Scene,
    TimeLaw,
    __version__,
    run_program,
    time_law,
)
from ._toolbox import JointPath, ctraj, jtraj
from ._viewer import Viewer

__all__ = [
    "Robot",
    "Scene",
    "IkSolution",
    "JointTrajectory",
    "TimeLaw",
    "Plan",
    "CheckReport",
    "Cell",
    "CellReport",
    "time_law",
    "run_program",
    "RevoluteDH",
    "PrismaticDH",
    "RevoluteMDH",
    "PrismaticMDH",
    "ctraj",
    "jtraj",
    "JointPath",
    "Viewer",
    "KinemaError",
    "InvalidInput",
    "UnknownRobot",
    "DescriptionError",
    "RobotFileError",
    "Unreachable",
    "TrajectoryError",
    "ProgramError",
    "PlanningError",
    "__version__",
]
