"""Tests of planners.solve_stats: the typed view of every planner's solve statistics."""

from __future__ import annotations

import pytest

from optraj import planners, problems
from optraj.errors import InvalidInputError


@pytest.fixture(scope="module")
def paddle():
    return problems.ece486_paddle_strike()


def test_optimal_control_stats_sum_every_round_of_its_solver(paddle):
    traj = planners.OptimalControl().plan(paddle)
    stats = planners.SolveStats.of(traj)
    assert stats.planner == traj.metadata["planner"] and stats.status == "ok"
    assert stats.solver == "ipopt" and stats.solver_status in ("Solve_Succeeded",)
    assert stats.iterations == sum(traj.metadata["round_iterations"]) > 0
    assert stats.rounds == len(traj.metadata["round_iterations"])
    assert 0 < stats.evaluation_time < stats.nlp_time < stats.solve_time
    assert stats.warm_started is False and stats.gridpoints is None


def test_profiles_have_no_solver_numbers_and_toppra_has_its_grid(paddle):
    move = problems.PointToPoint(paddle.robot, q_start=paddle.robot.home, q_goal=paddle.q_contact)
    cubic = planners.SolveStats.of(planners.Cubic().plan(move))
    assert cubic.planner == "cubic" and cubic.solve_time > 0
    assert cubic.iterations is cubic.solver is cubic.objective is None
    toppra = planners.SolveStats.of(planners.Toppra(gridpoints=50).plan(move))
    assert toppra.gridpoints == 50 and toppra.solves >= 1 and toppra.iterations is None


def test_stats_of_something_no_planner_made_are_refused(paddle):
    traj = planners.Cubic().plan(
        problems.PointToPoint(paddle.robot, q_start=paddle.robot.home, q_goal=paddle.q_contact)
    )
    traj.metadata.clear()
    with pytest.raises(InvalidInputError, match="names no planner"):
        planners.SolveStats.of(traj)
    with pytest.raises(InvalidInputError, match=r"needs a planners\.Trajectory"):
        planners.SolveStats.of({"planner": "cubic"})
