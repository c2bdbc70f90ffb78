"""The one exception hierarchy of optraj.

Every error that a user can cause derives from :class:`OptrajError`. Subclasses carry the data
that explains the failure (the offending value, the bound it broke, the solver status), so that
callers can react programmatically and the message can name the value and the limit.

This module imports nothing from the rest of the project.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Sequence

__all__ = [
    "ClusterError",
    "CollisionError",
    "CompilerError",
    "InfeasibleError",
    "InvalidInputError",
    "JointLimitError",
    "MissingDependencyError",
    "OptrajError",
    "OptrajWarning",
    "PathJumpError",
    "PathJumpWarning",
    "SolverError",
    "UnknownNameError",
    "UnreachableError",
    "UnsupportedModelError",
    "WorkspaceError",
]


class OptrajError(Exception):
    """Root of every error raised by optraj on bad input or failed planning.

    Errors pickle with their message and attributes (a plan run in a worker process raises
    the same error, with the same data, in the caller).
    """

    def __reduce__(self) -> tuple[object, ...]:
        # The subclasses' constructors take the data the message is made from, not the
        # message: rebuild from the message and the attributes instead of calling them.
        return (_rebuilt, (type(self), self.args, dict(self.__dict__)))


def _rebuilt(
    cls: type[OptrajError], args: tuple[object, ...], state: dict[str, object]
) -> OptrajError:
    """An error of class ``cls`` with the given ``args`` and attributes (for unpickling)."""
    error = cls.__new__(cls, *args)
    # The built-in base's own initialiser (ImportError keeps its message in ``msg``).
    super(OptrajError, error).__init__(*args)
    error.__dict__.update(state)
    return error


class InvalidInputError(OptrajError, ValueError):
    """A value has the wrong shape, type or range, or is NaN/inf.

    Attributes:
        name: Name of the offending argument or field, if known.
        value: The offending value, if useful to keep.
    """

    def __init__(self, message: str, *, name: str | None = None, value: object = None) -> None:
        super().__init__(message)
        self.name = name
        self.value = value


class UnknownNameError(OptrajError, LookupError):
    """A name (robot, frame, option, solver) is not one of the known ones.

    Attributes:
        kind: What was looked up, e.g. ``"robot"`` or ``"frame"``.
        name: The name that was asked for.
        known: The valid names.
    """

    def __init__(self, kind: str, name: str, known: Iterable[str]) -> None:
        self.kind = kind
        self.name = name
        self.known = tuple(known)
        message = f"unknown {kind} {name!r}; known: {', '.join(self.known) or '(none)'}"
        close = difflib.get_close_matches(str(name), self.known, n=1)
        if close:
            message += f" (did you mean {close[0]!r}?)"
        super().__init__(message)

    def __str__(self) -> str:
        # LookupError would otherwise quote the message like a dictionary key.
        return str(self.args[0])


class MissingDependencyError(OptrajError, ImportError):
    """An optional package is needed for this feature and is not installed.

    Attributes:
        package: The PyPI distribution that is missing.
        extra: The optraj extra that installs it, e.g. ``"examples"``.
    """

    def __init__(self, package: str, extra: str, feature: str) -> None:
        self.package = package
        self.extra = extra
        super().__init__(
            f"{feature} needs the package {package!r}, which is not installed; "
            f"install it with: pip install 'optraj[{extra}]'"
        )


class UnsupportedModelError(OptrajError):
    """A robot model uses a feature (joint type, structure) that optraj does not handle."""


class JointLimitError(OptrajError):
    """A joint value lies outside its limits.

    Attributes:
        joint: Joint name.
        quantity: What was limited, e.g. ``"position"`` or ``"velocity"``.
        value: The offending value.
        lower: Lower limit.
        upper: Upper limit.
        unit: Unit of the value, e.g. ``"rad"`` or ``"m/s"``.
    """

    def __init__(
        self,
        joint: str,
        value: float,
        lower: float,
        upper: float,
        *,
        quantity: str = "position",
        unit: str = "",
        context: str = "",
    ) -> None:
        self.joint = joint
        self.quantity = quantity
        self.value = float(value)
        self.lower = float(lower)
        self.upper = float(upper)
        self.unit = unit
        side = f"below the lower limit {lower:.6g}" if value < lower else ""
        if value > upper:
            side = f"above the upper limit {upper:.6g}"
        unit_text = f" {unit}" if unit else ""
        prefix = f"{context}: " if context else ""
        super().__init__(
            f"{prefix}joint {joint!r} {quantity} {value:.6g}{unit_text} is {side or 'out of range'}"
            f" (limits [{lower:.6g}, {upper:.6g}]{unit_text})"
        )


class WorkspaceError(OptrajError):
    """A Cartesian point lies outside the workspace of a robot.

    Attributes:
        point: The point [m], shape (3,).
        axis: The axis whose bound is broken (``"x"``, ``"y"`` or ``"z"``).
        value: The coordinate [m].
        lower: Lower bound of the workspace along that axis [m].
        upper: Upper bound of the workspace along that axis [m].
    """

    def __init__(
        self, point: Sequence[float], axis: str, value: float, lower: float, upper: float
    ) -> None:
        self.point = tuple(float(v) for v in point)
        self.axis = axis
        self.value = float(value)
        self.lower = float(lower)
        self.upper = float(upper)
        bound = f"{axis} >= {lower:.6g} m" if value < lower else f"{axis} <= {upper:.6g} m"
        super().__init__(
            f"point ({', '.join(f'{v:.6g}' for v in self.point)}) m is outside the workspace: "
            f"{axis} = {value:.6g} m breaks the bound {bound}"
        )


class UnreachableError(OptrajError):
    """No joint configuration reaches a target pose (inverse kinematics failed).

    Attributes:
        position_error: Smallest tool position error reached [m].
        orientation_error: Orientation error at that solution [rad] (0 for position-only).
        attempts: Number of starting configurations tried.
    """

    def __init__(
        self, message: str, *, position_error: float, orientation_error: float, attempts: int
    ) -> None:
        self.position_error = float(position_error)
        self.orientation_error = float(orientation_error)
        self.attempts = int(attempts)
        super().__init__(
            f"{message} (best of {attempts} attempts: position error {position_error:.3g} m, "
            f"orientation error {orientation_error:.3g} rad)"
        )


class InfeasibleError(OptrajError):
    """A motion cannot be made within the robot's limits.

    Attributes:
        limit: Which limit binds, e.g. ``"velocity"``.
        joint: The binding joint, if one is known.
        required: The value the motion needs.
        allowed: The limit.
        max_speed: For a strike, the fastest strike speed the finding allows [m/s]; None
            when the error is not about a strike's speed.
        found_by: Which check refused the motion: :data:`CONTACT_CHOICE` (before any
            solve, no contact configuration reaches the strike speed within the velocity
            limits, or a paddle contact leaves a joint too little room to pass it at that
            speed), :data:`WINDOW_CHECK` (a solve found the strike infeasible, and every strike
            window tried needs more than the limits), or None (any other finding).
    """

    def __init__(
        self,
        message: str,
        *,
        limit: str,
        joint: str | None = None,
        required: float | None = None,
        allowed: float | None = None,
        max_speed: float | None = None,
        found_by: str | None = None,
    ) -> None:
        self.limit = limit
        self.joint = joint
        self.required = required
        self.allowed = allowed
        self.max_speed = max_speed
        self.found_by = found_by
        super().__init__(message)


#: :attr:`InfeasibleError.found_by` of a strike the contact choice refuses before any solve
#: (too fast for the velocity limits, or for a paddle contact's room to its position limits).
CONTACT_CHOICE = "contact choice"
#: :attr:`InfeasibleError.found_by` of a strike the solver found infeasible whose strike
#: windows each need more than the limits.
WINDOW_CHECK = "window check"


class SolverError(OptrajError):
    """A numerical solver did not return a usable solution.

    Attributes:
        solver: Solver name, e.g. ``"ipopt"``.
        status: The solver's own status string.
        iterations: Iterations done, if known.
        detail: What else is known of the failure (may be empty).
    """

    def __init__(
        self, solver: str, status: str, *, iterations: int | None = None, detail: str = ""
    ) -> None:
        self.solver = solver
        self.status = status
        self.iterations = iterations
        self.detail = detail
        text = f"solver {solver!r} failed with status {status!r}"
        if iterations is not None:
            text += f" after {iterations} iterations"
        if detail:
            text += f": {detail}"
        super().__init__(text)


class CompilerError(OptrajError):
    """Generated C code could not be compiled: no C compiler on the machine, or it failed.

    Attributes:
        compiler: The compiler command that was tried, e.g. ``"gcc"``.
        detail: What the compiler or the code generator said.
    """

    def __init__(self, compiler: str, detail: str) -> None:
        self.compiler = compiler
        self.detail = detail
        super().__init__(
            f"could not compile the generated C code with {compiler!r}: {detail.strip()}; "
            "install a C compiler or evaluate without compiling"
        )


class ClusterError(OptrajError, ConnectionError):
    """A Dask cluster could not be reached, or it had no worker to plan on.

    Attributes:
        address: The scheduler's address, if known.
    """

    def __init__(self, message: str, *, address: str | None = None) -> None:
        self.address = address
        super().__init__(message)


class PathJumpError(OptrajError):
    """Following a Cartesian path, the joint solution jumps between neighbouring samples.

    This happens near a singularity or where the IK switches branch; the joint motion would
    need an unbounded speed there.

    Attributes:
        time: Time of the jump on the path [s].
        joint: Joint that jumps the most.
        jump: Its change between neighbouring samples [rad or m].
        threshold: The largest change allowed [rad or m].
    """

    def __init__(self, time: float, joint: str, jump: float, threshold: float) -> None:
        self.time = float(time)
        self.joint = joint
        self.jump = float(jump)
        self.threshold = float(threshold)
        super().__init__(
            f"the joint solution jumps at t = {time:.4g} s: joint {joint!r} changes by "
            f"{jump:.4g} between neighbouring samples (allowed {threshold:.4g}); the path passes "
            "near a singularity or the IK changed branch"
        )


class CollisionError(OptrajError):
    """Two shapes that may not touch overlap, or come nearer than a margin.

    A target inside an obstacle or in the arm, or a strike no contact configuration of which
    keeps the arm its margin clear of the scene.

    Attributes:
        first: The robot's shape, e.g. ``"tool/finger_left"`` or ``"link_3"``.
        second: The other shape: a scene object or another robot shape.
        distance: Their signed distance [m], negative: how deep they overlap.
        what: The configuration refused, e.g. ``"goal"`` or ``"pick 0"``.
        point: A witness point on ``first`` [m], world frame, or None.
        required: The least distance they must keep [m] (the scene's margin; 0: not touch).
    """

    def __init__(
        self,
        first: str,
        second: str,
        distance: float,
        *,
        what: str,
        point: Sequence[float] | None = None,
        required: float = 0.0,
    ) -> None:
        self.first = first
        self.second = second
        self.distance = float(distance)
        self.what = what
        self.point = None if point is None else tuple(float(v) for v in point)
        self.required = float(required)
        where = "" if self.point is None else f" at ({', '.join(f'{v:.4g}' for v in self.point)}) m"
        if self.distance < 0.0:
            how = f"overlaps {second!r} by {-self.distance * 1e3:.3g} mm"
        else:
            how = f"is only {self.distance * 1e3:.3g} mm from {second!r}"
        super().__init__(
            f"{what} is in collision: {first!r} {how}{where} (signed distance "
            f"{self.distance:.4g} m, required >= {self.required:.4g} m)"
        )


class OptrajWarning(UserWarning):
    """Root of the warnings optraj issues."""


class PathJumpWarning(OptrajWarning):
    """A joint solution jump along a Cartesian path, reported as a warning on request."""
