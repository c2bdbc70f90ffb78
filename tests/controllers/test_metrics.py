from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from conftest import get_robot
from scipy.spatial.transform import Rotation

from optraj.controllers.controller import sample_references
from optraj.controllers.metrics import (
    VIOLATION_SLACK,
    Metrics,
    StrikeMetrics,
    Violation,
    tracking_metrics,
    violation,
)
from optraj.planners.trajectory import Phase, Trajectory

SAWYER_STEP = np.array([0.25, -0.2, 0.3, 0.15, -0.3, 0.2, 0.4])
STRIKE = (0.605, 1.395)  # between grid points, so the window is 0.61 .. 1.39 s
WINDOW = (0.61, 1.39)
STRIKE_PHASES = (Phase("strike", *STRIKE),)


def _sawyer_run(phases=STRIKE_PHASES, samples=201):
    """A smooth 2 s Sawyer motion sampled every 10 ms, with a strike phase."""
    robot = get_robot("sawyer")
    q0 = robot.home
    q = np.stack([q0, q0 + SAWYER_STEP, q0 + 0.5 * SAWYER_STEP])
    qd = np.stack([np.zeros(7), 0.3 * SAWYER_STEP, np.zeros(7)])
    traj = Trajectory.from_hermite([0.0, 1.0, 2.0], q, qd, np.zeros_like(q), phases=phases)
    t = np.linspace(0.0, 2.0, samples)
    return robot, t, sample_references(robot, traj, t)


def _paddle_line_run():
    """Paddle4 moving only its first (prismatic) joint: the tool runs along a straight line."""
    robot = get_robot("paddle4")
    q0 = robot.home.copy()
    q1 = q0.copy()
    q0[0], q1[0] = 0.3, 0.7
    zeros = np.zeros((2, 4))
    traj = Trajectory.from_hermite(
        [0.0, 2.0], np.stack([q0, q1]), zeros, zeros, phases=[Phase("strike", 0.49, 1.51)]
    )
    t = np.linspace(0.0, 2.0, 101)
    return robot, t, sample_references(robot, traj, t)


def _metrics(robot, t, refs, q=None, qd=None, *, commands=None, tau=None, step_times=None, **kw):
    m, n = refs.q.shape
    q = refs.q if q is None else q
    qd = refs.qd if qd is None else qd
    commands = refs.qd[:-1] if commands is None else commands
    tau = np.zeros((m - 1, n)) if tau is None else tau
    step_times = np.full(m - 1, 1e-4) if step_times is None else step_times
    return tracking_metrics(robot, t, refs, q, qd, commands, tau, step_times, **kw)


def _line_distances(points, start, end):
    direction = (end - start) / np.linalg.norm(end - start)
    return np.linalg.norm(np.cross(points - start, direction), axis=1), direction


def test_perfect_tracking_has_zero_errors():
    robot, t, refs = _sawyer_run()
    metrics = _metrics(robot, t, refs)
    assert isinstance(metrics, Metrics)
    for value in (
        metrics.position_rms,
        metrics.position_max,
        metrics.orientation_rms,
        metrics.orientation_max,
        metrics.axis_max,
    ):
        assert value == pytest.approx(0.0, abs=1e-12)
    strike = metrics.strike
    assert isinstance(strike, StrikeMetrics)
    inside = (t >= STRIKE[0]) & (t <= STRIKE[1])
    assert strike.window == pytest.approx(WINDOW, abs=1e-12)
    assert strike.window == (t[inside][0], t[inside][-1])
    assert np.count_nonzero(inside) == 79
    for value in (
        strike.position_rms,
        strike.position_max,
        strike.axis_max,
        strike.speed_error_mean,
        strike.speed_error_max,
    ):
        assert value == pytest.approx(0.0, abs=1e-12)
    # The planned tool path is curved: line and direction errors are those of the plan itself.
    p = refs.T_world_tool[inside, :3, 3]
    distance, direction = _line_distances(p, p[0], p[-1])
    assert distance.max() > 1e-3
    assert strike.line_max == pytest.approx(distance.max(), rel=1e-9)
    v = refs.twist[inside, :3]
    cosine = v @ direction / np.linalg.norm(v, axis=1)
    assert strike.direction_max == pytest.approx(np.arccos(cosine.min()), abs=1e-7)
    assert metrics.within_limits
    assert metrics.fallbacks == 0
    assert metrics.saturated_steps == 0


