"""Tests of planners.time_optimal.toppra_failures: typed errors for what no timing can do."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import InfeasibleError
from optraj.planners.time_optimal.toppra_planner import Toppra


def test_gravity_alone_breaking_a_torque_limit_names_the_joint():
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    points = np.array([q0, q0 + np.array([0.5, -0.6, 0.3, 0.5, -0.4, 0.3, 0.2])])
    held = np.abs(robot.gravity_torque(np.linspace(points[0], points[1], 50))).max(axis=0)
    effort = robot.limits.effort.copy()
    effort[3] = 0.8 * held[3]
    problem = problems.Waypoints(
        robot, points, limits=dataclasses.replace(robot.limits, effort=effort)
    )
    with pytest.raises(InfeasibleError) as info:
        Toppra(torque=True).plan(problem)
    error = info.value
    assert error.limit == "torque" and error.joint == robot.joint_names[3]
    assert error.required > error.allowed == pytest.approx(effort[3])
    assert "gravity" in str(error) and "s = " in str(error)
    Toppra().plan(problem)  # without torque limits the same path is fine


def test_too_fast_start_path_velocity_is_infeasible():
    robot = get_robot("sawyer")
    limits = robot.limits
    q0 = robot.home.copy()
    q1 = q0.copy()
    q1[3] += 0.8  # s = chord length: joint 3 moves at the path velocity
    with pytest.raises(InfeasibleError) as info:
        Toppra().time_parametrize(np.array([q0, q1]), limits, sd_start=2 * limits.velocity[3])
    error = info.value
    assert error.limit == "path velocity"
    assert error.required == pytest.approx(2 * limits.velocity[3])
    assert error.allowed == pytest.approx(limits.velocity[3], rel=2e-3)
    assert "start path velocity" in str(error)
    traj = Toppra().time_parametrize(np.array([q0, q1]), limits, sd_start=0.99 * error.allowed)
    assert traj.sample(0.0).qd[3] == pytest.approx(0.99 * error.allowed)


def test_start_too_fast_to_stop_in_time_is_infeasible():
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    q1 = q0.copy()
    q1[3] += 0.01
    with pytest.raises(InfeasibleError, match="largest feasible start path velocity"):
        Toppra().time_parametrize(np.array([q0, q1]), robot.limits, sd_start=1.5)


def test_too_fast_end_path_velocity_names_the_joint():
    robot = get_robot("sawyer")
    limits = robot.limits
    q0 = robot.home.copy()
    q1 = q0.copy()
    q1[3] += 0.8
    with pytest.raises(InfeasibleError) as info:
        Toppra().time_parametrize(np.array([q0, q1]), limits, sd_end=2 * limits.velocity[3])
    assert info.value.joint == robot.joint_names[3]
    assert info.value.allowed == pytest.approx(limits.velocity[3], rel=2e-3)
