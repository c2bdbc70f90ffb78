"""The joint-limit findings: position, velocity, acceleration, jerk and torque.

One finding per quantity, for the worst joint and instant. Position, velocity, acceleration
and jerk are bounded exactly on every polynomial segment
(:func:`~planners.checker.polynomials.exact_candidates`), whatever the sampling rate; torque
(inverse dynamics, not a polynomial) is sampled. A jump in a lower derivative
(:mod:`planners.checker.jumps`) makes a quantity unbounded: its finding fails with ``inf``.

Example::

    findings = limit_findings(("velocity", "torque"), robot, ctx, jumps)
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.planners.checker.allowance import round_off
from optraj.planners.checker.context import CheckContext
from optraj.planners.checker.jumps import Jump
from optraj.planners.checker.polynomials import evaluate_piecewise, exact_candidates
from optraj.planners.checker.report import Finding, build_finding
from optraj.robots import JointLimits, Robot

__all__ = ["LIMIT_FIELD", "ORDER", "ORDER_NAME", "QUANTITIES", "UNIT_KEY", "limit_findings"]

FloatArray = NDArray[np.float64]

#: The limited joint quantities, in report order.
QUANTITIES: tuple[str, ...] = ("position", "velocity", "acceleration", "jerk", "torque")
#: Derivative order of each joint quantity (torque depends on the acceleration).
ORDER = {"position": 0, "velocity": 1, "acceleration": 2, "jerk": 3, "torque": 2}
#: JointLimits field of each symmetric quantity.
LIMIT_FIELD = {
    "velocity": "velocity",
    "acceleration": "acceleration",
    "jerk": "jerk",
    "torque": "effort",
}
#: Unit key (:meth:`robots.JointLimits.unit`) of each quantity.
UNIT_KEY = {**{q: q for q in QUANTITIES}, "torque": "effort"}
#: Name of each derivative order, the quantities a jump or a boundary state concerns.
ORDER_NAME = ("position", "velocity", "acceleration")


def limit_findings(
    quantities: tuple[str, ...],
    robot: Robot,
    ctx: CheckContext,
    jumps: list[Jump],
) -> list[Finding]:
    """One finding per requested joint quantity: the worst joint and time.

    Position, velocity, acceleration and jerk are bounded exactly on every segment
    (:func:`exact_candidates`), whatever the sampling rate; torque is sampled.
    """
    limits, names = ctx.limits, ctx.names
    findings: list[Finding] = []
    for quantity in quantities:
        unbounded = _jump_finding(quantity, jumps, limits, names)
        if unbounded is not None:
            findings.append(unbounded)
        elif quantity == "position":
            findings.append(_position_finding(ctx))
        elif quantity == "torque":
            sampled = [
                evaluate_piecewise(ctx.derivatives[r], ctx.knots, ctx.grid) for r in range(3)
            ]
            torque = robot.inverse_dynamics(*sampled)
            findings.append(_torque_finding(ctx, torque))
        else:
            findings.append(_symmetric_finding(quantity, ctx))
    return findings


def _worst(ratio: FloatArray, excess: FloatArray) -> Any:
    """Index of the worst candidate.

    The largest ratio among the candidates that fail (excess > 0), or overall when none fails.
    """
    failing = excess > 0.0
    scores = np.where(failing, ratio, -np.inf) if np.any(failing) else ratio
    index = np.unravel_index(int(np.argmax(scores)), scores.shape)
    return index[0] if len(index) == 1 else tuple(int(i) for i in index)


def _position_finding(ctx: CheckContext) -> Finding:
    """Position margin: the smallest distance inside the nearer bound (negative outside)."""
    limits = ctx.limits
    lower, upper = limits.lower, limits.upper

    def score(x: FloatArray, j: NDArray[np.intp]) -> FloatArray:  # = -margin
        return np.maximum(lower[j] - x, x - upper[j])

    found = exact_candidates(ctx.knots, ctx.derivatives[0], score, 0.0)
    scores = score(found.value, found.joint)
    slack = round_off((upper - lower)[found.joint], found.slope, ctx.duration)
    i = _worst(scores, scores - slack)
    j = int(found.joint[i])
    x, time = float(found.value[i]), float(found.time[i])
    low, high = float(lower[j]), float(upper[j])
    near_upper = (high - x) <= (x - low)
    bound = high if near_upper else low
    side = "upper" if near_upper else "lower"
    unit = limits.unit("position", j)
    margin = 0.0 - float(scores[i])  # (not -0.0 on a bound)
    where = "inside" if margin >= 0.0 else "beyond"
    detail = (
        f"joint {ctx.names[j]!r} reaches {x:.6g} {unit}, {abs(margin):.4g} {unit} {where} its "
        f"{side} limit {bound:.6g} {unit}"
    )
    half = 0.5 * (high - low)
    return build_finding(
        "position",
        "limit",
        x,
        bound,
        margin=margin,
        ratio=abs(x - 0.5 * (high + low)) / half,
        slack=float(slack[i]),
        time=time,
        joint=ctx.names[j],
        unit=unit,
        detail=detail,
    )


def _symmetric_finding(quantity: str, ctx: CheckContext) -> Finding:
    """Largest ``|x| / limit`` of velocity, acceleration or jerk, exactly over every segment."""
    bound = np.asarray(getattr(ctx.limits, LIMIT_FIELD[quantity]))

    def score(x: FloatArray, j: NDArray[np.intp]) -> FloatArray:
        return np.abs(x) / bound[j]

    found = exact_candidates(ctx.knots, ctx.derivatives[ORDER[quantity]], score, 1.0)
    magnitude = np.abs(found.value)
    limit = bound[found.joint]
    slack = round_off(limit, found.slope, ctx.duration)
    i = _worst(magnitude / limit, magnitude - limit - slack)
    return _magnitude_finding(
        quantity,
        ctx,
        float(magnitude[i]),
        float(found.time[i]),
        int(found.joint[i]),
        float(slack[i]),
    )


def _torque_finding(ctx: CheckContext, torque: FloatArray) -> Finding:
    """Largest ``|torque| / effort`` over the samples (torque is not a polynomial)."""
    bound = ctx.limits.effort
    magnitude = np.abs(torque)
    i, j = _worst(magnitude / bound, magnitude - bound - round_off(bound))
    return _magnitude_finding("torque", ctx, float(magnitude[i, j]), float(ctx.grid[i]), j, None)


def _magnitude_finding(
    quantity: str, ctx: CheckContext, value: float, time: float, j: int, slack: float | None
) -> Finding:
    """The finding for a symmetric quantity whose worst magnitude ``value`` is at ``time``."""
    limits = ctx.limits
    limit = float(getattr(limits, LIMIT_FIELD[quantity])[j])
    ratio = value / limit
    unit = limits.unit(UNIT_KEY[quantity], j)
    detail = (
        f"|{quantity}| of joint {ctx.names[j]!r} peaks at {value:.6g} {unit}, "
        f"{100.0 * ratio:.4g}% of its limit {limit:.6g} {unit}"
    )
    return build_finding(
        quantity,
        "limit",
        value,
        limit,
        ratio=ratio,
        slack=slack,
        time=time,
        joint=ctx.names[j],
        unit=unit,
        detail=detail,
    )


def _jump_finding(
    quantity: str, jumps: list[Jump], limits: JointLimits, names: tuple[str, ...]
) -> Finding | None:
    """A failing finding for ``quantity`` if a lower-order jump makes it unbounded."""
    order = ORDER[quantity]
    causes = [jump for jump in jumps if jump.order < order]
    if not causes:
        return None
    worst = max(causes, key=lambda jump: (jump.order, jump.size))
    j = worst.joint
    jumped = ORDER_NAME[worst.order]
    where = (
        f"(joint {names[j]!r})"
        if not worst.source
        else f"(joint {names[j]!r}) from the prescribed {worst.source}"
    )
    detail = (
        f"{jumped} jumps by {worst.delta:.4g} {limits.unit(jumped, j)} at "
        f"t = {worst.time:.6g} s {where}: needs unbounded {quantity}"
    )
    if len(causes) > 1:
        detail += f" ({len(causes) - 1} more jump{'s' if len(causes) > 2 else ''})"
    return build_finding(
        quantity,
        "limit",
        math.inf,
        float(getattr(limits, LIMIT_FIELD[quantity])[j]),
        time=worst.time,
        joint=names[j],
        unit=limits.unit(UNIT_KEY[quantity], j),
        detail=detail,
    )
