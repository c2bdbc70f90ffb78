"""Linear segments with parabolic blends (LSPB): trapezoidal-velocity rest-to-rest moves.

Each joint accelerates at a constant rate for a blend time ``tb``, cruises at a constant
velocity ``v``, and decelerates for ``tb`` again, so its velocity is a trapezoid (a triangle
when it never cruises) and its position is piecewise quadratic: C1, with jumps in acceleration.

Closed forms used here (textbook facts, our derivations and code):

* Spong, Hutchinson & Vidyasagar, *Robot Modeling and Control* (2006), ch. 5, "Linear segments
  with parabolic blends" and "Minimum-time trajectories": ``v = delta / (T - tb)``.
* Craig, *Introduction to Robotics* (3rd ed., 2005), sec. 7.3, the blend of a linear function
  with parabolic blends at a given acceleration ``a``:
  ``tb = T/2 - sqrt(a^2 T^2 - 4 a |delta|) / (2 a)``, which needs ``a >= 4 |delta| / T^2``.
* Biagiotti & Melchiorri, *Trajectory Planning for Automatic Machines and Robots* (2008),
  ch. 3, the trapezoidal velocity profile: minimum time with velocity and acceleration limits
  and its triangular case.

Every displacement, velocity and acceleration below is per joint, in [rad, rad/s, rad/s^2]
for revolute joints and [m, m/s, m/s^2] for prismatic ones.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.base import JointProfile, rest_to_rest_inputs, stamp
from optraj.planners.trajectory import Trajectory
from optraj.robots import JointLimits
from optraj.validation import (
    MAX_DURATION,
    MIN_DURATION,
    as_array,
    as_duration,
    as_flag,
    as_number,
)

__all__ = [
    "LSPB",
    "LSPBTiming",
    "lspb_fixed_blend",
    "lspb_fixed_cruise",
    "lspb_min_time",
    "lspb_shortest_blend",
    "lspb_trajectory",
]

FloatArray = NDArray[np.float64]

#: Relative excess over a limit that is taken as floating-point round-off, not a violation;
#: also the smallest gap between breakpoints, as a fraction of the duration.
ROUND_OFF = 1e-12
#: Shortest blend [-], as a fraction of the duration, that :func:`lspb_shortest_blend` makes.
MIN_BLEND = 1e-9


class LSPBTiming(NamedTuple):
    """Timing of rest-to-rest LSPB moves, one entry per joint.

    Attributes:
        duration: Move time T [s], shape (n,); 0 for a joint that does not move in a
            minimum-time timing.
        blend_time: Time tb [s] spent accelerating, and again decelerating, shape (n,);
            T / 2 when the profile is triangular, 0 for a joint that does not move.
        velocity: Cruise (peak) velocity v [rad/s or m/s], signed like the displacement,
            shape (n,).
        acceleration: Blend acceleration v / tb [rad/s^2 or m/s^2], signed like the
            displacement, shape (n,); 0 for a joint that does not move.
    """

    duration: FloatArray
    blend_time: FloatArray
    velocity: FloatArray
    acceleration: FloatArray


# ------------------------------------------------------------------------------ helpers


def _array(value: ArrayLike, name: str) -> FloatArray:
    """``value`` as a finite float array (any shape), or InvalidInputError naming it.

    No bools or strings: :func:`optraj.validation.as_array` checks it at its own shape.
    """
    try:
        shape = np.shape(value)
    except ValueError:  # ragged nesting: as_array reports it
        shape = (None,)
    return as_array(value, name, tuple(shape))


def _positive_array(value: ArrayLike, name: str) -> FloatArray:
    """``value`` as a finite float array with every entry > 0."""
    array = _array(value, name)
    if np.any(array <= 0.0):
        raise InvalidInputError(f"{name} must be > 0, got {array}", name=name, value=value)
    return array


def _positive_scalar(value: float, name: str) -> float:
    """``value`` as a time [s] in [MIN_DURATION, MAX_DURATION] (a duration or a blend)."""
    return as_duration(value, name)


def _non_negative_scalar(value: float, name: str) -> float:
    """``value`` as a time [s] in [0, MAX_DURATION] (a cruise time may be 0)."""
    return as_number(value, name, "s", minimum=0.0, maximum=MAX_DURATION)


def _broadcast(*arrays: FloatArray) -> list[FloatArray]:
    """Arrays broadcast to one shape, at least 1-D, as writable copies."""
    try:
        shaped = np.broadcast_arrays(*(np.atleast_1d(a) for a in arrays))
    except ValueError as exc:
        shapes = ", ".join(str(np.shape(a)) for a in arrays)
        raise InvalidInputError(
            f"per-joint arrays must have matching shapes, got {shapes}", name="delta"
        ) from exc
    return [np.array(a, dtype=float) for a in shaped]


def _joint_labels(
    size: int, names: Sequence[str] | None, units: Sequence[str] | None
) -> tuple[list[str], list[str]]:
    """Joint names (``joint 0`` ... when not given) and unit stems (``rad`` or ``m``)."""
    labels = list(names) if names is not None else [f"{j}" for j in range(size)]
    stems = list(units) if units is not None else [""] * size
    if len(labels) != size or len(stems) != size:
        raise InvalidInputError(
            f"names and units must have one entry per joint ({size})", name="names"
        )
    return labels, stems


def _unit(stem: str, power: int) -> str:
    """``rad/s``, ``m/s^2`` ... from a unit stem and the power of seconds (blank stem: '')."""
    if not stem:
        return ""
    return f" {stem}/s" if power == 1 else f" {stem}/s^{power}"


def _worst(required: FloatArray, allowed: FloatArray) -> int | None:
    """Index of the largest ratio required / allowed beyond round-off, or None."""
    excess = required / allowed
    worst = int(np.argmax(excess))
    return worst if excess[worst] > 1.0 + ROUND_OFF else None


# ------------------------------------------------------------------------ closed forms


def lspb_min_time(delta: ArrayLike, v_max: ArrayLike, a_max: ArrayLike) -> LSPBTiming:
    """Minimum-time rest-to-rest LSPB of each joint on its own (no synchronisation).

    A joint reaches its velocity limit when ``|delta| >= v_max^2 / a_max``: then
    ``tb = v_max / a_max`` and ``T = |delta| / v_max + v_max / a_max``. Otherwise the profile
    is triangular: ``tb = sqrt(|delta| / a_max)``, ``T = 2 tb``, ``v = a_max tb``
    (Biagiotti & Melchiorri 2008, ch. 3). A zero displacement gives ``T = tb = v = 0``.

    Args:
        delta: Displacements [rad or m], shape (n,) (or anything that broadcasts).
        v_max: Velocity limits [rad/s or m/s], > 0, broadcast against delta.
        a_max: Acceleration limits [rad/s^2 or m/s^2], > 0, broadcast against delta.

    Returns:
        The timing of each joint.

    Raises:
        InvalidInputError: Non-finite values, limits <= 0, or shapes that do not broadcast.
    """
    d, vmax, amax = _broadcast(
        _array(delta, "delta"), _positive_array(v_max, "v_max"), _positive_array(a_max, "a_max")
    )
    dist = np.abs(d)
    sign = np.sign(d)
    cruises = dist >= vmax**2 / amax
    blend = np.where(cruises, vmax / amax, np.sqrt(dist / amax))
    duration = np.where(cruises, dist / vmax + vmax / amax, 2.0 * blend)
    velocity = sign * np.where(cruises, vmax, amax * blend)
    return LSPBTiming(duration, blend, velocity, sign * amax)


def lspb_shortest_blend(
    delta: ArrayLike,
    a_max: ArrayLike,
    duration: float,
    *,
    v_max: ArrayLike | None = None,
    names: Sequence[str] | None = None,
    units: Sequence[str] | None = None,
) -> LSPBTiming:
    """LSPB of a given duration with the shortest blend whose acceleration fits ``a_max``.

    Each joint blends at exactly its acceleration limit ``a``; from ``|delta| = v (T - tb)`` and
    ``v = a tb`` (Craig 2005, sec. 7.3) the cruise velocity is
    ``v = (a T - sqrt(a^2 T^2 - 4 a |delta|)) / 2``, computed here in the cancellation-free
    form ``v = 2 |delta| / (T + sqrt(T^2 - 4 |delta| / a))``, and ``tb = v / a``. This is the
    slowest cruise (and shortest blend) of all LSPBs of duration T within the limit.

    Two round-off guards keep breakpoints apart: a cruise shorter than 1e-12 T is dropped
    (the profile becomes a triangle, its speed higher by at most 1e-12 of itself), and a
    joint whose blend would last under 1e-9 T (a displacement of round-off size) moves on a
    triangle over all of T, far below its acceleration limit.

    Args:
        delta: Displacements [rad or m], shape (n,).
        a_max: Acceleration limits [rad/s^2 or m/s^2], > 0, broadcast against delta.
        duration: Move time T [s], > 0, shared by every joint.
        v_max: Velocity limits [rad/s or m/s] to check the cruise velocity against, or None.
        names: Joint names for error messages.
        units: ``"rad"`` or ``"m"`` per joint, for error messages.

    Returns:
        The timing; every entry of ``duration`` is T.

    Raises:
        InfeasibleError: T is too short: some joint needs more than its acceleration limit
            (``4 |delta| / T^2``) or, when v_max is given, more than its velocity limit;
            names the joint, the required value and the limit.
        InvalidInputError: Non-finite values, limits <= 0 or T <= 0.
    """
    T = _positive_scalar(duration, "duration")
    arrays = [_array(delta, "delta"), _positive_array(a_max, "a_max")]
    if v_max is not None:
        arrays.append(_positive_array(v_max, "v_max"))
    d, amax, *rest = _broadcast(*arrays)
    labels, stems = _joint_labels(d.size, names, units)
    dist = np.abs(d)
    needed = 4.0 * dist / T**2
    worst = _worst(needed, amax)
    if worst is not None:
        raise InfeasibleError(
            f"LSPB in {T:.6g} s needs joint {labels[worst]!r} at {needed[worst]:.6g}"
            f"{_unit(stems[worst], 2)}, limit {amax[worst]:.6g}{_unit(stems[worst], 2)}",
            limit="acceleration",
            joint=labels[worst],
            required=float(needed[worst]),
            allowed=float(amax[worst]),
        )
    # Round-off may leave the discriminant a hair below zero when the acceleration binds.
    root = np.sqrt(np.maximum(T**2 - 4.0 * dist / amax, 0.0))
    speed = 2.0 * dist / (T + root)
    blend = np.minimum(speed / amax, 0.5 * T)
    vmax = rest[0] if rest else np.full_like(d, np.inf)
    if rest:
        worst = _worst(speed, vmax)
        if worst is not None:
            raise InfeasibleError(
                f"LSPB in {T:.6g} s needs joint {labels[worst]!r} at {speed[worst]:.6g}"
                f"{_unit(stems[worst], 1)}, limit {vmax[worst]:.6g}{_unit(stems[worst], 1)}",
                limit="velocity",
                joint=labels[worst],
                required=float(speed[worst]),
                allowed=float(vmax[worst]),
            )
    # Keep breakpoints well apart, so that they survive shifting (Trajectory.then): a cruise
    # shorter than round-off (1e-12 T) is dropped, which raises the speed by at most that
    # fraction; a blend shorter than MIN_BLEND T (a displacement of round-off size) becomes a
    # triangle over the whole move, far below the acceleration limit.
    moving = dist > 0.0
    tiny = moving & (blend <= MIN_BLEND * T) & (2.0 * dist / T <= vmax)
    triangle = moving & ((T - 2.0 * blend <= ROUND_OFF * T) | tiny)
    speed = np.where(triangle, 2.0 * dist / T, speed)
    blend = np.where(triangle, 0.5 * T, blend)
    sign = np.sign(d)
    acceleration = np.divide(speed, blend, out=np.zeros_like(speed), where=blend > 0.0)
    return LSPBTiming(np.full_like(d, T), blend, sign * speed, sign * acceleration)


def lspb_fixed_blend(delta: ArrayLike, duration: float, blend_time: float) -> LSPBTiming:
    """LSPB of a given duration and blend time: ``v = delta / (T - tb)``, ``a = v / tb``.

    (Spong, Hutchinson & Vidyasagar 2006, ch. 5.) Limits are not checked here.

    Args:
        delta: Displacements [rad or m], shape (n,).
        duration: Move time T [s], > 0.
        blend_time: Blend time tb [s], with 0 < tb <= T / 2.

    Returns:
        The timing; every joint has duration T and blend time tb.

    Raises:
        InvalidInputError: Non-finite values, T <= 0, or tb outside (0, T / 2].
    """
    T = _positive_scalar(duration, "duration")
    tb = _positive_scalar(blend_time, "blend_time")
    if tb > 0.5 * T:
        raise InvalidInputError(
            f"blend_time {tb:.6g} s must be at most half the duration {T:.6g} s",
            name="blend_time",
            value=tb,
        )
    (d,) = _broadcast(_array(delta, "delta"))
    velocity = d / (T - tb)
    return LSPBTiming(np.full_like(d, T), np.full_like(d, tb), velocity, velocity / tb)


def lspb_fixed_cruise(delta: ArrayLike, duration: float, cruise_time: float) -> LSPBTiming:
    """LSPB of a given duration and cruise time tc: ``tb = (T - tc) / 2``, ``v = 2 d / (T + tc)``.

    For the ECE486 seed, T = 3 s and tc = 1 s give tb = 1 s and v = delta / 2. Limits are not
    checked here.

    Args:
        delta: Displacements [rad or m], shape (n,).
        duration: Move time T [s], > 0.
        cruise_time: Time at constant velocity tc [s], with 0 <= tc < T (0: triangular).

    Returns:
        The timing; every joint has duration T and blend time (T - tc) / 2.

    Raises:
        InvalidInputError: Non-finite values, T <= 0, or tc outside [0, T).
    """
    T = _positive_scalar(duration, "duration")
    tc = _non_negative_scalar(cruise_time, "cruise_time")
    if not tc < T:
        raise InvalidInputError(
            f"cruise_time must be >= 0 s and below the duration {T:.6g} s, got {tc:.6g} s",
            name="cruise_time",
            value=tc,
        )
    (d,) = _broadcast(_array(delta, "delta"))
    blend = 0.5 * (T - tc)
    velocity = 2.0 * d / (T + tc)
    return LSPBTiming(np.full_like(d, T), np.full_like(d, blend), velocity, velocity / blend)


# ----------------------------------------------------------------------- trajectory


def lspb_trajectory(
    q_start: ArrayLike,
    q_goal: ArrayLike,
    timing: LSPBTiming,
    *,
    joint_names: Sequence[str] | None = None,
    metadata: Mapping[str, Any] | None = None,
) -> Trajectory:
    """The piecewise-quadratic trajectory of LSPB timings.

    Joint j accelerates on [0, tb_j], cruises on [tb_j, T_j - tb_j], decelerates on
    [T_j - tb_j, T_j] and, if it finishes before the slowest joint (T_j < T = max T_j), holds
    its goal until T. The breakpoints are the union of every joint's switching times
    (those within 1e-12 T of each other merged), so each segment is one polynomial per joint.

    Args:
        q_start: Start positions [rad or m], shape (n,).
        q_goal: Goal positions [rad or m], shape (n,).
        timing: Per-joint timing, e.g. from :func:`lspb_min_time` or
            :func:`lspb_shortest_blend`; its velocities must carry ``q_goal - q_start``.
        joint_names: Names of the n joints.
        metadata: Stored in the trajectory.

    Returns:
        A degree-2 trajectory of duration max T_j.

    Raises:
        InvalidInputError: Shapes disagree, a blend longer than half its move, or nothing
            moves in zero time (the trajectory would last 0 s).
    """
    start = _array(q_start, "q_start").reshape(-1)
    goal = _array(q_goal, "q_goal").reshape(-1)
    n = start.size
    fields = [_array(getattr(timing, f), f"timing.{f}").reshape(-1) for f in LSPBTiming._fields]
    if goal.size != n or any(f.size != n for f in fields):
        raise InvalidInputError(
            f"q_start, q_goal and every timing field must have {n} entries", name="timing"
        )
    ends, blends, velocity, acceleration = fields
    T = float(np.max(ends))
    if not T > 0.0:
        raise InvalidInputError(
            "the move lasts 0 s (q_goal equals q_start): give a duration to hold still",
            name="duration",
        )
    if np.any(blends < 0.0) or np.any(blends > 0.5 * ends * (1.0 + ROUND_OFF)):
        raise InvalidInputError(
            "every blend time must lie in [0, duration / 2]", name="timing.blend_time"
        )
    blends = np.minimum(blends, 0.5 * ends)
    delta = goal - start
    if not np.allclose(velocity * (ends - blends), delta, rtol=1e-9, atol=1e-12):
        raise InvalidInputError(
            "timing does not carry q_goal - q_start: velocity * (duration - blend_time) = "
            f"{velocity * (ends - blends)}, displacement {delta}",
            name="timing",
        )
    moving = blends > 0.0
    candidates = np.concatenate([blends[moving], (ends - blends)[moving], ends[ends > 0.0]])
    gap = ROUND_OFF * T  # closer switching times merge, so breakpoints survive shifting
    knots = [0.0]
    for t in np.sort(candidates):
        if t - knots[-1] > gap and T - t > gap:
            knots.append(float(t))
    knots.append(T)
    breakpoints = np.array(knots)
    t0 = breakpoints[:-1, None]  # segment starts, (K, 1)
    middle = 0.5 * (breakpoints[:-1] + breakpoints[1:])[:, None]
    half = 0.5 * acceleration
    left = ends - breakpoints[:-1, None]  # time left to each joint's end, (K, n)
    # One polynomial per joint and segment, expanded about the segment start t0 (tau = t - t0).
    phases = [
        (middle < blends, start + half * t0**2, acceleration * t0, half),
        (middle < ends - blends, start + velocity * (t0 - 0.5 * blends), velocity, 0.0 * half),
        (middle < ends, goal - half * left**2, acceleration * left, -half),
    ]
    c0 = np.broadcast_to(goal, (breakpoints.size - 1, n)).copy()
    c1 = np.zeros_like(c0)
    c2 = np.zeros_like(c0)
    done = np.zeros(c0.shape, dtype=bool)
    for mask, p0, p1, p2 in phases:
        use = np.broadcast_to(mask, c0.shape) & ~done
        c0 = np.where(use, p0, c0)
        c1 = np.where(use, p1, c1)
        c2 = np.where(use, p2, c2)
        done |= use
    coefficients = np.stack([c0, c1, c2], axis=1)
    return Trajectory(breakpoints, coefficients, joint_names=joint_names, metadata=metadata)


# ---------------------------------------------------------------------------- planner


class LSPB(JointProfile):
    """Rest-to-rest LSPB (trapezoidal velocity) moves, every joint synchronised.

    Without options, a move is as fast as the limits allow: the slowest joint's minimum time T,
    then every joint re-timed to T with the shortest blend at its own acceleration limit
    (:func:`lspb_shortest_blend`). With a duration (from :meth:`move` or the problem), the same
    re-timing at that duration.

    With ``blend_time`` or ``cruise_time`` every joint shares that blend (or cruise) time:
    with a duration the timing follows from it; without one, the duration is the shortest
    for which every joint stays within its velocity and acceleration limits.

    Args:
        blend_time: Fixed blend time tb [s], > 0; needs 0 < tb <= T / 2.
        cruise_time: Fixed cruise time tc [s], >= 0 (0: triangular); tb = (T - tc) / 2.
        check_limits: With a fixed blend or cruise time and a given duration, raise when the
            move breaks a velocity or acceleration limit (the default). ``False`` plans it
            anyway and lists the violations in ``metadata["limit_violations"]``.

    Raises:
        InvalidInputError: Both blend_time and cruise_time, values out of range, or
            ``check_limits=False`` without a fixed blend or cruise time.
    """

    name = "lspb"

    def __init__(
        self,
        *,
        blend_time: float | None = None,
        cruise_time: float | None = None,
        check_limits: bool = True,
    ) -> None:
        if blend_time is not None and cruise_time is not None:
            raise InvalidInputError(
                "give blend_time or cruise_time, not both (tb = (T - tc) / 2)",
                name="cruise_time",
            )
        self.blend_time = None if blend_time is None else _positive_scalar(blend_time, "blend_time")
        self.cruise_time = (
            None if cruise_time is None else _non_negative_scalar(cruise_time, "cruise_time")
        )
        check_limits = as_flag(check_limits, "check_limits")
        if not check_limits and blend_time is None and cruise_time is None:
            raise InvalidInputError(
                "check_limits=False applies only with a fixed blend_time or cruise_time; "
                "otherwise the move is planned within the limits",
                name="check_limits",
            )
        self.check_limits = check_limits

    def __repr__(self) -> str:
        options = []
        if self.blend_time is not None:
            options.append(f"blend_time={self.blend_time!r}")
        if self.cruise_time is not None:
            options.append(f"cruise_time={self.cruise_time!r}")
        if not self.check_limits:
            options.append("check_limits=False")
        return f"LSPB({', '.join(options)})"

    @property
    def mode(self) -> str:
        """How the blends are chosen: ``shortest_blend``, ``blend_time`` or ``cruise_time``."""
        if self.blend_time is not None:
            return "blend_time"
        if self.cruise_time is not None:
            return "cruise_time"
        return "shortest_blend"

    def timing(
        self,
        q_start: ArrayLike,
        q_goal: ArrayLike,
        limits: JointLimits,
        duration: float | None = None,
    ) -> LSPBTiming:
        """The synchronised timing :meth:`move` would use (no trajectory built).

        Args:
            q_start: Start positions [rad or m], shape (n,).
            q_goal: Goal positions [rad or m], shape (n,).
            limits: Joint limits (velocity, acceleration, names).
            duration: Fixed duration [s], or None for the fastest move within the limits.

        Returns:
            Per-joint timing; every joint has the same duration.

        Raises:
            InfeasibleError: The duration is too short for a joint's limits, or the fixed
                blend/cruise time breaks a limit at that duration (unless check_limits=False).
            InvalidInputError: Bad shapes or values, a fixed blend/cruise time that does not
                fit the duration, or nothing to move and no duration.
        """
        return self._timing(q_start, q_goal, limits, duration)[2]

    def move(
        self,
        q_start: ArrayLike,
        q_goal: ArrayLike,
        limits: JointLimits,
        duration: float | None = None,
    ) -> Trajectory:
        """One rest-to-rest LSPB move; every joint starts and ends together.

        Args:
            q_start: Start positions [rad or m], shape (n,).
            q_goal: Goal positions [rad or m], shape (n,).
            limits: Joint limits; the fastest move within them when ``duration`` is None.
            duration: Fixed duration [s], or None.

        Returns:
            A degree-2 trajectory with the joint names of ``limits``; metadata holds
            ``blend_times`` [s], ``cruise_velocities`` and ``accelerations`` (shape (n,)),
            ``mode``, ``duration_from`` (``limits`` or ``given``), ``limits_checked`` and
            ``limit_violations`` (messages, empty when the limits hold).

        Raises:
            InfeasibleError: See :meth:`timing`.
            InvalidInputError: See :meth:`timing`.
        """
        started = time.perf_counter()
        start, goal, timing, violations = self._timing(q_start, q_goal, limits, duration)
        metadata = {
            "profile": "lspb",
            "mode": self.mode,
            "duration_from": "limits" if duration is None else "given",
            "blend_times": timing.blend_time,
            "cruise_velocities": timing.velocity,
            "accelerations": timing.acceleration,
            "limits_checked": self.check_limits or duration is None,
            "limit_violations": violations,
        }
        traj = lspb_trajectory(start, goal, timing, joint_names=limits.names, metadata=metadata)
        return stamp(traj, self.name, started)

    # ------------------------------------------------------------------ internals

    def _timing(
        self,
        q_start: ArrayLike,
        q_goal: ArrayLike,
        limits: JointLimits,
        duration: float | None,
    ) -> tuple[FloatArray, FloatArray, LSPBTiming, list[str]]:
        """Start, goal, timing and the messages of any limit it breaks (check_limits=False)."""
        # refuses, as every planner does, a still move without a duration
        start, goal, duration = rest_to_rest_inputs(q_start, q_goal, limits, duration, self.name)
        delta = goal - start
        dist = np.abs(delta)
        vmax, amax = limits.velocity, limits.acceleration
        units = limits.kinds
        if self.blend_time is None and self.cruise_time is None:
            if duration is None:
                # a tiny move lasts MIN_DURATION, the shortest duration any planner takes
                fastest = float(np.max(lspb_min_time(delta, vmax, amax).duration))
                duration = max(fastest, MIN_DURATION)
            timing = lspb_shortest_blend(
                delta, amax, duration, v_max=vmax, names=limits.names, units=units
            )
            return start, goal, timing, []
        moving = dist > 0.0
        if self.blend_time is not None:
            tb = self.blend_time
            setting = f"blend_time {tb:.6g} s"
            fixed = lspb_fixed_blend
            if duration is None:
                # v = d / (T - tb) <= vmax and a = d / (tb (T - tb)) <= amax, solved for T.
                need = tb + np.maximum(dist / vmax, dist / (amax * tb))
                shortest = max(2.0 * tb, float(np.max(need[moving])))
        else:
            tb = float(self.cruise_time)  # type: ignore[arg-type]
            setting = f"cruise_time {tb:.6g} s"
            fixed = lspb_fixed_cruise
            if duration is None:
                # v = 2 d / (T + tc) <= vmax and a = 4 d / (T^2 - tc^2) <= amax, solved for T.
                # At least MIN_BLEND T of blend, so that a tiny move keeps its breakpoints apart.
                need = np.maximum(2.0 * dist / vmax - tb, np.sqrt(tb**2 + 4.0 * dist / amax))
                shortest = max(tb / (1.0 - 2.0 * MIN_BLEND), float(np.max(need[moving])))
        if duration is None:
            # The closed-form T is exact in real numbers; when a tiny displacement makes
            # T - tb cancel, step T up by a few ulps until the rounded timing fits too.
            duration = max(shortest, MIN_DURATION)  # as for the fastest move above
            for _ in range(64):
                if not _excess(fixed(delta, duration, tb), vmax, amax):
                    break
                duration = float(np.nextafter(duration, np.inf))
        timing = fixed(delta, duration, tb)
        violations = []
        for quantity, j, value, bound in _excess(timing, vmax, amax):
            unit = _unit(units[j], 1 if quantity == "velocity" else 2)
            message = (
                f"LSPB with {setting} in {duration:.6g} s needs joint {limits.names[j]!r} "
                f"at {value:.6g}{unit}, limit {bound:.6g}{unit}"
            )
            if self.check_limits:
                raise InfeasibleError(
                    message, limit=quantity, joint=limits.names[j], required=value, allowed=bound
                )
            violations.append(message)
        return start, goal, timing, violations


def _excess(
    timing: LSPBTiming, v_max: FloatArray, a_max: FloatArray
) -> list[tuple[str, int, float, float]]:
    """(quantity, joint, |value|, limit) of every value beyond round-off, worst ratio first."""
    found = []
    for quantity, values, bound in (
        ("velocity", np.abs(timing.velocity), v_max),
        ("acceleration", np.abs(timing.acceleration), a_max),
    ):
        for j in np.flatnonzero(values > bound * (1.0 + ROUND_OFF)):
            found.append((quantity, int(j), float(values[j]), float(bound[j])))
    return sorted(found, key=lambda item: item[2] / item[3], reverse=True)
