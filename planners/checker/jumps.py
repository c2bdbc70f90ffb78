"""Jumps: where position, velocity or acceleration changes at once, measured exactly.

:func:`breakpoint_jumps` compares the polynomials on the two sides of every inner
breakpoint; :func:`boundary_jumps` compares a prescribed start or end state with the
trajectory at that end. A difference within round-off (:mod:`planners.checker.allowance`)
is no jump. A jump in a quantity makes every higher derivative unbounded: the limit
findings of those quantities fail with value ``inf``
(:func:`planners.checker.joint_limits.limit_findings`).

Example::

    jumps = breakpoint_jumps(derivatives_of(trajectory.coefficients, 4), knots, limits)
    [(jump.order, jump.time, jump.joint) for jump in jumps]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.planners.checker.allowance import round_off, state_allowance, thresholds
from optraj.planners.checker.task import constraint_tolerance
from optraj.problems.constraints import BoundaryState
from optraj.robots import JointLimits

__all__ = ["Jump", "boundary_jumps", "breakpoint_jumps"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Jump:
    """A discontinuity of one joint quantity: at a breakpoint or against a boundary state."""

    order: int  # 0 position, 1 velocity, 2 acceleration
    time: float
    joint: int
    delta: float  # after minus before [rad.. or m..]
    size: float  # |delta| / threshold (> 1)
    source: str  # "" at a breakpoint, else "start state" / "end state"


def breakpoint_jumps(
    derivatives: list[FloatArray], knots: FloatArray, limits: JointLimits
) -> list[Jump]:
    """Jumps of position, velocity and acceleration between the two sides of inner breakpoints.

    Each side is evaluated exactly: segment k at its end ``tau = t_{k+1} - t_k`` against
    segment k + 1 at ``tau = 0``. A difference within :func:`round_off` is not a jump: the
    scale is the quantity's limit (the range for positions) plus the magnitudes summed on
    the left, the slope the sum of the two sides' slopes (moving a breakpoint by the time
    round-off changes the difference by at most that sum times the shift).
    """
    if len(knots) < 3:
        return []
    jumps: list[Jump] = []
    h = np.diff(knots)[:-1]  # lengths of the segments that end at an inner breakpoint
    duration = float(knots[-1] - knots[0])
    scales = thresholds(limits)
    for order in range(3):
        sides = []
        for coeffs in derivatives[order : order + 2]:
            left_rows = coeffs[:-1]  # (K - 1, d + 1, n)
            powers = h[:, None] ** np.arange(left_rows.shape[1])[None, :]  # (K - 1, d + 1)
            terms = left_rows * powers[:, :, None]
            sides.append((terms.sum(axis=1), coeffs[1:, 0, :], np.abs(terms).sum(axis=1)))
        (left, right, magnitude), (left_slope, right_slope, _) = sides
        delta = right - left
        threshold = round_off(
            scales[order][None, :] + magnitude,
            np.abs(left_slope) + np.abs(right_slope),
            duration,
        )
        rows, cols = np.nonzero(np.abs(delta) > threshold)
        for k, j in zip(rows.tolist(), cols.tolist(), strict=True):
            jumps.append(
                Jump(
                    order,
                    float(knots[k + 1]),
                    j,
                    float(delta[k, j]),
                    float(abs(delta[k, j]) / threshold[k, j]),
                    "",
                )
            )
    return jumps


def boundary_jumps(
    state: BoundaryState,
    wanted: list[FloatArray | None],
    actual: list[FloatArray],
    time: float,
    limits: JointLimits,
    duration: float,
) -> list[Jump]:
    """Jumps between a prescribed start/end state and the trajectory at that end.

    The robot is in the prescribed state before the start (after the end), so a difference in
    velocity, or in acceleration when one is prescribed, is a jump. A position difference is
    not counted as a jump: the ``start state`` / ``end state`` finding reports it. A difference
    within the state's own tolerance (plus round-off, :func:`state_allowance`) is not a jump
    either: it passes that finding too.

    Args:
        state: The prescribed state.
        wanted: Its validated q, qd, qdd (None where not prescribed).
        actual: The trajectory's q, qd, qdd, jerk at that end.
        time: The end's time [s].
        limits: The limits.
        duration: Trajectory duration [s].
    """
    tolerance = constraint_tolerance(state.tolerance, "BoundaryState.tolerance")
    allowed = state_allowance(wanted, actual[1:], tolerance, limits, duration)
    jumps: list[Jump] = []
    for order in (1, 2):
        target, threshold = wanted[order], allowed[order]
        if target is None or threshold is None:
            continue
        delta = actual[order] - target if state.at == "start" else target - actual[order]
        for j in np.flatnonzero(np.abs(delta) > threshold).tolist():
            jumps.append(
                Jump(
                    order,
                    time,
                    j,
                    float(delta[j]),
                    float(abs(delta[j]) / threshold[j]),
                    f"{state.at} state",
                )
            )
    return jumps
