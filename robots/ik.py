"""Numerical inverse kinematics for any robot, within its joint limits.

Each attempt runs a Levenberg-Marquardt iteration on the tool pose error. Joints that sit on a
position limit and are pushed outwards are held there for the step (an active set), so every
iterate, and hence the solution, lies within the limits. Several attempts start from the given
configuration and from random configurations; among the converged solutions the one closest to
``q_near`` is returned.

The pose error is ``[p(q) - p*; log(R(q) R*^T)]`` in world axes [m; rad]; for a position-only
target only the first three rows are used.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, UnreachableError
from optraj.robots.levenberg_marquardt import (
    Attempt,
    PoseError,
    levenberg_marquardt,
    levenberg_marquardt_batch,
)
from optraj.robots.robot import Robot
from optraj.validation import as_count, as_number, as_positive, as_transform, as_vector

__all__ = ["IKSolution", "LocalIK", "solve_ik"]

FloatArray = NDArray[np.float64]

#: Loosest convergence tolerance accepted [m or rad].
_MAX_TOLERANCE = 1e-3
#: Farthest target from the base [m]: no arm reaches a kilometre, and far beyond it the
#: squared residuals overflow (near 1e154 m).
MAX_TARGET_DISTANCE = 1e3
#: Position error at which the position-first stage of a random restart hands over [m].
_LOCATE_TOLERANCE = 1e-6
#: Random restarts run one by one while at most this many more solutions are wanted, and
#: otherwise in batches of twice the number wanted.
_ONE_BY_ONE = 2


@dataclass(frozen=True)
class IKSolution:
    """A converged inverse-kinematics solution.

    Attributes:
        q: Joint positions [rad or m], shape (n,), within the joint limits.
        position_error: Distance from the target position [m].
        orientation_error: Angle to the target orientation [rad]; 0 for position-only targets.
        iterations: Iterations summed over all attempts.
        attempts: Starting configurations tried.
        solutions: Distinct converged solutions found, shape (k, n), closest first.
    """

    q: FloatArray
    position_error: float
    orientation_error: float
    iterations: int
    attempts: int
    solutions: FloatArray


class LocalIK:
    """The first attempt of :func:`solve_ik`, repeated from many starts for one target.

    ``LocalIK(robot, position, axis=axis)(q)`` is ``solve_ik(robot, position, axis=axis,
    q_near=q, restarts=0).q`` (the same iteration, tolerance and result), or None where
    :func:`solve_ik` would raise :class:`~optraj.errors.UnreachableError`. The target and the
    settings are checked once, here; a start is only clipped to the position limits. A search
    that solves the same target from hundreds of nearby starts saves the per-call checks.

    Args:
        robot: The robot.
        position: Target position of the tool frame origin [m], shape (3,).
        axis: Direction the tool z axis must point along, shape (3,) (normalised here); None
            for a position-only target.
        tolerance: Convergence threshold on position [m] and axis angle [rad], in (0, 1e-3].
        max_iterations: Iteration cap of each attempt.

    Raises:
        InvalidInputError: Malformed robot, position, axis or settings.
    """

    def __init__(
        self,
        robot: Robot,
        position: ArrayLike,
        *,
        axis: ArrayLike | None = None,
        tolerance: float = 1e-9,
        max_iterations: int = 500,
    ) -> None:
        """Check the robot, target and settings once (see the class docstring)."""
        if not isinstance(robot, Robot):
            raise InvalidInputError(
                f"robot must be a robots.Robot, got {type(robot).__name__}", name="robot"
            )
        target = _target_position(position, "position")
        direction = None if axis is None else _unit_axis(axis)
        self.tolerance = _checked_tolerance(tolerance)
        self.max_iterations = as_count(max_iterations, "max_iterations", 1)
        self._problem = PoseError(robot, robot.tool_frame_id, target, None, direction)
        self._lower = robot.limits.lower
        self._upper = robot.limits.upper

    def __call__(self, q_start: FloatArray) -> FloatArray | None:
        """The converged configuration from ``q_start`` [rad or m], shape (n,), or None.

        ``q_start`` must be a float array of shape (n,) (not checked).
        """
        start = np.minimum(np.maximum(q_start, self._lower), self._upper)
        attempt = levenberg_marquardt(self._problem, start, self.tolerance, self.max_iterations)
        return attempt.q if attempt.worst_error <= self.tolerance else None


def _unit_axis(axis: ArrayLike) -> FloatArray:
    """``axis`` checked and normalised, shape (3,)."""
    direction = as_vector(axis, "axis", 3)
    norm = float(np.linalg.norm(direction))
    if norm < 1e-9:
        raise InvalidInputError(f"axis must be non-zero, got {direction}", name="axis")
    return direction / norm


def _checked_tolerance(tolerance: float) -> float:
    """The convergence tolerance as a float in (0, _MAX_TOLERANCE] [m or rad]."""
    return as_positive(tolerance, "tolerance", "m or rad", maximum=_MAX_TOLERANCE)


def _target_position(value: ArrayLike, name: str) -> FloatArray:
    """A target position [m], shape (3,), within MAX_TARGET_DISTANCE of the base."""
    position = as_vector(value, name, 3)
    for axis, coordinate in zip("xyz", position, strict=True):
        as_number(
            abs(coordinate),
            f"|{name} {axis}|",
            "m",
            maximum=MAX_TARGET_DISTANCE,
        )
    return position


def _checked_target(
    target: ArrayLike, axis: ArrayLike | None
) -> tuple[FloatArray, FloatArray | None, FloatArray | None]:
    """A target as ``(position [m], rotation (3, 3) or None, unit axis (3,) or None)``."""
    try:
        shape = np.shape(target)
    except ValueError:  # ragged input
        shape = None
    if shape not in ((3,), (4, 4)):
        raise InvalidInputError(
            f"target must be a position, shape (3,), or a pose T_world_frame, shape (4, 4); got "
            f"shape {shape if shape is not None else 'ragged'}",
            name="target",
        )
    if shape == (3,):
        position = _target_position(target, "target")
        return position, None, None if axis is None else _unit_axis(axis)
    if axis is not None:
        raise InvalidInputError(
            "axis goes with a position target (shape (3,)), not with a full pose",
            name="axis",
        )
    transform = as_transform(target, "target")
    return _target_position(transform[:3, 3], "target"), transform[:3, :3].copy(), None


@dataclass
class _Search:
    """The attempts of one :func:`solve_ik` call: the first, then random restarts.

    Attributes:
        problem: The target's pose error.
        locate: Its position-only error, for the first stage of a random full-pose (or
            position and axis) attempt; None for a position target.
        tolerance: Convergence threshold [m or rad].
        max_iterations: Iteration cap of each attempt.
        stall: Whether random restarts that stall are given up.
        min_solutions: Distinct solutions wanted.
        restarts: Most random restarts.
        attempts: Every attempt so far, in order.
        found: The distinct converged ones among them.
    """

    problem: PoseError
    locate: PoseError | None
    tolerance: float
    max_iterations: int
    stall: bool
    min_solutions: int
    restarts: int
    attempts: list[Attempt] = field(default_factory=list)
    found: list[Attempt] = field(default_factory=list)

    def keep(self, attempt: Attempt) -> bool:
        """Record an attempt; whether the search is over."""
        self.attempts.append(attempt)
        if attempt.worst_error <= self.tolerance and all(
            np.linalg.norm(attempt.q - other.q) > 1e-6 for other in self.found
        ):
            self.found.append(attempt)
        return len(self.found) >= self.min_solutions or len(self.attempts) > self.restarts

    def run(self, target: PoseError, starts: FloatArray, tolerance: float) -> list[Attempt]:
        """One attempt from each start: side by side when there are several."""
        iterations, stall = self.max_iterations, self.stall
        if len(starts) == 1:
            return [levenberg_marquardt(target, starts[0], tolerance, iterations, stall=stall)]
        return levenberg_marquardt_batch(target, starts, tolerance, iterations, stall=stall)

    def restart(self, rng: np.random.Generator) -> bool:
        """One batch of random restarts, kept in order; whether the search is over.

        Random restarts run in batches when many solutions are still wanted (see
        :func:`~optraj.robots.levenberg_marquardt.levenberg_marquardt_batch`), one by one
        otherwise, since a batch may overshoot the attempts needed. They are kept in order
        until the search would have stopped had they all run one by one and the rest of a
        batch is dropped: the attempts kept are those of a one-by-one search, up to rounding
        in the batched arithmetic (a Generator passed as the seed is advanced by whole
        batches).
        """
        problem, robot = self.problem, self.problem.robot
        wanted = self.min_solutions - len(self.found)
        size = min(
            self.restarts + 1 - len(self.attempts), 2 * wanted if wanted > _ONE_BY_ONE else 1
        )
        starts = robot.random_configurations(size, rng)
        batch: list[Attempt | None] = [None] * size
        if self.locate is not None:
            for index, located in enumerate(self.run(self.locate, starts, _LOCATE_TOLERANCE)):
                if located.stalled:  # given up: report the full error where it stopped
                    errors = problem.errors(problem.residual(robot.data, located.q)[0])
                    batch[index] = Attempt(located.q, errors[0], errors[1], 0, stalled=True)
                starts[index] = located.q
        going = [index for index in range(size) if batch[index] is None]
        if going:
            for index, attempt in zip(
                going, self.run(problem, starts[going], self.tolerance), strict=True
            ):
                batch[index] = attempt
        return any(attempt is not None and self.keep(attempt) for attempt in batch)


def _unreachable(search: _Search, what: str) -> UnreachableError:
    """The error of a search that found no solution, with the smallest error reached."""
    robot, problem = search.problem.robot, search.problem
    best = min(search.attempts, key=lambda attempt: attempt.worst_error)
    return UnreachableError(
        f"robot {robot.name!r}: no configuration within the joint limits reaches the target "
        f"{what} of frame {robot.model.frames[problem.frame_id].name!r}",
        position_error=best.position_error,
        orientation_error=best.orientation_error,
        attempts=len(search.attempts),
    )


def solve_ik(
    robot: Robot,
    target: ArrayLike,
    *,
    frame: str | None = None,
    axis: ArrayLike | None = None,
    q_near: ArrayLike | None = None,
    min_solutions: int = 1,
    restarts: int = 100,
    tolerance: float = 1e-9,
    max_iterations: int = 500,
    seed: int | np.random.Generator = 0,
    abandon_stalled: bool = False,
) -> IKSolution:
    """Joint configuration that puts a frame at a target pose or position.

    The first attempt starts at ``q_near`` (or the home pose); further attempts start at random
    configurations until ``min_solutions`` distinct solutions are found or ``restarts`` random
    attempts are spent. A random full-pose attempt first places the frame origin, then solves the
    pose. The solution closest to ``q_near`` (Euclidean joint distance) is returned.

    Args:
        robot: The robot.
        target: ``T_world_frame``, shape (4, 4), for a full pose, or a position [m], shape (3,),
            for position-only IK (or position + axis with ``axis``).
        frame: Frame to place; the tool frame when ``None``.
        axis: With a position target: the direction the frame's z axis must point along,
            shape (3,) (normalised here); rotation about it stays free (a cue's roll).
        q_near: Preferred configuration [rad or m], shape (n,); the home pose when ``None``.
        min_solutions: Distinct solutions to collect before choosing the closest; raise it to
            search more widely for a solution near ``q_near``.
        restarts: Most attempts from random configurations besides the first one.
        tolerance: Convergence threshold on position [m] and orientation [rad] errors, in
            (0, 1e-3].
        max_iterations: Iteration cap of each attempt (near singular solutions the error
            shrinks only linearly, so this is generous).
        seed: Seed or generator for the random restarts (results are reproducible).
        abandon_stalled: Give up a random restart that stalls: its error (the norm of the
            residual, [m] and [rad or -] together) still above 0.01 and less than 1 % below
            its value 10 iterations before, in either stage. Such starts mostly creep along the
            joint limits for many iterations and then fail, so this saves iterations when many
            solutions are wanted, at the price of the rare stalled start that would have
            converged; a robot whose solutions lie behind plateaus (youBot) loses some. The
            first attempt, from ``q_near``, is never given up.

    Returns:
        The solution, within the joint limits.

    Raises:
        UnreachableError: No attempt converged; reports the smallest error reached.
        InvalidInputError: Malformed target, q_near or settings.
        UnknownNameError: Unknown frame.
    """
    if not isinstance(robot, Robot):
        raise InvalidInputError(
            f"robot must be a robots.Robot, got {type(robot).__name__}", name="robot"
        )
    position, rotation, direction = _checked_target(target, axis)
    min_solutions = as_count(min_solutions, "min_solutions", 1)
    restarts = as_count(restarts, "restarts", 0)
    max_iterations = as_count(max_iterations, "max_iterations", 1)
    tol = _checked_tolerance(tolerance)
    if not isinstance(seed, np.random.Generator):
        as_count(seed, "seed (an integer >= 0 or a numpy Generator)", maximum=None)
    problem = PoseError(robot, robot.frame_id(frame), position, rotation, direction)
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    reference = robot.home if q_near is None else as_vector(q_near, "q_near", robot.dof)

    # A full-pose attempt first places the frame's origin, then its orientation: from a random
    # start this lands in the basin of a true solution more often than solving both at once.
    full = rotation is not None or direction is not None
    locate = PoseError(robot, problem.frame_id, position) if full else None
    stall = bool(abandon_stalled)
    search = _Search(problem, locate, tol, max_iterations, stall, min_solutions, restarts)
    # The first attempt, from the reference, is never given up.
    done = search.keep(
        levenberg_marquardt(problem, robot.limits.clip(reference), tol, max_iterations)
    )
    while not done:
        done = search.restart(rng)
    if not search.found:
        what = "pose" if rotation is not None else "position and axis" if full else "position"
        raise _unreachable(search, what)
    found = sorted(search.found, key=lambda attempt: float(np.linalg.norm(attempt.q - reference)))
    chosen = found[0]
    return IKSolution(
        q=chosen.q,
        position_error=chosen.position_error,
        orientation_error=chosen.orientation_error,
        iterations=sum(attempt.iterations for attempt in search.attempts),
        attempts=len(search.attempts),
        solutions=np.array([attempt.q for attempt in found]),
    )
