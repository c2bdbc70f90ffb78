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

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, UnreachableError
from optraj.robots.robot import Robot
from optraj.validation import as_count, as_number, as_positive, as_transform, as_vector

__all__ = ["IKSolution", "LocalIK", "solve_ik"]

FloatArray = NDArray[np.float64]

_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_MIN_DAMPING = 1e-12
_MAX_DAMPING = 1e8
#: Loosest convergence tolerance accepted [m or rad].
_MAX_TOLERANCE = 1e-3
#: Farthest target from the base [m]: no arm reaches a kilometre, and far beyond it the
#: squared residuals overflow (near 1e154 m).
MAX_TARGET_DISTANCE = 1e3
#: Position error at which the position-first stage of a random restart hands over [m].
_LOCATE_TOLERANCE = 1e-6
#: With ``abandon_stalled``, a random restart is given up when its error (residual norm),
#: still above _STALL_ERROR, has shrunk by less than 1 - _STALL_RATIO over the last
#: _STALL_WINDOW iterations.
_STALL_WINDOW = 10
_STALL_RATIO = 0.99
_STALL_ERROR = 1e-2
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


@dataclass
class _Attempt:
    q: FloatArray
    position_error: float
    orientation_error: float
    iterations: int
    stalled: bool = False  # given up early (see _levenberg_marquardt)

    @property
    def worst_error(self) -> float:
        """The larger of the position [m] and orientation [rad or -] errors."""
        return max(self.position_error, self.orientation_error)


#: Entries of a row-major 4 x 4 homogeneous transform: the origin, then the z axis.
_ORIGIN = np.array([3, 7, 11])
_ORIGIN_AND_Z = np.array([3, 7, 11, 2, 6, 10])


class _PoseError:
    """Residual and Jacobian of the frame pose error for one target.

    The orientation rows are ``log(R R*^T)`` for a full pose, ``z - a*`` (frame z axis minus
    the target axis) for an axis target, and absent for a position target. The methods take
    the Pinocchio workspace of the calling thread (``robot.data``) so that one object can serve
    repeated solves.
    """

    def __init__(
        self,
        robot: Robot,
        frame_id: int,
        position: FloatArray,
        rotation: FloatArray | None = None,
        axis: FloatArray | None = None,
    ) -> None:
        self.robot = robot
        self.model = robot.model
        self.frame_id = frame_id
        self.position = position
        self.rotation = rotation
        self.axis = axis
        self.lower = robot.limits.lower
        self.upper = robot.limits.upper
        # Identity matrices of every size, for the joints left free when some are held.
        self.identities = [np.eye(size) for size in range(robot.dof + 1)]
        # Position and axis targets read their residual straight off the frame's transform.
        if rotation is None:
            self._entries = _ORIGIN if axis is None else _ORIGIN_AND_Z
            self._target = position if axis is None else np.concatenate([position, axis])

    def residual(self, data: pin.Data, q: FloatArray) -> tuple[FloatArray, FloatArray | None]:
        """Stacked error [m; rad or -] and what the Jacobian needs of the orientation."""
        pin.forwardKinematics(self.model, data, q)
        pose = pin.updateFramePlacement(self.model, data, self.frame_id)
        if self.rotation is None:
            transform = pose.homogeneous
            residual = transform.ravel()[self._entries] - self._target
            return residual, (None if self.axis is None else transform[:3, 2])
        relative = pose.rotation @ self.rotation.T
        position_error = pose.translation - self.position
        return np.concatenate([position_error, pin.log3(relative)]), relative

    def jacobian(self, data: pin.Data, q: FloatArray, orientation: FloatArray | None) -> FloatArray:
        """d(residual)/dq, shape (3, n) or (6, n)."""
        jac = pin.computeFrameJacobian(self.model, data, q, self.frame_id, _WORLD_ALIGNED)
        if self.axis is not None:
            # The z axis turns as dz/dt = w x z = [-z]x w.
            jac[3:] = pin.skew(-orientation) @ jac[3:]
            return jac
        if orientation is None:
            return jac[:3]
        # Rotating the tool by w (world axes) turns R R*^T into exp(w) R R*^T
        # = (R R*^T) exp(R*R^T w): the log changes by Jlog3(R R*^T) (R R*^T)^T w.
        jac[3:] = pin.Jlog3(orientation) @ orientation.T @ jac[3:]
        return jac

    def errors(self, residual: FloatArray) -> tuple[float, float]:
        """Position error [m] and orientation error [rad] of a residual."""
        head = residual[:3]
        position = math.sqrt(float(head @ head))
        if residual.size == 3:
            return position, 0.0
        tail = residual[3:]
        gap = math.sqrt(float(tail @ tail))
        if self.axis is not None:  # |z - a| = 2 sin(angle / 2)
            return position, 2.0 * math.asin(min(1.0, 0.5 * gap))
        return position, gap


