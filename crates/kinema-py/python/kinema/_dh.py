"""DH links for :meth:`kinema.Robot.from_dh`, named and ordered as the toolbox's
``RevoluteDH``, ``PrismaticDH``, ``RevoluteMDH`` and ``PrismaticMDH``."""

from __future__ import annotations

from typing import Optional, Sequence


class _DHLink:
    """One row of a DH table (m, rad). ``offset`` is added to the joint
    variable (θ = q + offset for a revolute joint, d = q + offset for a
    prismatic one); ``qlim`` is ``(lower, upper)`` or None for no limits."""

    prismatic = False
    modified = False

    def __init__(
        self,
        *,
        d: float = 0.0,
        a: float = 0.0,
        alpha: float = 0.0,
        theta: float = 0.0,
        offset: float = 0.0,
        qlim: Optional[Sequence[float]] = None,
        name: Optional[str] = None,
    ):
        self.d = d
        self.a = a
        self.alpha = alpha
        self.theta = theta
        self.offset = offset
        self.qlim = qlim
        self.name = name

    def __repr__(self) -> str:
        fixed = "theta" if self.prismatic else "d"
        values = f"{fixed}={getattr(self, fixed)!r}, a={self.a!r}, alpha={self.alpha!r}, offset={self.offset!r}"
        extra = "".join(f", {k}={getattr(self, k)!r}" for k in ("qlim", "name") if getattr(self, k) is not None)
        return f"{type(self).__name__}({values}{extra})"


class RevoluteDH(_DHLink):
    """A revolute joint's row of a standard DH table: θ is the joint variable."""

    def __init__(self, d=0.0, a=0.0, alpha=0.0, offset=0.0, qlim=None, name=None):
        super().__init__(d=d, a=a, alpha=alpha, offset=offset, qlim=qlim, name=name)


class PrismaticDH(_DHLink):
    """A prismatic joint's row of a standard DH table: d is the joint variable."""

    prismatic = True

    def __init__(self, theta=0.0, a=0.0, alpha=0.0, offset=0.0, qlim=None, name=None):
        super().__init__(theta=theta, a=a, alpha=alpha, offset=offset, qlim=qlim, name=name)


class RevoluteMDH(RevoluteDH):
    """A revolute joint's row of a modified (Craig) DH table."""

    modified = True


class PrismaticMDH(PrismaticDH):
    """A prismatic joint's row of a modified (Craig) DH table."""

    modified = True
