"""Timing of linear segments with parabolic blends (LSPB): closed forms and limit checks.

Each joint accelerates at a constant rate for a blend time ``tb``, cruises at a constant
velocity ``v``, and decelerates for ``tb`` again, so its velocity is a trapezoid (a triangle
when it never cruises). The functions here give an :class:`LSPBTiming` (T, tb, v, a per joint)
for a displacement: the fastest one within limits (:func:`lspb_min_time`), the one of a given
duration with the shortest blend (:func:`lspb_shortest_blend`), or one with a fixed blend or
cruise time (:func:`lspb_fixed_blend`, :func:`lspb_fixed_cruise`, :func:`lspb_fixed`) and the
shortest duration that keeps it within limits (:func:`lspb_fixed_shortest`).
:func:`optraj.planners.profiles.lspb.lspb_trajectory` turns a timing into a trajectory, and
:class:`optraj.planners.profiles.lspb.LSPB` plans with them.

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

from collections.abc import Sequence
from typing import Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError
from optraj.validation import MAX_DURATION, MIN_DURATION, as_array, as_duration, as_number

__all__ = [
    "MIN_BLEND",
    "ROUND_OFF",
    "LSPBTiming",
    "finite_array",
    "limit_excess",
    "lspb_fixed",
    "lspb_fixed_blend",
    "lspb_fixed_cruise",
    "lspb_fixed_shortest",
    "lspb_min_time",
    "lspb_shortest_blend",
    "unit_suffix",
]

FloatArray = NDArray[np.float64]

#: Relative excess over a limit that is taken as floating-point round-off, not a violation;
#: also the smallest gap between breakpoints, as a fraction of the duration.
ROUND_OFF = 1e-12
#: Shortest blend [-], as a fraction of the duration, that :func:`lspb_shortest_blend` makes.
MIN_BLEND = 1e-9
#: Which time an LSPB fixes besides its duration: the blend time or the cruise time.
FixedSetting = Literal["blend_time", "cruise_time"]


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


def finite_array(value: ArrayLike, name: str) -> FloatArray:
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
    array = finite_array(value, name)
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


def unit_suffix(stem: str, power: int) -> str:
    """`` rad/s``, `` m/s^2`` ... from a unit stem and the power of seconds (blank stem: '').

    For messages: the text follows a number directly, so it starts with a space.
    """
    if not stem:
        return ""
    return f" {stem}/s" if power == 1 else f" {stem}/s^{power}"


def _worst(required: FloatArray, allowed: FloatArray) -> int | None:
    """Index of the largest ratio required / allowed beyond round-off, or None."""
    excess = required / allowed
    worst = int(np.argmax(excess))
    return worst if excess[worst] > 1.0 + ROUND_OFF else None


def _too_short(
    duration: float, limit: str, joint: str, stem: str, required: float, allowed: float
) -> InfeasibleError:
    """The error of a duration too short for a joint's velocity or acceleration limit."""
    unit = unit_suffix(stem, 1 if limit == "velocity" else 2)
    return InfeasibleError(
        f"LSPB in {duration:.6g} s needs joint {joint!r} at {required:.6g}{unit}, "
        f"limit {allowed:.6g}{unit}",
        limit=limit,
        joint=joint,
        required=float(required),
        allowed=float(allowed),
    )


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
        finite_array(delta, "delta"),
        _positive_array(v_max, "v_max"),
        _positive_array(a_max, "a_max"),
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
    arrays = [finite_array(delta, "delta"), _positive_array(a_max, "a_max")]
    if v_max is not None:
        arrays.append(_positive_array(v_max, "v_max"))
    d, amax, *rest = _broadcast(*arrays)
    labels, stems = _joint_labels(d.size, names, units)
    dist = np.abs(d)
    needed = 4.0 * dist / T**2
    worst = _worst(needed, amax)
    if worst is not None:
        raise _too_short(T, "acceleration", labels[worst], stems[worst], needed[worst], amax[worst])
    # Round-off may leave the discriminant a hair below zero when the acceleration binds.
    root = np.sqrt(np.maximum(T**2 - 4.0 * dist / amax, 0.0))
    speed = 2.0 * dist / (T + root)
    blend = np.minimum(speed / amax, 0.5 * T)
    vmax = rest[0] if rest else np.full_like(d, np.inf)
    if rest:
        worst = _worst(speed, vmax)
        if worst is not None:
            raise _too_short(T, "velocity", labels[worst], stems[worst], speed[worst], vmax[worst])
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
    (d,) = _broadcast(finite_array(delta, "delta"))
    velocity = d / (T - tb)
    return LSPBTiming(np.full_like(d, T), np.full_like(d, tb), velocity, velocity / tb)


