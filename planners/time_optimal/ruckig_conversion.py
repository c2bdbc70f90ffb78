"""Ruckig's result as an exact piecewise-cubic :class:`~planners.trajectory.Trajectory`.

Every joint of a Ruckig move is a chain of constant-jerk phases (a brake pre-profile, the
seven phases of its main profile, then constant acceleration from its final state), so it is
piecewise cubic in time, which is what :class:`Trajectory` stores. :func:`native_to_trajectory`
converts without sampling; :func:`native_pieces` gives the breakpoints and coefficients alone::

    traj = native_to_trajectory(native, joint_names=limits.names)

Breakpoints closer than the checker's time round-off (:data:`planners.checker.TIME_ROUND_OFF`
per second of duration) are merged, the rule :func:`planners.checker.check` applies.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np
import ruckig
from numpy.typing import NDArray

from optraj.errors import InvalidInputError, SolverError
from optraj.planners.checker import TIME_ROUND_OFF
from optraj.planners.trajectory import Phase, Trajectory

__all__ = ["native_pieces", "native_to_trajectory"]

FloatArray = NDArray[np.float64]


def _pieces(profile: Any) -> tuple[list[float], list[list[float]]]:
    """One joint's constant-jerk pieces, as Ruckig's ``at_time`` walks them.

    First the brake pre-profile (present when the start state would otherwise break a
    limit), then the seven phases of the main profile, then, from its end on, constant
    acceleration from the final state (what Ruckig does after a joint has arrived).

    Returns:
        Start times [s] of the pieces and, per piece, [p, v, a, jerk] at its start.
    """
    starts: list[float] = []
    states: list[list[float]] = []
    clock = 0.0
    brake = profile.brake
    if brake.duration > 0.0:
        fields = zip(brake.t, brake.p, brake.v, brake.a, brake.j, strict=True)
        # The brake's clock counts its phases of positive length only; it then ends at
        # its own duration.
        _add_pieces(starts, states, clock, (phase for phase in fields if phase[0] > 0.0))
        clock = brake.duration
    # Each field access converts a whole array: read them once.
    fields = zip(profile.t, profile.p, profile.v, profile.a, profile.j, strict=False)
    clock = _add_pieces(starts, states, clock, fields)
    starts.append(clock)
    states.append([profile.pf, profile.vf, profile.af, 0.0])
    return starts, states


def _add_pieces(
    starts: list[float],
    states: list[list[float]],
    clock: float,
    phases: Iterable[tuple[float, float, float, float, float]],
) -> float:
    """Append the phases of positive length to ``starts`` and ``states``, from ``clock`` on.

    Args:
        starts: Start times [s] of the pieces so far; appended to.
        states: [p, v, a, jerk] at the start of each piece so far; appended to.
        clock: Time [s] at which the first phase starts.
        phases: (length [s], p, v, a, jerk) of each phase, in order.

    Returns:
        The time [s] at which the last phase ends.
    """
    for length, p, v, a, jerk in phases:
        if length > 0.0:
            starts.append(clock)
            states.append([p, v, a, jerk])
        clock += length
    return clock


def native_to_trajectory(
    native: ruckig.Trajectory,
    *,
    joint_names: Sequence[str] | None = None,
    phases: Iterable[Phase] = (),
    metadata: Mapping[str, Any] | None = None,
) -> Trajectory:
    """Convert a Ruckig trajectory exactly into a piecewise-cubic :class:`Trajectory`.

    The breakpoints are the union of every joint's phase boundaries (segments shorter than
    the checker's time round-off, :data:`planners.checker.TIME_ROUND_OFF` per second of
    duration, are merged into their neighbours);
    on each segment every joint's cubic is re-expanded about the segment start as
    ``[p, v, a / 2, j / 6]``. The result matches ``native.at_time`` to round-off.

    Args:
        native: A computed ``ruckig.Trajectory`` without intermediate waypoints.
        joint_names: Names of the joints, or None.
        phases: Phases of the result.
        metadata: Metadata of the result.

    Returns:
        A degree-3 trajectory of duration ``native.duration``.

    Raises:
        InvalidInputError: Not a ``ruckig.Trajectory``, a trajectory of zero duration, or
            one with waypoint sections.
        SolverError: A Ruckig profile this conversion does not know (an acceleration
            post-profile, unused by Ruckig 0.19's ``at_time``).
    """
    if not isinstance(native, ruckig.Trajectory):
        raise InvalidInputError(
            f"native must be a ruckig.Trajectory, got {type(native).__name__}", name="native"
        )
    breaks, coefficients = native_pieces(native)
    return Trajectory(
        breaks, coefficients, joint_names=joint_names, phases=phases, metadata=metadata
    )


def native_pieces(native: ruckig.Trajectory) -> tuple[FloatArray, FloatArray]:
    """The polynomials of a Ruckig trajectory (see :func:`native_to_trajectory`).

    Returns:
        Breakpoints [s], shape (K + 1,), and cubic coefficients, shape (K, 4, n).
    """
    duration = float(native.duration)
    if not (math.isfinite(duration) and duration > 0.0):
        raise InvalidInputError(
            f"a ruckig trajectory of duration {duration!r} s has nothing to convert",
            name="native",
        )
    sections = native.profiles
    if len(sections) != 1:
        raise InvalidInputError(
            f"only ruckig trajectories without waypoints can be converted, got "
            f"{len(sections)} sections",
            name="native",
        )
    tolerance = TIME_ROUND_OFF * max(1.0, duration)
    per_joint: list[tuple[list[float], list[list[float]]]] = []
    knots: list[float] = [0.0, duration]
    for dof, profile in enumerate(sections[0]):
        if profile.accel.duration > 0.0:
            raise SolverError(
                "ruckig",
                "accel post-profile",
                detail=f"DoF {dof} has an acceleration post-profile this conversion does not "
                "support",
            )
        starts, states = _pieces(profile)
        per_joint.append((starts, states))
        knots.extend(t for t in starts if 0.0 < t < duration)
    # Merge boundaries closer than the tolerance; keep 0 and the duration exactly.
    merged = [0.0]
    for t in sorted(knots)[1:]:
        if t - merged[-1] >= tolerance:
            merged.append(t)
    if merged[-1] != duration:
        if len(merged) > 1 and duration - merged[-1] < tolerance:
            merged[-1] = duration
        else:
            merged.append(duration)
    breaks = np.asarray(merged)
    middles = 0.5 * (breaks[:-1] + breaks[1:])
    # Every joint's pieces in one padded array (starts past the end: inf), so each segment
    # finds its piece in all joints at once: the last piece starting at or before its middle.
    n, width = len(per_joint), max(len(starts) for starts, _ in per_joint)
    piece_starts = np.full((n, width), np.inf)
    piece_states = np.zeros((n, width, 4))
    for dof, (starts, states) in enumerate(per_joint):
        piece_starts[dof, : len(starts)] = starts
        piece_states[dof, : len(states)] = states
    piece = np.maximum((middles[None, :, None] >= piece_starts[:, None, :]).sum(axis=2) - 1, 0)
    rows = np.arange(n)[:, None]
    p, v, a, jerk = np.moveaxis(piece_states[rows, piece], -1, 0)  # each (n, K)
    tau = breaks[None, :-1] - piece_starts[rows, piece]
    coefficients = np.stack(
        [
            p + tau * (v + tau * (a / 2.0 + tau * jerk / 6.0)),
            v + tau * (a + tau * jerk / 2.0),
            (a + tau * jerk) / 2.0,
            jerk / 6.0,
        ],
        axis=1,
    )  # (n, 4, K)
    return breaks, np.ascontiguousarray(coefficients.transpose(2, 1, 0))
