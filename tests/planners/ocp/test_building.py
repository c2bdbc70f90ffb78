"""Tests of planners.ocp.building."""

from __future__ import annotations

import pickle

import casadi as ca
import numpy as np
import pytest
from conftest import get_robot
from ocp_support import paddle_move, sawyer_shots

from optraj import problems
from optraj.planners import check
from optraj.planners.compiled_cache import ProcessCache
from optraj.planners.ocp.building import COMPILED, first_barrier
from optraj.planners.ocp.optimal_control import (
    OptimalControl,
)
from optraj.planners.ocp.options import CLOSE_MU_INIT, STRIKE_MU_INIT


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


def test_planner_objects_share_the_compiled_nlps_of_the_process():
    robot = get_robot("youbot")
    problem = problems.PointToPoint(robot, robot.home, robot.home + 0.2)
    first = OptimalControl("time").build(problem)
    other = OptimalControl("time").build(problem)
    assert other.compiled is first.compiled  # built once, by the first object
    assert COMPILED.get(first.compiled.structure) is first.compiled
    # Different solver options shape a different solver.
    tighter = OptimalControl("time", tolerance=1e-7).build(problem)
    assert tighter.compiled is not first.compiled


def test_a_process_cache_keeps_the_most_recently_used_entries():
    built: list[str] = []

    def build(key: str):
        def make() -> str:
            built.append(key)
            return key.upper()

        return make

    cache: ProcessCache[str] = ProcessCache(2)
    assert cache.get_or_build("a", build("a")) == "A"
    assert cache.get_or_build("b", build("b")) == "B"
    assert cache.get_or_build("a", build("a")) == "A"  # kept: not built again
    assert cache.get_or_build("c", build("c")) == "C"  # drops "b", the least recently used
    assert len(cache) == 2 and cache.get("b") is None and cache.get("a") == "A"
    assert built == ["a", "b", "c"]
    cache.clear()
    assert len(cache) == 0


def test_cold_solves_start_the_barrier_by_how_close_the_first_point_is():
    robot = get_robot("panda")
    limits = robot.limits
    q0 = limits.lower + 0.3 * (limits.upper - limits.lower)
    q1 = limits.lower + 0.6 * (limits.upper - limits.lower)
    planner = OptimalControl("time")
    free = planner._spec(problems.PointToPoint(robot, q0, q1))
    fixed = planner._spec(problems.PointToPoint(robot, q0, q1, duration=3.0))
    strike = planner._spec(next(sawyer_shots(1, speed=1.0)))
    assert first_barrier(free) == CLOSE_MU_INIT
    assert first_barrier(strike) == STRIKE_MU_INIT
    assert first_barrier(fixed) is None
    options = dict(planner.build(problems.PointToPoint(robot, q0, q1)).compiled.structure.options)
    assert options["ipopt.mu_init"] == CLOSE_MU_INIT
    # solver_options still have the last word.
    mine = OptimalControl("time", solver_options={"ipopt.mu_init": 0.1})
    options = dict(mine.build(problems.PointToPoint(robot, q0, q1)).compiled.structure.options)
    assert options["ipopt.mu_init"] == 0.1
