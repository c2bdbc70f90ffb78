"""Tests of robots.loading: names, options, limits, tool frames and optional packages."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from conftest import HAVE_ERD, get_robot

from optraj import robots
from optraj.errors import InvalidInputError, MissingDependencyError, UnknownNameError


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


# robots.md: youbot_driver encoder ranges.
YOUBOT_DRIVER_LOWER = [0.0100692, 0.0100692, -5.02655, 0.0221239, 0.110619]
YOUBOT_DRIVER_UPPER = [5.84014, 2.61799, -0.015708, 3.4292, 5.64159]


def test_youbot_plans_with_driver_ranges():
    robot = get_robot("youbot")
    np.testing.assert_array_equal(robot.limits.lower, YOUBOT_DRIVER_LOWER)
    np.testing.assert_array_equal(robot.limits.upper, YOUBOT_DRIVER_UPPER)
    np.testing.assert_array_equal(robot.model.lowerPositionLimit, YOUBOT_DRIVER_LOWER)
    np.testing.assert_array_equal(robot.limits.velocity, [1.570796] * 5)
    np.testing.assert_array_equal(robot.limits.effort, [9.5, 9.5, 6, 2, 1])


def test_paddle4_mixes_prismatic_and_revolute_units():
    assert get_robot("paddle4").limits.kinds == ("m", "rad", "m", "rad")


@pytest.mark.skipif(not HAVE_ERD, reason="needs optraj[examples]")
def test_panda_has_fingers_locked_and_franka_limits():
    robot = get_robot("panda")
    assert robot.dof == 7
    assert "panda_finger_joint1" not in robot.joint_names
    # robots.md: Franka's published acceleration and jerk limits.
    np.testing.assert_array_equal(robot.limits.acceleration, [15, 7.5, 10, 12.5, 15, 20, 20])
    np.testing.assert_array_equal(robot.limits.jerk, [7500, 3750, 5000, 6250, 7500, 10000, 10000])
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


# robots.md: mass, COM (link frame) and inertia about the COM (ixx iyy izz ixy ixz iyz).
SAWYER_INERTIALS = {
    "right_arm_base_link": (2.0687, (-0.0006241, -2.8025e-5, 0.065404),
                            (0.0067599, 0.0067877, 0.0074031, -4.2024e-5, -6.1904e-7, 1.5888e-5)),
    "right_l0": (5.3213, (0.024366, 0.010969, 0.14363),
                 (0.053314, 0.057902, 0.023659, 0.0047093, 0.011734, 0.0080179)),
    "right_l1": (4.505, (-0.0030849, -0.026811, 0.092521),
                 (0.022398, 0.014613, 0.017295, -0.00023986, -0.00029362, -0.0060875)),
    "right_l2": (1.745, (-0.00016044, -0.014967, 0.13582),
                 (0.025506, 0.0253, 0.0034179, 4.4101e-6, 1.4955e-5, -0.0033204)),
    "right_l3": (2.5097, (-0.0048135, -0.0281, -0.084154),
                 (0.01016, 0.0065685, 0.0069078, -9.7452e-6, 0.00026624, 0.0030316)),
    "right_l4": (1.1136, (-0.0018844, 0.0069001, 0.1341),
                 (0.013557, 0.013555, 0.0013658, 1.8109e-5, 0.00013523, 0.0010561)),
    "right_l5": (1.5625, (0.0061133, -0.023697, 0.076416),
                 (0.0047328, 0.0029676, 0.0031762, 0.00011526, 4.6269e-5, -0.0011557)),
    "right_l6": (0.3292, (-8.0726e-6, 0.0085838, -0.0049566),
                 (0.00031105, 0.00021549, 0.00035976, 1.4771e-6, -3.7074e-7, -8.4533e-6)),
}  # fmt: skip
YOUBOT_INERTIALS = {
    "arm_link_1": (1.390, (0.01489, 0.00213, 0.00213), (0.0029525, 0.0060091, 0.0058821, 0, 0, 0)),
    "arm_link_2": (1.318, (0.01053, -0.0307, 0.08597), (0.0031145, 0.0005843, 0.0031631, 0, 0, 0)),
    "arm_link_3": (0.821, (0.0001, 0.0207, 0.07107), (0.00172767, 0.00041967, 0.0018468, 0, 0, 0)),
    "arm_link_4": (0.769, (0.00011, -0.02, 0.05019), (0.0006764, 0.0010573, 0.000661, 0, 0, 0)),
    "arm_link_5": (0.687, (0, 0.00115, -0.01683), (0.0001934, 0.0001602, 0.0000689, 0, 0, 0)),
}  # fmt: skip


@pytest.mark.parametrize(
    ("name", "table"), [("sawyer", SAWYER_INERTIALS), ("youbot", YOUBOT_INERTIALS)]
)
def test_urdf_inertials_match_the_fact_sheet(name, table):
    import xml.etree.ElementTree as ET
    from importlib import resources

    root = ET.fromstring((resources.files("optraj.robots") / "urdf" / f"{name}.urdf").read_text())
    for link_name, (mass, com, inertia) in table.items():
        inertial = root.find(f"link[@name='{link_name}']/inertial")
        assert float(inertial.find("mass").get("value")) == mass
        np.testing.assert_array_equal(
            [float(v) for v in inertial.find("origin").get("xyz").split()], com
        )
        got = inertial.find("inertia")
        keys = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
        np.testing.assert_array_equal([float(got.get(k)) for k in keys], inertia)
