"""Type stubs of the compiled part of kinema (re-exported by ``kinema``)."""

import os
from ._viewer import Viewer
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = Union[npt.ArrayLike, Sequence[float]]
"""Anything numpy can turn into a float64 array (list, tuple, ndarray)."""
JointVector = Union[ArrayLike, str]
"""n joint values (rad / m), or the name of one of the robot's poses."""
F64Array = npt.NDArray[np.float64]
ProfileName = Literal["trapezoid", "scurve", "cubic", "quintic", "linear"]
PoseLike = ArrayLike
"""A pose: a 4x4 homogeneous transform, or 6 numbers x, y, z [m], roll, pitch, yaw [rad] (convention ``rpy``)."""
RpyName = Literal["zyx", "xyz"]
SolverName = Literal["auto", "analytic", "numeric"]

class IkSolution:
    """One inverse-kinematics solution."""

    @property
    def q(self) -> F64Array:
        """Joint values, shape (n,) (rad / m)."""
    @property
    def branch(self) -> str:
        """Branch label, e.g. ``"shoulder-left/elbow-up/wrist-noflip"`` or ``"numeric"``."""
    @property
    def solver(self) -> str:
        """Solver that found it: ``"iiwa"``, ``"pieper"``, ``"scorbot"``, ``"numeric"``, ..."""
    @property
    def position_error(self) -> float:
        """|p_target - p(q)| [m], from forward kinematics of ``q``."""
    @property
    def orientation_error(self) -> float:
        """Angle of R_target R(q)^T [rad], from forward kinematics of ``q``."""
    @property
    def residual(self) -> Tuple[float, float]:
        """``(position_error [m], orientation_error [rad])``."""
    @property
    def within_limits(self) -> bool:
        """Whether every joint value is within its limits."""
    @property
    def success(self) -> bool:
        """``within_limits`` and both residuals at most 1e-6 (m, rad)."""
    @property
    def iterations(self) -> Optional[int]:
        """Iterations of the numeric solver (None for analytic solutions)."""
    @property
    def restarts(self) -> Optional[int]:
        """Restarts of the numeric solver (None for analytic solutions)."""
    def to_dict(self) -> Dict[str, Any]:
        """The solution as ``kinema ik --json`` lists it: q, branch, within_limits, position_error,
        orientation_error (None for a position-only target); numeric: iterations, restarts, stop."""

class JointTrajectory:
    """A sampled joint trajectory (from Robot.ptp, Robot.lin, Robot.circ or Robot.expr)."""

    @property
    def t(self) -> F64Array:
        """Sample times, shape (K,) [s]."""
    @property
    def q(self) -> F64Array:
        """Joint positions, shape (K, n)."""
    @property
    def qd(self) -> F64Array:
        """Joint velocities, shape (K, n)."""
    @property
    def qdd(self) -> F64Array:
        """Joint accelerations, shape (K, n)."""
    @property
    def duration(self) -> float:
        """Length of the motion [s]."""
    @property
    def profile(self) -> str:
        """Time-law family: trapezoid, scurve, cubic, quintic or linear; ``"expression"`` for Robot.expr."""
    @property
    def phase_times(self) -> List[float]:
        """Durations of the time law's phases [s]; empty for a Cartesian motion of several segments and for expr."""
    @property
    def poses(self) -> Optional[F64Array]:
        """Planned tool poses at the sample times, shape (K, 4, 4) (lin, circ); None for ptp."""
    @property
    def segment_starts(self) -> List[float]:
        """Start time of each segment [s] ([0.0] for ptp)."""
    @property
    def blend_times(self) -> List[float]:
        """Duration of each blend between consecutive segments [s]."""
    @property
    def skipped(self) -> List[int]:
        """Indices (among via, then T) of waypoints lin(..., skip_unreachable=True) left out."""
    def to_dict(self) -> Dict[str, Any]:
        """The motion as ``kinema traj ptp|lin|circ|expr --json --out FILE`` prints it (without the samples):
        robot, motion, profile, duration, samples and the motion's own fields."""
    def __len__(self) -> int: ...

