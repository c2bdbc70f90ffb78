"""Tests of problems.scenarios: the ready-made problems build and are what they say."""

from __future__ import annotations

import numpy as np
import pytest

from optraj import problems
from optraj.errors import InvalidInputError


def test_ece486_paddle_strike_is_the_ece486_set_up():
    problem = problems.ece486_paddle_strike()
    np.testing.assert_allclose(problem.ball, [1.1, 0.8, 0.7])
    assert problem.contact_time == 2.0


def test_pool_shot_is_horizontal_and_reachable():
    problem = problems.sawyer_pool_shot(speed=1.5, heading_deg=90.0)
    np.testing.assert_allclose(problem.direction, [0.0, 1.0, 0.0], atol=1e-15)
    assert problem.speed == 1.5


@pytest.mark.parametrize("heading", ["abc", np.nan, np.inf, None])
def test_a_pool_shot_heading_must_be_a_finite_number(heading):
    with pytest.raises(InvalidInputError) as info:
        problems.sawyer_pool_shot(heading_deg=heading)
    assert info.value.name == "heading_deg"


def test_two_blocks():
    problem = problems.youbot_two_blocks()
    assert problem.count == 2 and problem.robot.name == "youbot"