def test_joint_offset_gives_forward_kinematics_difference():
    robot, t, refs = _sawyer_run()
    offset = np.array([0.02, -0.01, 0.015, 0.01, -0.02, 0.01, 0.03])
    q = refs.q + offset
    metrics = _metrics(robot, t, refs, q=q)
    realised = robot.tool_pose(q)
    distance = np.linalg.norm(realised[:, :3, 3] - refs.T_world_tool[:, :3, 3], axis=1)
    angle = Rotation.from_matrix(
        np.einsum("mij,mkj->mik", realised[:, :3, :3], refs.T_world_tool[:, :3, :3])
    ).magnitude()
    axis_cos = np.einsum("mi,mi->m", realised[:, :3, 2], refs.T_world_tool[:, :3, 2])
    axis_angle = np.arccos(np.clip(axis_cos, -1.0, 1.0))
    assert distance.min() > 1e-3
    assert metrics.position_rms == pytest.approx(np.sqrt(np.mean(distance**2)), rel=1e-12)
    assert metrics.position_max == pytest.approx(distance.max(), rel=1e-12)
    assert metrics.orientation_rms == pytest.approx(np.sqrt(np.mean(angle**2)), rel=1e-9)
    assert metrics.orientation_max == pytest.approx(angle.max(), rel=1e-9)
    assert metrics.axis_max == pytest.approx(axis_angle.max(), rel=1e-7)
    inside = (t >= STRIKE[0]) & (t <= STRIKE[1])
    assert metrics.strike.position_max == pytest.approx(distance[inside].max(), rel=1e-12)
    assert metrics.strike.position_rms == pytest.approx(
        np.sqrt(np.mean(distance[inside] ** 2)), rel=1e-12
    )
    assert metrics.strike.axis_max == pytest.approx(axis_angle[inside].max(), rel=1e-7)


def test_ten_percent_faster_along_a_straight_line():
    robot, t, refs = _paddle_line_run()
    metrics = _metrics(robot, t, refs, qd=1.1 * refs.qd)
    strike = metrics.strike
    assert strike.window == pytest.approx((0.5, 1.5), abs=1e-12)
    assert strike.speed_error_max == pytest.approx(0.1, abs=1e-12)
    assert strike.speed_error_mean == pytest.approx(0.1, abs=1e-12)
    assert strike.line_max == pytest.approx(0.0, abs=1e-12)
    assert strike.direction_max == pytest.approx(0.0, abs=1e-9)
    assert strike.position_max == pytest.approx(0.0, abs=1e-12)
    assert metrics.position_max == pytest.approx(0.0, abs=1e-12)


def test_ten_percent_faster_on_a_curved_path():
    robot, t, refs = _sawyer_run()
    metrics = _metrics(robot, t, refs, qd=1.1 * refs.qd)
    inside = (t >= STRIKE[0]) & (t <= STRIKE[1])
    p = refs.T_world_tool[inside, :3, 3]
    _, direction = _line_distances(p, p[0], p[-1])
    v = refs.twist[inside, :3]
    # Only the speed along the line counts: 0.1 |v . d| / |v|.
    expected = 0.1 * np.abs(v @ direction) / np.linalg.norm(v, axis=1)
    assert metrics.strike.speed_error_max == pytest.approx(expected.max(), rel=1e-9)
    assert metrics.strike.speed_error_mean == pytest.approx(expected.mean(), rel=1e-9)
    assert 0.05 < metrics.strike.speed_error_max <= 0.1 + 1e-12


def test_no_strike_phase_gives_no_strike_metrics():
    _, _, refs = _sawyer_run(phases=())
    assert _metrics(get_robot("sawyer"), refs.t, refs).strike is None
    robot, t, refs = _sawyer_run(phases=(Phase("approach", 0.0, 1.0),))
    assert _metrics(robot, t, refs).strike is None


def test_violation_counts_rows_and_finds_worst():
    values = np.array(
        [
            [0.5, 1.0],  # within
            [1.5, 0.0],  # joint a beyond
            [0.0, -3.2],  # joint b beyond, the worst: 1.6
            [-1.2, 2.5],  # both beyond: one row
            [1.0, -2.0],  # exactly at the limits: not beyond
        ]
    )
    limit = np.array([1.0, 2.0])
    times = np.array([0.0, 0.1, 0.2, 0.3, 0.4])
    result = violation("velocity", values, limit, times, ("a", "b"))
    assert result == Violation("velocity", 3, pytest.approx(1.6, abs=1e-15), "b", 0.2)
    assert result.count == 3
    assert result.worst == pytest.approx(1.6, abs=1e-15)
    assert (result.joint, result.time) == ("b", 0.2)


def test_violation_slack_and_all_within():
    limit = np.array([2.0])
    times = np.array([0.0, 1.0])
    tiny = violation(
        "x", np.array([[2.0 * (1 + 0.1 * VIOLATION_SLACK)], [1.0]]), limit, times, ("j",)
    )
    assert tiny.count == 0
    real = violation(
        "x", np.array([[1.0], [-2.0 * (1 + 10 * VIOLATION_SLACK)]]), limit, times, ("j",)
    )
    assert real.count == 1
    assert real.time == 1.0
    within = violation("x", np.array([[0.5], [-1.5]]), limit, times, ("j",))
    assert (within.count, within.worst, within.joint, within.time) == (0, 0.75, "j", 1.0)
    empty = violation("x", np.zeros((0, 1)), limit, np.zeros(0), ("j",))
    assert (empty.count, empty.worst) == (0, 0.0)


