"""Tests of planners.profiles.duration_search: the bisection and its replay on a found root."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.planners.profiles.duration_search import WIDTH, bisect, shortest_in
from optraj.planners.profiles.time_scaling import Cubic, Quintic


def _counted(function):
    calls = []

    def wrapped(duration):
        calls.append(duration)
        return function(duration)

    return wrapped, calls


def test_replay_returns_what_the_bisection_returns_with_fewer_checks():
    rng = np.random.default_rng(35)
    for _ in range(200):
        crossing = float(rng.uniform(0.01, 50.0))
        power = float(rng.uniform(0.5, 3.0))
        bend = float(rng.uniform(-0.3, 0.3))

        def margin(duration, crossing=crossing, power=power, bend=bend):
            x = math.log(crossing / duration)
            return power * x + bend * x * x * (1.0 if x > 0 else -1.0)

        def fits(duration, margin=margin):
            return margin(duration) <= 0.0

        high = 1e-3 * 2.0 ** math.ceil(math.log2(crossing / 1e-3))
        counted, calls = _counted(fits)
        expected = bisect(fits, high / 2.0, high)
        assert shortest_in(counted, margin, high / 2.0, high) == expected
        assert len(calls) <= 3  # the result, and a step that fell inside the narrowed bracket
        assert expected >= crossing and expected - crossing <= WIDTH * expected


def test_a_bracket_with_two_crossings_gives_a_fitting_end():
    # fits on [1, 1.2] and from 1.6 on: the replay may pick either; its result must fit
    def fits(duration):
        return 1.0 <= duration <= 1.2 or duration >= 1.6

    def margin(duration):
        return 1.0 if not fits(duration) else -1.0

    found = shortest_in(fits, margin, 0.9, 1.8)
    assert fits(found) and not fits(found * (1.0 - 2.0 * WIDTH))


def test_a_margin_that_does_not_bracket_leaves_it_to_the_bisection():
    def fits(duration):
        return duration >= 0.3

    expected = bisect(fits, 0.25, 0.5)
    assert shortest_in(fits, lambda duration: -1.0, 0.25, 0.5) == expected


@pytest.mark.parametrize("profile", [Cubic(), Quintic()])
def test_shortest_with_moving_ends_equals_the_plain_bisection(profile):
    robot = get_robot("panda")
    limits = robot.limits
    span = limits.upper - limits.lower
    rng = np.random.default_rng(36)
    zeros = np.zeros(robot.dof)
    for _ in range(8):
        q0, q1 = limits.lower + span * rng.uniform(0.1, 0.9, (2, robot.dof))
        v0, v1 = rng.uniform(0.05, 0.5) * limits.velocity * rng.uniform(-1, 1, (2, robot.dof))
        boundary = {"v0": v0, "v1": v1, "a0": zeros, "a1": zeros}

        def fits(duration, boundary=boundary, q0=q0, q1=q1):
            coeffs = profile._coefficients(q0, q1, duration, boundary)
            return profile._check(coeffs, duration, limits) is None

        high = 1e-3
        while not fits(high):
            high *= 2.0
        found = profile._shortest(q0, q1, limits, boundary, rest=False)
        assert found == bisect(fits, high / 2.0, high)
        problem = problems.PointToPoint(robot, q0, q1, v0, v1)
        assert profile.plan(problem).duration == found
