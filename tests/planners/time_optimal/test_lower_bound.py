"""Tests of planners.time_optimal.lower_bound: Ruckig attains it, the jerk-free form bounds it."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.profiles.lspb import LSPB
from optraj.planners.time_optimal.lower_bound import (
    check_state_torques,
    joint_min_durations,
    lower_bound,
    lower_bound_va,
)
from optraj.planners.time_optimal.ruckig_planner import Ruckig


def _random_limits(robot, rng, jerk=None):
    scale = rng.uniform(0.3, 2.0, size=(3, robot.dof))
    base = robot.limits
    velocity = base.velocity * scale[0]
    acceleration = base.acceleration * scale[1]
    return dataclasses.replace(
        base,
        velocity=velocity,
        acceleration=acceleration,
        jerk=base.jerk * scale[2] if jerk is None else jerk(velocity, acceleration),
    )


def test_ruckig_rest_to_rest_moves_take_exactly_the_lower_bound():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(31)
    planner = Ruckig()
    worst = 0.0
    for _ in range(1000):
        limits = _random_limits(robot, rng)
        q0, q1 = limits.sample(rng, 2)
        bound = lower_bound(q_start=q0, q_goal=q1, limits=limits)
        worst = max(worst, abs(planner.move(q0, q1, limits).duration - bound))
    assert worst < 1e-6


def test_lower_bound_tends_to_the_jerk_free_closed_form():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(32)
    for _ in range(200):
        # Jerk so large that ramping the acceleration takes a negligible a / j.
        limits = _random_limits(robot, rng, jerk=lambda v, a: 1e5 * a * a / v)
        q0, q1 = limits.sample(rng, 2)
        bound = lower_bound(q_start=q0, q_goal=q1, limits=limits)
        closed = lower_bound_va(q1 - q0, limits.velocity, limits.acceleration)
        assert closed <= bound * (1 + 1e-12)  # a jerk limit can only slow a move down
        assert bound == pytest.approx(closed, rel=1e-3)


def test_jerk_free_closed_form_on_hand_cases():
    # Trapezoid: |d| = 2 >= v^2 / a = 0.5: T = 2 / 1 + 1 / 2.
    assert lower_bound_va(2.0, 1.0, 2.0) == pytest.approx(2.5, abs=1e-12)
    assert lower_bound_va(-2.0, 1.0, 2.0) == pytest.approx(2.5, abs=1e-12)
    # Triangle: |d| = 0.1 < 0.5: T = 2 sqrt(0.1 / 2).
    assert lower_bound_va(0.1, 1.0, 2.0) == pytest.approx(2 * math.sqrt(0.05), abs=1e-12)
    # On the boundary both forms give 2 v / a.
    assert lower_bound_va(0.5, 1.0, 2.0) == pytest.approx(1.0, abs=1e-12)
    # Several joints: the slowest; no motion: 0.
    assert lower_bound_va([2.0, 0.1, 0.0], 1.0, [2.0, 2.0, 2.0]) == pytest.approx(2.5)
    assert lower_bound_va([0.0, 0.0], [1.0, 1.0], [1.0, 1.0]) == 0.0
    # The LSPB planner's minimum time is the same closed form.
    robot = get_robot("sawyer")
    goal = robot.home + np.array([1.0, -0.5, 0.2, 0.0, 2.0, 0.1, -0.7])
    lspb = LSPB().move(robot.home, goal, robot.limits)
    expected = lower_bound_va(goal - robot.home, robot.limits.velocity, robot.limits.acceleration)
    assert lspb.duration == pytest.approx(expected, rel=1e-12)


def test_jerk_free_closed_form_rejects_bad_values():
    with pytest.raises(InvalidInputError, match="vmax"):
        lower_bound_va(1.0, 0.0, 1.0)
    with pytest.raises(InvalidInputError, match="amax"):
        lower_bound_va(1.0, 1.0, [1.0, -1.0])
    with pytest.raises(InvalidInputError, match="delta"):
        lower_bound_va([1.0, np.inf], 1.0, 1.0)
    with pytest.raises(InvalidInputError, match="broadcast"):
        lower_bound_va([1.0, 2.0, 3.0], [1.0, 1.0], 1.0)
    # No bool or string posing as a number.
    with pytest.raises(InvalidInputError, match="vmax"):
        lower_bound_va(1.0, True, 1.0)
    with pytest.raises(InvalidInputError, match="delta"):
        lower_bound_va("1.0", 1.0, 1.0)


def test_a_prescribed_state_past_the_effort_limits_names_the_joint_and_the_scale():
    robot = get_robot("sawyer")
    q = robot.home
    zeros = np.zeros(robot.dof)
    gravity = np.abs(robot.gravity_torque(q))
    limits = robot.limits.scaled(0.05, ("effort",))
    joint = int(np.argmax(gravity / limits.effort))
    with pytest.raises(InfeasibleError, match="the start state needs joint") as info:
        check_state_torques(robot, limits, [("the start state", q, zeros, zeros)])
    error = info.value
    assert (error.limit, error.joint) == ("effort", robot.limits.names[joint])
    assert error.required == pytest.approx(gravity[joint], rel=1e-9)
    assert error.allowed == pytest.approx(limits.effort[joint])
    assert f"{gravity[joint] / limits.effort[joint]:.4g} times as large" in str(error)
    # Exactly at the limits it holds; a moving state counts its inertial torques too.
    exact = dataclasses.replace(robot.limits, effort=np.maximum(gravity, 1e-3))
    check_state_torques(robot, exact, [("the start state", q, zeros, zeros)])
    with pytest.raises(InfeasibleError, match="the goal state"):
        check_state_torques(robot, exact, [("the goal state", q, zeros, np.ones(robot.dof))])
    with pytest.raises(InvalidInputError, match="qd"):
        check_state_torques(robot, exact, [("the start state", q, [0.0], zeros)])


def test_problem_and_keyword_forms_agree_for_state_to_state_moves():
    robot = get_robot("sawyer")
    limits = robot.limits
    qd_goal = 0.4 * limits.velocity
    qd_start = -0.2 * limits.velocity
    problem = problems.PointToPoint(
        robot, robot.home, robot.home + 0.4, qd_start=qd_start, qd_goal=qd_goal
    )
    from_problem = lower_bound(problem)
    from_keywords = lower_bound(
        q_start=robot.home,
        q_goal=robot.home + 0.4,
        qd_start=qd_start,
        qd_goal=qd_goal,
        limits=limits,
    )
    assert from_problem == from_keywords > 0.0
    per_joint = joint_min_durations(problem)
    assert per_joint.shape == (7,) and per_joint.max() == from_problem
    # The synchronised state-to-state Ruckig move attains the bound.
    assert Ruckig().plan(problem).duration == pytest.approx(from_problem, rel=1e-12)
    # No joint moves: nothing to wait for.
    assert lower_bound(q_start=robot.home, q_goal=robot.home, limits=limits) == 0.0


def test_lower_bound_input_errors():
    robot = get_robot("sawyer")
    limits = robot.limits
    problem = problems.PointToPoint(robot, robot.home, robot.home + 0.1)
    with pytest.raises(InvalidInputError, match="not both"):
        lower_bound(problem, limits=limits)
    with pytest.raises(InvalidInputError, match="missing q_goal"):
        lower_bound(q_start=robot.home, limits=limits)
    with pytest.raises(InvalidInputError, match="PointToPoint"):
        lower_bound(problems.ece486_paddle_strike())
    with pytest.raises(InvalidInputError, match="shape"):
        lower_bound(q_start=np.zeros(3), q_goal=np.zeros(7), limits=limits)
    qd_goal = np.zeros(7)
    qd_goal[4] = 4.0
    with pytest.raises(InfeasibleError, match="right_j4"):
        lower_bound(q_start=robot.home, q_goal=robot.home, qd_goal=qd_goal, limits=limits)
    # A misspelt keyword is refused by the signature, which names the function.
    with pytest.raises(TypeError, match=r"lower_bound\(\) got an unexpected .*'q_strat'"):
        lower_bound(q_strat=robot.home, q_goal=robot.home, limits=limits)
    with pytest.raises(TypeError, match=r"joint_min_durations\(\) got an unexpected .*'q_strat'"):
        joint_min_durations(problem, q_strat=robot.home)
