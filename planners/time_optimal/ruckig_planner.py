"""Time-optimal jerk-limited joint motion with Ruckig, as exact optraj trajectories.

Ruckig (``pip install ruckig``; Berscheid & Kröger, "Jerk-limited real-time trajectory
generation with arbitrary target states", RSS 2021) computes, for every joint, the fastest
motion from any state (position, velocity, acceleration) to any reachable target state under
box velocity, acceleration and jerk limits, and then stretches the faster joints so that all
of them arrive together. Each joint's motion is a chain of constant-jerk phases, so it is
piecewise cubic in time, which is exactly what :class:`~planners.trajectory.Trajectory`
stores: :func:`native_to_trajectory` converts Ruckig's result without sampling.

This module offers

* :class:`Ruckig`, a planner for :class:`problems.PointToPoint` that, unlike the classic time
  scalings, accepts moving start and target states (this is how a strike is entered at speed);
* :func:`state_to_state`, the same as a plain function;
* :func:`stop`, the fastest stop from a moving state (Ruckig's velocity interface), used to
  brake after a strike;
* :class:`OnlineRuckig`, one control tick at a time, for controllers.

Limits are checked three times. The start and target states are validated before Ruckig
runs (a target that no motion within the limits can reach raises :class:`InfeasibleError`
naming the joint). The position limits, which Ruckig's open-source version does not plan
around, are checked when a move is planned: exactly for a move that starts or ends moving; for
a move from rest to rest, which stays between its start and its target, on those two. And the
exact peaks of the finished polynomials are compared with every limit. Ruckig plans in
microseconds while building the polynomials takes about half a millisecond, so a checked
move's polynomials are built on first use (:meth:`Trajectory.deferred`); its duration, phases
and metadata are there at once. Its polynomials are never handed out unchecked: a breach found
when they are built (which would be a fault of Ruckig's) raises :class:`SolverError`.

Every limit and state comparison here follows the checker's one round-off rule
(:func:`planners.checker.round_off`), so that a plan that :meth:`Ruckig.plan` returns passes
:func:`planners.checker.check`: on a long move a breakpoint is known only to about 1e-13 s, over
which a steep acceleration ramp moves by more than a relative 1e-9 of its limit.
"""

from __future__ import annotations

import functools
import math
import operator
import re
import threading
import time
from collections.abc import Iterable, Mapping, Sequence
from typing import Any, cast

import numpy as np
import ruckig
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError, SolverError, UnknownNameError
from optraj.planners.base import JointProfile, rest_to_rest_inputs
from optraj.planners.checker import (
    ABSOLUTE_SLACK,
    RELATIVE_SLACK,
    TIME_ROUND_OFF,
    round_off,
    state_allowance,
)
from optraj.planners.trajectory import Phase, Trajectory
from optraj.problems import PointToPoint
from optraj.robots import JointLimits
from optraj.validation import as_duration, as_flag, as_vector

__all__ = [
    "SYNCHRONIZATIONS",
    "OnlineRuckig",
    "Ruckig",
    "calculate",
    "check_state",
    "checked_limits",
    "native_to_trajectory",
    "ruckig_input",
    "state_or_zeros",
    "state_to_state",
    "stop",
]

FloatArray = NDArray[np.float64]

#: Synchronisation names accepted here and Ruckig's matching options: ``time`` (every joint
#: starts and ends together), ``phase`` (also on a straight line in joint space when the
#: states allow it, else as ``time``), ``time_if_necessary`` (only joints that end moving
#: are synchronised) and ``none`` (every joint at its own fastest; a joint that arrives
#: early rests there, so ``none`` needs a target at rest).
SYNCHRONIZATIONS: Mapping[str, ruckig.Synchronization] = {
    "time": ruckig.Synchronization.Time,
    "phase": ruckig.Synchronization.Phase,
    "time_if_necessary": ruckig.Synchronization.TimeIfNecessary,
    "none": ruckig.Synchronization.No,
}

#: Results that carry a usable trajectory.
_GOOD = (ruckig.Result.Working, ruckig.Result.Finished)
#: Ruckig's control interfaces by name: move to a target state, or only to a velocity.
_INTERFACES = {
    "position": ruckig.ControlInterface.Position,
    "velocity": ruckig.ControlInterface.Velocity,
}


# --------------------------------------------------------------------------- validation


def _synchronization(name: str) -> ruckig.Synchronization:
    """Ruckig's synchronisation option for a name of :data:`SYNCHRONIZATIONS`."""
    if not isinstance(name, str) or name not in SYNCHRONIZATIONS:
        raise UnknownNameError("synchronization", str(name), SYNCHRONIZATIONS)
    return SYNCHRONIZATIONS[name]


