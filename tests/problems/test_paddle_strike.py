"""Tests of problems.paddle_strike."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj.errors import InvalidInputError, WorkspaceError
from optraj.problems import PaddleStrike, ToolContact


def test_seed_defaults_and_contact_constraint():
    problem = PaddleStrike(get_robot("paddle4"), ball=(1.1, 0.8, 0.7))
    assert problem.contact_time == 2.0 and problem.speed == 0.0
    np.testing.assert_allclose(problem.q_start, [0.45, 0, 0, 0])
    np.testing.assert_allclose(problem.q_contact, [0.9, 0.3911, 0.9985, -0.3911], atol=1e-4)
    _, contact, end = problem.constraints()
    assert isinstance(contact, ToolContact) and contact.time == 2.0 and contact.offset == 0.01
    np.testing.assert_allclose(contact.velocity, 0.0)
    np.testing.assert_allclose(end.q, problem.q_contact)  # rest at contact ends the motion


def test_strike_at_speed_has_a_velocity_along_the_normal():
    problem = PaddleStrike(get_robot("paddle4"), ball=(0.8, 0.0, 0.3), contact_angle=0.3, speed=2.0)
    contact = problem.constraints()[1]
    np.testing.assert_allclose(contact.velocity, 2.0 * np.array([np.cos(0.3), np.sin(0.3), 0.0]))
    assert problem.constraints()[2].q is None  # stops anywhere


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"ball": (1.3, 0.0, 0.3)}, WorkspaceError, "x <= 1.1"),
        ({"speed": -1.0}, InvalidInputError, "speed must be >= 0"),
        ({"contact_time": 0.0}, InvalidInputError, "contact_time must be >= 1e-06 s, got 0 s"),
        ({"contact_time": 1e200}, InvalidInputError, "contact_time must be <= 86400 s"),
        ({"speed": 1e308}, InvalidInputError, "speed must be <= 343 m/s"),
        ({"contact_angle": "0.1"}, InvalidInputError, "contact_angle must be a numeric"),
        ({"velocity_tolerance": None}, InvalidInputError, "velocity_tolerance must be a numeric"),
        ({"angle_tolerance": -1e-6}, InvalidInputError, "angle_tolerance must be > 0 rad"),
        ({"robot": "sawyer"}, InvalidInputError, "robots.Robot"),
    ],
)
def test_bad_values(kwargs, error, match):
    fields = {"robot": get_robot("paddle4"), "ball": (0.8, 0.0, 0.3)}
    fields.update(kwargs)
    with pytest.raises(error, match=match):
        PaddleStrike(**fields)


def test_needs_the_paddle_robot():
    with pytest.raises(InvalidInputError, match="needs the 'paddle4' robot"):
        PaddleStrike(get_robot("sawyer"), ball=(0.8, 0.0, 0.3))