def _stalls(history: list[float], cost: float) -> bool:
    """Whether an attempt at this cost has stalled (see :data:`_STALL_WINDOW`).

    ``history`` holds the attempt's error (the residual norm) at the start of each earlier
    iteration; unless the attempt stalls, this one's is appended.
    """
    error = math.sqrt(cost)
    if (
        len(history) >= _STALL_WINDOW
        and error > _STALL_ERROR
        and error >= _STALL_RATIO * history[-_STALL_WINDOW]
    ):
        return True
    history.append(error)
    return False


def _unconverged_cost(tolerance: float) -> float:
    """A cost (squared residual norm) above which no attempt has converged to ``tolerance``.

    The worst error is at least sqrt(cost / 2) (position and orientation rows share the cost,
    and the axis angle exceeds the chord), so above this bound the exact test can wait (it is
    loosened well beyond rounding).
    """
    return 2.0 * (1.0 + 1e-6) * tolerance * tolerance


def _levenberg_marquardt(
    problem: _PoseError,
    q0: FloatArray,
    tolerance: float,
    max_iterations: int,
    *,
    stall: bool = False,
) -> _Attempt:
    """One Levenberg-Marquardt attempt from q0 [rad or m] down to ``tolerance`` [m or rad].

    With ``stall`` the attempt also gives up (``stalled``) once its error (the residual norm),
    still above :data:`_STALL_ERROR`, has shrunk by less than 1 - :data:`_STALL_RATIO` over the
    last :data:`_STALL_WINDOW` iterations.
    """
    data = problem.robot.data
    lower, upper, eye = problem.lower, problem.upper, problem.identities[-1]
    not_yet = _unconverged_cost(tolerance)
    q = q0.copy()
    residual, relative = problem.residual(data, q)
    cost = float(residual @ residual)
    damping = 1e-3
    iteration = 0
    history: list[float] = []
    stalled = False
    errors = None  # (position, orientation) errors of the current residual, once computed
    while iteration < max_iterations:
        if cost <= not_yet:
            errors = problem.errors(residual)
            if max(errors) <= tolerance:
                break
        if stall and _stalls(history, cost):
            stalled = True
            break
        iteration += 1
        jac = problem.jacobian(data, q, relative)
        gradient = jac.T @ residual
        free = None
        # (np.count_nonzero is the cheapest way to ask whether any entry is set.)
        if np.count_nonzero(q <= lower) or np.count_nonzero(q >= upper):
            # Joints on a limit that the gradient pushes outwards are held for this step.
            held = ((q <= lower) & (gradient > 0.0)) | ((q >= upper) & (gradient < 0.0))
            if np.count_nonzero(held):
                free = ~held
        if free is None:
            normal, identity, descent = jac.T @ jac, eye, -gradient
        else:
            jf = jac[:, free]
            normal, descent = jf.T @ jf, -gradient[free]
            identity = problem.identities[descent.size]
        while damping <= _MAX_DAMPING:
            solved = np.linalg.solve(normal + damping * identity, descent)
            if free is None:
                step = solved
            else:
                step = np.zeros_like(q)
                step[free] = solved
            candidate = np.minimum(np.maximum(q + step, lower), upper)
            new_residual, new_relative = problem.residual(data, candidate)
            new_cost = float(new_residual @ new_residual)
            if new_cost < cost:
                q, residual, relative, cost = candidate, new_residual, new_relative, new_cost
                damping = max(damping / 3.0, _MIN_DAMPING)
                errors = None
                break
            damping *= 4.0
        else:
            break  # no step lowers the error: a local minimum or a limit blocks the way
    if errors is None:
        errors = problem.errors(residual)
    return _Attempt(q, errors[0], errors[1], iteration, stalled)


