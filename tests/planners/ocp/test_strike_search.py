"""Tests of planners.ocp.strike_search."""

from __future__ import annotations

import pytest
from ocp_support import tight_choice

from optraj import problems
from optraj.errors import (
    InfeasibleError,
    SolverError,
)
from optraj.planners.ocp.optimal_control import (
    OptimalControl,
)
from optraj.planners.strike.window_check import WindowRatio


def _window(ratio: float, status: str = "Solve_Succeeded") -> WindowRatio:
    return WindowRatio(
        ratio=ratio,
        velocity=ratio,
        acceleration=0.5,
        jerk=0.25,
        effort=0.3,
        limit="velocity",
        joint="right_j3",
        required=1.957 * ratio,
        allowed=1.957,
        unit="rad/s",
        max_speed=1.5 / ratio,
        status=status,
        iterations=20,
    )


def test_a_strike_is_refused_only_when_every_window_tried_needs_more_than_the_limits():
    problem = problems.sawyer_pool_shot(1.5)
    planner = OptimalControl("time")
    failure = SolverError("ipopt", "Infeasible_Problem_Detected", iterations=7, detail="x")
    tight = tight_choice(1.55)
    refused = planner._strike_error(
        failure, problem, [tight, tight], [_window(1.08), _window(1.03)]
    )
    assert isinstance(refused, InfeasibleError)
    assert (refused.limit, refused.joint) == ("velocity", "right_j3")
    assert refused.required == pytest.approx(1.957 * 1.03)  # the least window, not the first
    assert "each of the 2 contact configurations tried" in str(refused)
    # A window within the limits, one not checked, one not converged, or another failure
    # than infeasibility: the solver's error (with the velocity hint where it applies).
    for windows in (
        [_window(1.08), _window(0.99)],
        [_window(1.08), None],
        [_window(1.08), _window(1.2, "Maximum_Iterations_Exceeded")],
        [],
    ):
        kept = planner._strike_error(failure, problem, [tight, tight], windows)
        assert isinstance(kept, SolverError) and "97.0 % of a velocity limit" in kept.detail
    missed = SolverError("ipopt", "Maximum_Iterations_Exceeded")
    assert planner._strike_error(missed, problem, [tight], [_window(1.08)]) is missed
