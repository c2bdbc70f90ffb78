"""Tests of planners.time_optimal.toppra_constraints: the limits TOPPRA retimes under."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.planners.checker import check
from optraj.planners.time_optimal.toppra_constraints import (
    chord_safe_bound,
    joint_speed_rates,
    normalised_rows,
)
from optraj.planners.time_optimal.toppra_path import GeometricPath
from optraj.planners.time_optimal.toppra_planner import Toppra
from optraj.planners.time_optimal.toppra_problem import MARGIN

KINEMATIC = ("position", "velocity", "acceleration")


def test_torque_limits_slow_the_motion_and_hold():
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    points = np.array([q0, q0 + np.array([0.5, -0.6, 0.3, 0.5, -0.4, 0.3, 0.2])])
    fast = dataclasses.replace(robot.limits, acceleration=robot.limits.acceleration * 4)
    free = Toppra().plan(problems.Waypoints(robot, points, limits=fast))
    held = np.abs(robot.gravity_torque(np.linspace(points[0], points[1], 50))).max(axis=0)
    limits = dataclasses.replace(fast, effort=np.maximum(1.3 * held, 1.0))
    problem = problems.Waypoints(robot, points, limits=limits)
    assert not check(free, problem, quantities=("torque",)).ok  # too fast for these torques
    slow = Toppra(torque=True).plan(problem)
    assert slow.duration > 1.2 * free.duration
    report = check(slow, problem, quantities=(*KINEMATIC, "torque"))
    assert report.ok, report.violations
    assert report["torque"].ratio > 0.99  # the torque limit binds
    assert slow.metadata["limit_ratio"]["torque"] <= 1.0


@pytest.mark.parametrize("cap", [0.6, 0.25])
def test_tool_speed_cap_holds(cap):
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    problem = problems.Waypoints(
        robot, [q0, q0 + np.array([0.5, -0.6, 0.3, 0.5, -0.4, 0.3, 0.2]), q0]
    )
    free = Toppra().plan(problem)
    capped = Toppra(tool_speed=cap).plan(problem)
    sample = capped.sample(capped.times(2000.0))
    J = robot.jacobian(sample.q)
    speed = np.linalg.norm(np.einsum("kij,kj->ki", J[:, :3], sample.qd), axis=1)
    assert speed.max() <= cap
    assert speed.max() >= 0.99 * cap  # and it binds
    assert capped.duration > free.duration
    assert check(capped, problem, quantities=KINEMATIC).ok


def test_chord_safe_bounds_hold_between_gridpoints():
    # a parabola through three waypoints: joint speeds per unit path speed vary along it
    path = GeometricPath.spline(np.array([[0.0, 0.0], [0.4, 0.3], [0.5, 0.9]]))
    rates = joint_speed_rates(np.array([1.0, 2.0]))
    grid = np.linspace(path.knots[0], path.knots[-1], 9)
    bound = chord_safe_bound(rates, path.native, grid)
    fine = np.linspace(0.0, 1.0, 101)
    assert bound.shape == grid.shape and np.all(bound > 0.0)
    # x linear between gridpoints stays below 1 / max rate^2 where the rates are sampled
    # (quarters of each interval), and within MARGIN of it in between (a second-order loss)
    for theta, allowed in ((np.array([0.0, 0.25, 0.5, 0.75, 1.0]), 1e-12), (fine, MARGIN)):
        s = grid[:-1, None] + np.diff(grid)[:, None] * theta
        x = bound[:-1, None] + (bound[1:] - bound[:-1])[:, None] * theta
        peak = np.max(rates(path.native, s.ravel()), axis=1).reshape(s.shape)
        assert np.all(x * peak**2 <= 1.0 + allowed)


def test_normalised_rows_are_unit_rows_of_the_same_bounds():
    rng = np.random.default_rng(8)
    a, b, c = rng.normal(size=(3, 5, 2))
    a_end, b_end, c_end = rng.normal(size=(3, 4, 2))
    limit = np.array([1.5, 0.5])
    rows_a, rows_b, rows_c, F, g, _, _ = normalised_rows(a, b, c, a_end, b_end, c_end, limit)
    assert rows_a.shape == (5, 8) and F.shape == (8, 8) and g.shape == (8,)
    np.testing.assert_allclose(np.hypot(rows_a, rows_b), 1.0, rtol=1e-12)
    # at any (u, x) the rows say a u + b x + c <= limit and >= -limit at the gridpoint
    u, x = 0.3, 0.7
    value = a * u + b * x + c
    held = rows_a[:, :4] * u + rows_b[:, :4] * x + rows_c[:, :4] <= 0.0
    expected = np.hstack([value <= limit, -value <= limit])
    np.testing.assert_array_equal(held, expected)


def test_a_joint_that_barely_moves_keeps_unit_rows():
    a = np.array([[1.0, 1e-14], [2.0, 0.0]])
    b = np.array([[0.5, 0.0], [0.1, 0.0]])
    rows_a, rows_b, rows_c, *_ = normalised_rows(a, b, None, a[1:], b[1:], None, np.ones(2))
    assert np.all(rows_a[:, [1, 3, 5, 7]] == 0.0) and np.all(rows_b[:, [1, 3, 5, 7]] == 0.0)
    assert np.all(rows_c[:, [1, 3, 5, 7]] == pytest.approx(-1.0))  # a constant row: 0 <= 1