def _check_unsynchronised(name: str, qd1: FloatArray, qdd1: FloatArray) -> None:
    """Refuse ``none`` with a moving target: early joints would move on past their target.

    Ruckig lets a joint that arrives before the others continue with its target velocity
    and acceleration, so the move would not end in the target state.
    """
    if name == "none" and (np.any(qd1 != 0.0) or np.any(qdd1 != 0.0)):
        raise InvalidInputError(
            "synchronization 'none' needs a target at rest: a joint that arrives early would "
            "move on with its target velocity and acceleration; use 'time_if_necessary' to "
            "synchronise only the joints that end moving",
            name="synchronization",
        )


def _minimum_duration(*values: float | None) -> float | None:
    """The largest of the given minimum durations [s], or None when none is given.

    Raises:
        InvalidInputError: A value that is not a duration in [MIN_DURATION, MAX_DURATION]
            seconds (:func:`optraj.validation.as_duration`).
    """
    found: list[float] = []
    for value in values:
        if value is not None:
            found.append(as_duration(value, "minimum_duration"))
    return max(found) if found else None


def _joint_names(joint_names: Sequence[str] | None, limits: JointLimits) -> tuple[str, ...]:
    """The result's joint names: those of ``limits`` when None, else n strings.

    Raises:
        InvalidInputError: Not a sequence of ``limits.n`` strings (a single string is refused:
            its characters are not names).
    """
    if joint_names is None:
        return limits.names
    names = None if isinstance(joint_names, str) else _as_tuple(joint_names)
    if names is None or len(names) != limits.n or not all(isinstance(x, str) for x in names):
        raise InvalidInputError(
            f"joint_names must be a sequence of {limits.n} strings, got {joint_names!r}",
            name="joint_names",
        )
    return names


def _as_tuple(values: object) -> tuple[object, ...] | None:
    """``values`` as a tuple, or None when it is not iterable."""
    try:
        return tuple(cast(Iterable[object], values))
    except TypeError:
        return None


def checked_limits(limits: object) -> JointLimits:
    """``limits`` if it is a :class:`robots.JointLimits`, else InvalidInputError."""
    if not isinstance(limits, JointLimits):
        raise InvalidInputError(
            f"limits must be a robots.JointLimits, got {type(limits).__name__}", name="limits"
        )
    return limits


def state_or_zeros(value: ArrayLike | None, name: str, n: int) -> FloatArray:
    """A state vector of length n; zeros when None."""
    return np.zeros(n) if value is None else as_vector(value, name, n)


def check_state(
    qd: FloatArray, qdd: FloatArray, limits: JointLimits, label: str, *, arriving: bool
) -> None:
    """Raise InfeasibleError if a velocity/acceleration state is outside what the limits allow.

    Beyond the box limits, a state is out of reach when the velocity it implies while the
    acceleration ramps to or from zero at the jerk limit breaks the velocity limit: leaving a
    start state with acceleration a, the velocity still changes by a^2 / (2 j) in the sign of
    a; arriving at a target with acceleration a, it was a^2 / (2 j) further the other way.

    Args:
        qd: Velocities [rad/s or m/s], shape (n,).
        qdd: Accelerations [rad/s^2 or m/s^2], shape (n,).
        limits: Joint limits.
        label: ``"start"`` or ``"target"``.
        arriving: Whether the state is reached (target) rather than left (start). Targets
            are judged strictly, as Ruckig judges them; starts with round-off slack, as
            the finished trajectory is.
    """
    floats = limits.floats
    states = zip(qd.tolist(), qdd.tolist(), strict=True)
    # Python floats: seven joints cost less this way than in NumPy calls.
    for j, (velocity, acceleration) in enumerate(states):
        speed_limit = floats["velocity"][j]
        velocity_bound = (
            speed_limit if arriving else speed_limit * (1.0 + RELATIVE_SLACK) + ABSOLUTE_SLACK
        )
        swing = acceleration * abs(acceleration) / (2.0 * floats["jerk"][j])
        implied = velocity - swing if arriving else velocity + swing
        for quantity, value, allowed in (
            ("velocity", velocity, speed_limit),
            ("acceleration", acceleration, floats["acceleration"][j]),
        ):
            bound = allowed if arriving else allowed * (1.0 + RELATIVE_SLACK) + ABSOLUTE_SLACK
            if abs(value) > bound:
                raise InfeasibleError(
                    f"{label} {quantity} {value:.6g} {limits.unit(quantity, j)} of joint "
                    f"{limits.names[j]!r} exceeds its limit {allowed:.6g} "
                    f"{limits.unit(quantity, j)}",
                    limit=quantity,
                    joint=limits.names[j],
                    required=abs(value),
                    allowed=allowed,
                )
        if abs(implied) > velocity_bound:
            when = "before it arrives at" if arriving else "after it leaves"
            raise InfeasibleError(
                f"joint {limits.names[j]!r} reaches a velocity of {implied:.6g} "
                f"{limits.unit('velocity', j)} {when} its {label} state (velocity "
                f"{velocity:.6g}, acceleration {acceleration:.6g}) with jerk limit "
                f"{floats['jerk'][j]:.6g}; its velocity limit is {speed_limit:.6g}",
                limit="velocity",
                joint=limits.names[j],
                required=abs(implied),
                allowed=speed_limit,
            )


