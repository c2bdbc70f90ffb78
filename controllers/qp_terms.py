r"""Small pieces of the differential-IK QP, and the one function that adds them up.

The decision variable is the joint velocity command :math:`\dot q` [rad/s or m/s], shape (n,).
Objective pieces return :class:`Objective` ``(H, c)`` for :math:`\tfrac12 \dot q^T H \dot q +
c^T \dot q`; box limits on :math:`\dot q` return :class:`Bounds`; any other linear rows return
:class:`Constraint` ``lower <= G qd <= upper``. :func:`combine` adds the objectives, intersects
the bounds in priority order and stacks the rows into one :class:`QP`.

.. math::

    \min_{\dot q} \; \tfrac12 \| J \dot q - v \|_W^2 + \tfrac{\lambda}{2} \|\dot q\|^2
    + \tfrac{w}{2} \| \dot q - (\dot q_{ref} + k (q_{ref} - q)) \|^2

The pieces take plain arrays (no robot, no state), so that each is tested on its own.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError

__all__ = [
    "QP",
    "Bounds",
    "Constraint",
    "Objective",
    "acceleration_bounds",
    "combine",
    "damping_objective",
    "identity",
    "position_bounds",
    "posture_objective",
    "task_objective",
    "task_weights",
    "velocity_bounds",
]

FloatArray = NDArray[np.float64]


class Objective(NamedTuple):
    r"""A quadratic cost :math:`\tfrac12 x^T H x + c^T x`.

    Attributes:
        H: Symmetric positive semi-definite, shape (n, n).
        c: Shape (n,).
    """

    H: FloatArray
    c: FloatArray


class Bounds(NamedTuple):
    """Box limits on the joint velocity command, ``lower <= qd <= upper``.

    Attributes:
        lower: Shape (n,) [rad/s or m/s].
        upper: Shape (n,) [rad/s or m/s].
        name: Which limit they come from, e.g. ``"velocity"``; named when relaxed.
    """

    lower: FloatArray
    upper: FloatArray
    name: str


class Constraint(NamedTuple):
    """Linear rows ``lower <= G qd <= upper``.

    Attributes:
        G: Shape (m, n).
        lower: Shape (m,); ``-inf`` for none.
        upper: Shape (m,); ``+inf`` for none.
    """

    G: FloatArray
    lower: FloatArray
    upper: FloatArray


class QP(NamedTuple):
    """The assembled problem ``min 1/2 x'Hx + c'x  s.t.  lower <= A x <= upper``.

    Attributes:
        H: Shape (n, n).
        c: Shape (n,).
        A: The identity for the bounds, then every constraint row, shape (n + m, n).
        lower: Shape (n + m,).
        upper: Shape (n + m,).
        relaxed: Names of bounds that conflicted with higher-priority ones and were relaxed
            to the nearest feasible value (empty when all hold together).
    """

    H: FloatArray
    c: FloatArray
    A: FloatArray
    lower: FloatArray
    upper: FloatArray
    relaxed: tuple[str, ...]


# ----------------------------------------------------------------------------- objectives


def task_weights(linear: float, angular: float, axis: FloatArray | None = None) -> FloatArray:
    """Task weight matrix ``W`` in world axes, shape (6, 6).

    Args:
        linear: Weight of the linear velocity error [1/(m/s)^2 relative].
        angular: Weight of the angular velocity error [1/(rad/s)^2 relative].
        axis: Tool z axis in world axes, shape (3,), for a 5-D task: the angular velocity
            about it is left free (its weight is 0). ``None`` for the full 6-D task.
    """
    W = np.diag([linear, linear, linear, angular, angular, angular])
    if axis is not None:
        W[3:, 3:] -= angular * (axis[:, None] * axis)
    return W


def task_objective(J: FloatArray, v: FloatArray, W: FloatArray) -> Objective:
    r"""Track a tool twist: :math:`\tfrac12 \|J \dot q - v\|_W^2` (constant dropped).

    Args:
        J: Task Jacobian, shape (6, n).
        v: Wanted twist [m/s; rad/s], shape (6,).
        W: Symmetric PSD weights, shape (6, 6), or the diagonal of a diagonal ``W``, shape (6,)
            (cheaper: one scaling instead of a matrix product).
    """
    WJ = W[:, None] * J if W.ndim == 1 else W @ J
    return Objective(J.T @ WJ, -(v @ WJ))


def damping_objective(n: int, damping: float) -> Objective:
    r"""Levenberg-Marquardt damping :math:`\tfrac{\lambda}{2}\|\dot q\|^2`, keeps H positive."""
    return Objective(damping * np.eye(n), np.zeros(n))


def posture_objective(
    q: FloatArray,
    q_posture: FloatArray,
    weight: float,
    gain: float,
    qd_posture: FloatArray | None = None,
) -> Objective:
    r"""Pull towards a moving posture: :math:`\tfrac{w}{2}\|\dot q - (\dot q_p + k (q_p - q))\|^2`.

    On a redundant arm this sets the self-motion the task leaves free; keep ``weight`` small
    against the task so that it does not bend the tool path. With the planned joint velocity
    as ``qd_posture`` the self-motion follows the plan's instead of only being pulled back to
    its positions (constant dropped):

    .. math:: H = w I, \qquad c = w k (q - q_p) - w \dot q_p.

    Args:
        q: Joint positions now [rad or m], shape (n,).
        q_posture: Posture to move towards, e.g. the planned joint positions, shape (n,).
        weight: Weight ``w`` relative to the task [-].
        gain: Rate ``k`` at which the posture error is closed [1/s].
        qd_posture: Velocity of the posture [rad/s or m/s], e.g. the planned joint
            velocities, shape (n,); None for a posture at rest.
    """
    c = (weight * gain) * (q - q_posture)
    if qd_posture is not None:
        c -= weight * qd_posture
    return Objective(weight * identity(q.size), c)


# ---------------------------------------------------------------------------------- bounds


def velocity_bounds(velocity: FloatArray, scale: float = 1.0) -> Bounds:
    """``-scale v_max <= qd <= scale v_max`` [rad/s or m/s]."""
    limit = scale * velocity
    return Bounds(-limit, limit, "velocity")


def acceleration_bounds(qd_last: FloatArray, acceleration: FloatArray, dt: float) -> Bounds:
    """The command may change by at most ``a_max dt`` from the last one in a step.

    Args:
        qd_last: Last command [rad/s or m/s], shape (n,).
        acceleration: Acceleration limits [rad/s^2 or m/s^2], shape (n,).
        dt: Control period [s].
    """
    step = acceleration * dt
    return Bounds(qd_last - step, qd_last + step, "acceleration")


def position_bounds(
    q: FloatArray,
    lower: FloatArray,
    upper: FloatArray,
    acceleration: FloatArray,
    dt: float,
    gain: float = 0.95,
) -> Bounds:
    r"""Stay within the position limits over the next step and keep room to brake.

    .. math::

        \dot q \le \min\left(k \frac{q_{max} - q}{\Delta t},\;
        -a_{max} \Delta t + \sqrt{(a_{max} \Delta t)^2 + 2 a_{max} (q_{max} - q)}\right)

    and symmetrically below. The second term is the fastest speed ``u`` from which a joint
    commanded in steps of ``dt``, first ``u`` for one step and then slowing by ``a_max dt`` per
    step, still stops at the limit: it covers ``u^2 / (2 a_max) + u dt`` at most. A joint
    already beyond a limit is asked to move back.

    Args:
        q: Joint positions [rad or m], shape (n,).
        lower: Lower position limits, shape (n,).
        upper: Upper position limits, shape (n,).
        acceleration: Acceleration limits [rad/s^2 or m/s^2], shape (n,).
        dt: Control period [s].
        gain: Fraction of the distance to the limit that one step may cover, in (0, 1].
    """
    n = q.size
    room = np.concatenate((upper - q, q - lower))  # [to the upper limit; to the lower one]
    a = np.concatenate((acceleration, acceleration))  # for both sides
    step = a * dt
    brake = np.sqrt(step * step + (a + a) * np.maximum(room, 0.0)) - step
    speed = np.minimum((gain / dt) * room, brake)
    return Bounds(-speed[n:], speed[:n], "position")


# -------------------------------------------------------------------------------- combine


def combine(
    objectives: Sequence[Objective],
    bounds: Sequence[Bounds] = (),
    constraints: Sequence[Constraint] = (),
) -> QP:
    """Add the objectives, intersect the bounds, stack the constraint rows.

    Bounds are intersected in the order given, which is their priority: when a later bound
    leaves no room next to the earlier ones (a joint pushed beyond its position limit while
    the acceleration bound forbids turning back at once), that joint keeps the value of the
    earlier interval nearest to it, and the bound's name is listed in ``QP.relaxed``.

    Called at every control step, so it checks shapes but otherwise keeps to few array
    operations: with no constraint rows, ``QP.A`` is a shared read-only identity.

    Raises:
        InvalidInputError: No objective, pieces that are not an Objective, Bounds or
            Constraint, shapes that disagree, or a first bound with lower > upper.
    """
    if not objectives:
        raise InvalidInputError("combine needs at least one objective", name="objectives")
    for pieces, kind, name in (
        (objectives, Objective, "objectives"),
        (bounds, Bounds, "bounds"),
        (constraints, Constraint, "constraints"),
    ):
        if not isinstance(pieces, (list, tuple)) or not all(
            isinstance(piece, kind) for piece in pieces
        ):
            raise InvalidInputError(
                f"{name} must be a list or tuple of controllers.{kind.__name__}, got "
                f"{type(pieces).__name__}",
                name=name,
            )
    n = objectives[0].c.size
    for objective in objectives:
        if objective.H.shape != (n, n) or objective.c.shape != (n,):
            raise InvalidInputError(
                f"objective shapes {objective.H.shape}, {objective.c.shape} differ from "
                f"({n}, {n}), ({n},)",
                name="objectives",
            )
    H = objectives[0].H.copy()  # the sum must not share memory with a piece
    c = objectives[0].c.copy()
    for objective in objectives[1:]:
        H += objective.H
        c += objective.c
    lower, upper, relaxed = _intersect(bounds, n)
    if not constraints:
        return QP(H, c, identity(n), lower, upper, relaxed)
    rows = [identity(n)]
    row_lower = [lower]
    row_upper = [upper]
    for constraint in constraints:
        if constraint.G.ndim != 2 or constraint.G.shape[1] != n:
            raise InvalidInputError(
                f"constraint G must have shape (m, {n}), got {constraint.G.shape}",
                name="constraints",
            )
        rows.append(constraint.G)
        row_lower.append(constraint.lower)
        row_upper.append(constraint.upper)
    return QP(
        H,
        c,
        np.vstack(rows),
        np.concatenate(row_lower),
        np.concatenate(row_upper),
        relaxed,
    )


def _intersect(bounds: Sequence[Bounds], n: int) -> tuple[FloatArray, FloatArray, tuple[str, ...]]:
    """Intersect boxes in priority order: (lower, upper, names of the relaxed ones).

    The usual case, where every box overlaps the others, takes one pass; only when the
    intersection comes out empty are the boxes gone through one by one to relax the later ones.
    """
    if not bounds:
        return np.full(n, -math.inf), np.full(n, math.inf), ()
    lower, upper = bounds[0].lower, bounds[0].upper
    for box in bounds[1:]:
        lower = np.maximum(lower, box.lower)
        upper = np.minimum(upper, box.upper)
    if len(bounds) > 1 and not (lower > upper).any():
        return lower, upper, ()
    lower = np.full(n, -math.inf)
    upper = np.full(n, math.inf)
    relaxed: list[str] = []
    for index, box in enumerate(bounds):
        new_lower = np.maximum(lower, box.lower)
        new_upper = np.minimum(upper, box.upper)
        empty = new_lower > new_upper
        if empty.any():
            if index == 0:
                j = int(np.flatnonzero(empty)[0])
                raise InvalidInputError(
                    f"{box.name} bounds of joint {j}: lower {box.lower[j]:.6g} > upper "
                    f"{box.upper[j]:.6g}",
                    name="bounds",
                )
            nearest = np.where(box.upper < lower, lower, upper)
            new_lower = np.where(empty, nearest, new_lower)
            new_upper = np.where(empty, nearest, new_upper)
            relaxed.append(box.name)
        lower, upper = new_lower, new_upper
    return lower, upper, tuple(relaxed)


@functools.cache
def identity(n: int) -> FloatArray:
    """The n x n identity, shared and read-only."""
    identity = np.eye(n)
    identity.flags.writeable = False
    return identity
