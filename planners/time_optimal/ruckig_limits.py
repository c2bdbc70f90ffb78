"""Limit checks of Ruckig moves: the exact peaks of piecewise cubics against every limit.

:func:`limit_violations` finds every breach of a piecewise cubic (position, velocity,
acceleration, jerk) from its exact extrema, as the checker judges it (its round-off rule,
:func:`planners.checker.round_off`). The planners use it three ways:

* :func:`position_breach` and :func:`ends_breach`, when a move is planned: Ruckig's
  open-source version does not plan around position limits, so a move that starts or ends
  moving is checked on them (cheaply first, exactly where it matters), and a move from rest
  to rest, which stays between its start and its target, on those two;
* :func:`checked_pieces`, when a checked move's polynomials are first built: a breach there
  would be a fault of Ruckig's and raises :class:`SolverError`;
* directly, to list every breach of a move planned without checks.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import ruckig
from numpy.typing import NDArray

from optraj.errors import InfeasibleError, SolverError
from optraj.planners.checker import ABSOLUTE_SLACK, RELATIVE_SLACK, round_off
from optraj.planners.time_optimal.ruckig_conversion import native_pieces
from optraj.robots import JointLimits

__all__ = ["checked_pieces", "ends_breach", "limit_violations", "position_breach"]

FloatArray = NDArray[np.float64]


def _position_error(
    limits: JointLimits, j: int, value: float, when: float, upper: bool
) -> InfeasibleError:
    """Joint j reaching ``value`` [rad or m] at ``when`` [s], past one of its position limits."""
    name = limits.names[j]
    bound = float(limits.upper[j] if upper else limits.lower[j])
    side = "above its upper" if upper else "below its lower"
    return InfeasibleError(
        f"joint {name!r} reaches {value:.6g} {limits.unit('position', j)} at t = {when:.4g} s, "
        f"{side} position limit {bound:.6g}",
        limit="position",
        joint=name,
        required=float(value),
        allowed=bound,
    )


def _position_slack(lower: Any, upper: Any) -> Any:
    """Round-off allowed past position limits [rad or m] where the joint is at rest.

    The checker's rule (:func:`planners.checker.round_off`) on the range; works on floats
    (one joint) and on arrays (every joint) alike.
    """
    return RELATIVE_SLACK * (upper - lower) + ABSOLUTE_SLACK


def position_breach(
    native: ruckig.Trajectory, limits: JointLimits, start: FloatArray, goal: FloatArray | None
) -> InfeasibleError | None:
    """The first position limit a move passes, exactly; None when it passes none.

    Ruckig's ``position_extrema`` cannot be used: in 0.19 it misses extrema inside
    constant-acceleration phases (pantor/ruckig#215).
    Instead, a joint is first bounded by its speed limit alone: over a move of duration T
    from p0 to p1 it stays within (p0 + p1 -/+ v_max T) / 2. Only where that bound reaches
    past a limit is Ruckig asked when the joint first gets there
    (``get_first_time_at_position``, which solves each phase's cubic; it ignores a brake
    pre-profile, which a start state within the limits does not have). When it names a
    time, the exact check on the polynomials (:func:`limit_violations`) decides.

    Args:
        native: The computed move.
        limits: Its limits.
        start: Start positions, shape (n,).
        goal: End positions, shape (n,), or None when the end is free (a stop): then every
            joint is asked.
    """
    floats = limits.floats
    # Twice the bound's half-width per unit speed [s]; unbounded when the end is free.
    width = math.inf if goal is None else float(native.duration) * (1.0 + RELATIVE_SLACK)
    ends = start if goal is None else goal
    first_time = native.get_first_time_at_position
    joints = zip(
        start.tolist(),
        ends.tolist(),
        floats["lower"],
        floats["upper"],
        floats["velocity"],
        strict=True,
    )
    for j, (p0, p1, lower, upper, speed) in enumerate(joints):
        twice_middle = p0 + p1
        spread = speed * width
        if twice_middle - spread < lower + lower and (
            first_time(j, lower - _position_slack(lower, upper)) is not None
        ):
            break
        if twice_middle + spread > upper + upper and (
            first_time(j, upper + _position_slack(lower, upper)) is not None
        ):
            break
    else:
        return None
    # Rare: settle it on the polynomials. Ruckig's root finder can also report a crossing
    # that is not there (a joint starting at rest on a limit), so its answer only selects.
    return _exact_position_breach(native, limits)


def ends_breach(
    native: ruckig.Trajectory, limits: JointLimits, start: FloatArray, goal: FloatArray
) -> InfeasibleError | None:
    """The position check of a move from rest to rest: on its start and target only.

    Such a move stays between the two: Ruckig does not overshoot a target at rest (its
    author, pantor/ruckig#22), nor back off its start (a seeded randomised test of this
    module's guards both). The ends were accepted within 1e-9 of the limits, more than the
    round-off slack of a joint with a short range, so ends that are not within the limits
    themselves are settled on the exact polynomials.

    Args:
        native: The computed move.
        limits: Its limits.
        start: Start positions, shape (n,).
        goal: Target positions, shape (n,).
    """
    floats = limits.floats
    lower, upper = floats["lower"], floats["upper"]
    # A loop over Python floats: for a few joints cheaper than NumPy calls.
    for p0, p1, low, high in zip(start.tolist(), goal.tolist(), lower, upper, strict=True):
        if not (low <= p0 <= high and low <= p1 <= high):
            return _exact_position_breach(native, limits)
    return None


def _exact_position_breach(
    native: ruckig.Trajectory, limits: JointLimits
) -> InfeasibleError | None:
    """The first position breach on the exact polynomials, or None."""
    knots, coefficients = native_pieces(native)
    for error in limit_violations(knots, coefficients, limits):
        if error.limit == "position":
            return error
    return None


def limit_violations(
    knots: FloatArray, c: FloatArray, limits: JointLimits
) -> list[InfeasibleError]:
    """Exact peaks of a piecewise cubic against every joint limit; one error per breach.

    Args:
        knots: Breakpoints [s], shape (K + 1,).
        c: Coefficients, shape (K, 4, n), as :class:`Trajectory` stores them.
        limits: The limits.

    Velocity peaks lie at segment ends or at the vertex of the quadratic, position extremes
    at segment ends or where the velocity vanishes; acceleration is linear and jerk constant
    on each segment. Candidate times outside a segment are replaced by its start (already a
    candidate), so no masking is needed. A limit is breached as the checker judges it: by
    more than :func:`planners.checker.round_off` of the limit and of the slope there (the
    breakpoints of a long move are known only to round-off, over which a steep quantity
    moves).
    """
    c0, c1, c2, c3 = (c[:, i, :] for i in range(4))  # each (K, n)
    h = np.broadcast_to(np.diff(knots)[:, None], c0.shape)
    zero = np.zeros_like(c0)
    duration = float(knots[-1] - knots[0])

    def inside(tau: FloatArray) -> FloatArray:
        return np.where((tau > 0.0) & (tau < h), tau, 0.0)

    with np.errstate(divide="ignore", invalid="ignore"):
        cubic = c3 != 0.0
        vertex = inside(-c2 / (3.0 * c3))
        root = np.sqrt(np.maximum(c2 * c2 - 3.0 * c1 * c3, 0.0))
        linear = -c1 / (2.0 * c2)
        first = inside(np.where(cubic, (-c2 + root) / (3.0 * c3), linear))
        second = inside(np.where(cubic, (-c2 - root) / (3.0 * c3), 0.0))
    errors: list[InfeasibleError] = []
    # Position: both bounds. Times of the extremes are looked up only for a breach.
    taus = np.stack([zero, h, first, second])  # (m, K, n)
    values = c0 + taus * (c1 + taus * (c2 + taus * c3))
    low, high = values.min(axis=(0, 1)), values.max(axis=(0, 1))
    if _within_least_slack(c, low, high, vertex, h, zero, limits):
        return errors
    slack = round_off(limits.upper - limits.lower, c1 + taus * (2 * c2 + 3 * taus * c3), duration)
    below = (limits.lower - values - slack).max(axis=(0, 1)) > 0.0
    above = (values - limits.upper - slack).max(axis=(0, 1)) > 0.0
    for j in np.flatnonzero(below).tolist():
        when = _time_of(values, taus, knots, j, lowest=True)
        errors.append(_position_error(limits, j, float(low[j]), when, upper=False))
    for j in np.flatnonzero(above).tolist():
        when = _time_of(values, taus, knots, j, lowest=False)
        errors.append(_position_error(limits, j, float(high[j]), when, upper=True))
    # Velocity, acceleration, jerk: magnitudes, and the slopes (next derivative) there.
    for quantity, taus_q, evaluate, derivative in (
        (
            "velocity",
            np.stack([zero, h, vertex]),
            lambda t: c1 + t * (2 * c2 + 3 * t * c3),
            lambda t: 2 * c2 + 6 * t * c3,
        ),
        ("acceleration", np.stack([zero, h]), lambda t: 2 * c2 + 6 * t * c3, lambda t: 6 * c3),
        ("jerk", zero[None], lambda t: 6 * c3 + 0 * t, lambda t: 0 * t),
    ):
        magnitude = np.abs(evaluate(taus_q))  # (m, K, n)
        peak = magnitude.max(axis=(0, 1))
        allowed = getattr(limits, quantity)
        excess = magnitude - allowed - round_off(allowed, derivative(taus_q), duration)
        for j in np.flatnonzero(excess.max(axis=(0, 1)) > 0.0).tolist():
            name = limits.names[j]
            when = _time_of(magnitude, taus_q, knots, j, lowest=False)
            article = "an" if quantity == "acceleration" else "a"
            errors.append(
                InfeasibleError(
                    f"joint {name!r} reaches {article} {quantity} of {peak[j]:.6g} "
                    f"{limits.unit(quantity, j)} at t = {when:.4g} s, above its limit "
                    f"{allowed[j]:.6g}",
                    limit=quantity,
                    joint=name,
                    required=float(peak[j]),
                    allowed=float(allowed[j]),
                )
            )
    return errors


def _within_least_slack(
    c: FloatArray,
    low: FloatArray,
    high: FloatArray,
    vertex: FloatArray,
    h: FloatArray,
    zero: FloatArray,
    limits: JointLimits,
) -> bool:
    """Whether every candidate peak is within its limit plus the least round-off allowed.

    :func:`limit_violations` allows ``round_off(scale, slope)``, which is never below
    ``RELATIVE_SLACK * scale + ABSOLUTE_SLACK`` (the slope term is >= 0, and rounding is
    monotone), so peaks within that allowance are no breach whatever the slopes; this
    skips the slopes of the common case, a move that meets its limits (Ruckig's peaks sit
    on them, a few ulps either way). False means: decide on the full rule.

    Args:
        c: Coefficients, shape (K, 4, n).
        low: Lowest candidate position of each joint, shape (n,).
        high: Highest candidate position of each joint, shape (n,).
        vertex: Local time of each segment's velocity extremum (or 0), shape (K, n).
        h: Segment lengths, shape (K, n).
        zero: Zeros, shape (K, n).
        limits: The limits.
    """
    c1, c2, c3 = c[:, 1, :], c[:, 2, :], c[:, 3, :]
    spread = RELATIVE_SLACK * (limits.upper - limits.lower) + ABSOLUTE_SLACK
    if np.any(limits.lower - low > spread) or np.any(high - limits.upper > spread):
        return False
    taus = np.stack([zero, h, vertex])
    for quantity, peak in (
        ("velocity", np.abs(c1 + taus * (2 * c2 + 3 * taus * c3)).max(axis=(0, 1))),
        ("acceleration", np.maximum(np.abs(2 * c2), np.abs(2 * c2 + 6 * h * c3)).max(axis=0)),
        ("jerk", np.abs(6 * c3).max(axis=0)),
    ):
        allowed = getattr(limits, quantity)
        if np.any(peak - allowed > RELATIVE_SLACK * allowed + ABSOLUTE_SLACK):
            return False
    return True


def _time_of(
    values: FloatArray, taus: FloatArray, knots: FloatArray, j: int, *, lowest: bool
) -> float:
    """When joint j takes its lowest or highest candidate value [s].

    Args:
        values: Candidate values, shape (m, K, n): m candidate times on each of K segments.
        taus: The candidate times within their segments [s], shape (m, K, n).
        knots: Breakpoints [s], shape (K + 1,).
        j: The joint.
        lowest: The lowest value's time, else the highest's.
    """
    column = values[..., j]
    candidate, segment = np.unravel_index(
        int(column.argmin() if lowest else column.argmax()), column.shape
    )
    return float(knots[segment] + taus[candidate, segment, j])


def checked_pieces(native: ruckig.Trajectory, limits: JointLimits) -> tuple[FloatArray, FloatArray]:
    """The polynomials of a move whose start state was within the limits, checked exactly.

    Ruckig keeps such a move within the velocity, acceleration and jerk limits by
    construction, and its positions were checked when it was planned (from rest to rest:
    they lie between the start and the target); a breach found here would be a fault of
    Ruckig's, reported as one rather than returned.

    Raises:
        SolverError: The polynomials break a limit.
    """
    knots, coefficients = native_pieces(native)
    errors = limit_violations(knots, coefficients, limits)
    if errors:
        raise SolverError("ruckig", "limits exceeded", detail=str(errors[0]))
    return knots, coefficients
