"""First guesses: moves, a pool strike's window along its strike line, a free move's first grid."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    OptrajError,
    PathJumpError,
    UnreachableError,
)
from optraj.planners.ocp.options import (
    LINE_SAMPLES,
    LINE_SAMPLES_FINE,
    MIN_INTERVAL,
)
from optraj.planners.profiles.time_scaling import quintic_coefficients
from optraj.planners.strike.contact import (
    ContactChoice,
)
from optraj.planners.strike.time_optimal_strike import strike_line
from optraj.planners.time_optimal.ruckig_planner import state_to_state
from optraj.planners.trajectory import Trajectory
from optraj.problems import PoolStrike
from optraj.robots import JointLimits

FloatArray = NDArray[np.float64]


# ---------------------------------------------------------------------------- problem specs


def zero_vector(n: int) -> FloatArray:
    """A zero vector of ``n`` entries."""
    return np.zeros(n)


def quintic_guess(
    q0: FloatArray,
    q1: FloatArray,
    duration: float,
    v1: FloatArray | None = None,
    a1: FloatArray | None = None,
) -> Trajectory:
    """A one-piece quintic from ``q0`` at rest to ``q1`` (velocity ``v1``, acceleration ``a1``)."""
    n = q0.size
    coefficients = quintic_coefficients(
        q0,
        q1,
        duration,
        0.0,
        zero_vector(n) if v1 is None else v1,
        0.0,
        zero_vector(n) if a1 is None else a1,
    )
    return Trajectory([0.0, duration], coefficients[None])


def move_guess(
    q0: FloatArray,
    v0: FloatArray,
    a0: FloatArray,
    q1: FloatArray,
    v1: FloatArray,
    a1: FloatArray,
    limits: JointLimits,
    duration: float | None = None,
) -> Trajectory:
    """Ruckig's time-optimal move (limits not enforced: it is only a guess)."""
    try:
        return state_to_state(
            q0, v0, a0, q1, v1, a1, limits, minimum_duration=duration, check_limits=False
        )
    except OptrajError:
        span = np.max(np.abs(q1 - q0) / limits.velocity)
        return quintic_guess(q0, q1, duration or max(2.0 * span, 0.2), v1, a1)


def window_guess(problem: PoolStrike, choice: ContactChoice) -> Trajectory:
    """The strike window of a pool strike's first guess, ``problem.window`` long.

    The line followed by IK with the cue's roll kept from the contact configuration
    (:func:`planners.strike.time_optimal_strike.strike_line`, :data:`LINE_SAMPLES` samples, then
    :data:`LINE_SAMPLES_FINE` when the joints jump between them: a joint pinned on a
    position limit makes the others turn fast). When the finer line still jumps, or a pose on
    it has no solution with that roll, the guess joins the contact choice's own entry,
    contact and exit configurations (which it reached with the roll free) by quintics at the
    contact's joint velocity; the solver then puts the cue on the line.
    """
    failure: OptrajError | None = None
    for samples in (LINE_SAMPLES, LINE_SAMPLES_FINE):
        try:
            return strike_line(problem, samples, q_contact=choice.q)
        except (PathJumpError, UnreachableError) as error:
            failure = error
            if isinstance(error, UnreachableError):
                break  # more samples reach no more poses
    if choice.q_entry is None or choice.q_exit is None:  # pragma: no cover
        # A pool choice always has its entry and exit; the loop above always ran.
        raise failure or OptrajError("the strike line has no guess")
    q = np.asarray(choice.q, dtype=float)
    qd = np.asarray(choice.qd, dtype=float)
    into = float(problem.contact_delay)
    out = float(problem.window) - into
    coefficients = np.stack(
        [
            quintic_coefficients(choice.q_entry, q, into, qd, qd),
            quintic_coefficients(q, choice.q_exit, out, qd, qd),
        ]
    )
    return Trajectory([0.0, into, into + out], coefficients)


def switch_times(
    guess: Trajectory, joint: int, intervals: int, max_interval: float
) -> FloatArray | None:
    """Node times [s] of a free move's first grid: on the jerk switches of one joint.

    A minimum-time move's solution has nodes on the jerk switches of the joint that needs
    longest alone: with joint limits like the Panda's, a few milliseconds of jerk at each end
    of each acceleration phase. An even grid puts them mid-interval, and the solver spends
    most of its iterations moving nodes there. Here the times where ``joint``'s jerk changes
    in ``guess`` (a Ruckig move: its jerk is constant between breakpoints) are nodes, and
    each span between them gets intervals in proportion to its length, each at most
    ``max_interval`` long. When that needs more than ``intervals``, only the first and last
    switch are kept (the jerk ramps at the two ends); when even that does not fit, or
    ``guess`` is not piecewise cubic, None (an even grid).

    Args:
        guess: The first guess, from 0 to its duration.
        joint: The joint whose switches are kept.
        intervals: Intervals of the phase.
        max_interval: Longest interval [s].

    Returns:
        ``intervals + 1`` increasing times from 0 to ``guess.duration``, or None.
    """
    knots = np.asarray(guess.breakpoints, dtype=float)
    coefficients = np.asarray(guess.coefficients, dtype=float)
    if coefficients.shape[1] != 4:
        return None
    duration = float(knots[-1])
    jerk = 6.0 * coefficients[:, 3, joint]
    steps = np.abs(np.diff(jerk)) > 1e-9 * max(float(np.max(np.abs(jerk))), 1e-300)
    edges = [0.0]
    for time in knots[1:-1][steps].tolist():  # spans shorter than MIN_INTERVAL are merged
        if time - edges[-1] >= MIN_INTERVAL and duration - time >= MIN_INTERVAL:
            edges.append(time)
    edges.append(duration)
    counts = _span_counts(np.diff(edges), intervals, max_interval)
    if counts is None and len(edges) > 4:
        edges = [0.0, edges[1], edges[-2], duration]
        counts = _span_counts(np.diff(edges), intervals, max_interval)
    if counts is None:
        return None
    pieces = [
        np.linspace(a, b, c + 1)[:-1] for a, b, c in zip(edges, edges[1:], counts, strict=False)
    ]
    return np.concatenate([*pieces, [duration]])


def _span_counts(spans: FloatArray, intervals: int, max_interval: float) -> NDArray[np.int_] | None:
    """Intervals per span [s], ``intervals`` in all; None when they do not fit.

    Each span gets at least one interval and as many as ``max_interval`` [s] needs; the
    rest go one by one to the span whose intervals are longest.
    """
    counts = np.maximum(1, np.ceil(spans / max_interval)).astype(int)
    if counts.sum() > intervals:
        return None
    for _ in range(intervals - int(counts.sum())):
        counts[int(np.argmax(spans / counts))] += 1
    return counts
