"""Tests of planners.time_optimal.toppra_solve: solves, retries, slow-downs and the result."""

from __future__ import annotations

import time

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.planners.checker import check
from optraj.planners.time_optimal import toppra_solve
from optraj.planners.time_optimal.toppra_planner import Toppra
from optraj.planners.trajectory import Trajectory
from optraj.validation import MIN_DURATION

KINEMATIC = ("position", "velocity", "acceleration")


def test_path_with_stops_and_a_dwell_is_retimed_without_a_large_slowdown():
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    q1 = q0 + 0.3
    go = planners.Quintic().plan(problems.PointToPoint(robot, q0, q1))
    back = planners.Quintic().plan(problems.PointToPoint(robot, q1, q0))
    single = Toppra().time_parametrize(go, robot.limits).duration
    for path in (go.then(Trajectory.constant(q1, 0.5), back), go.then(back)):
        traj = Toppra().time_parametrize(path, robot.limits)
        assert check(traj, robot, quantities=KINEMATIC).ok
        # both moves as fast as alone (within the grid's resolution); the dwell takes ~0 s
        assert traj.duration < 2.0 * single * 1.08
        assert traj.metadata["slowdown"] < 1.01


@pytest.mark.parametrize("size", [2e-12, 1e-11, 1e-10, 1e-9, 3e-9, 1e-7])
def test_tiny_moves_are_feasible(size):
    # toppra's absolute tolerances would call the controllable set of these moves empty;
    # a short path is solved in a stretched parameter (toppra_grid.stretch_factor).
    robot = get_robot("sawyer")
    q1 = robot.home.copy()
    q1[0] += size
    problem = problems.PointToPoint(robot, robot.home, q1)
    traj = Toppra().plan(problem)
    assert check(traj, problem, quantities=KINEMATIC).ok
    # One joint moves: the optimum is the bang-bang (LSPB) minimum time, within MARGIN.
    fastest = planners.LSPB().plan(problem).duration
    assert traj.duration == pytest.approx(
        fastest, rel=2 * planners.time_optimal.toppra_planner.MARGIN
    )


def test_solve_stamps_the_result_with_the_planner_and_its_solves():
    robot = get_robot("paddle4")
    points = robot.random_configurations(3, np.random.default_rng(5))
    problem = Toppra(gridpoints=30).build(points, robot.limits)
    traj = toppra_solve.solve(problem, "mine", time.perf_counter())
    meta = traj.metadata
    assert meta["planner"] == "mine" and 1 <= meta["solves"] <= toppra_solve.RETRIES + 1
    assert meta["grid"].size - 1 >= 30 and meta["slowdown"] >= 1.0
    assert max(meta["limit_ratio"].values()) <= 1.0
    assert traj.duration >= MIN_DURATION
