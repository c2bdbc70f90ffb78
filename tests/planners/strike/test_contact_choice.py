"""Tests of planners.strike.contact_choice: the errors of a strike too fast for the limits."""

from __future__ import annotations

import dataclasses
import time

import numpy as np
import pytest
from conftest import get_robot
from strike_support import pool_shots

from optraj.errors import CONTACT_CHOICE, InfeasibleError, InvalidInputError
from optraj.planners.strike.contact import choose_contact
from optraj.planners.strike.contact_choice import as_margin, too_fast_error


def test_too_fast_pool_strike_is_rejected_within_a_second_and_the_bound_is_exact():
    problem = next(pool_shots(1, speed=2.5, seed=11))
    robot = problem.robot
    elapsed, errors = [], []
    for _ in range(2):  # the first call may load HiGHS; the second is the steady state
        started = time.perf_counter()
        with pytest.raises(InfeasibleError) as info:
            choose_contact(problem)
        elapsed.append(time.perf_counter() - started)
        errors.append(info.value)
    assert elapsed[1] < 1.0, f"rejection took {elapsed} s"
    error = errors[1]
    assert error.limit == "velocity"
    assert error.joint in robot.joint_names
    j = robot.joint_names.index(error.joint)
    assert error.allowed == pytest.approx(problem.limits.velocity[j])
    assert error.required > error.allowed
    assert error.joint in str(error) and "2.5 m/s" in str(error)
    assert 0.0 < error.max_speed < 2.5
    assert error.found_by == CONTACT_CHOICE
    # Same geometry at other speeds: the ratios scale, so the reported speed is the boundary.
    choice = choose_contact(dataclasses.replace(problem, speed=0.99 * error.max_speed))
    assert 0.98 <= choice.ratio <= 1.0
    with pytest.raises(InfeasibleError):
        choose_contact(dataclasses.replace(problem, speed=1.01 * error.max_speed))


def test_margin_keeps_part_of_the_velocity_limits_in_reserve():
    problem = next(pool_shots(1, speed=1.0, seed=11))
    with pytest.raises(InfeasibleError) as too_fast:
        choose_contact(dataclasses.replace(problem, speed=10.0))
    ratio = 1.0 / too_fast.value.max_speed  # the smallest ratio found at 1 m/s
    margin = 1.0 - 0.9 * ratio  # asks for ratio <= 0.9 * the best one found
    with pytest.raises(InfeasibleError, match="margin") as info:
        choose_contact(problem, margin=margin)
    error = info.value
    j = problem.robot.joint_names.index(error.joint)
    assert error.allowed == pytest.approx((1.0 - margin) * problem.limits.velocity[j])
    assert error.required > error.allowed
    assert 0.9 - 1e-9 <= error.max_speed <= 0.9 * 1.02
    assert choose_contact(problem, margin=1.0 - 1.01 * ratio).ratio <= 1.01 * ratio


def test_as_margin_accepts_a_share_below_one_only():
    assert as_margin(0.25) == 0.25
    assert as_margin(0) == 0.0
    for bad in (1.0, -0.1, True, "0.1", float("nan")):
        with pytest.raises(InvalidInputError) as info:
            as_margin(bad)
        assert info.value.name == "margin"


def test_a_motion_no_joint_velocity_gives_is_refused_as_singular():
    limits = get_robot("paddle4").limits
    error = too_fast_error(limits, 1.0, np.inf, [], np.full(4, np.nan), 0.0, "the contact")
    assert (error.limit, error.joint, error.required, error.allowed) == (
        "velocity",
        None,
        None,
        None,
    )
    assert (error.max_speed, error.found_by) == (0.0, CONTACT_CHOICE)
    assert str(error) == (
        "strike speed 1 m/s: the contact cannot move the tool along the strike direction at "
        "all (singular)"
    )
