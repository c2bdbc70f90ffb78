"""Tests of planners.strike.twist_ratio: the strike LP against independent references.

References (tests/strike_support.py): the LP optimum by enumerating every vertex of the LP and
by scipy's linprog on the full formulation; the task rows rebuilt here from the Jacobian (and,
for the paddle's ball point, by finite differences of its position).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from conftest import get_robot
from hypothesis import given, settings
from hypothesis import strategies as st
from strike_support import (
    ball_point_jacobian,
    by_linprog,
    by_vertices,
    random_unit,
    reference_rows,
)

from optraj.errors import InvalidInputError
from optraj.planners.strike.twist_ratio import twist_ratio
from optraj.robots.paddle_ik import BALL_OFFSET


def test_twist_ratio_meets_the_rows_and_equals_two_independent_optima():
    robot = get_robot("sawyer")
    vmax = robot.limits.velocity
    rng = np.random.default_rng(3)
    for q in robot.random_configurations(8, rng):
        direction = random_unit(rng)
        speed = rng.uniform(0.2, 2.0)
        ratio, qd, joint = twist_ratio(robot, q, direction, speed)
        rows, target = reference_rows(robot, q, direction)
        np.testing.assert_allclose(rows @ qd, speed * target, rtol=0, atol=1e-9)
        np.testing.assert_allclose(np.abs(qd / vmax).max(), ratio, rtol=1e-12)
        assert abs(qd[joint]) / vmax[joint] == pytest.approx(ratio, rel=1e-9)
        np.testing.assert_allclose(ratio, speed * by_vertices(rows, target, vmax), rtol=1e-6)
        np.testing.assert_allclose(ratio, speed * by_linprog(rows, target, vmax), rtol=1e-6)
        # The LP beats the least-squares joint velocity (minimum norm, not minimum ratio).
        least_squares = np.linalg.lstsq(rows, speed * target, rcond=None)[0]
        assert ratio <= np.abs(least_squares / vmax).max() + 1e-12


@settings(max_examples=40, derandomize=True, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), align_axis=st.booleans())
def test_twist_ratio_stress_against_vertex_enumeration(seed, align_axis):
    robot = get_robot("sawyer")
    rng = np.random.default_rng(seed)
    q = robot.random_configurations(1, rng)[0]
    direction = random_unit(rng)
    ratio, qd, _ = twist_ratio(robot, q, direction, 1.0, align_axis=align_axis)
    rows, target = reference_rows(robot, q, direction, align_axis)
    np.testing.assert_allclose(rows @ qd, target, rtol=0, atol=1e-9)
    reference = by_vertices(rows, target, robot.limits.velocity)
    np.testing.assert_allclose(ratio, reference, rtol=1e-6)


def test_twist_ratio_is_linear_in_speed_and_zero_at_rest():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(5)
    q = robot.random_configurations(1, rng)[0]
    direction = random_unit(rng)
    unit_ratio, _, unit_joint = twist_ratio(robot, q, direction, 1.0)
    for speed in (0.3, 2.7):
        ratio, qd, joint = twist_ratio(robot, q, direction, speed)
        np.testing.assert_allclose(ratio, speed * unit_ratio, rtol=1e-9)
        assert joint == unit_joint
        np.testing.assert_allclose(np.abs(qd / robot.limits.velocity).max(), ratio, rtol=1e-12)
    ratio, qd, joint = twist_ratio(robot, q, direction, 0.0)
    assert (ratio, joint) == (0.0, 0)
    np.testing.assert_array_equal(qd, np.zeros(robot.dof))


def test_twist_ratio_uses_the_given_velocity_limits():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(6)
    q = robot.random_configurations(1, rng)[0]
    direction = random_unit(rng)
    halved = robot.limits.velocity / 2.0
    slow = dataclasses.replace(robot.limits, velocity=halved)
    ratio, _, _ = twist_ratio(robot, q, direction, 1.0, limits=slow)
    rows, target = reference_rows(robot, q, direction)
    np.testing.assert_allclose(ratio, by_vertices(rows, target, halved), rtol=1e-6)
    np.testing.assert_allclose(ratio, 2.0 * twist_ratio(robot, q, direction, 1.0)[0], rtol=1e-6)


def test_ball_point_rows_match_finite_differences():
    robot = get_robot("paddle4")
    rng = np.random.default_rng(8)
    for q in robot.random_configurations(5, rng):
        direction = random_unit(rng)
        ratio, qd, _ = twist_ratio(robot, q, direction, 0.8, offset=BALL_OFFSET, align_axis=False)
        jac = ball_point_jacobian(robot, q)
        np.testing.assert_allclose(jac @ qd, 0.8 * direction, rtol=0, atol=1e-6)
        reference = by_vertices(jac, direction, robot.limits.velocity)
        np.testing.assert_allclose(ratio, 0.8 * reference, rtol=1e-5)


def test_rank_deficient_rows_with_a_solution_give_the_analytic_optimum():
    # paddle4 turns about z only: the two angular rows across z vanish (rank 3 of 5), and only
    # the vertical prismatic J1 moves the paddle up, so qd = (v, 0, 0, 0) exactly.
    robot = get_robot("paddle4")
    q = robot.random_configurations(1, np.random.default_rng(9))[0]
    ratio, qd, joint = twist_ratio(robot, q, [0.0, 0.0, 1.0], 0.4)
    np.testing.assert_allclose(qd, [0.4, 0.0, 0.0, 0.0], rtol=0, atol=1e-12)
    assert ratio == pytest.approx(0.4 / robot.limits.velocity[0], rel=1e-12)
    assert joint == 0


def test_a_motion_the_arm_cannot_make_has_an_infinite_ratio():
    # youBot moves its tool sideways (along its pitch axes) only by yawing the base, which
    # turns the tool across that direction: with the axis held, no joint velocity does it.
    robot = get_robot("youbot")
    for q in robot.random_configurations(3, np.random.default_rng(10)):
        sideways = robot.jacobian(q)[3:, 1]
        rows, target = reference_rows(robot, q, sideways)
        residual = rows @ np.linalg.lstsq(rows, target, rcond=None)[0] - target
        assert np.linalg.norm(residual) > 1e-3  # independent: no exact solution
        ratio, qd, joint = twist_ratio(robot, q, sideways, 1.0)
        assert ratio == math.inf and joint == -1 and np.all(np.isnan(qd))
        assert math.isfinite(twist_ratio(robot, q, sideways, 1.0, align_axis=False)[0])


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"q": np.zeros(3)}, "q"),
        ({"direction": [0.0, 0.0, 0.0]}, "direction"),
        ({"direction": [np.nan, 0.0, 1.0]}, "direction"),
        ({"speed": -1.0}, "speed"),
        ({"offset": np.inf}, "offset"),
        ({"offset": 1e300}, "offset"),
        ({"limits": "sawyer"}, "limits"),
    ],
)
def test_twist_ratio_rejects_bad_input(kwargs, name):
    robot = get_robot("sawyer")
    arguments = {"q": robot.home, "direction": [1.0, 0.0, 0.0], "speed": 1.0, **kwargs}
    extra = {key: arguments.pop(key) for key in ("offset", "limits") if key in arguments}
    with pytest.raises(InvalidInputError) as info:
        twist_ratio(robot, arguments["q"], arguments["direction"], arguments["speed"], **extra)
    assert info.value.name == name
    with pytest.raises(InvalidInputError, match=r"robots\.Robot"):
        twist_ratio("sawyer", robot.home, [1.0, 0.0, 0.0], 1.0)
