"""Controllers with random valid settings, in closed loop along a short plan: a finished run
with no NaN anywhere in its result, or a typed error."""

from __future__ import annotations

from functools import cache

import numpy as np
from conftest import get_robot
from hypothesis import given, settings

from fuzz.budget import examples, recorded
from fuzz.oracles import assert_nan_free
from fuzz.strategies import ControllerSpec, controller_specs
from optraj import controllers, planners, problems
from optraj.errors import OptrajError


@cache
def _plan(robot_name: str) -> planners.Trajectory:
    """A short Ruckig move of every joint from home (0.05 rad or m, inside the limits)."""
    robot = get_robot(robot_name)
    goal = robot.limits.clip(robot.home + 0.05)
    goal = np.where(np.isclose(goal, robot.home), robot.home - 0.05, goal)
    return planners.Ruckig().plan(problems.PointToPoint(robot, robot.home, goal))


@settings(max_examples=examples("controller"))
@given(spec=controller_specs())
@recorded
def test_a_closed_loop_run_finishes_without_nan_or_is_refused(spec: ControllerSpec):
    return closed_loop(spec)


def test_known_case_tiny_damping_of_the_pseudo_inverse():
    # A damping of 9.7e-107 made the pseudo-inverse of a rank-deficient axis task raise
    # numpy's LinAlgError; it is refused now (0 or in [1e-6, 1e3]).
    options = {"kp": 0.0, "kd": 0.0, "ki": 0.0, "task": "axis", "damping": 9.7e-107}
    run = {"dt": 0.001, "plant": "kinematic", "latency": 0, "settle": 0.0}
    closed_loop(ControllerSpec("paddle4", "PseudoInversePID", options, run))


def closed_loop(spec: ControllerSpec) -> str:
    """A run without NaN, or the name of the typed error that refused it."""
    robot = get_robot(spec.robot)
    try:
        controller = spec.build()
        result = controllers.simulate(
            robot, _plan(spec.robot), controller, **spec.simulate_options()
        )
    except OptrajError as exc:
        return type(exc).__name__
    assert isinstance(result, controllers.Result)
    assert_nan_free(result, "result")
    assert np.all(np.isfinite(result.q)) and np.all(np.isfinite(result.command))
    return "ran"
