"""Linear segments with parabolic blends (LSPB): trapezoidal-velocity rest-to-rest moves.

Each joint accelerates at a constant rate for a blend time ``tb``, cruises at a constant
velocity ``v``, and decelerates for ``tb`` again, so its velocity is a trapezoid (a triangle
when it never cruises) and its position is piecewise quadratic: C1, with jumps in acceleration.

:class:`LSPB` plans synchronised moves; :func:`lspb_trajectory` turns per-joint timings into a
trajectory. The timings themselves (closed forms, with their references) are in
:mod:`optraj.planners.profiles.lspb_timing`, and re-exported here.

Every displacement, velocity and acceleration below is per joint, in [rad, rad/s, rad/s^2]
for revolute joints and [m, m/s, m/s^2] for prismatic ones.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.base import JointProfile, rest_to_rest_inputs, stamp
from optraj.planners.profiles.lspb_timing import (
    ROUND_OFF,
    FixedSetting,
    LSPBTiming,
    finite_array,
    limit_excess,
    lspb_fixed,
    lspb_fixed_blend,
    lspb_fixed_cruise,
    lspb_fixed_shortest,
    lspb_min_time,
    lspb_shortest_blend,
    unit_suffix,
)
from optraj.planners.trajectory import Trajectory
from optraj.robots import JointLimits
from optraj.validation import MAX_DURATION, MIN_DURATION, as_duration, as_flag, as_number

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
    start = finite_array(q_start, "q_start").reshape(-1)
    goal = finite_array(q_goal, "q_goal").reshape(-1)
    n = start.size
    fields = [
        finite_array(getattr(timing, f), f"timing.{f}").reshape(-1) for f in LSPBTiming._fields
    ]
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
        self.blend_time = None if blend_time is None else as_duration(blend_time, "blend_time")
        self.cruise_time = (
            None
            if cruise_time is None
            else as_number(cruise_time, "cruise_time", "s", minimum=0.0, maximum=MAX_DURATION)
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
        fixed = self._fixed()
        return "shortest_blend" if fixed is None else fixed[0]

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

    def _fixed(self) -> tuple[FixedSetting, float] | None:
        """The fixed blend or cruise time, as (setting, time [s]), or None."""
        if self.blend_time is not None:
            return "blend_time", self.blend_time
        if self.cruise_time is not None:
            return "cruise_time", self.cruise_time
        return None

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
        vmax, amax = limits.velocity, limits.acceleration
        fixed = self._fixed()
        if fixed is None:
            if duration is None:
                # a tiny move lasts MIN_DURATION, the shortest duration any planner takes
                fastest = float(np.max(lspb_min_time(delta, vmax, amax).duration))
                duration = max(fastest, MIN_DURATION)
            timing = lspb_shortest_blend(
                delta, amax, duration, v_max=vmax, names=limits.names, units=limits.kinds
            )
            return start, goal, timing, []
        setting, tb = fixed
        if duration is None:
            duration = lspb_fixed_shortest(delta, vmax, amax, setting, tb)
        timing = lspb_fixed(delta, duration, setting, tb)
        violations = []
        for quantity, j, value, bound in limit_excess(timing, vmax, amax):
            unit = unit_suffix(limits.kinds[j], 1 if quantity == "velocity" else 2)
            message = (
                f"LSPB with {setting} {tb:.6g} s in {duration:.6g} s needs joint "
                f"{limits.names[j]!r} at {value:.6g}{unit}, limit {bound:.6g}{unit}"
            )
            if self.check_limits:
                raise InfeasibleError(
                    message, limit=quantity, joint=limits.names[j], required=value, allowed=bound
                )
            violations.append(message)
        return start, goal, timing, violations
