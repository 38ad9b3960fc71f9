"""Type stubs of the compiled part of kinema (re-exported by ``kinema``)."""

import os
from typing import Dict, List, Literal, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = Union[npt.ArrayLike, Sequence[float]]
"""Anything numpy can turn into a float64 array (list, tuple, ndarray)."""
JointVector = Union[ArrayLike, str]
"""n joint values (rad / m), or the name of one of the robot's poses."""
F64Array = npt.NDArray[np.float64]

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

class JointTrajectory:
    """A sampled joint trajectory (from Robot.ptp)."""

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
        """Time-law family: trapezoid, scurve, cubic, quintic or linear."""
    @property
    def phase_times(self) -> List[float]:
        """Times at which the time law changes phase [s]."""
    def __len__(self) -> int: ...

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
    def fkine(self, q: JointVector) -> F64Array:
        """Tool pose base_from_tool, shape (4, 4)."""
    def fkine_all(self, q: JointVector) -> F64Array:
        """Base, link 1..n and tool frames, shape (n + 2, 4, 4)."""
    def jacob0(self, q: JointVector) -> F64Array:
        """Geometric Jacobian in the base frame, shape (6, n)."""
    def jacobe(self, q: JointVector) -> F64Array:
        """Geometric Jacobian in the tool frame, shape (6, n)."""
    def manipulability(self, q: JointVector, axes: Literal["all", "trans", "rot"] = "all") -> float:
        """Yoshikawa manipulability of the selected Jacobian rows."""
    def fkine_batch(self, Q: ArrayLike) -> F64Array:
        """(N, n) configurations -> (N, 4, 4) poses; GIL released, parallel."""
    def jacob0_batch(self, Q: ArrayLike) -> F64Array:
        """(N, n) configurations -> (N, 6, n) base-frame Jacobians; GIL released, parallel."""
    def jacobe_batch(self, Q: ArrayLike) -> F64Array:
        """(N, n) configurations -> (N, 6, n) tool-frame Jacobians; GIL released, parallel."""
    def ptp(
        self,
        q0: JointVector,
        qf: JointVector,
        dt: float,
        profile: Literal["trapezoid", "scurve", "cubic", "quintic", "linear"] = "trapezoid",
        vmax: Optional[ArrayLike] = None,
        amax: Optional[ArrayLike] = None,
        jmax: Optional[ArrayLike] = None,
        speed: float = 1.0,
        duration: Optional[float] = None,
    ) -> JointTrajectory:
        """Synchronised point-to-point joint motion sampled every dt. Raises InvalidInput, TrajectoryError."""
    @overload
    def ik(
        self,
        T: ArrayLike,
        all: Literal[False] = False,
        q0: Optional[JointVector] = None,
        solver: Literal["auto", "analytic", "numeric"] = "auto",
        q3: Optional[float] = None,
        psi: Optional[float] = None,
        seed: int = 0,
    ) -> IkSolution:
        """One solution within limits (nearest to q0 when given). Raises Unreachable."""
    @overload
    def ik(
        self,
        T: ArrayLike,
        all: Literal[True],
        q0: Optional[JointVector] = None,
        solver: Literal["auto", "analytic", "numeric"] = "auto",
        q3: Optional[float] = None,
        psi: Optional[float] = None,
        seed: int = 0,
    ) -> List[IkSolution]:
        """Every solution found, also those outside the limits. Raises Unreachable."""