class CheckReport:
    """What Robot.check found (kinema traj check --json)."""

    @property
    def ok(self) -> bool:
        """No violation."""
    @property
    def samples(self) -> int:
        """Number of samples checked."""
    @property
    def peak_velocity(self) -> F64Array:
        """Largest |qd| per joint, shape (n,)."""
    @property
    def peak_acceleration(self) -> F64Array:
        """Largest |qdd| per joint, shape (n,)."""
    @property
    def peak_jerk(self) -> F64Array:
        """Largest |q⃛| per joint, shape (n,)."""
    @property
    def min_manipulability(self) -> Optional[Tuple[float, float]]:
        """(t, value) of the smallest manipulability when min_manip was given, else None."""
    @property
    def violations(self) -> List[Dict[str, Any]]:
        """One dict per problem: kind, t, sample (from 0), joint (from 1 or None), value, limit, message."""
    @property
    def warnings(self) -> List[Dict[str, Any]]:
        """Singular passages (kind "singular"), one per passage, as dicts like violations."""
    def to_dict(self) -> Dict[str, Any]:
        """The report as ``kinema traj check --json`` prints it."""
    def raise_if_violations(self) -> None:
        """Raises TrajectoryError when a limit is broken."""

class TimeLaw:
    """A time law s(t) from 0 to 1, scaled by ``distance`` (from time_law)."""

    @property
    def profile(self) -> str:
        """Family: trapezoid, scurve, cubic, quintic or linear."""
    @property
    def distance(self) -> float:
        """Distance covered (unit of the limits)."""
    @property
    def duration(self) -> float:
        """Duration T [s]."""
    @property
    def phase_times(self) -> List[float]:
        """Durations of the phases [s] (zero-length phases left out)."""
    @property
    def peaks(self) -> Tuple[float, float, float]:
        """Largest |velocity|, |acceleration|, |jerk| (scaled by distance; inf where unbounded)."""
    def to_dict(self, dt: Optional[float] = None) -> Dict[str, Any]:
        """The law as ``kinema traj law --json`` prints it; with dt [s] also its samples every dt seconds."""
    def sample(self, t: ArrayLike) -> Tuple[F64Array, F64Array, F64Array, F64Array]:
        """(p, v, a, j) at the times t, each of t's shape. Raises InvalidInput for NaN."""
    def times(self, dt: float) -> F64Array:
        """0, dt, 2 dt, ... and the end time. Raises InvalidInput for a bad dt."""

def time_law(
    profile: ProfileName = "trapezoid",
    distance: float = 1.0,
    vmax: Optional[float] = None,
    amax: Optional[float] = None,
    jmax: Optional[float] = None,
    duration: Optional[float] = None,
) -> TimeLaw:
    """The fastest law within vmax/amax/jmax covering distance, or one lasting duration. Raises InvalidInput."""

class Plan:
    """A robot program run on a robot (from run_program): kinema run's joint signals and the motion plan."""

    @property
    def t(self) -> F64Array:
        """Sample times, shape (K,) [s]."""
    @property
    def q(self) -> F64Array:
        """Joint positions, shape (K, n)."""
    @property
    def qd(self) -> F64Array:
        """Joint velocities, shape (K, n)."""
    @property
    def qdd(self) -> F64Array:
        """Joint accelerations, shape (K, n)."""
    @property
    def duration(self) -> float:
        """Total duration [s]."""
    @property
    def motions(self) -> List[Dict[str, Any]]:
        """One dict per motion: line, kind, start, end, profile, target."""
    @property
    def warnings(self) -> List[str]:
        """Warnings, one line each: file:line:col: warning: message."""
    @property
    def robot(self) -> "Robot":
        """The robot as it ends the program (with its last TOOL)."""
    def to_dict(self) -> Dict[str, Any]:
        """The program's answer as ``kinema run --json`` prints it (without the samples): robot, duration,
        samples, motions, final_q, final_pose, warnings."""
    def listing(self) -> str:
        """The motion plan as text (kinema compile --listing)."""
    def __len__(self) -> int: ...

