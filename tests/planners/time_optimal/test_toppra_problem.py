"""Tests of planners.time_optimal.toppra_problem: the built problem, open to inspection."""

from __future__ import annotations

import numpy as np
from conftest import get_robot

from optraj.planners.time_optimal.toppra_planner import Toppra
from optraj.planners.time_optimal.toppra_problem import MARGIN, ToppraProblem, initial_scale


def test_built_problem_can_be_inspected_before_solving():
    robot = get_robot("paddle4")
    points = robot.random_configurations(3, np.random.default_rng(2))
    planner = Toppra(gridpoints=50)
    built = planner.build(points, robot.limits)
    assert isinstance(built, ToppraProblem)
    assert built.grid.size == 51 and built.grid[0] == 0.0
    assert set(built.path.knots) <= set(built.grid)  # every knot is a gridpoint
    assert len(built.constraints()) == 2
    traj = planner.solve(built)
    assert traj.metadata["gridpoints"] == 50


def test_moving_and_the_initial_scale_follow_the_problem():
    robot = get_robot("paddle4")
    points = robot.random_configurations(3, np.random.default_rng(2))
    rest = Toppra().build(points, robot.limits)
    assert not rest.moving
    assert initial_scale(rest) == {"velocity": 1 - MARGIN, "acceleration": 1 - MARGIN}
    planner = Toppra(torque=True, tool_speed=0.5)
    moving = planner.build(points, robot.limits, robot=robot, sd_end=0.1)
    assert moving.moving
    assert set(initial_scale(moving)) == {"velocity", "acceleration", "torque", "tool speed"}
    assert len(moving.constraints()) == 4
    assert len(moving.constraints({"velocity": 0.5})) == 4
