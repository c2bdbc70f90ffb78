"""Tracking metrics of a closed-loop run: tool errors, strike errors, limit violations, timing.

:func:`tracking_metrics` compares the realised tool motion with the planned one at every
control time. The strike window is the trajectory's ``strike`` phase; along it the strike line
runs from the planned tool position at the start of the window to the one at its end.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from optraj.controllers.controller import References
from optraj.robots import JointLimits, Robot

__all__ = ["Metrics", "StrikeMetrics", "Violation", "tracking_metrics", "violation"]

FloatArray = NDArray[np.float64]

#: Name of the phase whose samples make the strike window.
STRIKE_PHASE = "strike"
#: A sample counts as beyond a limit when it exceeds it by more than this fraction.
VIOLATION_SLACK = 1e-9


@dataclass(frozen=True)
class Violation:
    """How one limited quantity fared over a run.

    Attributes:
        quantity: ``"position"``, ``"velocity"``, ``"command"`` (the commanded velocity),
            ``"acceleration"`` or ``"effort"`` (the applied torque; a plant that clips its
            torques to the limits never goes over, it saturates: see
            :attr:`Metrics.saturated_steps`).
        count: Samples beyond the limit.
        worst: Largest value over limit: ``|value| / limit`` for symmetric quantities (> 1 is
            a violation), for positions the distance beyond the nearer bound divided by the
            range, plus 1 (so > 1 is a violation here too) [-].
        joint: Joint of the worst sample.
        time: Time of the worst sample [s].
    """

    quantity: str
    count: int
    worst: float
    joint: str
    time: float


@dataclass(frozen=True)
class StrikeMetrics:
    """Errors inside the strike window.

    Attributes:
        window: Start and end of the window [s].
        position_rms: RMS distance of the tool from its planned position [m].
        position_max: Largest such distance [m].
        line_max: Largest distance of the tool from the strike line [m].
        axis_max: Largest angle between the tool axis and the planned one [rad].
        speed_error_mean: Mean of ``|v . d - v_ref . d| / |v_ref|`` along the line [-].
        speed_error_max: Largest such relative speed error [-].
        direction_max: Largest angle between the tool velocity and the line [rad].
    """

    window: tuple[float, float]
    position_rms: float
    position_max: float
    line_max: float
    axis_max: float
    speed_error_mean: float
    speed_error_max: float
    direction_max: float


@dataclass(frozen=True)
class Metrics:
    """Everything :func:`tracking_metrics` measures.

    Attributes:
        position_rms: RMS tool position error over the whole run [m].
        position_max: Largest tool position error [m].
        orientation_rms: RMS tool orientation error (rotation angle) [rad].
        orientation_max: Largest orientation error [rad].
        axis_max: Largest tool z-axis error, roll ignored [rad].
        strike: Errors in the strike window; ``None`` when the trajectory has no strike phase.
        violations: One :class:`Violation` per limited quantity, keyed by quantity.
        fallbacks: Steps on which the controller sent a safe fallback command.
        saturated_steps: Steps on which the plant clipped a torque to its effort limit.
        step_time_median: Median controller wall time per step [s].
        step_time_p95: 95th percentile of it [s].
        step_time_max: Largest of it [s].
    """

    position_rms: float
    position_max: float
    orientation_rms: float
    orientation_max: float
    axis_max: float
    strike: StrikeMetrics | None
    violations: dict[str, Violation]
    fallbacks: int
    saturated_steps: int
    step_time_median: float
    step_time_p95: float
    step_time_max: float

    @property
    def within_limits(self) -> bool:
        """Whether no quantity went beyond its limit (saturated torques are not counted)."""
        return all(v.count == 0 for v in self.violations.values())

    def as_dict(self) -> dict[str, Any]:
        """Plain nested dict (for tables and JSON)."""
        return asdict(self)


def violation(
    quantity: str,
    values: FloatArray,
    limit: FloatArray,
    times: FloatArray,
    names: tuple[str, ...],
) -> Violation:
    """Count and locate samples of a symmetric quantity beyond ``+-limit``.

    Args:
        quantity: Name for the report.
        values: Samples, shape (m, n).
        limit: Limits, shape (n,), > 0.
        times: Sample times [s], shape (m,).
        names: Joint names, length n.
    """
    ratio = np.abs(values) / limit
    return _summary(quantity, ratio, times, names)


def _position_violation(q: FloatArray, limits: JointLimits, times: FloatArray) -> Violation:
    span = limits.upper - limits.lower
    beyond = np.maximum(q - limits.upper, limits.lower - q) / span
    return _summary("position", 1.0 + beyond, times, limits.names)


def _summary(
    quantity: str, ratio: FloatArray, times: FloatArray, names: tuple[str, ...]
) -> Violation:
    if ratio.size == 0:
        return Violation(quantity, 0, 0.0, names[0], 0.0)
    k, j = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
    count = int(np.count_nonzero(np.any(ratio > 1.0 + VIOLATION_SLACK, axis=1)))
    return Violation(quantity, count, float(ratio[k, j]), names[j], float(times[k]))


def tracking_metrics(
    robot: Robot,
    t: FloatArray,
    references: References,
    q: FloatArray,
    qd: FloatArray,
    commands: FloatArray,
    tau: FloatArray,
    step_times: FloatArray,
    *,
    limits: JointLimits | None = None,
    fallbacks: int = 0,
    saturated_steps: int = 0,
    poses: FloatArray | None = None,
) -> Metrics:
    """Compare a run with its plan.

    Args:
        robot: The robot.
        t: Sample times [s], shape (m,), increasing.
        references: The plan at every sample time (held at its end after it ends).
        q: Realised joint positions at those times, shape (m, n).
        qd: Realised joint velocities, shape (m, n).
        commands: Commanded joint velocities, shape (m - 1, n) (one per step).
        tau: Applied joint torques, shape (m - 1, n).
        step_times: Controller wall time per step [s], shape (m - 1,).
        limits: Limits to count violations against; the robot's when None.
        fallbacks: Steps that sent a fallback command.
        saturated_steps: Steps whose torques were clipped.
        poses: The realised tool poses, shape (m, 4, 4), when already computed.
    """
    limits = robot.limits if limits is None else limits
    poses = robot.tool_pose(q) if poses is None else poses
    jacobians = robot.jacobian(q)
    twists = np.einsum("mij,mj->mi", jacobians, qd)
    ref_poses = references.T_world_tool
    position_error = np.linalg.norm(poses[:, :3, 3] - ref_poses[:, :3, 3], axis=1)
    relative = np.einsum("mji,mjk->mik", ref_poses[:, :3, :3], poses[:, :3, :3])
    orientation_error = np.array([np.linalg.norm(pin.log3(R)) for R in relative])
    axis_error = _angles(poses[:, :3, 2], ref_poses[:, :3, 2])

    step_t = t[:-1]
    velocity_step = np.diff(qd, axis=0) / np.diff(t)[:, None]
    violations = {
        "position": _position_violation(q, limits, t),
        "velocity": violation("velocity", qd, limits.velocity, t, limits.names),
        "command": violation("command", commands, limits.velocity, step_t, limits.names),
        "acceleration": violation(
            "acceleration", velocity_step, limits.acceleration, step_t, limits.names
        ),
        "effort": violation("effort", tau, limits.effort, step_t, limits.names),
    }
    strike = _strike_metrics(t, references, poses, twists, position_error, axis_error)
    return Metrics(
        position_rms=_rms(position_error),
        position_max=float(position_error.max()),
        orientation_rms=_rms(orientation_error),
        orientation_max=float(orientation_error.max()),
        axis_max=float(axis_error.max()),
        strike=strike,
        violations=violations,
        fallbacks=int(fallbacks),
        saturated_steps=int(saturated_steps),
        step_time_median=float(np.median(step_times)) if step_times.size else 0.0,
        step_time_p95=float(np.percentile(step_times, 95)) if step_times.size else 0.0,
        step_time_max=float(step_times.max()) if step_times.size else 0.0,
    )


def _strike_metrics(
    t: FloatArray,
    references: References,
    poses: FloatArray,
    twists: FloatArray,
    position_error: FloatArray,
    axis_error: FloatArray,
) -> StrikeMetrics | None:
    inside = np.array([name == STRIKE_PHASE for name in references.phase])
    if np.count_nonzero(inside) < 2:
        return None
    index = np.flatnonzero(inside)
    start = references.T_world_tool[index[0], :3, 3]
    end = references.T_world_tool[index[-1], :3, 3]
    length = float(np.linalg.norm(end - start))
    planned = references.twist[index, :3]
    speed_ref = np.linalg.norm(planned, axis=1)
    if length > 1e-9:
        direction = (end - start) / length
    else:  # a window too short to give a line: the mean planned velocity's direction
        mean = planned.mean(axis=0)
        direction = mean / max(float(np.linalg.norm(mean)), 1e-12)
    p = poses[index, :3, 3]
    offset = p - start
    off_line = offset - np.outer(offset @ direction, direction)
    v = twists[index, :3]
    speed_error = np.abs(v @ direction - planned @ direction) / np.maximum(speed_ref, 1e-12)
    return StrikeMetrics(
        window=(float(t[index[0]]), float(t[index[-1]])),
        position_rms=_rms(position_error[index]),
        position_max=float(position_error[index].max()),
        line_max=float(np.linalg.norm(off_line, axis=1).max()),
        axis_max=float(axis_error[index].max()),
        speed_error_mean=float(speed_error.mean()),
        speed_error_max=float(speed_error.max()),
        direction_max=float(_angles(v, np.broadcast_to(direction, v.shape)).max()),
    )


def _angles(a: FloatArray, b: FloatArray) -> FloatArray:
    """Angle between matching rows of ``a`` and ``b`` [rad] (0 where either is zero)."""
    cross = np.linalg.norm(np.cross(a, b), axis=1)
    dot = np.einsum("ij,ij->i", a, b)
    return np.arctan2(cross, dot)


def _rms(values: FloatArray) -> float:
    return float(np.sqrt(np.mean(np.square(values))))