def test_position_violation_ratio_is_one_plus_distance_over_range():
    robot, t, refs = _sawyer_run()
    limits = robot.limits
    span = limits.upper - limits.lower
    q = refs.q.copy()
    q[10, 2] = limits.upper[2] + 0.1 * span[2]  # 10 % of the range above
    q[50, 4] = limits.lower[4] - 0.05 * span[4]  # 5 % below
    q[60, 1] = limits.upper[1]  # at the bound: not beyond
    position = _metrics(robot, t, refs, q=q).violations["position"]
    assert position.quantity == "position"
    assert position.count == 2
    assert position.worst == pytest.approx(1.1, abs=1e-12)
    assert position.joint == limits.names[2]
    assert position.time == t[10]


def test_position_worst_within_limits_is_one_minus_margin_over_range():
    robot, t, refs = _sawyer_run()
    limits = robot.limits
    position = _metrics(robot, t, refs).violations["position"]
    margin = np.minimum(refs.q - limits.lower, limits.upper - refs.q) / (
        limits.upper - limits.lower
    )
    k, j = np.unravel_index(np.argmin(margin), margin.shape)
    assert position.count == 0
    assert position.worst == pytest.approx(1.0 - margin[k, j], abs=1e-12)
    assert position.worst < 1.0
    assert (position.joint, position.time) == (limits.names[j], t[k])


def test_velocity_command_effort_and_acceleration_violations():
    robot, t, refs = _sawyer_run()
    peak = np.abs(refs.qd).max(axis=0)
    velocity = 2.0 * peak
    velocity[3] = 0.8 * peak[3]  # only joint 3 is too fast, by 25 % at its peak
    limits = dataclasses.replace(robot.limits, velocity=velocity)
    tau = np.zeros((t.size - 1, 7))
    tau[7, 0] = -1.5 * limits.effort[0]
    tau[20, 5] = 1.2 * limits.effort[5]
    metrics = _metrics(robot, t, refs, tau=tau, limits=limits)
    speed = metrics.violations["velocity"]
    too_fast = np.abs(refs.qd[:, 3]) > 0.8 * peak[3] * (1 + VIOLATION_SLACK)
    assert speed.count == np.count_nonzero(too_fast) > 0
    assert speed.worst == pytest.approx(1.25, rel=1e-12)
    assert speed.joint == limits.names[3]
    assert speed.time == t[np.argmax(np.abs(refs.qd[:, 3]))]
    command = metrics.violations["command"]  # the commands are refs.qd[:-1]
    assert command.count == np.count_nonzero(too_fast[:-1])
    assert command.worst == pytest.approx(1.25, rel=1e-12)
    effort = metrics.violations["effort"]
    assert (effort.count, effort.joint, effort.time) == (2, limits.names[0], t[7])
    assert effort.worst == pytest.approx(1.5, abs=1e-12)
    acceleration = metrics.violations["acceleration"]
    finite_difference = np.abs(np.diff(refs.qd, axis=0) / np.diff(t)[:, None])
    ratio = finite_difference / limits.acceleration
    assert acceleration.count == 0
    assert acceleration.worst == pytest.approx(ratio.max(), rel=1e-12)
    assert acceleration.time == t[np.unravel_index(np.argmax(ratio), ratio.shape)[0]]
    assert not metrics.within_limits
    assert _metrics(robot, t, refs).within_limits  # the robot's own limits are kept


def test_step_time_statistics_and_counters():
    robot, t, refs = _sawyer_run()
    rng = np.random.default_rng(51)
    step_times = rng.lognormal(-9.0, 0.7, t.size - 1)
    metrics = _metrics(robot, t, refs, step_times=step_times, fallbacks=3, saturated_steps=5)
    assert metrics.step_time_median == pytest.approx(np.median(step_times), rel=1e-15)
    assert metrics.step_time_p95 == pytest.approx(np.percentile(step_times, 95), rel=1e-15)
    assert metrics.step_time_max == pytest.approx(step_times.max(), rel=0)
    assert metrics.step_time_median < metrics.step_time_p95 < metrics.step_time_max
    assert (metrics.fallbacks, metrics.saturated_steps) == (3, 5)


def test_as_dict_is_plain_nested_data():
    robot, t, refs = _sawyer_run()
    tau = np.zeros((t.size - 1, 7))
    tau[3, 1] = 2.0 * robot.limits.effort[1]
    metrics = _metrics(robot, t, refs, tau=tau)
    data = metrics.as_dict()
    assert set(data) == {f.name for f in dataclasses.fields(Metrics)}
    assert set(data["violations"]) == {"position", "velocity", "command", "acceleration", "effort"}
    assert data["violations"]["effort"] == {
        "quantity": "effort",
        "count": 1,
        "worst": pytest.approx(2.0, abs=1e-12),
        "joint": robot.limits.names[1],
        "time": t[3],
    }
    assert data["strike"]["window"] == pytest.approx(WINDOW, abs=1e-12)
    assert data["position_max"] == metrics.position_max
    assert json.loads(json.dumps(data))["violations"]["effort"]["count"] == 1
    assert not metrics.within_limits
    _, _, no_strike = _sawyer_run(phases=())
    assert _metrics(robot, t, no_strike).as_dict()["strike"] is None
