"""Tests of planners.ocp.formulation."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import (
    InfeasibleError,
)
from optraj.planners import check, lower_bound
from optraj.planners.ocp.optimal_control import (
    OptimalControl,
)


def test_fixed_durations_below_a_joints_bound_are_infeasible_before_any_solve():
    paddle = get_robot("paddle4")
    rest = problems.PaddleStrike(paddle, ball=(1.1, 0.8, 0.7), contact_time=0.6)
    bound = lower_bound(problems.PointToPoint(paddle, rest.q_start, rest.q_contact))
    with pytest.raises(InfeasibleError, match=r"contact_time is 0\.6 s") as info:
        OptimalControl().plan(rest)
    assert info.value.limit == "duration" and info.value.allowed == 0.6
    assert info.value.required == pytest.approx(bound, rel=1e-9)
    # (At 0.5 m/s this contact, J3 1.5 mm from its limit, has too little room: the contact
    # choice refuses that first.)
    moving = dataclasses.replace(rest, speed=0.2, contact_time=0.05)
    with pytest.raises(InfeasibleError, match="within its velocity limit") as info:
        OptimalControl().plan(moving)
    spans = np.abs(rest.q_contact - rest.q_start) / paddle.limits.velocity
    assert info.value.required == pytest.approx(spans.max(), rel=1e-12)
    assert info.value.joint == paddle.limits.names[int(np.argmax(spans))]
    sawyer = get_robot("sawyer")
    points = np.array([sawyer.home, sawyer.home + 0.5, sawyer.home - 0.3])
    waypoints = problems.Waypoints(sawyer, points, segment_durations=(2.0, 0.5))
    with pytest.raises(InfeasibleError, match=r"segment 2 .* segment_durations\[1\] is 0\.5 s"):
        OptimalControl().plan(waypoints)
    # A via point may be passed within its tolerance: 1 rad at right_j0's 1.74 rad/s needs
    # 0.575 s, but 0.55 rad (1 - 0.45) fits in 0.5 s, and the plan passes the checker.
    step = np.eye(7)[0]
    points = np.array([sawyer.home, sawyer.home + step, sawyer.home + 2 * step])
    loose = problems.Waypoints(sawyer, points, segment_durations=(0.5, 1.5), via_tolerance=0.45)
    traj = OptimalControl().plan(loose)
    report = check(traj, loose, quantities=("position", "velocity", "acceleration", "jerk"))
    assert report.ok, report.summary()


def test_a_fixed_duration_shorter_than_the_limits_allow_is_infeasible():
    robot = get_robot("sawyer")
    q0 = robot.home
    q1 = q0 + 0.5 * (robot.limits.upper - q0)
    problem = problems.PointToPoint(robot, q0, q1, duration=0.2)
    with pytest.raises(InfeasibleError, match="needs at least"):
        OptimalControl().plan(problem)
