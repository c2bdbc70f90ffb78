"""The tool path and tool speed findings of a :class:`problems.ToolPath` and a speed cap.

``tool path position``: how far the tool frame origin leaves the straight line from the
start pose to the end pose (and misses either end); ``tool path orientation``: how far its
orientation leaves the SLERP between the two poses, taken at the fraction of the way along
the line. ``tool speed``: the tool origin's fastest speed against a cap, over a path's phase
or (:func:`tool_speed_check`) the whole trajectory. Sampled at the check's rate and every
breakpoint.

Example::

    evaluations.append(tool_path_check(path, ctx))
    evaluations.append(tool_speed_check(0.3, ctx))  # check(..., tool_speed=0.3)
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.checker.context import CheckContext
from optraj.planners.checker.report import Finding
from optraj.planners.checker.rotations import rotation_angle, rotation_exp, rotation_log
from optraj.planners.checker.task import (
    Evaluation,
    constraint_tolerance,
    missing_findings,
    task_finding,
)
from optraj.planners.trajectory import Phase
from optraj.problems.constraints import ToolPath
from optraj.validation import as_positive

__all__ = ["tool_path_check", "tool_speed_check"]

FloatArray = NDArray[np.float64]
#: One candidate worst deviation: (value [unit], time [s], where it is measured from).
_Gap = tuple[float, float, str]


def tool_path_check(path: ToolPath, ctx: CheckContext) -> Evaluation:
    """``tool path position`` and ``tool path orientation`` over the phase (or everything)."""
    position = constraint_tolerance(path.position_tolerance, "ToolPath.position_tolerance", "m")
    angle = constraint_tolerance(path.angle_tolerance, "ToolPath.angle_tolerance", "rad")
    expected = [("tool path position", position, "m"), ("tool path orientation", angle, "rad")]
    start = np.asarray(path.T_start, dtype=float)
    end = np.asarray(path.T_end, dtype=float)
    for label, T in (("T_start", start), ("T_end", end)):
        if T.shape != (4, 4) or not np.all(np.isfinite(T)):
            raise InvalidInputError(f"ToolPath.{label} must be a finite 4x4 pose", name=label)
    if path.phase is None:
        window: Phase | None = Phase("all", 0.0, ctx.duration)
    else:
        window = ctx.phase(path.phase)
    if window is None:
        return missing_findings(expected, f"phase {path.phase!r} missing")
    times = ctx.window(window.t_start, window.t_end)
    cap = None if path.speed is None else as_positive(path.speed, "ToolPath.speed", "m/s")
    ctx.kinematics.need(times, twist=cap is not None)

    def evaluate() -> list[Finding]:
        speed = [] if cap is None else [_speed_finding(ctx, times, cap)]
        poses = ctx.kinematics.pose(times)
        gaps, fraction = _position_gaps(poses[:, :3, 3], start, end, times, window)
        turns = _orientation_turns(poses[:, :3, :3], start, end, times, fraction)
        findings = []
        for (name, tolerance, unit), items in zip(expected, (gaps, turns), strict=True):
            value, time, where = max(items, key=lambda item: item[0])
            detail = f"tool {value:.4g} {unit} {where} at t = {time:.6g} s"
            findings.append(task_finding(name, value, tolerance, time, unit, detail))
        return findings + speed

    return evaluate


def _position_gaps(
    p: FloatArray, start: FloatArray, end: FloatArray, times: FloatArray, window: Phase
) -> tuple[list[_Gap], FloatArray]:
    """How far the tool origins ``p`` (m, 3) [m] leave the line and miss its two ends.

    Returns:
        The candidate gaps (off the line, from the start, from the end) and the fraction of
        the way along the line at each instant, shape (m,); the fraction of the window's
        time when the line has no length.
    """
    p0, p1 = start[:3, 3], end[:3, 3]
    length = float(np.linalg.norm(p1 - p0))
    if length > 1e-12:
        axis = (p1 - p0) / length
        along = np.clip((p - p0) @ axis, 0.0, length)
        fraction = along / length
    else:  # no line to measure along: the fraction of the time instead
        span = max(window.t_end - window.t_start, 1e-300)
        along = np.zeros(len(times))
        fraction = np.clip((times - window.t_start) / span, 0.0, 1.0)
        axis = np.zeros(3)
    offset = np.linalg.norm(p - (p0 + along[:, None] * axis[None, :]), axis=1)
    gaps = [
        (float(np.max(offset)), float(times[int(np.argmax(offset))]), "off the line"),
        (float(np.linalg.norm(p[0] - p0)), float(times[0]), "from the start pose"),
        (float(np.linalg.norm(p[-1] - p1)), float(times[-1]), "from the end pose"),
    ]
    return gaps, fraction


def _orientation_turns(
    R: FloatArray, start: FloatArray, end: FloatArray, times: FloatArray, fraction: FloatArray
) -> list[_Gap]:
    """How far the tool orientations ``R`` (m, 3, 3) leave the SLERP at ``fraction`` [rad].

    Returns:
        The candidate angles: from the SLERP, from the start and from the end orientation.
    """
    R0, R1 = start[:3, :3], end[:3, :3]
    turn = rotation_log(R0.T @ R1)
    reference = R0[None] @ rotation_exp(fraction[:, None] * turn[None, :])
    angle = rotation_angle(np.swapaxes(reference, 1, 2) @ R)
    return [
        (float(np.max(angle)), float(times[int(np.argmax(angle))]), "from the SLERP"),
        (float(rotation_angle(R0.T @ R[0])), float(times[0]), "from the start orientation"),
        (float(rotation_angle(R1.T @ R[-1])), float(times[-1]), "from the end orientation"),
    ]


def _speed_finding(ctx: CheckContext, times: FloatArray, cap: float) -> Finding:
    """``tool speed``: the tool origin's fastest speed at ``times`` against ``cap`` [m/s].

    Sampled at the check's rate and every breakpoint (the speed is not a polynomial).
    """
    speed = np.linalg.norm(ctx.kinematics.twist(times)[:, :3], axis=1)
    worst = int(np.argmax(speed))
    value = float(speed[worst])
    time = float(times[worst])
    detail = f"tool origin at {value:.4g} m/s at t = {time:.6g} s (cap {cap:.4g} m/s)"
    return task_finding("tool speed", value, cap, time, "m/s", detail)


def tool_speed_check(cap: float, ctx: CheckContext) -> Evaluation:
    """The ``tool_speed`` cap of :func:`planners.checker.check` over the whole trajectory."""
    times = ctx.window(0.0, ctx.duration)
    ctx.kinematics.need(times, twist=True)
    return lambda: [_speed_finding(ctx, times, cap)]