def _levenberg_marquardt_batch(
    problem: _PoseError,
    starts: FloatArray,
    tolerance: float,
    max_iterations: int,
    *,
    stall: bool = False,
) -> list[_Attempt]:
    """:func:`_levenberg_marquardt` from each row of ``starts`` [rad or m], shape (k, n).

    The attempts run side by side: each takes the steps it would take alone (the same tests,
    damping updates and held joints; the stacked linear algebra may differ in the last bit),
    while the matrix products and solves of all attempts share one NumPy call each, whose
    overhead dominates the time of an attempt run alone.
    """
    data = problem.robot.data
    lower, upper = problem.lower, problem.upper
    count, n = starts.shape
    not_yet = _unconverged_cost(tolerance)
    q = starts.copy()
    first = [problem.residual(data, row) for row in q]
    residuals = np.array([residual for residual, _ in first])
    orientations = [orientation for _, orientation in first]
    cost = [float(residual @ residual) for residual in residuals]
    damping = [1e-3] * count
    iterations = [0] * count
    histories: list[list[float]] = [[] for _ in range(count)]
    stalled = [False] * count
    normal = np.empty((count, n, n))
    descent = np.empty((count, n))
    running = list(range(count))
    moved = set(running)  # at a new iterate: test it, then linearise there
    eye = problem.identities[-1]
    while running:
        trying, linearised = [], []
        for i in running:
            if i in moved:
                if iterations[i] >= max_iterations:
                    continue
                if cost[i] <= not_yet and max(problem.errors(residuals[i])) <= tolerance:
                    continue
                if stall and _stalls(histories[i], cost[i]):
                    stalled[i] = True
                    continue
                iterations[i] += 1
                linearised.append(i)
            trying.append(i)
        if not trying:
            break
        if linearised:
            rows = np.array(linearised)
            jac = np.array([problem.jacobian(data, q[i], orientations[i]) for i in linearised])
            jac_t = jac.transpose(0, 2, 1)
            gradient = (jac_t @ residuals[rows][:, :, None])[:, :, 0]
            normals = jac_t @ jac
            here = q[rows]
            # Joints on a limit that the gradient pushes outwards are held for the step: their
            # rows and columns are cleared, so the damped solve gives them a zero step.
            held = ((here <= lower) & (gradient > 0.0)) | ((here >= upper) & (gradient < 0.0))
            if np.count_nonzero(held):
                free = ~held
                normals *= free[:, :, None] & free[:, None, :]
                gradient *= free
            normal[rows] = normals
            descent[rows] = -gradient
        rows = np.array(trying)
        factors = np.array([damping[i] for i in trying])
        steps = np.linalg.solve(normal[rows] + factors[:, None, None] * eye, descent[rows, :, None])
        candidates = np.minimum(np.maximum(q[rows] + steps[:, :, 0], lower), upper)
        running = []
        for candidate, i in zip(candidates, trying, strict=True):
            residual, orientation = problem.residual(data, candidate)
            new_cost = float(residual @ residual)
            if new_cost < cost[i]:
                q[i], residuals[i], orientations[i] = candidate, residual, orientation
                cost[i] = new_cost
                damping[i] = max(damping[i] / 3.0, _MIN_DAMPING)
                moved.add(i)
                running.append(i)
                continue
            damping[i] *= 4.0
            moved.discard(i)
            if damping[i] <= _MAX_DAMPING:  # else no step lowers the error: given up
                running.append(i)
    attempts = []
    for i in range(count):
        position_error, orientation_error = problem.errors(residuals[i])
        attempts.append(
            _Attempt(q[i].copy(), position_error, orientation_error, iterations[i], stalled[i])
        )
    return attempts


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
        if not isinstance(robot, Robot):
            raise InvalidInputError(
                f"robot must be a robots.Robot, got {type(robot).__name__}", name="robot"
            )
        target = _target_position(position, "position")
        direction = None if axis is None else _unit_axis(axis)
        self.tolerance = _checked_tolerance(tolerance)
        self.max_iterations = as_count(max_iterations, "max_iterations", 1)
        self._problem = _PoseError(robot, robot.tool_frame_id, target, None, direction)
        self._lower = robot.limits.lower
        self._upper = robot.limits.upper

    def __call__(self, q_start: FloatArray) -> FloatArray | None:
        """The converged configuration from ``q_start`` [rad or m], shape (n,), or None.

        ``q_start`` must be a float array of shape (n,) (not checked).
        """
        start = np.minimum(np.maximum(q_start, self._lower), self._upper)
        attempt = _levenberg_marquardt(self._problem, start, self.tolerance, self.max_iterations)
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
            joint limits for many iterations and then fail, so this saves about half of the
            iterations when many solutions are wanted (on Sawyer pool shots about 1 stalled
            start in 400 would have converged); a robot whose solutions lie behind plateaus
            (youBot) loses some. The first attempt, from ``q_near``, is never given up.

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
    position_only = shape == (3,)
    direction = None
    if position_only:
        position, rotation = _target_position(target, "target"), None
        if axis is not None:
            direction = _unit_axis(axis)
    else:
        if axis is not None:
            raise InvalidInputError(
                "axis goes with a position target (shape (3,)), not with a full pose",
                name="axis",
            )
        transform = as_transform(target, "target")
        position, rotation = _target_position(transform[:3, 3], "target"), transform[:3, :3].copy()
    min_solutions = as_count(min_solutions, "min_solutions", 1)
    restarts = as_count(restarts, "restarts", 0)
    max_iterations = as_count(max_iterations, "max_iterations", 1)
    tol = _checked_tolerance(tolerance)
    if not isinstance(seed, np.random.Generator):
        as_count(seed, "seed (an integer >= 0 or a numpy Generator)", maximum=None)
    problem = _PoseError(robot, robot.frame_id(frame), position, rotation, direction)
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    reference = robot.home if q_near is None else as_vector(q_near, "q_near", robot.dof)

    # A full-pose attempt first places the frame's origin, then its orientation: from a random
    # start this lands in the basin of a true solution more often than solving both at once
    # (on hard 5-DOF youBot targets, 26% of starts instead of 18%).
    full = rotation is not None or direction is not None
    locate = _PoseError(robot, problem.frame_id, position) if full else None

    def keep(attempt: _Attempt) -> bool:
        """Record an attempt; whether the search is over."""
        attempts.append(attempt)
        if attempt.worst_error <= tol and all(
            np.linalg.norm(attempt.q - other.q) > 1e-6 for other in found
        ):
            found.append(attempt)
        return len(found) >= min_solutions or len(attempts) > restarts

    attempts: list[_Attempt] = []
    found: list[_Attempt] = []
    # The first attempt, from the reference, is never given up.
    done = keep(_levenberg_marquardt(problem, robot.limits.clip(reference), tol, max_iterations))
    stall = bool(abandon_stalled)

    def run(target: _PoseError, starts: FloatArray, tolerance: float) -> list[_Attempt]:
        """One attempt from each start: side by side when there are several."""
        if len(starts) == 1:
            return [_levenberg_marquardt(target, starts[0], tolerance, max_iterations, stall=stall)]
        return _levenberg_marquardt_batch(target, starts, tolerance, max_iterations, stall=stall)

    while not done:
        # Random restarts run in batches when many solutions are still wanted (see
        # _levenberg_marquardt_batch), one by one otherwise, since a batch may overshoot the
        # attempts needed. They are kept in order until the search would have stopped had
        # they all run one by one and the rest of a batch is dropped: the attempts kept are
        # those of a one-by-one search, up to rounding in the batched arithmetic (a Generator
        # passed as the seed is advanced by whole batches).
        wanted = min_solutions - len(found)
        size = min(restarts + 1 - len(attempts), 2 * wanted if wanted > _ONE_BY_ONE else 1)
        starts = robot.random_configurations(size, rng)
        batch: list[_Attempt | None] = [None] * size
        if locate is not None:
            for index, located in enumerate(run(locate, starts, _LOCATE_TOLERANCE)):
                if located.stalled:  # given up: report the full error where it stopped
                    errors = problem.errors(problem.residual(robot.data, located.q)[0])
                    batch[index] = _Attempt(located.q, errors[0], errors[1], 0, stalled=True)
                starts[index] = located.q
        going = [index for index in range(size) if batch[index] is None]
        if going:
            for index, attempt in zip(going, run(problem, starts[going], tol), strict=True):
                batch[index] = attempt
        for attempt in batch:
            if attempt is not None and keep(attempt):
                done = True
                break
    iterations = sum(attempt.iterations for attempt in attempts)
    if not found:
        best = min(attempts, key=lambda attempt: attempt.worst_error)
        what = "pose" if rotation is not None else "position and axis" if full else "position"
        raise UnreachableError(
            f"robot {robot.name!r}: no configuration within the joint limits reaches the target "
            f"{what} of frame {robot.model.frames[problem.frame_id].name!r}",
            position_error=best.position_error,
            orientation_error=best.orientation_error,
            attempts=len(attempts),
        )
    found.sort(key=lambda attempt: float(np.linalg.norm(attempt.q - reference)))
    chosen = found[0]
    return IKSolution(
        q=chosen.q,
        position_error=chosen.position_error,
        orientation_error=chosen.orientation_error,
        iterations=iterations,
        attempts=len(attempts),
        solutions=np.array([attempt.q for attempt in found]),
    )
