"""Tests of planners.ocp.building."""

from __future__ import annotations

import pickle

import casadi as ca
import numpy as np
import pytest
from conftest import get_robot
from ocp_support import paddle_move

from optraj import problems
from optraj.planners import check
from optraj.planners.ocp.optimal_control import (
    OptimalControl,
)


@pytest.mark.skipif(not ca.has_nlpsol("sqpmethod"), reason="CasADi without sqpmethod")
def test_sqpmethod_plans_a_small_move_with_nested_solver_options():
    problem = paddle_move()
    options = {"qpsol_options": {"printLevel": "none", "enableRegularisation": True}}
    traj = OptimalControl("time", solver="sqpmethod", solver_options=options).plan(problem)
    report = check(traj, problem)
    assert report.ok, report.summary()
    reference = OptimalControl("time").plan(problem)
    assert traj.duration == pytest.approx(reference.duration, rel=1e-3)


def test_planner_pickles_without_its_compiled_solvers():
    planner = OptimalControl("time")
    problem = problems.PointToPoint(
        get_robot("youbot"), get_robot("youbot").home, get_robot("youbot").home + 0.2
    )
    first = planner.plan(problem)
    copy = pickle.loads(pickle.dumps(planner))
    again = copy.plan(problem)
    np.testing.assert_allclose(again.breakpoints, first.breakpoints, atol=1e-9)