# ------------------------------------------------------------------------- ruckig calls


def ruckig_input(
    limits: JointLimits,
    q0: FloatArray,
    q1: FloatArray,
    states: tuple[list[float], list[float], list[float], list[float]] | None,
    *,
    synchronization: ruckig.Synchronization,
    minimum_duration: float | None,
    interface: ruckig.ControlInterface = ruckig.ControlInterface.Position,
) -> ruckig.InputParameter:
    """Ruckig's input for one move (states in the joint units, limits from ``limits``).

    Args:
        limits: Velocity, acceleration and jerk limits.
        q0: Start positions, shape (n,).
        q1: Target positions, shape (n,).
        states: Start velocities and accelerations, target velocities and accelerations,
            or None for rest at both ends (Ruckig's default).
        synchronization: Ruckig's synchronisation option.
        minimum_duration: Shortest duration [s], or None.
        interface: Ruckig's control interface.
    """
    inp = ruckig.InputParameter(limits.n)
    if interface != ruckig.ControlInterface.Position:
        inp.control_interface = interface
    if synchronization != ruckig.Synchronization.Time:
        inp.synchronization = synchronization
    inp.current_position = q0.tolist()
    inp.target_position = q1.tolist()
    if states is not None:
        (
            inp.current_velocity,
            inp.current_acceleration,
            inp.target_velocity,
            inp.target_acceleration,
        ) = states
    floats = limits.floats
    inp.max_velocity = floats["velocity"]
    inp.max_acceleration = floats["acceleration"]
    inp.max_jerk = floats["jerk"]
    if minimum_duration is not None:
        inp.minimum_duration = minimum_duration
    return inp


def _ruckig_error(exc: Exception, limits: JointLimits) -> Exception:
    """A typed error for an exception raised inside Ruckig, its DoF index named as a joint."""
    text = str(exc).strip().removeprefix("[ruckig]").strip()
    found = re.search(r"DoF (\d+)", text)
    joint = None
    if found and int(found.group(1)) < limits.n:
        joint = limits.names[int(found.group(1))]
        text = text.replace(found.group(0), f"joint {joint!r}")
    if "exceed" in text or "undercut" in text:
        limit = "acceleration" if "acceleration limit" in text else "velocity"
        return InfeasibleError(f"ruckig: {text}", limit=limit, joint=joint)
    return SolverError("ruckig", type(exc).__name__, detail=text)


class _Calculators(threading.local):
    """Ruckig calculators by joint count, one set per thread.

    Building a calculator costs about as much as an offline calculation, which starts
    afresh from its input every time (results do not depend on earlier calls); a
    calculator holds scratch space, so threads do not share one.
    """

    def __init__(self) -> None:
        self.by_dof: dict[int, ruckig.Ruckig] = {}


_CALCULATORS = _Calculators()


def _calculator(n: int) -> ruckig.Ruckig:
    """This thread's Ruckig calculator for n joints (offline use only)."""
    calculators = _CALCULATORS.by_dof
    calculator = calculators.get(n)
    if calculator is None:
        calculator = calculators[n] = ruckig.Ruckig(n)
    return calculator


def calculate(inp: ruckig.InputParameter, limits: JointLimits) -> ruckig.Trajectory:
    """Run Ruckig's offline calculation.

    Raises:
        InfeasibleError: Ruckig finds the input out of reach within the limits.
        SolverError: Any other Ruckig failure, with Ruckig's status.
    """
    native = ruckig.Trajectory(limits.n)
    try:
        result = _calculator(limits.n).calculate(inp, native)
    except (ruckig.RuckigError, RuntimeError) as exc:  # RuckigError is a bare Exception
        raise _ruckig_error(exc, limits) from exc
    except ValueError as exc:  # a status the binding's Result enum lacks, e.g. -101
        raise SolverError(
            "ruckig",
            str(exc).split()[0],
            detail="Ruckig returned a status its Python binding does not name (-101: the "
            "duration exceeds Ruckig's numerical range, about 7.6e3 s)",
        ) from exc
    if result not in _GOOD:
        raise SolverError(
            "ruckig",
            result.name,
            detail="no trajectory within the velocity, acceleration and jerk limits was found",
        )
    return native


# ---------------------------------------------------------------------------- conversion


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
        for length, p, v, a, jerk in fields:
            if length > 0.0:
                starts.append(clock)
                states.append([p, v, a, jerk])
                clock += length
        clock = brake.duration
    # Each field access converts a whole array: read them once.
    fields = zip(profile.t, profile.p, profile.v, profile.a, profile.j, strict=False)
    for length, p, v, a, jerk in fields:
        if length > 0.0:
            starts.append(clock)
            states.append([p, v, a, jerk])
        clock += length
    starts.append(clock)
    states.append([profile.pf, profile.vf, profile.af, 0.0])
    return starts, states


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
    breaks, coefficients = _native_pieces(native)
    return Trajectory(
        breaks, coefficients, joint_names=joint_names, phases=phases, metadata=metadata
    )


