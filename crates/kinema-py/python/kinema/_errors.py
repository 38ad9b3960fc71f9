"""The exceptions kinema raises.

Every exception derives from :class:`KinemaError`. Bad input (a joint vector of
the wrong length, NaN, an array of the wrong shape, an unknown robot or pose
name, a malformed robot file) also derives from :class:`ValueError`, so code
that already catches ``ValueError`` keeps working. The message is the text the
Rust core (and the ``kinema`` command line) prints for the same mistake.
"""

import copy
from typing import Iterable, List, Optional, Tuple


class KinemaError(Exception):
    """Base class of every exception raised by kinema."""


class InvalidInput(KinemaError, ValueError):
    """An argument kinema cannot use: wrong joint count, a non-finite value,
    an array of the wrong shape, an unknown option or named pose."""


class UnknownRobot(InvalidInput):
    """A name that is not one of the built-in robots."""


class DescriptionError(KinemaError, ValueError):
    """A robot description (TOML or URDF) that is malformed or inconsistent.
    The message names the file, and for TOML the line and column."""


class RobotFileError(KinemaError, OSError):
    """A robot description file that cannot be read."""


class Unreachable(KinemaError):
    """An inverse-kinematics target that cannot be reached.

    Attributes:
        solver: name of the solver that decided (``"iiwa"``, ``"pieper"``,
            ``"numeric"``, ...).
        reason: why, in words (outside the reach, every solution violates a
            joint limit, no convergence, ...).
        closest: the configuration that came closest, when the solver found
            one: a dict with ``q`` (list of joint values), ``position_error``
            [m] and ``orientation_error`` [rad] on the constrained components;
            else None.
    """

    def __init__(
        self,
        message: str,
        solver: Optional[str] = None,
        reason: Optional[str] = None,
        closest: Optional[dict] = None,
        answer: Optional[dict] = None,
    ) -> None:
        super().__init__(message)
        self.solver = solver
        self.reason = reason
        self.closest = closest
        self._answer = answer

    def to_dict(self) -> dict:
        """The answer ``kinema ik --json`` prints for the same target (exit
        code 2): ``error`` (``"unreachable"``), ``solver``, ``reason`` and
        ``closest``."""
        if self._answer is not None:
            return copy.deepcopy(self._answer)
        return {"error": "unreachable", "solver": self.solver, "reason": self.reason, "closest": self.closest}


class TrajectoryError(KinemaError):
    """A planned trajectory that breaks a limit (position, velocity,
    acceleration, jerk); the message names the first violation and the count."""



class PlanningError(KinemaError):
    """A collision-free motion that was not found within the planner's
    budget (``Robot.plan``'s ``time_limit`` or ``max_iterations``); the
    message says which budget ran out and how far the search got."""


class ProgramError(KinemaError, ValueError):
    """A robot program that does not compile or run (:func:`kinema.run_program`).

    The message is the report ``kinema run`` prints: for every diagnostic
    ``file:line:col: error: message``, the source line with the place
    underlined and a hint, then a count.

    Attributes:
        diagnostics: the errors as ``(line, col, message)`` tuples, line and
            column counted from 1 (the column in characters), in source order.
    """

    def __init__(self, message: str, diagnostics: Iterable[Tuple[int, int, str]] = ()) -> None:
        super().__init__(message)
        self.diagnostics: List[Tuple[int, int, str]] = [tuple(d) for d in diagnostics]  # type: ignore[misc]


__all__ = [
    "KinemaError",
    "InvalidInput",
    "UnknownRobot",
    "DescriptionError",
    "RobotFileError",
    "Unreachable",
    "TrajectoryError",
    "ProgramError",
]
