"""Tests of planners.strike.paddle_contact: the paddle contact and the room to pass it."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from conftest import get_robot
from strike_support import ball_point_jacobian, by_linprog

from optraj import problems
from optraj.errors import CONTACT_CHOICE, InfeasibleError, InvalidInputError
from optraj.planners.profiles.cartesian import paddle_contact_velocity
from optraj.planners.strike.contact import choose_contact
from optraj.planners.strike.paddle_contact import stopping_speeds


def test_paddle_at_rest_needs_no_joint_velocity():
    problem = problems.PaddleStrike(get_robot("paddle4"), ball=(1.0, 0.3, 0.4), contact_angle=0.3)
    choice = choose_contact(problem)
    np.testing.assert_array_equal(choice.q, problem.q_contact)
    np.testing.assert_array_equal(choice.qd, np.zeros(4))
    assert choice.ratio == 0.0 and choice.q_entry is None and choice.q_exit is None
    assert math.isfinite(choice.max_speed) and choice.binding_joint in problem.robot.joint_names


@pytest.mark.parametrize(
    ("ball", "angle"), [((1.0, 0.3, 0.4), 0.3), ((0.6, -0.5, 0.1), -0.8), ((0.9, 0.0, 0.6), 0.0)]
)
def test_paddle_at_speed_moves_the_ball_point_along_the_normal(ball, angle):
    robot = get_robot("paddle4")
    problem = problems.PaddleStrike(robot, ball=ball, contact_angle=angle, speed=0.5)
    choice = choose_contact(problem)
    np.testing.assert_array_equal(choice.q, problem.q_contact)
    velocity = ball_point_jacobian(robot, choice.q) @ choice.qd
    np.testing.assert_allclose(velocity, 0.5 * problem.normal, rtol=0, atol=1e-6)
    # The normal is held still at contact, as the time-optimal strike planner does.
    np.testing.assert_allclose(robot.jacobian(choice.q)[3:] @ choice.qd, 0.0, atol=1e-9)
    np.testing.assert_allclose(choice.qd, paddle_contact_velocity(problem), atol=1e-9)
    ratio = float(np.abs(choice.qd / robot.limits.velocity).max())
    np.testing.assert_allclose(choice.ratio, ratio, rtol=1e-12)
    np.testing.assert_allclose(choice.max_speed * choice.ratio, 0.5, rtol=1e-12)


def test_too_fast_paddle_strike_names_the_joint():
    robot = get_robot("paddle4")
    problem = problems.PaddleStrike(robot, ball=(1.0, 0.3, 0.4), contact_angle=0.3, speed=3.0)
    with pytest.raises(InfeasibleError) as info:
        choose_contact(problem)
    error = info.value
    assert error.limit == "velocity" and error.joint in robot.joint_names
    assert error.required > error.allowed
    slower = problems.PaddleStrike(
        robot, ball=(1.0, 0.3, 0.4), contact_angle=0.3, speed=0.999 * error.max_speed
    )
    assert choose_contact(slower).ratio == pytest.approx(0.999, rel=1e-9)


def test_stopping_speeds_leave_room_to_start_and_stop_on_both_sides():
    limits = get_robot("paddle4").limits  # J1, J3 in [0, 1] m; J2 in [-pi, pi], J4 in [-pi/2, pi/2]
    q = np.array([0.3, 3.0, 1.0, 0.0])
    room = np.array([0.3, np.pi - 3.0, 0.0, np.pi / 2])  # to the nearer limit
    expected = np.sqrt(2.0 * limits.acceleration * room)
    np.testing.assert_allclose(stopping_speeds(limits, q), expected, rtol=1e-12)
    # A joint on its limit cannot pass it moving; halving the room takes v by sqrt(2).
    assert stopping_speeds(limits, q)[2] == 0.0
    nearer = stopping_speeds(limits, [0.15, 3.0, 1.0, 0.0])[0]
    assert nearer == pytest.approx(expected[0] / np.sqrt(2.0), rel=1e-12)
    with pytest.raises(InvalidInputError):
        stopping_speeds(limits, [0.3, 0.0])


def test_paddle_contact_without_room_to_pass_it_is_refused_with_the_joint():
    # Found by a seeded random probe: the ball sits where J3 (the arm's extension) is 29 mm
    # from its upper limit at contact; the NLP found the strike infeasible after 77
    # iterations and said only "dynamics". No motion from rest to rest can pass a joint at
    # speed v with less than v^2 / (2 a) of room on either side.
    robot = get_robot("paddle4")
    ball, angle = (1.08197713, -0.72308109, 0.24624905), 0.5057469237104932
    problem = problems.PaddleStrike(robot, ball=ball, contact_angle=angle, speed=1.5)
    with pytest.raises(InfeasibleError) as info:
        choose_contact(problem)
    error = info.value
    q = np.asarray(problem.q_contact)
    assert (error.limit, error.joint, error.found_by) == ("position", "J3", CONTACT_CHOICE)
    assert error.allowed == pytest.approx(1.0 - q[2], rel=1e-12) and error.required > error.allowed
    assert "J3 is 0.02909 m from its upper limit" in str(error)
    # The fastest speed, from an independent LP over the ball point's velocity rows (the
    # paddle may turn) with each joint held to the speed its room and acceleration allow.
    limits = problem.limits
    room = np.minimum(q - limits.lower, limits.upper - q)
    allowed = np.minimum(limits.velocity, np.sqrt(2.0 * limits.acceleration * room))
    reference = 1.0 / by_linprog(ball_point_jacobian(robot, q), problem.normal, allowed)
    assert error.max_speed == pytest.approx(reference, rel=1e-5)
    assert 1.4 < error.max_speed < 1.5
    slower = dataclasses.replace(problem, speed=0.999 * error.max_speed)
    assert choose_contact(slower).q == pytest.approx(q)
