"""Tests of planners.time_optimal.ruckig_validation: synchronisation names, boundary states out
of the limits or out of reach, and bad arguments, each a typed error naming the value."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import InfeasibleError, InvalidInputError, JointLimitError, UnknownNameError
from optraj.planners.checker import ABSOLUTE_SLACK, RELATIVE_SLACK
from optraj.planners.time_optimal.ruckig_conversion import native_to_trajectory
from optraj.planners.time_optimal.ruckig_move import state_to_state, stop
from optraj.planners.time_optimal.ruckig_online import OnlineRuckig
from optraj.planners.time_optimal.ruckig_planner import Ruckig
from optraj.planners.time_optimal.ruckig_validation import check_state


def test_unsynchronised_moves_need_a_target_at_rest():
    limits = get_robot("sawyer").limits
    with pytest.raises(InvalidInputError, match="time_if_necessary"):
        state_to_state(
            np.zeros(7),
            None,
            None,
            np.ones(7),
            np.full(7, 0.1),
            None,
            limits,
            synchronization="none",
        )


def test_unknown_synchronisation_lists_the_options():
    with pytest.raises(UnknownNameError, match="time_if_necessary"):
        Ruckig("fastest")
    with pytest.raises(UnknownNameError):
        state_to_state(
            np.zeros(7),
            None,
            None,
            np.ones(7),
            None,
            None,
            get_robot("sawyer").limits,
            synchronization="Time",
        )


def test_target_velocity_above_the_limit_names_the_joint_and_values():
    limits = get_robot("sawyer").limits
    qd1 = np.zeros(7)
    qd1[0] = 2.5
    with pytest.raises(InfeasibleError) as info:
        state_to_state(np.zeros(7), None, None, np.full(7, 0.3), qd1, None, limits)
    error = info.value
    assert (error.limit, error.joint, error.required, error.allowed) == (
        "velocity",
        "right_j0",
        2.5,
        pytest.approx(1.74),
    )
    assert "target velocity 2.5 rad/s of joint 'right_j0' exceeds its limit 1.74" in str(error)


def test_target_acceleration_and_unreachable_target_states_raise():
    limits = get_robot("sawyer").limits
    qdd1 = np.zeros(7)
    qdd1[3] = -9.0
    with pytest.raises(InfeasibleError, match="right_j3") as info:
        state_to_state(np.zeros(7), None, None, np.full(7, 0.3), None, qdd1, limits)
    assert info.value.limit == "acceleration" and info.value.allowed == 8.0
    # Arriving at 1.7 rad/s while decelerating at 7 rad/s^2 means having been faster than
    # the limit 1.74 just before: 1.7 + 7^2 / (2 * 140) = 1.875.
    qd1, qdd1 = np.zeros(7), np.zeros(7)
    qd1[0], qdd1[0] = 1.7, -7.0
    with pytest.raises(InfeasibleError, match="right_j0") as info:
        state_to_state(np.zeros(7), None, None, np.full(7, 0.3), qd1, qdd1, limits)
    assert info.value.limit == "velocity"
    assert info.value.required == pytest.approx(1.7 + 49.0 / 280.0)


def test_bad_inputs_raise_typed_errors():
    robot = get_robot("sawyer")
    limits = robot.limits
    with pytest.raises(InvalidInputError, match="q_goal equals q_start"):
        Ruckig().move(robot.home, robot.home, limits)
    with pytest.raises(InvalidInputError, match="shape"):
        Ruckig().move(np.zeros(6), np.zeros(7), limits)
    with pytest.raises(InvalidInputError, match="finite"):
        state_to_state(np.zeros(7), [np.nan] * 7, None, np.ones(7), None, None, limits)
    with pytest.raises(JointLimitError, match="right_j1"):
        state_to_state(np.zeros(7), None, None, np.full(7, 2.5), None, None, limits)
    with pytest.raises(InvalidInputError, match="JointLimits"):
        state_to_state(np.zeros(7), None, None, np.ones(7), None, None, robot)
    with pytest.raises(InvalidInputError, match="PointToPoint"):
        Ruckig().plan(problems.ece486_paddle_strike())


def test_bad_options_raise_typed_errors():
    robot = get_robot("sawyer")
    limits = robot.limits
    start, goal = robot.home, robot.home + 0.1
    for options, match in (
        ({"joint_names": "abcdefg"}, "joint_names must be a sequence of 7 strings"),
        ({"joint_names": 5}, "joint_names"),
        ({"joint_names": ["a"] * 6}, "joint_names"),
        ({"check_limits": "no"}, "check_limits must be True or False"),
        ({"minimum_duration": 1e300}, r"minimum_duration must be <= 86400 s"),
        ({"minimum_duration": True}, "minimum_duration"),
    ):
        with pytest.raises(InvalidInputError, match=match):
            state_to_state(start, None, None, goal, None, None, limits, **options)
    with pytest.raises(InvalidInputError, match="check_limits"):
        stop(start, 0.1 * limits.velocity, None, limits, check_limits=1)
    with pytest.raises(InvalidInputError, match=r"dt must be <= 86400 s"):
        OnlineRuckig(limits, 1e300)
    with pytest.raises(InvalidInputError, match=r"ruckig\.Trajectory"):
        native_to_trajectory("not a trajectory")  # type: ignore[arg-type]
    names = [f"joint {j}" for j in range(7)]
    named = state_to_state(start, None, None, goal, None, None, limits, joint_names=names)
    assert named.joint_names == tuple(names)


def test_check_state_refuses_exactly_what_the_rule_refuses_on_seeded_random_states():
    # The rule, in NumPy: |qd| and |qdd| within their limits, and the velocity implied
    # while the acceleration ramps at the jerk limit, qd -/+ qdd |qdd| / (2 j), within the
    # velocity limit; strictly when arriving, with the checker's slack when leaving.
    limits = get_robot("panda").limits
    rng = np.random.default_rng(3510)
    refused = {True: 0, False: 0}
    for _ in range(600):
        arriving = bool(rng.random() < 0.5)
        qd = limits.velocity * rng.choice([0.3, 0.9, 1.0, 1.0 + 1e-12, 1.1], limits.n)
        qd *= rng.choice([-1.0, 1.0], limits.n)
        qdd = np.zeros(limits.n)
        if rng.random() < 0.6:
            qdd = limits.acceleration * rng.choice([0.0, 0.5, 1.0, 1.0 + 1e-12], limits.n)
            qdd *= rng.choice([-1.0, 1.0], limits.n)
        factor, extra = (1.0, 0.0) if arriving else (1.0 + RELATIVE_SLACK, ABSOLUTE_SLACK)
        implied = qd - qdd * np.abs(qdd) / (2.0 * limits.jerk) * (1.0 if arriving else -1.0)
        bad = (
            np.any(np.abs(qd) > limits.velocity * factor + extra)
            or np.any(np.abs(qdd) > limits.acceleration * factor + extra)
            or np.any(np.abs(implied) > limits.velocity * factor + extra)
        )
        try:
            check_state(qd, qdd, limits, "target" if arriving else "start", arriving=arriving)
        except InfeasibleError:
            assert bad
            refused[bool(qdd.any())] += 1
        else:
            assert not bad
    assert min(refused.values()) > 20  # both ways through the check were refused often