def run_program(
    text: str,
    robot: Union["Robot", str],
    dt: float = 0.01,
    start: Optional[JointVector] = None,
    filename: str = "<program>",
    time_limit: Optional[float] = None,
    skip_unreachable: bool = False,
    scene: Optional[Scene] = None,
    margin: Optional[float] = None,
) -> Plan:
    """Compiles and runs a robot program as `kinema run` does, on a worker thread without the GIL.

    time_limit: seconds after which the program is stopped (ProgramError "stopped here: the time
    budget of … s ran out"); None for no limit. Ctrl-C stops it and raises KeyboardInterrupt.
    Raises ProgramError."""

class Scene:
    """Obstacles with poses (a scene file's [[obstacle]] tables), for scene= of collides, distance, ik, check."""

    @staticmethod
    def from_file(path: Union[str, "os.PathLike[str]"]) -> "Scene":
        """Reads a scene TOML file. Raises RobotFileError, DescriptionError."""
    @staticmethod
    def from_toml(text: str, base_dir: Optional[Union[str, "os.PathLike[str]"]] = None) -> "Scene":
        """A scene from TOML text (mesh paths relative to base_dir). Raises DescriptionError."""
    @property
    def obstacles(self) -> List[str]:
        """The obstacles' names, in file order."""

class Robot:
    """A serial robot arm (immutable). SI units; Jacobian rows [vx vy vz wx wy wz]."""

    @staticmethod
    def builtin(name: str) -> "Robot":
        """A built-in robot by name. Raises UnknownRobot."""
    @staticmethod
    def builtins() -> List[str]:
        """Names of the built-in robots, sorted."""
    @staticmethod
    def from_file(path: Union[str, "os.PathLike[str]"], tip: Optional[str] = None) -> "Robot":
        """Loads a .toml or .urdf description. Raises RobotFileError, DescriptionError, InvalidInput."""
    @staticmethod
    def from_dh(
        links: Sequence[Any],
        name: str = "robot",
        base: Optional[Any] = None,
        tool: Optional[Any] = None,
        poses: Optional[Dict[str, ArrayLike]] = None,
    ) -> "Robot":
        """A robot from RevoluteDH/PrismaticDH (or RevoluteMDH/PrismaticMDH) links, as the toolbox's
        DHRobot; base/tool 4x4 or SE3; ``home`` zeros unless in ``poses``. Raises DescriptionError
        listing every problem, InvalidInput for a link or argument of the wrong kind."""
    @staticmethod
    def from_urdf_string(text: str, tip: Optional[str] = None) -> "Robot":
        """A robot from URDF text (its <collision> shapes serve collides/distance). Raises DescriptionError."""
    def plot(self, q: Any, *, frames: bool = True, file: Optional[Any] = None, ax: Optional[Any] = None) -> Any:
        """3D stick figure with link frames at q (a configuration, pose name, (N, n) array or
        trajectory), with matplotlib; returns the Figure, saved to ``file`` when given."""
    def plot_joints(self, trajectory: Any, *, file: Optional[Any] = None) -> Any:
        """Joint positions, velocities, accelerations against time (matplotlib Figure)."""
    def plot_cartesian(self, trajectory: Any, *, file: Optional[Any] = None) -> Any:
        """Tool position and linear velocity against time (matplotlib Figure)."""
    def show(self, q: Any, scene: Optional[Scene] = None, *, open_browser: bool = True) -> "Viewer":
        """The browser viewer (`kinema serve`, one per process) on the robot at q; a second call
        moves the same page. Displays inline in Jupyter. Raises InvalidInput, FileNotFoundError."""
    def animate(self, trajectory: Any, scene: Optional[Scene] = None, *, open_browser: bool = True) -> "Viewer":
        """Plays a JointTrajectory, Plan or (t, q) pair in the browser viewer. Raises InvalidInput."""
    @property
    def name(self) -> str:
        """Robot name."""
    @property
    def n(self) -> int:
        """Number of joints."""
    @property
    def joint_names(self) -> List[str]:
        """Joint names, base first."""
    @property
    def joint_types(self) -> str:
        """Joint types, e.g. ``"RRRRRR"``."""
    @property
    def qlim(self) -> F64Array:
        """Position limits, shape (2, n): row 0 lower, row 1 upper."""
    @property
    def home(self) -> F64Array:
        """The ``home`` configuration, shape (n,)."""
    @property
    def poses(self) -> Dict[str, F64Array]:
        """Named configurations."""
    def pose(self, name: str) -> F64Array:
        """A named configuration. Raises InvalidInput for an unknown name."""
    def to_dict(self) -> Dict[str, Any]:
        """What the robot is, as ``kinema info --json`` prints it and ``GET /api/robots/{name}`` returns it."""
    def fk_dict(self, q: JointVector, rpy: RpyName = "zyx") -> Dict[str, Any]:
        """Forward kinematics as ``kinema fk --json`` prints it and ``POST /api/fk`` returns it."""
    def jacobian_dict(
        self, q: JointVector, frame: Literal["base", "tool"] = "base", analytic: Optional[RpyName] = None
    ) -> Dict[str, Any]:
        """The Jacobian as ``kinema jacobian --json`` prints it (analytic: of the roll-pitch-yaw rates)."""
    def manip_dict(self, q: JointVector, direction: Optional[ArrayLike] = None) -> Dict[str, Any]:
        """Manipulability measures as ``kinema manip --json`` prints them and ``POST /api/manip`` returns them."""
    def fkine(self, q: JointVector, out: Optional[F64Array] = None, as_se3: bool = False) -> Any:
        """Tool pose world_from_tool, shape (4, 4); written into ``out`` (a writeable C-contiguous
        float64 (4, 4) array, returned) when given; a spatialmath SE3 with ``as_se3=True``.
        Raises InvalidInput for a bad ``q`` or ``out``."""
    def fkine_all(self, q: JointVector) -> F64Array:
        """Base, link 1..n and tool frames, shape (n + 2, 4, 4)."""
    def jacob0(self, q: JointVector, out: Optional[F64Array] = None) -> F64Array:
        """Geometric Jacobian in the base frame, shape (6, n); into ``out`` as in fkine."""
    def jacobe(self, q: JointVector, out: Optional[F64Array] = None) -> F64Array:
        """Geometric Jacobian in the tool frame, shape (6, n); into ``out`` as in fkine."""
    def manipulability(self, q: JointVector, axes: Literal["all", "trans", "rot"] = "all") -> float:
        """Yoshikawa manipulability of the selected Jacobian rows."""
    def fkine_batch(self, Q: ArrayLike, out: Optional[F64Array] = None, as_se3: bool = False) -> Any:
        """(N, n) configurations -> (N, 4, 4) poses; GIL released, parallel. With ``out`` (a
        writeable C-contiguous float64 (N, 4, 4) array, returned): no copies, GIL held, parallel.
        ``as_se3=True``: one spatialmath SE3 of N poses."""
    def jacob0_batch(self, Q: ArrayLike, out: Optional[F64Array] = None) -> F64Array:
        """(N, n) configurations -> (N, 6, n) base-frame Jacobians; GIL released, parallel; ``out`` as in fkine_batch."""
    def jacobe_batch(self, Q: ArrayLike, out: Optional[F64Array] = None) -> F64Array:
        """(N, n) configurations -> (N, 6, n) tool-frame Jacobians; GIL released, parallel; ``out`` as in fkine_batch."""
    def rne(self, q: JointVector, qd: ArrayLike, qdd: ArrayLike, gravity: Optional[ArrayLike] = None) -> F64Array:
        """Inverse dynamics (recursive Newton-Euler, Corke's ``rne``): joint torques
        tau = M(q) qdd + C(q, qd) qd + g(q) [N m revolute, N prismatic]. Arguments of shape (n,), or
        all (N, n) for N configurations (result (n,) or (N, n)). ``gravity``: the acceleration of
        gravity in the world frame [m/s^2], default [0, 0, -9.81] (Corke's ``Robot.gravity``).
        ``rne(q, qd, 0, gravity=[0, 0, 0])`` is the Coriolis and centrifugal torque C(q, qd) qd.
        Raises InvalidInput (shapes, NaN/inf), KinemaError (a link without mass properties)."""
    def inertia(self, q: JointVector) -> F64Array:
        """Joint-space inertia (mass) matrix M(q), symmetric positive definite, shape (n, n), or
        (N, n, n) for (N, n) configurations [kg m^2, kg m or kg]."""
    def coriolis(self, q: JointVector, qd: ArrayLike) -> F64Array:
        """Coriolis and centrifugal matrix C(q, qd) (Corke's ``coriolis``), shape (n, n), or (N, n, n)
        for (N, n) rows; C qd is the velocity part of rne and dM/dt - 2C is skew-symmetric."""
    def gravload(self, q: JointVector, gravity: Optional[ArrayLike] = None) -> F64Array:
        """Gravity torques g(q) = rne(q, 0, 0, gravity), shape (n,) or (N, n); ``gravity`` as in rne."""
    def accel(self, q: JointVector, qd: ArrayLike, torque: ArrayLike, gravity: Optional[ArrayLike] = None) -> F64Array:
        """Forward dynamics (Corke's ``accel``): joint accelerations M(q)^-1 (torque - C(q, qd) qd - g(q))
        [rad/s^2 or m/s^2]; shapes and ``gravity`` as in rne."""
    def ik_batch(
        self,
        T: Optional[ArrayLike] = None,
        *,
        position: Optional[ArrayLike] = None,
        q0: Optional[JointVector] = None,
        solver: SolverName = "auto",
        mask: Optional[Sequence[Union[bool, int]]] = None,
        seed: int = 0,
        rpy: RpyName = "zyx",
        tol_position: float = 1e-6,
        tol_orientation: float = 1e-6,
        scene: Optional[Scene] = None,
        margin: Optional[float] = None,
    ) -> Tuple[F64Array, npt.NDArray[np.bool_], List[str]]:
        """V targets (T: (V, 4, 4) or (V, 6); or position: (V, 3)) -> (Q (V, n) with NaN rows where unsolved,
        success (V,), reasons), each solved as ik() would; GIL released, parallel."""
    def ptp(
        self,
        q0: JointVector,
        qf: JointVector,
        dt: float,
        profile: Optional[ProfileName] = None,
        vmax: Optional[ArrayLike] = None,
        amax: Optional[ArrayLike] = None,
        jmax: Optional[ArrayLike] = None,
        speed: float = 1.0,
        duration: Optional[float] = None,
        *,
        v0: Optional[ArrayLike] = None,
        a0: Optional[ArrayLike] = None,
        v1: Optional[ArrayLike] = None,
        a1: Optional[ArrayLike] = None,
    ) -> JointTrajectory:
        """Synchronised point-to-point joint motion sampled every dt; v0/a0/v1/a1: joint velocities and
        accelerations at the start and end (one per joint, default 0). Raises InvalidInput, TrajectoryError."""
    def expr(
        self,
        joints: Union[Dict[int, str], Sequence[Tuple[int, str]]],
        duration: float,
        dt: float = 0.01,
        q0: Optional[JointVector] = None,
        *,
        vmax: Optional[ArrayLike] = None,
        amax: Optional[ArrayLike] = None,
        jmax: Optional[ArrayLike] = None,
    ) -> JointTrajectory:
        """Joints (numbered from 1) following expressions of t, the others at q0 (home); checked against
        the robot's limits or vmax/amax/jmax where given.

        Raises InvalidInput, TrajectoryError."""
    @overload
    def check(
        self,
        t: Union[JointTrajectory, Plan],
        *,
        vmax: Optional[ArrayLike] = None,
        amax: Optional[ArrayLike] = None,
        jmax: Optional[ArrayLike] = None,
        min_manip: Optional[float] = None,
        singular: float = 1e-3,
        resolution: float = 0.0,
        time_resolution: float = 0.0,
        scene: Optional[Scene] = None,
        margin: Optional[float] = None,
    ) -> CheckReport:
        """Checks a trajectory against the robot's limits (kinema traj check). Raises InvalidInput."""
    @overload
    def check(
        self,
        t: ArrayLike,
        q: ArrayLike,
        qd: Optional[ArrayLike] = None,
        qdd: Optional[ArrayLike] = None,
        *,
        vmax: Optional[ArrayLike] = None,
        amax: Optional[ArrayLike] = None,
        jmax: Optional[ArrayLike] = None,
        min_manip: Optional[float] = None,
        singular: float = 1e-3,
        resolution: float = 0.0,
        time_resolution: float = 0.0,
        scene: Optional[Scene] = None,
        margin: Optional[float] = None,
    ) -> CheckReport:
        """Checks samples t (K,), q (K, n) [qd, qdd estimated when absent]. Raises InvalidInput."""
    def lin(
        self,
        q0: JointVector,
        T: PoseLike,
        dt: float,
        *,
        vmax: float,
        amax: float,
        via: Optional[ArrayLike] = None,
        profile: ProfileName = "trapezoid",
        jmax: Optional[float] = None,
        rot_vmax: Optional[float] = None,
        rot_amax: Optional[float] = None,
        rot_jmax: Optional[float] = None,
        blend: Union[Literal["decel", "none"], str, float, None] = "decel",
        orientation: Literal["slerp", "rpy"] = "slerp",
        rpy: RpyName = "zyx",
        method: Literal["ik", "rate"] = "ik",
        max_step: Optional[float] = None,
        max_angle: float = 0.05,
        min_manip: Optional[float] = None,
        q3: Union[Literal["auto", "hold", "track", "manipulability", "avoid-limits"], float, None] = None,
        psi: Union[Literal["hold"], float, None] = None,
        skip_unreachable: bool = False,
    ) -> JointTrajectory:
        """Straight-line Cartesian motion from fkine(q0) through via to T (4x4 or x, y, z, roll, pitch, yaw).

        Raises InvalidInput, Unreachable, TrajectoryError."""
    def circ(
        self,
        q0: JointVector,
        via: ArrayLike,
        T: PoseLike,
        dt: float,
        *,
        vmax: float,
        amax: float,
        profile: ProfileName = "trapezoid",
        jmax: Optional[float] = None,
        rot_vmax: Optional[float] = None,
        rot_amax: Optional[float] = None,
        rot_jmax: Optional[float] = None,
        rpy: RpyName = "zyx",
        method: Literal["ik", "rate"] = "ik",
        max_step: Optional[float] = None,
        max_angle: float = 0.05,
        min_manip: Optional[float] = None,
        q3: Union[Literal["auto", "hold", "track", "manipulability", "avoid-limits"], float, None] = None,
        psi: Union[Literal["hold"], float, None] = None,
    ) -> JointTrajectory:
        """Circular arc from fkine(q0) through the point via to T. Raises InvalidInput, Unreachable, TrajectoryError."""
    @overload
    def ik(
        self,
        T: Optional[PoseLike] = None,
        all: Literal[False] = False,
        q0: Optional[JointVector] = None,
        solver: SolverName = "auto",
        q3: Optional[float] = None,
        psi: Optional[float] = None,
        seed: int = 0,
        *,
        position: Optional[ArrayLike] = None,
        pitch: Optional[float] = None,
        roll: Optional[float] = None,
        approach: Optional[ArrayLike] = None,
        alpha: Optional[float] = None,
        rpy: RpyName = "zyx",
        mask: Optional[Sequence[Union[bool, int]]] = None,
        tol_position: float = 1e-6,
        tol_orientation: float = 1e-6,
        scene: Optional[Scene] = None,
        margin: Optional[float] = None,
    ) -> IkSolution:
        """One solution within limits (nearest to q0 when given) of a pose T or of position=[x, y, z]
        (alone, or with pitch and roll: Scorbot; approach: ROMMEL; alpha: SCARA). Raises Unreachable, InvalidInput."""
    @overload
    def ik(
        self,
        T: Optional[PoseLike] = None,
        *,
        all: Literal[True],
        q0: Optional[JointVector] = None,
        solver: SolverName = "auto",
        q3: Optional[float] = None,
        psi: Optional[float] = None,
        seed: int = 0,
        position: Optional[ArrayLike] = None,
        pitch: Optional[float] = None,
        roll: Optional[float] = None,
        approach: Optional[ArrayLike] = None,
        alpha: Optional[float] = None,
        rpy: RpyName = "zyx",
        mask: Optional[Sequence[Union[bool, int]]] = None,
        tol_position: float = 1e-6,
        tol_orientation: float = 1e-6,
        scene: Optional[Scene] = None,
        margin: Optional[float] = None,
    ) -> List[IkSolution]:
        """Every solution found, also those outside the limits. Raises Unreachable, InvalidInput."""
    @overload
    def ik(
        self,
        T: Optional[PoseLike],
        all: Literal[True],
        q0: Optional[JointVector] = None,
        solver: SolverName = "auto",
        q3: Optional[float] = None,
        psi: Optional[float] = None,
        seed: int = 0,
        *,
        position: Optional[ArrayLike] = None,
        pitch: Optional[float] = None,
        roll: Optional[float] = None,
        approach: Optional[ArrayLike] = None,
        alpha: Optional[float] = None,
        rpy: RpyName = "zyx",
        mask: Optional[Sequence[Union[bool, int]]] = None,
        tol_position: float = 1e-6,
        tol_orientation: float = 1e-6,
        scene: Optional[Scene] = None,
        margin: Optional[float] = None,
    ) -> List[IkSolution]:
        """Every solution found, also those outside the limits. Raises Unreachable, InvalidInput."""
    def ik_dict(
        self,
        T: Optional[PoseLike] = None,
        all: bool = False,
        q0: Optional[JointVector] = None,
        solver: SolverName = "auto",
        q3: Optional[float] = None,
        psi: Optional[float] = None,
        seed: int = 0,
        *,
        position: Optional[ArrayLike] = None,
        pitch: Optional[float] = None,
        roll: Optional[float] = None,
        approach: Optional[ArrayLike] = None,
        alpha: Optional[float] = None,
        rpy: RpyName = "zyx",
        mask: Optional[Sequence[Union[bool, int]]] = None,
        tol_position: float = 1e-6,
        tol_orientation: float = 1e-6,
        scene: Optional[Scene] = None,
        margin: Optional[float] = None,
    ) -> Dict[str, Any]:
        """The answer of ``kinema ik --json`` (``--all`` with all=True) to the request ik takes: solutions,
        tolerance, discarded candidates, folded copies. Raises Unreachable, InvalidInput."""

    def collides(self, q: JointVector, scene: Optional[Scene] = None, margin: float = 0.0) -> bool:
        """Whether the robot at q collides with itself or scene's obstacles (pairs closer than margin [m])."""
    def distance(self, q: JointVector, scene: Optional[Scene] = None) -> float:
        """The smallest distance [m] between checked pairs (negative: overlap depth; inf: no pair)."""
    def collide_dict(self, q: JointVector, scene: Optional[Scene] = None, margin: float = 0.0) -> Dict[str, Any]:
        """The answer of kinema collide --json: collision, pairs, min_distance, margin, q."""
    def collides_batch(
        self, Q: ArrayLike, scene: Optional[Scene] = None, margin: float = 0.0
    ) -> npt.NDArray[np.bool_]:
        """collides() for each row of Q (V, n), on all cores with the GIL released."""
    def plan(
        self,
        q0: JointVector,
        qf: Optional[JointVector] = None,
        *,
        pose: Optional[PoseLike] = None,
        scene: Optional[Scene] = None,
        margin: float = 0.0,
        seed: int = 0,
        time_limit: float = 1.0,
        max_iterations: int = 100_000,
        step: Optional[float] = None,
        dt: float = 0.01,
        profile: Optional[ProfileName] = None,
        speed: float = 1.0,
        vmax: Optional[ArrayLike] = None,
        amax: Optional[ArrayLike] = None,
        jmax: Optional[ArrayLike] = None,
        rpy: str = "zyx",
    ) -> JointTrajectory:
        """A collision-free motion to qf or to any collision-free IK solution of pose (kinema plan):
        RRT-Connect, shortened, timed with a PTP per segment; to_dict()["plan"] holds the via points and
        counts. Raises InvalidInput (a colliding start or goal names the pair), Unreachable, PlanningError."""

