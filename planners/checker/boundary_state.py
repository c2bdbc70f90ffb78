"""The ``start state`` / ``end state`` finding of a :class:`problems.BoundaryState`.

The finding reports the largest deviation of the prescribed q (if given), qd and qdd (if
given) at that end of the trajectory; it passes when each is within the state's tolerance
plus round-off (:func:`~planners.checker.allowance.state_allowance`, the rule the boundary
jumps of :mod:`planners.checker.jumps` use too).

Example::

    wanted = boundary_wanted(state, limits.n)
    evaluations.append(boundary_state_check(state, wanted, ctx))
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.checker.allowance import state_allowance
from optraj.planners.checker.context import CheckContext
from optraj.planners.checker.joint_limits import ORDER_NAME
from optraj.planners.checker.report import Finding
from optraj.planners.checker.task import (
    Evaluation,
    constraint_tolerance,
    constraint_vector,
    task_finding,
)
from optraj.problems.constraints import BoundaryState

__all__ = ["boundary_state_check", "boundary_wanted"]

FloatArray = NDArray[np.float64]
_STATE_NAME = ("q", "qd", "qdd")


def boundary_wanted(state: BoundaryState, n: int) -> list[FloatArray | None]:
    """A boundary state's validated q, qd, qdd (None where not prescribed), each shape (n,)."""
    if state.at not in ("start", "end"):
        raise InvalidInputError(
            f"BoundaryState.at must be 'start' or 'end', got {state.at!r}", name="at"
        )
    return [
        None if state.q is None else constraint_vector(state.q, "BoundaryState.q", n),
        constraint_vector(state.qd, "BoundaryState.qd", n),
        None if state.qdd is None else constraint_vector(state.qdd, "BoundaryState.qdd", n),
    ]


def boundary_state_check(
    state: BoundaryState, wanted: list[FloatArray | None], ctx: CheckContext
) -> Evaluation:
    """``start state`` / ``end state``: largest deviation of q (if given), qd, qdd (if given).

    The finding passes when every prescribed quantity is within the state's tolerance plus
    round-off (:func:`state_allowance`, the rule the boundary jumps use too); it reports the
    largest deviation, or, when some quantity fails, the one that misses by the most.
    """
    time = 0.0 if state.at == "start" else ctx.duration
    tolerance = constraint_tolerance(state.tolerance, "BoundaryState.tolerance")

    def evaluate() -> list[Finding]:
        actual = ctx.state(time)
        allowed = state_allowance(wanted, actual[1:], tolerance, ctx.limits, ctx.duration)
        value, order, j = _worst_deviation(wanted, allowed, actual)
        quantity = ORDER_NAME[order]
        unit = ctx.limits.unit(quantity, j)
        target = wanted[order]
        bound = allowed[order]
        if target is None or bound is None:  # unreachable: qd is always prescribed
            raise RuntimeError("boundary state without a prescribed velocity")
        detail = (
            f"{_STATE_NAME[order]} of joint {ctx.names[j]!r} is {actual[order][j]:.6g} {unit}, "
            f"prescribed {target[j]:.6g} {unit}"
        )
        slack = float(bound[j]) - tolerance
        name = f"{state.at} state"
        return [
            task_finding(
                name, value, tolerance, time, unit, detail, joint=ctx.names[j], slack=slack
            )
        ]

    return evaluate


def _worst_deviation(
    wanted: list[FloatArray | None],
    allowed: list[FloatArray | None],
    actual: list[FloatArray],
) -> tuple[float, int, int]:
    """The deviation to report: (value, order, joint).

    The largest deviation over the prescribed quantities, or, when some quantity misses its
    allowance, the one that misses by the most.
    """
    best = (-math.inf, -1.0, 0, 0)  # (failing, error, order, joint), largest wins
    for order, target in enumerate(wanted):
        bound = allowed[order]
        if target is None or bound is None:
            continue
        error = np.abs(actual[order] - target)
        excess = error - bound
        j = int(np.argmax(excess)) if np.any(excess > 0.0) else int(np.argmax(error))
        key = (float(excess[j]) if excess[j] > 0.0 else -math.inf, float(error[j]))
        if key > best[:2]:
            best = (*key, order, j)
    _, value, order, j = best
    return value, order, j