def lspb_fixed_cruise(delta: ArrayLike, duration: float, cruise_time: float) -> LSPBTiming:
    """LSPB of a given duration and cruise time tc: ``tb = (T - tc) / 2``, ``v = 2 d / (T + tc)``.

    For the ECE486 task, T = 3 s and tc = 1 s give tb = 1 s and v = delta / 2. Limits are not
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
    (d,) = _broadcast(finite_array(delta, "delta"))
    blend = 0.5 * (T - tc)
    velocity = 2.0 * d / (T + tc)
    return LSPBTiming(np.full_like(d, T), np.full_like(d, blend), velocity, velocity / blend)


def lspb_fixed(
    delta: ArrayLike, duration: float, setting: FixedSetting, fixed_time: float
) -> LSPBTiming:
    """:func:`lspb_fixed_blend` or :func:`lspb_fixed_cruise`, as ``setting`` names.

    Args:
        delta: Displacements [rad or m], shape (n,).
        duration: Move time T [s], > 0.
        setting: ``"blend_time"`` or ``"cruise_time"``: which time ``fixed_time`` is.
        fixed_time: The blend time tb or the cruise time tc [s].

    Returns:
        The timing; every joint has duration T.

    Raises:
        InvalidInputError: As the function ``setting`` names.
    """
    if setting == "blend_time":
        return lspb_fixed_blend(delta, duration, fixed_time)
    return lspb_fixed_cruise(delta, duration, fixed_time)


def lspb_fixed_shortest(
    delta: FloatArray,
    v_max: FloatArray,
    a_max: FloatArray,
    setting: FixedSetting,
    fixed_time: float,
) -> float:
    """Shortest duration [s] of an LSPB with a fixed blend or cruise time, within the limits.

    With a fixed blend tb, ``v = d / (T - tb) <= v_max`` and ``a = d / (tb (T - tb)) <= a_max``;
    with a fixed cruise tc, ``v = 2 d / (T + tc) <= v_max`` and ``a = 4 d / (T^2 - tc^2) <=
    a_max``; each is solved for T, and T is at least 2 tb (a blend fits twice) or keeps a blend
    of MIN_BLEND T (so that a tiny move keeps its breakpoints apart), and at least MIN_DURATION.

    Args:
        delta: Displacements [rad or m], shape (n,), at least one not zero.
        v_max: Velocity limits [rad/s or m/s], shape (n,).
        a_max: Acceleration limits [rad/s^2 or m/s^2], shape (n,).
        setting: ``"blend_time"`` or ``"cruise_time"``: which time ``fixed_time`` is.
        fixed_time: The blend time tb or the cruise time tc [s].

    Returns:
        The duration, for which :func:`limit_excess` of :func:`lspb_fixed` finds nothing
        (unless 64 steps of one ulp do not get there).
    """
    dist = np.abs(delta)
    moving = dist > 0.0
    tb = fixed_time
    if setting == "blend_time":
        need = tb + np.maximum(dist / v_max, dist / (a_max * tb))
        shortest = max(2.0 * tb, float(np.max(need[moving])))
    else:
        need = np.maximum(2.0 * dist / v_max - tb, np.sqrt(tb**2 + 4.0 * dist / a_max))
        shortest = max(tb / (1.0 - 2.0 * MIN_BLEND), float(np.max(need[moving])))
    # The closed-form T is exact in real numbers; when a tiny displacement makes T - tb
    # cancel, step T up by a few ulps until the rounded timing fits too.
    duration = max(shortest, MIN_DURATION)  # a move lasts at least MIN_DURATION
    for _ in range(64):
        if not limit_excess(lspb_fixed(delta, duration, setting, tb), v_max, a_max):
            break
        duration = float(np.nextafter(duration, np.inf))
    return duration


def limit_excess(
    timing: LSPBTiming, v_max: FloatArray, a_max: FloatArray
) -> list[tuple[str, int, float, float]]:
    """Every velocity or acceleration of ``timing`` beyond its limit (more than round-off).

    Args:
        timing: The timing.
        v_max: Velocity limits [rad/s or m/s], shape (n,).
        a_max: Acceleration limits [rad/s^2 or m/s^2], shape (n,).

    Returns:
        (quantity, joint, |value|, limit) of each, the worst ratio value / limit first.
    """
    found = []
    for quantity, values, bound in (
        ("velocity", np.abs(timing.velocity), v_max),
        ("acceleration", np.abs(timing.acceleration), a_max),
    ):
        for j in np.flatnonzero(values > bound * (1.0 + ROUND_OFF)):
            found.append((quantity, int(j), float(values[j]), float(bound[j])))
    return sorted(found, key=lambda item: item[2] / item[3], reverse=True)