class CellReport:
    """What Cell.run computed (kinema cell's CSV and JSON); dicts keyed by robot name or (a, b) pair."""

    @property
    def names(self) -> List[str]:
        """The robots, in the order they were added."""
    @property
    def bodies(self) -> List[Dict[str, Any]]:
        """How close the robots' link shapes come to each other and to the scene (robots, closest, links, ok)."""
    @property
    def t(self) -> F64Array:
        """The common clock's sample times, shape (K,) [s]."""
    @property
    def duration(self) -> float:
        """The last sample time [s]."""
    @property
    def q(self) -> Dict[str, F64Array]:
        """Per robot, its joint values, shape (K, n); held after its own end."""
    @property
    def tool_positions(self) -> Dict[str, F64Array]:
        """Per robot, its tool point in the cell's world frame, shape (K, 3) [m]."""
    @property
    def manipulability(self) -> Dict[str, F64Array]:
        """Per robot, its translational manipulability (Yoshikawa, linear rows), shape (K,)."""
    @property
    def ends(self) -> Dict[str, float]:
        """Per robot, the time its own trajectory ends [s]."""
    @property
    def distances(self) -> Dict[Tuple[str, str], F64Array]:
        """Per pair (in the order added), the distance between the tool points, shape (K,) [m]."""
    @property
    def closest(self) -> Dict[Tuple[str, str], Tuple[float, float]]:
        """Per pair, (t, distance) of the closest approach."""
    @property
    def closer_than_minimum(self) -> Dict[Tuple[str, str], List[Tuple[float, float]]]:
        """Per pair, the spans (from, to) [s] closer than min_distance (empty without one)."""
    @property
    def checks(self) -> Dict[str, CheckReport]:
        """Per robot, the check of its trajectory (as Robot.check)."""
    @property
    def min_distance(self) -> Optional[float]:
        """The cell's minimum tool distance [m], or None."""
    @property
    def ok(self) -> bool:
        """No check violation and no pair closer than min_distance."""
    def to_dict(self) -> Dict[str, Any]:
        """The cell's answer as ``kinema cell --json`` prints it (without the cell file's name)."""
    def __len__(self) -> int: ...

