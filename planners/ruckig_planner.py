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

Limits are checked twice: the start and target states are validated before Ruckig runs
(a target that no motion within the limits can reach raises :class:`InfeasibleError` naming
the joint), and the finished trajectory's exact peaks are compared with every limit, the
position limits included (Ruckig's open-source version does not plan around them), so a
trajectory that breaks a limit is never returned silently.
"""

from __future__ import annotations

import math
import re
import time
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np
import ruckig
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError, SolverError, UnknownNameError
from optraj.validation import as_positive, as_vector
from planners.base import JointProfile, rest_to_rest_inputs, stamp
from planners.trajectory import Phase, Trajectory
from problems import PointToPoint
from robots import JointLimits

__all__ = [
    "SYNCHRONIZATIONS",
    "OnlineRuckig",
    "Ruckig",
    "native_to_trajectory",
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

#: Relative slack on limits for floating-point round-off (the checker's is the same).
_SLACK = 1e-9
#: Absolute slack on limits [unit of the quantity].
_ABSOLUTE_SLACK = 1e-12
#: Shortest segment kept [s], per second of duration; shorter ones are Ruckig's round-off.
_MIN_SEGMENT = 1e-12
#: Results that carry a usable trajectory.
_GOOD = (ruckig.Result.Working, ruckig.Result.Finished)


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
    """The largest of the given minimum durations [s] (each None or > 0), or None."""
    found: list[float] = []
    for value in values:
        if value is not None:
            found.append(as_positive(value, "minimum_duration", "s"))
    return max(found) if found else None


def _limits(limits: object) -> JointLimits:
    """``limits`` if it is a :class:`robots.JointLimits`, else InvalidInputError."""
    if not isinstance(limits, JointLimits):
        raise InvalidInputError(
            f"limits must be a robots.JointLimits, got {type(limits).__name__}", name="limits"
        )
    return limits


def _optional(value: ArrayLike | None, name: str, n: int) -> FloatArray:
    """A state vector of length n; zeros when None."""
    return np.zeros(n) if value is None else as_vector(value, name, n)


def _bound(limit: ArrayLike) -> FloatArray:
    """Limits with the round-off slack added (same shape)."""
    return np.asarray(limit, dtype=float) * (1.0 + _SLACK) + _ABSOLUTE_SLACK


def _check_state(
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
    bound = (lambda limit: limit) if arriving else _bound
    for j, name in enumerate(limits.names):
        for quantity, value, allowed in (
            ("velocity", qd[j], limits.velocity[j]),
            ("acceleration", qdd[j], limits.acceleration[j]),
        ):
            if abs(value) > bound(allowed):
                raise InfeasibleError(
                    f"{label} {quantity} {value:.6g} {limits.unit(quantity, j)} of joint "
                    f"{name!r} exceeds its limit {allowed:.6g} {limits.unit(quantity, j)}",
                    limit=quantity,
                    joint=name,
                    required=float(abs(value)),
                    allowed=float(allowed),
                )
        swing = qdd[j] * abs(qdd[j]) / (2.0 * limits.jerk[j])
        implied = qd[j] - swing if arriving else qd[j] + swing
        if abs(implied) > bound(limits.velocity[j]):
            when = "before it arrives at" if arriving else "after it leaves"
            raise InfeasibleError(
                f"joint {name!r} reaches a velocity of {implied:.6g} "
                f"{limits.unit('velocity', j)} {when} its {label} state (velocity "
                f"{qd[j]:.6g}, acceleration {qdd[j]:.6g}) with jerk limit "
                f"{limits.jerk[j]:.6g}; its velocity limit is {limits.velocity[j]:.6g}",
                limit="velocity",
                joint=name,
                required=float(abs(implied)),
                allowed=float(limits.velocity[j]),
            )


# ------------------------------------------------------------------------- ruckig calls


def _input(
    limits: JointLimits,
    q0: FloatArray,
    qd0: FloatArray,
    qdd0: FloatArray,
    q1: FloatArray,
    qd1: FloatArray,
    qdd1: FloatArray,
    *,
    synchronization: ruckig.Synchronization,
    minimum_duration: float | None,
    interface: ruckig.ControlInterface = ruckig.ControlInterface.Position,
) -> ruckig.InputParameter:
    """Ruckig's input for one move (states in the joint units, limits from ``limits``)."""
    inp = ruckig.InputParameter(limits.n)
    inp.control_interface = interface
    inp.synchronization = synchronization
    inp.current_position = q0.tolist()
    inp.current_velocity = qd0.tolist()
    inp.current_acceleration = qdd0.tolist()
    inp.target_position = q1.tolist()
    inp.target_velocity = qd1.tolist()
    inp.target_acceleration = qdd1.tolist()
    inp.max_velocity = limits.velocity.tolist()
    inp.max_acceleration = limits.acceleration.tolist()
    inp.max_jerk = limits.jerk.tolist()
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


def _calculate(inp: ruckig.InputParameter, limits: JointLimits) -> ruckig.Trajectory:
    """Run Ruckig's offline calculation.

    Raises:
        InfeasibleError: Ruckig finds the input out of reach within the limits.
        SolverError: Any other Ruckig failure, with Ruckig's status.
    """
    native = ruckig.Trajectory(limits.n)
    try:
        result = ruckig.Ruckig(limits.n).calculate(inp, native)
    except (ruckig.RuckigError, RuntimeError) as exc:  # RuckigError is a bare Exception
        raise _ruckig_error(exc, limits) from exc
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
    1e-12 s per second of duration, Ruckig's round-off, are merged into their neighbours);
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
        InvalidInputError: A trajectory of zero duration, or one with waypoint sections.
        SolverError: A Ruckig profile this conversion does not know (an acceleration
            post-profile, unused by Ruckig 0.19's ``at_time``).
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
    tolerance = _MIN_SEGMENT * max(1.0, duration)
    per_joint: list[tuple[FloatArray, FloatArray]] = []
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
        per_joint.append((np.asarray(starts), np.asarray(states)))
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
    coefficients = np.empty((len(middles), 4, len(per_joint)))
    for dof, (starts, states) in enumerate(per_joint):
        piece = np.clip(np.searchsorted(starts, middles, side="right") - 1, 0, None)
        tau = breaks[:-1] - starts[piece]
        p, v, a, jerk = states[piece].T
        coefficients[:, 0, dof] = p + tau * (v + tau * (a / 2.0 + tau * jerk / 6.0))
        coefficients[:, 1, dof] = v + tau * (a + tau * jerk / 2.0)
        coefficients[:, 2, dof] = (a + tau * jerk) / 2.0
        coefficients[:, 3, dof] = jerk / 6.0
    return Trajectory(
        breaks, coefficients, joint_names=joint_names, phases=phases, metadata=metadata
    )


# ------------------------------------------------------------------------- limit checks


def _violations(traj: Trajectory, limits: JointLimits) -> list[InfeasibleError]:
    """Exact peaks of a piecewise cubic against every joint limit; one error per breach.

    Velocity peaks lie at segment ends or at the vertex of the quadratic, position extremes
    at segment ends or where the velocity vanishes; acceleration is linear and jerk constant
    on each segment. Candidate times outside a segment are replaced by its start (already a
    candidate), so no masking is needed.
    """
    knots = traj.breakpoints
    c = traj.coefficients
    c0, c1, c2, c3 = (c[:, i, :] for i in range(4))  # each (K, n)
    h = np.broadcast_to(np.diff(knots)[:, None], c0.shape)
    zero = np.zeros_like(c0)

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
    # Position: both bounds.
    taus = np.stack([zero, h, first, second])  # (m, K, n)
    values = (c0 + taus * (c1 + taus * (c2 + taus * c3))).reshape(-1, c0.shape[1])
    times = (knots[:-1, None] + taus).reshape(values.shape)
    slack = _SLACK * (limits.upper - limits.lower) + _ABSOLUTE_SLACK
    for sign, bound, side in (
        (-1.0, limits.lower, "below its lower"),
        (1.0, limits.upper, "above its upper"),
    ):
        worst = np.argmax(sign * values, axis=0)
        extreme = values[worst, np.arange(limits.n)]
        for j in np.flatnonzero(sign * (extreme - bound) > slack).tolist():
            name = limits.names[j]
            when = float(times[worst[j], j])
            errors.append(
                InfeasibleError(
                    f"joint {name!r} reaches {extreme[j]:.6g} {limits.unit('position', j)} at "
                    f"t = {when:.4g} s, {side} position limit {bound[j]:.6g}",
                    limit="position",
                    joint=name,
                    required=float(extreme[j]),
                    allowed=float(bound[j]),
                )
            )
    # Velocity, acceleration, jerk: magnitudes.
    for quantity, taus_q, evaluate in (
        ("velocity", np.stack([zero, h, vertex]), lambda t: c1 + t * (2 * c2 + 3 * t * c3)),
        ("acceleration", np.stack([zero, h]), lambda t: 2 * c2 + 6 * t * c3),
        ("jerk", zero[None], lambda t: 6 * c3 + 0 * t),
    ):
        magnitude = np.abs(evaluate(taus_q)).reshape(-1, c0.shape[1])
        times = (knots[:-1, None] + taus_q).reshape(magnitude.shape)
        worst = np.argmax(magnitude, axis=0)
        peak = magnitude[worst, np.arange(limits.n)]
        allowed = getattr(limits, quantity)
        for j in np.flatnonzero(peak > _bound(allowed)).tolist():
            name = limits.names[j]
            when = float(times[worst[j], j])
            errors.append(
                InfeasibleError(
                    f"joint {name!r} reaches a {quantity} of {peak[j]:.6g} "
                    f"{limits.unit(quantity, j)} at t = {when:.4g} s, above its limit "
                    f"{allowed[j]:.6g}",
                    limit=quantity,
                    joint=name,
                    required=float(peak[j]),
                    allowed=float(allowed[j]),
                )
            )
    return errors


# ------------------------------------------------------------------------------ moves


def _finish(
    native: ruckig.Trajectory,
    limits: JointLimits,
    *,
    started: float,
    phase: str,
    check_limits: bool,
    joint_names: Sequence[str] | None,
    extra: Mapping[str, Any],
) -> Trajectory:
    """Convert, check against the limits, and stamp the metadata."""
    if native.duration <= 0.0:
        raise InvalidInputError(
            "nothing to move: the start state is the target state; give a minimum_duration "
            "to hold it",
            name="q_goal",
        )
    names = limits.names if joint_names is None else tuple(joint_names)
    traj = native_to_trajectory(
        native, joint_names=names, phases=[Phase(phase, 0.0, float(native.duration))]
    )
    errors = _violations(traj, limits)
    if errors and check_limits:
        raise errors[0]
    return stamp(
        traj,
        "ruckig",
        started,
        status="ok" if not errors else "limits exceeded",
        limit_violations=[str(error) for error in errors],
        independent_min_durations=np.asarray(native.independent_min_durations, dtype=float),
        native=native,
        **extra,
    )


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

    Raises:
        InfeasibleError: A start or target state out of the limits or out of reach within
            them (names the joint, the required and the allowed value), or a move that
            breaks a limit on the way (e.g. overshoots a position limit).
        JointLimitError: A start or target position outside the position limits.
        InvalidInputError: Bad shapes or values, nothing to move and no minimum duration,
            or synchronisation ``none`` with a target that is not at rest.
        UnknownNameError: An unknown synchronisation.
        SolverError: Ruckig fails otherwise; carries its status.
    """
    started = time.perf_counter()
    limits = _limits(limits)
    sync = _synchronization(synchronization)
    minimum = _minimum_duration(minimum_duration)
    n = limits.n
    start = as_vector(q0, "q0", n)
    goal = as_vector(q1, "q1", n)
    limits.check_position(start, tolerance=1e-9, context="start position")
    limits.check_position(goal, tolerance=1e-9, context="target position")
    v0, a0 = _optional(qd0, "qd0", n), _optional(qdd0, "qdd0", n)
    v1, a1 = _optional(qd1, "qd1", n), _optional(qdd1, "qdd1", n)
    _check_unsynchronised(synchronization, v1, a1)
    if check_limits:
        _check_state(v0, a0, limits, "start", arriving=False)
    _check_state(v1, a1, limits, "target", arriving=True)
    inp = _input(
        limits, start, v0, a0, goal, v1, a1, synchronization=sync, minimum_duration=minimum
    )
    native = _calculate(inp, limits)
    return _finish(
        native,
        limits,
        started=started,
        phase="move",
        check_limits=check_limits,
        joint_names=joint_names,
        extra={"synchronization": synchronization, "minimum_duration": minimum},
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
        InvalidInputError: Bad shapes or values, or the state is already at rest.
        SolverError: Ruckig fails; carries its status.
    """
    started = time.perf_counter()
    limits = _limits(limits)
    sync = _synchronization(synchronization)
    n = limits.n
    start = as_vector(q0, "q0", n)
    limits.check_position(start, tolerance=1e-9, context="start position")
    v0, a0 = as_vector(qd0, "qd0", n), _optional(qdd0, "qdd0", n)
    if check_limits:
        _check_state(v0, a0, limits, "start", arriving=False)
    zeros = np.zeros(n)
    inp = _input(
        limits,
        start,
        v0,
        a0,
        start,
        zeros,
        zeros,
        synchronization=sync,
        minimum_duration=None,
        interface=ruckig.ControlInterface.Velocity,
    )
    native = _calculate(inp, limits)
    if native.duration <= 0.0:
        raise InvalidInputError("nothing to stop: the joints are already at rest", name="qd0")
    traj = _finish(
        native,
        limits,
        started=started,
        phase="stop",
        check_limits=check_limits,
        joint_names=joint_names,
        extra={"synchronization": synchronization, "interface": "velocity"},
    )
    traj.metadata["stop_position"] = traj.sample(traj.duration).q
    return traj


class Ruckig(JointProfile):
    """Time-optimal jerk-limited moves, rest-to-rest or between moving states.

    Args:
        synchronization: How the joints are coordinated, one of :data:`SYNCHRONIZATIONS`:
            ``time`` (default; all start and end together), ``phase`` (also on a straight
            joint-space line when possible), ``time_if_necessary`` or ``none``.
        minimum_duration: Shortest duration [s] of every move, or None.

    Raises:
        UnknownNameError: An unknown synchronisation.
        InvalidInputError: A minimum duration <= 0.
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
        limits = _limits(limits)
        start, goal, duration = rest_to_rest_inputs(q_start, q_goal, limits, duration)
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
        any, is a minimum duration.

        Raises:
            InvalidInputError: Not a PointToPoint.
            InfeasibleError: The target state is out of reach within the limits, or the
                move breaks a limit (see :func:`state_to_state`).
        """
        if not isinstance(problem, PointToPoint):
            raise InvalidInputError(
                f"{type(self).__name__} plans a problems.PointToPoint, got "
                f"{type(problem).__name__}",
                name="problem",
            )
        started = time.perf_counter()
        limits = _limits(problem.limits)
        traj = state_to_state(
            problem.q_start,
            problem.qd_start,
            problem.qdd_start,
            problem.q_goal,
            problem.qd_goal,
            problem.qdd_goal,
            limits,
            synchronization=self.synchronization,
            minimum_duration=_minimum_duration(problem.duration, self.minimum_duration),
            joint_names=limits.names,
        )
        traj.metadata["solve_time"] = time.perf_counter() - started
        return traj


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
        dt: Control period [s], > 0.
        synchronization: One of :data:`SYNCHRONIZATIONS`.

    Raises:
        InvalidInputError: Bad limits or period.
        UnknownNameError: An unknown synchronisation.
    """

    def __init__(self, limits: JointLimits, dt: float, *, synchronization: str = "time") -> None:
        self.limits = _limits(limits)
        self.dt = as_positive(dt, "dt", "s")
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
        velocity, acceleration = _optional(qd, "qd", n), _optional(qdd, "qdd", n)
        _check_state(velocity, acceleration, self.limits, "start", arriving=False)
        self._inp = _input(
            self.limits,
            position,
            velocity,
            acceleration,
            position,
            np.zeros(n),
            np.zeros(n),
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
        velocity = _optional(target_qd, "target_qd", n)
        acceleration = _optional(target_qdd, "target_qdd", n)
        _check_unsynchronised(self.synchronization, velocity, acceleration)
        _check_state(velocity, acceleration, self.limits, "target", arriving=True)
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
