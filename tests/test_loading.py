"""Tests of robots.loading: names, options, limits, tool frames and optional packages."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from conftest import HAVE_ERD, get_robot

import robots
from optraj.errors import InvalidInputError, MissingDependencyError, UnknownNameError
from robots import loading


def test_known_robots():
    assert list(robots.known_robots()) == ["paddle4", "sawyer", "youbot", "panda", "ur5"]


def test_unknown_robot_lists_known_names():
    with pytest.raises(
        UnknownNameError, match="known: paddle4, sawyer, youbot, panda, ur5"
    ) as info:
        robots.load("sawer")
    assert "did you mean 'sawyer'" in str(info.value)


def test_unknown_option_lists_accepted_options():
    with pytest.raises(UnknownNameError, match="known: cue_length"):
        robots.load("sawyer", cue=0.3)


@pytest.mark.parametrize(("length", "match"), [(0.0, "must be > 0 m"), (2.0, "<= 1.5 m")])
def test_cue_length_is_checked(length, match):
    with pytest.raises(InvalidInputError, match=match):
        robots.load("sawyer", cue_length=length)


def test_name_is_case_insensitive():
    assert robots.load("YouBot").name == "youbot"


@pytest.mark.parametrize(
    ("name", "dof", "tool", "poses"),
    [
        ("paddle4", 4, "paddle", {"home"}),
        ("sawyer", 7, "cue_tip", {"home", "neutral"}),
        ("youbot", 5, "tcp", {"home", "candle"}),
    ],
)
def test_shipped_robot_structure(name, dof, tool, poses):
    robot = get_robot(name)
    assert robot.dof == dof
    assert robot.tool_frame == tool
    assert set(robot.poses) == poses
    assert robot.limits.contains(robot.home)


def test_sawyer_limits_come_from_the_fact_sheet():
    limits = get_robot("sawyer").limits
    np.testing.assert_array_equal(limits.velocity, [1.74, 1.328, 1.957, 1.957, 3.485, 3.485, 4.545])
    np.testing.assert_array_equal(limits.acceleration, [7, 5, 8, 8, 8, 8, 8])
    np.testing.assert_array_equal(limits.effort, [80, 80, 40, 40, 9, 9, 9])
    np.testing.assert_array_equal(
        limits.upper, [3.0503, 2.2736, 3.0426, 3.0439, 2.9761, 2.9761, 4.7124]
    )
    np.testing.assert_allclose(limits.jerk, 20.0 * limits.acceleration)


def test_youbot_plans_with_driver_ranges():
    robot = get_robot("youbot")
    np.testing.assert_array_equal(robot.limits.lower, loading.YOUBOT_LOWER)
    np.testing.assert_array_equal(robot.limits.upper, loading.YOUBOT_UPPER)
    np.testing.assert_array_equal(robot.model.lowerPositionLimit, loading.YOUBOT_LOWER)


def test_paddle4_mixes_prismatic_and_revolute_units():
    assert get_robot("paddle4").limits.kinds == ("m", "rad", "m", "rad")


@pytest.mark.skipif(not HAVE_ERD, reason="needs optraj[examples]")
def test_panda_has_fingers_locked_and_franka_limits():
    robot = get_robot("panda")
    assert robot.dof == 7
    assert "panda_finger_joint1" not in robot.joint_names
    np.testing.assert_array_equal(robot.limits.jerk, loading.PANDA_JERK)
    # robots.md: at q = 0, panda_hand_tcp is at (0.088, 0, 0.8226).
    np.testing.assert_allclose(robot.tool_position(np.zeros(7)), [0.088, 0.0, 0.8226], atol=1e-3)


@pytest.mark.skipif(not HAVE_ERD, reason="needs optraj[examples]")
def test_ur5_loads_with_tool0():
    robot = get_robot("ur5")
    assert (robot.dof, robot.tool_frame) == (6, "tool0")


def test_missing_optional_package_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "example_robot_data", None)  # makes the import fail
    with pytest.raises(MissingDependencyError, match=r"pip install 'optraj\[examples\]'") as info:
        robots.load("panda")
    assert info.value.package == "example-robot-data"


def test_loaded_robots_are_independent():
    a, b = robots.load("paddle4"), robots.load("paddle4")
    assert a.model is not b.model
    assert a.data is not b.data
