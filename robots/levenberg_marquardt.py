"""Levenberg-Marquardt iterations on a frame's pose error, within the joint limits.

Joints that sit on a position limit and are pushed outwards are held there for the step (an
active set), so every iterate lies within the limits. :func:`levenberg_marquardt` runs one
attempt; :func:`levenberg_marquardt_batch` runs several side by side.

The pose error is ``[p(q) - p*; log(R(q) R*^T)]`` in world axes [m; rad]; for a position-only
target only the first three rows are used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from optraj.robots.robot import Robot

__all__ = [
    "STALL_ERROR",
    "STALL_RATIO",
    "STALL_WINDOW",
    "Attempt",
    "PoseError",
    "levenberg_marquardt",
    "levenberg_marquardt_batch",
]

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_MIN_DAMPING = 1e-12
_MAX_DAMPING = 1e8
#: With ``stall``, an attempt is given up when its error (residual norm), still above
#: STALL_ERROR, has shrunk by less than 1 - STALL_RATIO over the last STALL_WINDOW iterations.
STALL_WINDOW = 10
STALL_RATIO = 0.99
STALL_ERROR = 1e-2


@dataclass
class Attempt:
    """Where one attempt ended.

    Attributes:
        q: Its last iterate [rad or m], shape (n,).
        position_error: Distance from the target position there [m].
        orientation_error: Angle to the target orientation there [rad]; 0 without one.
        iterations: Iterations it took.
        stalled: Given up early (see :func:`levenberg_marquardt`).
    """

    q: FloatArray
    position_error: float
    orientation_error: float
    iterations: int
    stalled: bool = False

    @property
    def worst_error(self) -> float:
        """The larger of the position [m] and orientation [rad or -] errors."""
        return max(self.position_error, self.orientation_error)


#: Entries of a row-major 4 x 4 homogeneous transform: the origin, then the z axis.
_ORIGIN = np.array([3, 7, 11])
_ORIGIN_AND_Z = np.array([3, 7, 11, 2, 6, 10])


class PoseError:
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
        """Hold the target: a position [m], and a rotation (3, 3) or a unit axis (3,) or none."""
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
            assert orientation is not None  # an axis target's residual gives the z axis
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
    """Whether an attempt at this cost has stalled (see :data:`STALL_WINDOW`).

    ``history`` holds the attempt's error (the residual norm) at the start of each earlier
    iteration; unless the attempt stalls, this one's is appended.
    """
    error = math.sqrt(cost)
    if (
        len(history) >= STALL_WINDOW
        and error > STALL_ERROR
        and error >= STALL_RATIO * history[-STALL_WINDOW]
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


def _free_joints(
    q: FloatArray, lower: FloatArray, upper: FloatArray, gradient: FloatArray
) -> BoolArray | None:
    """The joints free to move this step, or None when none is held.

    Joints on a limit that the gradient pushes outwards are held for the step.
    """
    # (np.count_nonzero is the cheapest way to ask whether any entry is set.)
    if np.count_nonzero(q <= lower) or np.count_nonzero(q >= upper):
        held = ((q <= lower) & (gradient > 0.0)) | ((q >= upper) & (gradient < 0.0))
        if np.count_nonzero(held):
            return ~held
    return None


def _normal_equations(
    problem: PoseError, jac: FloatArray, gradient: FloatArray, free: BoolArray | None
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``(J'J, identity, -J'r)`` over the free joints (all of them when ``free`` is None)."""
    if free is None:
        return jac.T @ jac, problem.identities[-1], -gradient
    jf = jac[:, free]
    normal, descent = jf.T @ jf, -gradient[free]
    return normal, problem.identities[descent.size], descent


_Iterate = tuple[FloatArray, FloatArray, FloatArray | None, float]
"""An accepted iterate: ``(q, residual, orientation, cost)``."""


def _damped_step(
    problem: PoseError,
    data: pin.Data,
    q: FloatArray,
    cost: float,
    damping: float,
    system: tuple[FloatArray, FloatArray, FloatArray],
    free: BoolArray | None,
) -> tuple[_Iterate | None, float]:
    """Raise the damping until a clipped step lowers the cost: (the new iterate, damping).

    The iterate is None when no damping up to the largest lowers the cost.
    """
    normal, identity, descent = system
    lower, upper = problem.lower, problem.upper
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
            iterate = (candidate, new_residual, new_relative, new_cost)
            return iterate, max(damping / 3.0, _MIN_DAMPING)
        damping *= 4.0
    return None, damping


def levenberg_marquardt(
    problem: PoseError,
    q0: FloatArray,
    tolerance: float,
    max_iterations: int,
    *,
    stall: bool = False,
) -> Attempt:
    """One Levenberg-Marquardt attempt from q0 [rad or m] down to ``tolerance`` [m or rad].

    With ``stall`` the attempt also gives up (``stalled``) once its error (the residual norm),
    still above :data:`STALL_ERROR`, has shrunk by less than 1 - :data:`STALL_RATIO` over the
    last :data:`STALL_WINDOW` iterations.
    """
    data = problem.robot.data
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
        free = _free_joints(q, problem.lower, problem.upper, gradient)
        system = _normal_equations(problem, jac, gradient, free)
        iterate, damping = _damped_step(problem, data, q, cost, damping, system, free)
        if iterate is None:
            break  # no step lowers the error: a local minimum or a limit blocks the way
        q, residual, relative, cost = iterate
        errors = None
    if errors is None:
        errors = problem.errors(residual)
    return Attempt(q, errors[0], errors[1], iteration, stalled)