class Cell:
    """Several robots in one world on a common clock (kinema cell; seed 004 §VIII-E)."""

    def __init__(self, dt: float = 0.01, min_distance: Optional[float] = None, scene: Optional[Scene] = None) -> None:
        """dt: the clock's sample period [s] (programs too); min_distance [m]; scene: obstacles for the link
        distances. Raises InvalidInput."""
    @property
    def dt(self) -> float: ...
    @property
    def min_distance(self) -> Optional[float]: ...
    @property
    def names(self) -> List[str]: ...
    def add(
        self,
        name: str,
        robot: Union["Robot", str],
        trajectory: Optional[Union[JointTrajectory, Plan]] = None,
        *,
        base: Optional[PoseLike] = None,
        rpy: RpyName = "zyx",
        t: Optional[ArrayLike] = None,
        q: Optional[ArrayLike] = None,
        qd: Optional[ArrayLike] = None,
        qdd: Optional[ArrayLike] = None,
        resolution: float = 0.0,
        time_resolution: float = 0.0,
        program: Optional[str] = None,
        start: Optional[JointVector] = None,
        filename: Optional[str] = None,
        time_limit: Optional[float] = None,
    ) -> "Cell":
        """Adds a robot placed at base (its own world frame in the cell's) with one motion: a trajectory,
        arrays t and q, or a program run on the placed robot (targets in the cell's world frame).
        The trajectory is checked at once. Raises InvalidInput, ProgramError."""
    def run(self) -> CellReport:
        """Every robot on the common clock to the end of the longest; a finished robot holds. Raises InvalidInput."""
    def __len__(self) -> int: ...

def _interpolate_poses(T0: ArrayLike, T1: ArrayLike, s: ArrayLike) -> F64Array:
    """Poses at fractions s of the line from T0 to T1 (slerp), (N, 4, 4); kinema.ctraj's core."""

def _to_se3(matrices: F64Array) -> Any:
    """A (4, 4) or (N, 4, 4) array as a spatialmath SE3 (imported now)."""
