"""Tests of planners.ocp.solve."""

from __future__ import annotations

import pytest
from ocp_support import paddle_move, sawyer_shots

import optraj.planners.ocp.budget as budget
import optraj.planners.ocp.solve as solve
from optraj import problems
from optraj.errors import (
    SolverError,
)
from optraj.planners import check
from optraj.planners.ocp.optimal_control import (
    BUDGET_SPENT,
    OptimalControl,
)
from optraj.planners.ocp.transcription import WARM_ITERATIONS


def _moved_2_cm(ball, heading_deg):
    """A benchmark shot (1 m/s) and the same shot with its ball 2 cm further along y."""
    return tuple(
        problems.sawyer_pool_shot(1.0, (ball[0], ball[1] + dy, ball[2]), heading_deg)
        for dy in (0.0, 0.02)
    )


@pytest.mark.slow
def test_a_warm_solve_that_does_not_converge_is_redone_cold():
    # Strike benchmark shot 27 of seed 7: the search keeps the branch, but the previous
    # multipliers lead IPOPT through 508 iterations; capped, the same primal point solves cold.
    # (Cold solves from IPOPT's own first barrier, 0.1, as when this shot was found.)
    first, moved = _moved_2_cm(
        (0.7210827554047025, 0.13168447027359653, -0.023475261672147738), 16.367172559622002
    )
    planner = OptimalControl("time", solver_options={"ipopt.mu_init": 0.1})
    traj = planner.plan(moved, warm_start=planner.plan(first))
    meta = traj.metadata
    assert meta["warm_started"] is True and meta["warm_abandoned"] is True
    assert WARM_ITERATIONS < meta["iterations"] < WARM_ITERATIONS + 120
    assert check(traj, moved).ok
    # The iterations and times count the abandoned solve (the cold one alone takes 94).
    assert meta["nlp_time"] > meta["evaluation_time"] > 0.0


def test_a_budget_spent_inside_a_solve_stops_it_and_no_contact_retry_swallows_it(monkeypatch):
    # The planner's deadline check lets the first solve start; the solver's iteration callback
    # then finds the deadline past and stops it at its first iteration.
    checks = iter([1.0, 1.0])
    monkeypatch.setattr(solve, "time_left", lambda: next(checks, -1.0))
    monkeypatch.setattr(budget, "time_left", lambda: -1.0)
    problem = next(sawyer_shots(1, speed=1.0))
    with pytest.raises(SolverError, match="User_Requested_Stop") as info:
        OptimalControl(contact_retries=2).plan(problem)
    assert info.value.status == BUDGET_SPENT and info.value.iterations == 0


def test_a_solver_that_raises_gives_a_solver_error_with_its_reason():
    # CasADi's error_on_fail turns IPOPT's iteration cap into an exception.
    planner = OptimalControl("time", solver_options={"error_on_fail": True, "ipopt.max_iter": 2})
    with pytest.raises(SolverError, match=r"Maximum_Iterations_Exceeded.*nlpsol process") as info:
        planner.plan(paddle_move())
    assert info.value.iterations == 2 and "Function::call" not in str(info.value)