@dataclass
class _Batch:
    """The state of attempts run side by side: row ``i`` of each field is attempt ``i``'s."""

    q: FloatArray
    residuals: FloatArray
    orientations: list[FloatArray | None]
    cost: list[float]
    damping: list[float]
    normal: FloatArray
    descent: FloatArray
    iterations: list[int] = field(default_factory=list)
    histories: list[list[float]] = field(default_factory=list)
    stalled: list[bool] = field(default_factory=list)

    @classmethod
    def start(cls, problem: PoseError, data: pin.Data, starts: FloatArray) -> _Batch:
        """The attempts at their starts [rad or m], shape (k, n)."""
        count, n = starts.shape
        q = starts.copy()
        first = [problem.residual(data, row) for row in q]
        residuals = np.array([residual for residual, _ in first])
        return cls(
            q=q,
            residuals=residuals,
            orientations=[orientation for _, orientation in first],
            cost=[float(residual @ residual) for residual in residuals],
            damping=[1e-3] * count,
            normal=np.empty((count, n, n)),
            descent=np.empty((count, n)),
            iterations=[0] * count,
            histories=[[] for _ in range(count)],
            stalled=[False] * count,
        )

    def attempts(self, problem: PoseError) -> list[Attempt]:
        """Where every attempt ended."""
        attempts = []
        for i in range(len(self.cost)):
            position_error, orientation_error = problem.errors(self.residuals[i])
            attempts.append(
                Attempt(
                    self.q[i].copy(),
                    position_error,
                    orientation_error,
                    self.iterations[i],
                    self.stalled[i],
                )
            )
        return attempts


def _batch_linearise(
    problem: PoseError, data: pin.Data, batch: _Batch, linearised: list[int]
) -> None:
    """Store the (held-joint masked) normal equations of the ``linearised`` attempts."""
    rows = np.array(linearised)
    jac = np.array([problem.jacobian(data, batch.q[i], batch.orientations[i]) for i in linearised])
    jac_t = jac.transpose(0, 2, 1)
    gradient = (jac_t @ batch.residuals[rows][:, :, None])[:, :, 0]
    normals = jac_t @ jac
    here = batch.q[rows]
    lower, upper = problem.lower, problem.upper
    # Joints on a limit that the gradient pushes outwards are held for the step: their
    # rows and columns are cleared, so the damped solve gives them a zero step.
    held = ((here <= lower) & (gradient > 0.0)) | ((here >= upper) & (gradient < 0.0))
    if np.count_nonzero(held):
        free = ~held
        normals *= free[:, :, None] & free[:, None, :]
        gradient *= free
    batch.normal[rows] = normals
    batch.descent[rows] = -gradient


def _batch_try(
    problem: PoseError, data: pin.Data, batch: _Batch, trying: list[int], moved: set[int]
) -> list[int]:
    """One damped step of each attempt in ``trying``; the attempts still running."""
    eye = problem.identities[-1]
    rows = np.array(trying)
    factors = np.array([batch.damping[i] for i in trying])
    steps = np.linalg.solve(
        batch.normal[rows] + factors[:, None, None] * eye, batch.descent[rows, :, None]
    )
    candidates = np.minimum(
        np.maximum(batch.q[rows] + steps[:, :, 0], problem.lower), problem.upper
    )
    running = []
    for candidate, i in zip(candidates, trying, strict=True):
        residual, orientation = problem.residual(data, candidate)
        new_cost = float(residual @ residual)
        if new_cost < batch.cost[i]:
            batch.q[i], batch.residuals[i], batch.orientations[i] = candidate, residual, orientation
            batch.cost[i] = new_cost
            batch.damping[i] = max(batch.damping[i] / 3.0, _MIN_DAMPING)
            moved.add(i)
            running.append(i)
            continue
        batch.damping[i] *= 4.0
        moved.discard(i)
        if batch.damping[i] <= _MAX_DAMPING:  # else no step lowers the error: given up
            running.append(i)
    return running


def levenberg_marquardt_batch(
    problem: PoseError,
    starts: FloatArray,
    tolerance: float,
    max_iterations: int,
    *,
    stall: bool = False,
) -> list[Attempt]:
    """:func:`levenberg_marquardt` from each row of ``starts`` [rad or m], shape (k, n).

    The attempts run side by side: each takes the steps it would take alone (the same tests,
    damping updates and held joints; the stacked linear algebra may differ in the last bit),
    while the matrix products and solves of all attempts share one NumPy call each, whose
    overhead dominates the time of an attempt run alone.
    """
    data = problem.robot.data
    not_yet = _unconverged_cost(tolerance)
    batch = _Batch.start(problem, data, starts)
    running = list(range(starts.shape[0]))
    moved = set(running)  # at a new iterate: test it, then linearise there
    while running:
        trying, linearised = [], []
        for i in running:
            if i in moved:
                if batch.iterations[i] >= max_iterations:
                    continue
                if (
                    batch.cost[i] <= not_yet
                    and max(problem.errors(batch.residuals[i])) <= tolerance
                ):
                    continue
                if stall and _stalls(batch.histories[i], batch.cost[i]):
                    batch.stalled[i] = True
                    continue
                batch.iterations[i] += 1
                linearised.append(i)
            trying.append(i)
        if not trying:
            break
        if linearised:
            _batch_linearise(problem, data, batch, linearised)
        running = _batch_try(problem, data, batch, trying, moved)
    return batch.attempts(problem)