def _native_pieces(native: ruckig.Trajectory) -> tuple[FloatArray, FloatArray]:
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


# ------------------------------------------------------------------------- limit checks


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


def _position_breach(
    native: ruckig.Trajectory, limits: JointLimits, start: FloatArray, goal: FloatArray | None
) -> InfeasibleError | None:
    """The first position limit a move passes, exactly; None when it passes none.

    Ruckig's ``position_extrema`` cannot be used: in 0.19 it misses extrema inside
    constant-acceleration phases (pantor/ruckig#215; here 0.15 rad on a Sawyer wrist move).
    Instead, a joint is first bounded by its speed limit alone: over a move of duration T
    from p0 to p1 it stays within (p0 + p1 -/+ v_max T) / 2. Only where that bound reaches
    past a limit is Ruckig asked when the joint first gets there
    (``get_first_time_at_position``, which solves each phase's cubic; it ignores a brake
    pre-profile, which a start state within the limits does not have). When it names a
    time, the exact check on the polynomials (:func:`_violations`) decides.

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


def _ends_breach(
    native: ruckig.Trajectory, limits: JointLimits, start: FloatArray, goal: FloatArray
) -> InfeasibleError | None:
    """The position check of a move from rest to rest: on its start and target only.

    Such a move stays between the two (see :func:`_move`). They were accepted within 1e-9 of
    the limits, more than the round-off slack of a joint with a short range, so ends that are
    not within the limits themselves are settled on the exact polynomials.
    """
    floats = limits.floats
    lower, upper = floats["lower"], floats["upper"]
    for ends in (start.tolist(), goal.tolist()):
        # map over float tuples: seven comparisons without a Python-level loop.
        if not (all(map(operator.le, lower, ends)) and all(map(operator.le, ends, upper))):
            return _exact_position_breach(native, limits)
    return None


def _exact_position_breach(
    native: ruckig.Trajectory, limits: JointLimits
) -> InfeasibleError | None:
    """The first position breach on the exact polynomials, or None."""
    knots, coefficients = _native_pieces(native)
    for error in _violations(knots, coefficients, limits):
        if error.limit == "position":
            return error
    return None


def _violations(knots: FloatArray, c: FloatArray, limits: JointLimits) -> list[InfeasibleError]:
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
    slack = round_off(limits.upper - limits.lower, c1 + taus * (2 * c2 + 3 * taus * c3), duration)
    low, high = values.min(axis=(0, 1)), values.max(axis=(0, 1))
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


def _checked_pieces(
    native: ruckig.Trajectory, limits: JointLimits
) -> tuple[FloatArray, FloatArray]:
    """The polynomials of a move whose start state was within the limits, checked exactly.

    Ruckig keeps such a move within the velocity, acceleration and jerk limits by
    construction, and its positions were checked when it was planned (from rest to rest:
    they lie between the start and the target); a breach found here would be a fault of
    Ruckig's, reported as one rather than returned.

    Raises:
        SolverError: The polynomials break a limit.
    """
    knots, coefficients = _native_pieces(native)
    errors = _violations(knots, coefficients, limits)
    if errors:
        raise SolverError("ruckig", "limits exceeded", detail=str(errors[0]))
    return knots, coefficients


# ------------------------------------------------------------------------------ moves


def _move(
    limits: JointLimits,
    start: FloatArray,
    v0: FloatArray,
    a0: FloatArray | None,
    goal: FloatArray,
    v1: FloatArray,
    a1: FloatArray | None,
    *,
    started: float,
    synchronization: str,
    minimum_duration: float | None,
    check_limits: bool,
    joint_names: Sequence[str] | None,
    interface: str = "position",
) -> Trajectory:
    """Plan one move from validated states (positions within their limits).

    Accelerations of None are zero. With ``check_limits`` the start state must be within the
    limits; the result is then exact and checked, but its polynomials are built on first
    use (:meth:`Trajectory.deferred`), since Ruckig plans in microseconds and the conversion
    costs more. Without it, the polynomials are built and every breach is listed at once.
    """
    n = limits.n
    zeros = np.zeros(n)
    a0 = zeros if a0 is None else a0
    a1 = zeros if a1 is None else a1
    # Lists: testing seven floats in Python is cheaper than one NumPy call.
    states = (v0.tolist(), a0.tolist(), v1.tolist(), a1.tolist())
    moving = any(any(values) for values in states)
    if moving:
        _check_unsynchronised(synchronization, v1, a1)
        if check_limits:
            check_state(v0, a0, limits, "start", arriving=False)
        check_state(v1, a1, limits, "target", arriving=True)
    inp = ruckig_input(
        limits,
        start,
        goal,
        states if moving else None,
        synchronization=_synchronization(synchronization),
        minimum_duration=minimum_duration,
        interface=_INTERFACES[interface],
    )
    native = calculate(inp, limits)
    duration = float(native.duration)
    if duration <= 0.0:
        if interface == "velocity":
            raise InvalidInputError("nothing to stop: the joints are already at rest", name="qd0")
        raise InvalidInputError(
            "q_goal equals q_start and the boundary velocities and accelerations match, so "
            "the move lasts 0 s: give a minimum_duration to hold still",
            name="q_goal",
        )
    stopping = interface == "velocity"
    if check_limits:
        # From rest to rest a joint stays between its start and its target: Ruckig does not
        # overshoot a target at rest (its author, pantor/ruckig#22), nor, in our tests, back
        # off its start; so only those two are checked. Other moves are checked exactly.
        # Every move's polynomials are checked again when first built.
        breach = (
            _position_breach(native, limits, start, None if stopping else goal)
            if moving
            else _ends_breach(native, limits, start, goal)
        )
        if breach is not None:
            raise breach
        errors: list[InfeasibleError] = []
    else:
        knots, coefficients = _native_pieces(native)
        errors = _violations(knots, coefficients, limits)
    # The metadata that planners.base.stamp writes, assembled in one go (this path is timed
    # against Ruckig itself, in microseconds).
    metadata = {
        "planner": "ruckig",
        "status": "limits exceeded" if errors else "ok",
        "limit_violations": [str(error) for error in errors],
        "independent_min_durations": np.array(native.independent_min_durations, dtype=float),
        "native": native,
        "synchronization": synchronization,
    }
    if stopping:
        metadata["interface"] = interface
    else:
        metadata["minimum_duration"] = minimum_duration
    names = _joint_names(joint_names, limits)
    phases = (Phase("stop" if stopping else "move", 0.0, duration),)
    if check_limits:
        traj = Trajectory.deferred(
            duration,
            n,
            functools.partial(_checked_pieces, native, limits),
            joint_names=names,
            phases=phases,
            metadata=metadata,
        )
    else:
        traj = Trajectory(knots, coefficients, joint_names=names, phases=phases, metadata=metadata)
    traj.metadata["solve_time"] = time.perf_counter() - started
    return traj


def state_to_state(
    q0: ArrayLike,
    qd0: ArrayLike | None,
    qdd0: ArrayLike | None,
    q1: ArrayLike,
    qd1: ArrayLike | None,
    qdd1: ArrayLike | None,
    limits: JointLimits,
    *,
    synchronization: str = "time",
    minimum_duration: float | None = None,
    joint_names: Sequence[str] | None = None,
    check_limits: bool = True,
) -> Trajectory:
    """The time-optimal jerk-limited move from one joint state to another.

    Args:
        q0: Start positions [rad or m], shape (n,).
        qd0: Start velocities [rad/s or m/s], shape (n,); rest when None.
        qdd0: Start accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        q1: Target positions [rad or m], shape (n,).
        qd1: Target velocities [rad/s or m/s], shape (n,); rest when None.
        qdd1: Target accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        limits: Velocity, acceleration and jerk limits (and position limits, checked).
        synchronization: One of :data:`SYNCHRONIZATIONS`.
        minimum_duration: Shortest duration [s]; a longer move is stretched to it.
        joint_names: Names in the result; those of ``limits`` when None.
        check_limits: Raise when the move breaks a limit (the default). With False it is
            returned with the breaches listed in ``metadata["limit_violations"]`` and
            ``metadata["status"] == "limits exceeded"``; only a start state out of the
            limits can cause one (Ruckig brakes it back first), or an overshoot of a
            position limit.

    Returns:
        A degree-3 trajectory with one phase ``move``; metadata holds ``planner``
        (``"ruckig"``), ``solve_time`` [s], ``status``, ``independent_min_durations`` [s]
        (shape (n,), each joint's own fastest time), ``synchronization``,
        ``minimum_duration``, ``limit_violations`` and ``native`` (the ``ruckig.Trajectory``).
        With ``check_limits`` its polynomials are built on first use (the duration,
        phases and metadata are there at once; see :meth:`Trajectory.deferred`).

    Raises:
        InfeasibleError: A start or target state out of the limits or out of reach within
            them (names the joint, the required and the allowed value), or a move that
            breaks a limit on the way (e.g. overshoots a position limit).
        JointLimitError: A start or target position outside the position limits.
        InvalidInputError: Bad shapes or values, nothing to move and no minimum duration,
            a minimum duration outside [1e-6, 86400] s, joint names that are not n strings,
            a check_limits that is not a bool, or synchronisation ``none`` with a target
            that is not at rest.
        UnknownNameError: An unknown synchronisation.
        SolverError: Ruckig fails otherwise; carries its status. Also raised by the first
            use of the polynomials if they break a limit (a fault of Ruckig's, not seen in
            our tests).
    """
    started = time.perf_counter()
    limits = checked_limits(limits)
    _synchronization(synchronization)
    minimum = _minimum_duration(minimum_duration)
    check_limits = as_flag(check_limits, "check_limits")
    n = limits.n
    start = as_vector(q0, "q0", n)
    goal = as_vector(q1, "q1", n)
    limits.check_position(start, tolerance=1e-9, context="start position")
    limits.check_position(goal, tolerance=1e-9, context="target position")
    return _move(
        limits,
        start,
        state_or_zeros(qd0, "qd0", n),
        state_or_zeros(qdd0, "qdd0", n),
        goal,
        state_or_zeros(qd1, "qd1", n),
        state_or_zeros(qdd1, "qdd1", n),
        started=started,
        synchronization=synchronization,
        minimum_duration=minimum,
        check_limits=check_limits,
        joint_names=joint_names,
    )


def stop(
    q0: ArrayLike,
    qd0: ArrayLike,
    qdd0: ArrayLike | None,
    limits: JointLimits,
    *,
    synchronization: str = "time",
    joint_names: Sequence[str] | None = None,
    check_limits: bool = True,
) -> Trajectory:
    """The fastest stop from a moving state within the limits; the position is free.

    Ruckig's velocity interface brings every joint to zero velocity and acceleration as
    fast as the acceleration and jerk limits allow (with ``synchronization="time"`` all
    joints come to rest together, at the slowest joint's time).

    Args:
        q0: Start positions [rad or m], shape (n,).
        qd0: Start velocities [rad/s or m/s], shape (n,).
        qdd0: Start accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.
        limits: Joint limits; the result is checked against all of them.
        synchronization: One of :data:`SYNCHRONIZATIONS`.
        joint_names: Names in the result; those of ``limits`` when None.
        check_limits: Raise when the stop breaks a limit (default), else list the breaches
            in ``metadata["limit_violations"]`` (e.g. a stop that runs past a position
            limit: it is still the shortest possible stop).

    Returns:
        A degree-3 trajectory with one phase ``stop``, ending at rest; metadata as for
        :func:`state_to_state` plus ``stop_position`` [rad or m], shape (n,).

    Raises:
        InfeasibleError: The start state is out of the limits, or the stop breaks a limit
            (names the joint and the values).
        JointLimitError: A start position outside the position limits.
        InvalidInputError: Bad shapes or values, joint names that are not n strings, a
            check_limits that is not a bool, or the state is already at rest.
        SolverError: Ruckig fails; carries its status.
    """
    started = time.perf_counter()
    limits = checked_limits(limits)
    _synchronization(synchronization)
    check_limits = as_flag(check_limits, "check_limits")
    n = limits.n
    start = as_vector(q0, "q0", n)
    limits.check_position(start, tolerance=1e-9, context="start position")
    zeros = np.zeros(n)
    traj = _move(
        limits,
        start,
        as_vector(qd0, "qd0", n),
        state_or_zeros(qdd0, "qdd0", n),
        start,
        zeros,
        zeros,
        started=started,
        synchronization=synchronization,
        minimum_duration=None,
        check_limits=check_limits,
        joint_names=joint_names,
        interface="velocity",
    )
    # From Ruckig's own result: sampling ours would build the polynomials now.
    native = traj.metadata["native"]
    traj.metadata["stop_position"] = np.array(native.at_time(native.duration)[0], dtype=float)
    return traj


class Ruckig(JointProfile):
    """Time-optimal jerk-limited moves, rest-to-rest or between moving states.

    Results are exact piecewise cubics, checked against every limit; their polynomials are
    built on first use (:meth:`Trajectory.deferred`), so planning costs little more than
    Ruckig itself.

    Args:
        synchronization: How the joints are coordinated, one of :data:`SYNCHRONIZATIONS`:
            ``time`` (default; all start and end together), ``phase`` (also on a straight
            joint-space line when possible), ``time_if_necessary`` or ``none``.
        minimum_duration: Shortest duration [s] of every move, or None.

    Raises:
        UnknownNameError: An unknown synchronisation.
        InvalidInputError: A minimum duration outside [1e-6, 86400] s.
    """

    name = "ruckig"

    def __init__(
        self, synchronization: str = "time", minimum_duration: float | None = None
    ) -> None:
        _synchronization(synchronization)
        self.synchronization = synchronization
        self.minimum_duration = _minimum_duration(minimum_duration)

    def __repr__(self) -> str:
        return (
            f"Ruckig(synchronization={self.synchronization!r}, "
            f"minimum_duration={self.minimum_duration!r})"
        )

    def move(
        self,
        q_start: ArrayLike,
        q_goal: ArrayLike,
        limits: JointLimits,
        duration: float | None = None,
    ) -> Trajectory:
        """One rest-to-rest move, as fast as the limits allow.

        Args:
            q_start: Start positions [rad or m], shape (n,).
            q_goal: Goal positions [rad or m], shape (n,).
            limits: Joint limits.
            duration: Shortest duration [s] (Ruckig stretches a faster move to it; a move
                that needs longer takes longer), or None.

        Returns:
            See :func:`state_to_state`.

        Raises:
            See :func:`state_to_state`.
        """
        limits = checked_limits(limits)
        still_rule = None if self.minimum_duration is not None else self.name
        start, goal, duration = rest_to_rest_inputs(q_start, q_goal, limits, duration, still_rule)
        return state_to_state(
            start,
            None,
            None,
            goal,
            None,
            None,
            limits,
            synchronization=self.synchronization,
            minimum_duration=_minimum_duration(duration, self.minimum_duration),
        )

    def plan(self, problem: PointToPoint) -> Trajectory:
        """Plan a :class:`problems.PointToPoint`, which may start and end moving.

        Unprescribed accelerations (None) are taken as zero; the problem's duration, if
        any, is a minimum duration. The problem has already checked its states' shapes and
        positions, so only what Ruckig needs beyond that is checked here.

        Raises:
            InvalidInputError: Not a PointToPoint.
            InfeasibleError: The target state is out of reach within the limits, or the
                move breaks a limit (see :func:`state_to_state`).
            SolverError: Ruckig fails, or it ends farther from the target state than the
                problem's tolerance allows as the checker judges it (Ruckig meets targets to
                about 1e-8; a smaller tolerance may not be met).

        A returned plan passes :func:`planners.checker.check` against the problem.
        """
        if not isinstance(problem, PointToPoint):
            raise InvalidInputError(
                f"{type(self).__name__} plans a problems.PointToPoint, got "
                f"{type(problem).__name__}",
                name="problem",
            )
        if self.minimum_duration is None:  # with one, a still move is a hold
            problem.require_motion(self.name)
        started = time.perf_counter()
        limits = checked_limits(problem.limits)
        minimum = self.minimum_duration
        if problem.duration is not None:
            minimum = _minimum_duration(problem.duration, minimum)
        # PointToPoint stores its states as validated float arrays (velocities zero at rest).
        traj = _move(
            limits,
            cast(FloatArray, problem.q_start),
            cast(FloatArray, problem.qd_start),
            cast("FloatArray | None", problem.qdd_start),
            cast(FloatArray, problem.q_goal),
            cast(FloatArray, problem.qd_goal),
            cast("FloatArray | None", problem.qdd_goal),
            started=started,
            synchronization=self.synchronization,
            minimum_duration=minimum,
            check_limits=True,
            joint_names=limits.names,
        )
        _check_end(traj.metadata["native"], problem, limits)
        return traj


def _check_end(native: ruckig.Trajectory, problem: PointToPoint, limits: JointLimits) -> None:
    """Raise SolverError when Ruckig misses the prescribed end state as the checker judges it.

    Ruckig meets a target state only to its own precision (in our tests up to 1e-8 rad off
    the target position), so a problem with a tighter tolerance would fail the checker's
    ``end state``. The rule is the checker's (:func:`planners.checker.state_allowance`),
    with no allowance for the jerk at the end, so a move that passes here passes there.
    The start needs no check: Ruckig's first piece is the start state itself.
    """
    duration = float(native.duration)
    ends = native.at_time(duration)  # lists: seven joints cost less in Python than in NumPy
    wanted = (
        cast(FloatArray, problem.q_goal),
        cast(FloatArray, problem.qd_goal),
        cast("FloatArray | None", problem.qdd_goal),
    )
    tolerance = float(problem.tolerance)
    # Within the bare tolerance is within the rule's allowance (which adds round-off to it).
    if all(
        abs(x - y) <= tolerance
        for got, target in zip(ends, wanted, strict=True)
        if target is not None
        for x, y in zip(got, target.tolist(), strict=True)
    ):
        return
    actual = tuple(np.array(x, dtype=float) for x in ends)  # position, velocity, acceleration
    allowed = state_allowance(
        wanted, (actual[1], actual[2], np.zeros(limits.n)), tolerance, limits, duration
    )
    for order, (target, bound) in enumerate(zip(wanted, allowed, strict=True)):
        if target is None or bound is None:
            continue
        miss = np.abs(actual[order] - target)
        j = int(np.argmax(miss - bound))
        if miss[j] > bound[j]:
            quantity = ("position", "velocity", "acceleration")[order]
            unit = limits.unit(quantity, j)
            raise SolverError(
                "ruckig",
                "target state missed",
                detail=f"the move ends with the {quantity} of joint {limits.names[j]!r} "
                f"{miss[j]:.3g} {unit} off its target {target[j]:.6g} {unit}, beyond the "
                f"problem's tolerance {tolerance:.3g} (Ruckig meets targets to about 1e-8); "
                "give a larger tolerance",
            )


class OnlineRuckig:
    """Ruckig one control tick at a time: follow a (possibly changing) target state.

    Each :meth:`update` advances the jerk-limited motion by ``dt`` and returns the new
    commanded state; when the target changes, Ruckig re-plans from the current state.

    Example::

        online = OnlineRuckig(robot.limits, dt=1e-3)
        online.reset(q)
        while not online.finished:
            q, qd, qdd = online.update(q_target)

    Args:
        limits: Velocity, acceleration and jerk limits; targets are checked against all.
        dt: Control period [s], in [1e-6, 86400].
        synchronization: One of :data:`SYNCHRONIZATIONS`.

    Raises:
        InvalidInputError: Bad limits or period.
        UnknownNameError: An unknown synchronisation.
    """

    def __init__(self, limits: JointLimits, dt: float, *, synchronization: str = "time") -> None:
        self.limits = checked_limits(limits)
        self.dt = as_duration(dt, "dt")
        self.synchronization = synchronization
        self._sync = _synchronization(synchronization)
        self._otg = ruckig.Ruckig(self.limits.n, self.dt)
        self._out = ruckig.OutputParameter(self.limits.n)
        self._inp: ruckig.InputParameter | None = None
        self._result: ruckig.Result | None = None

    def reset(
        self, q: ArrayLike, qd: ArrayLike | None = None, qdd: ArrayLike | None = None
    ) -> None:
        """Start from a joint state; rest when velocities and accelerations are not given.

        Args:
            q: Positions [rad or m], shape (n,).
            qd: Velocities [rad/s or m/s], shape (n,), or None.
            qdd: Accelerations [rad/s^2 or m/s^2], shape (n,), or None.

        Raises:
            InvalidInputError: Bad shapes or values.
            InfeasibleError: A state out of the limits.
            JointLimitError: A position outside the position limits.
        """
        n = self.limits.n
        position = as_vector(q, "q", n)
        self.limits.check_position(position, tolerance=1e-9, context="reset position")
        velocity, acceleration = state_or_zeros(qd, "qd", n), state_or_zeros(qdd, "qdd", n)
        check_state(velocity, acceleration, self.limits, "start", arriving=False)
        zeros = [0.0] * n
        self._inp = ruckig_input(
            self.limits,
            position,
            position,
            (velocity.tolist(), acceleration.tolist(), zeros, zeros),
            synchronization=self._sync,
            minimum_duration=None,
        )
        self._otg.reset()
        self._result = None

    def update(
        self,
        target_q: ArrayLike,
        target_qd: ArrayLike | None = None,
        target_qdd: ArrayLike | None = None,
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Advance one tick towards a target state.

        Args:
            target_q: Target positions [rad or m], shape (n,).
            target_qd: Target velocities [rad/s or m/s], shape (n,); rest when None.
            target_qdd: Target accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.

        Returns:
            The new (q, qd, qdd) after ``dt``, each shape (n,).

        Raises:
            InvalidInputError: Bad shapes or values, :meth:`reset` was never called, or a
                moving target with synchronisation ``none``.
            InfeasibleError: A target state out of the limits or out of reach.
            JointLimitError: A target position outside the position limits.
            SolverError: Ruckig fails; carries its status.
        """
        if self._inp is None:
            raise InvalidInputError(
                "OnlineRuckig.update needs a start state: call reset(q) first", name="reset"
            )
        n = self.limits.n
        goal = as_vector(target_q, "target_q", n)
        self.limits.check_position(goal, tolerance=1e-9, context="target position")
        velocity = state_or_zeros(target_qd, "target_qd", n)
        acceleration = state_or_zeros(target_qdd, "target_qdd", n)
        _check_unsynchronised(self.synchronization, velocity, acceleration)
        check_state(velocity, acceleration, self.limits, "target", arriving=True)
        self._inp.target_position = goal.tolist()
        self._inp.target_velocity = velocity.tolist()
        self._inp.target_acceleration = acceleration.tolist()
        try:
            result = self._otg.update(self._inp, self._out)
        except (ruckig.RuckigError, RuntimeError) as exc:
            raise _ruckig_error(exc, self.limits) from exc
        if result not in _GOOD:
            raise SolverError("ruckig", result.name, detail="online update failed")
        self._result = result
        self._out.pass_to_input(self._inp)
        return (
            np.array(self._out.new_position, dtype=float),
            np.array(self._out.new_velocity, dtype=float),
            np.array(self._out.new_acceleration, dtype=float),
        )

    @property
    def finished(self) -> bool:
        """Whether the last :meth:`update` reached the target state."""
        return self._result == ruckig.Result.Finished

    @property
    def time(self) -> float:
        """Time [s] along the current plan (reset when the target changes)."""
        return float(self._out.time)

    @property
    def duration(self) -> float:
        """Duration [s] of the current plan, from its last (re)calculation."""
        return float(self._out.trajectory.duration)
