"""Tests of problems.common: the shared checks."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj.errors import InvalidInputError, JointLimitError
from optraj.problems.common import (
    MAX_TOOL_SPEED,
    check_robot,
    joint_state,
    non_negative,
    normal_pair,
    positive,
    resolve_limits,
    unit_vector,
)


def test_unit_vector_and_numbers():
    np.testing.assert_allclose(unit_vector([0, 3, 4], "d"), [0, 0.6, 0.8])
    assert positive(2, "x", "m") == 2.0 and non_negative(0, "x", "m") == 0.0
    with pytest.raises(InvalidInputError, match="x must be > 0 m, got 0 m"):
        positive(0, "x", "m")


@pytest.mark.parametrize("value", ["2", True, None])
def test_numbers_are_numbers(value):
    # The problems' checks are optraj.validation's (no bool or string).
    for check in (positive, non_negative):
        with pytest.raises(InvalidInputError, match="x must be a numeric"):
            check(value, "x", "m")


def test_an_upper_bound_names_its_unit():
    assert positive(343.0, "speed", "m/s", maximum=MAX_TOOL_SPEED) == 343.0
    with pytest.raises(InvalidInputError, match=r"speed must be <= 343 m/s, got 1e\+308 m/s"):
        positive(1e308, "speed", "m/s", maximum=MAX_TOOL_SPEED)
    with pytest.raises(InvalidInputError, match="d must be <= 1 m, got 2 m"):
        non_negative(2.0, "d", "m", maximum=1.0)


def test_joint_state_checks_speed_against_the_limit():
    limits = get_robot("youbot").limits
    _, qd, qdd = joint_state(limits, limits.lower, None, None, "start")
    np.testing.assert_array_equal(qd, 0.0)
    assert qdd is None
    with pytest.raises(
        JointLimitError, match=r"velocity at the goal: joint 'arm_joint_2' velocity -2"
    ):
        joint_state(limits, None, [0, -2.0, 0, 0, 0], None, "goal")


def test_check_robot_and_limits():
    robot = get_robot("paddle4")
    assert check_robot(robot, "paddle4") is robot
    assert resolve_limits(robot, None) is robot.limits
    with pytest.raises(InvalidInputError, match="needs the 'sawyer' robot"):
        check_robot(robot, "sawyer")


def test_normal_pair_completes_a_right_handed_orthonormal_basis():
    rng = np.random.default_rng(41)
    for direction in [*np.eye(3), *rng.normal(size=(50, 3))]:
        d = direction / np.linalg.norm(direction)
        first, second = normal_pair(d)
        basis = np.array([d, first, second])
        np.testing.assert_allclose(basis @ basis.T, np.eye(3), atol=1e-12)
        np.testing.assert_allclose(np.cross(d, first), second, atol=1e-12)


def test_joint_state_accepts_and_refuses_as_the_numpy_rule_on_seeded_random_states():
    # Within-limit states are recognised in Python floats; the verdict must be the NumPy
    # rule's: excess = max(lower - q, q - upper), or |value| - limit, above 1e-9.
    limits = get_robot("panda").limits
    rng = np.random.default_rng(3503)
    span = limits.upper - limits.lower
    for _ in range(400):
        step = rng.choice([0.0, 1e-9, 2e-9, 1e-6]) * rng.choice([-1.0, 1.0], size=limits.n)
        q = np.where(rng.random(limits.n) < 0.5, limits.upper, limits.lower) + step
        q = np.where(rng.random(limits.n) < 0.7, limits.lower + span * rng.random(limits.n), q)
        qd = limits.velocity * rng.choice([0.5, 1.0], size=limits.n) + step
        qdd = -limits.acceleration * rng.choice([0.5, 1.0], size=limits.n) - step
        position_out = np.max(np.maximum(limits.lower - q, q - limits.upper)) > 1e-9
        velocity_out = np.max(np.abs(qd) - limits.velocity) > 1e-9
        acceleration_out = np.max(np.abs(qdd) - limits.acceleration) > 1e-9
        try:
            joint_state(limits, q, qd, qdd, "start")
        except JointLimitError as error:
            first = "position" if position_out else "velocity" if velocity_out else "acceleration"
            assert error.quantity == first
        else:
            assert not (position_out or velocity_out or acceleration_out)
