"""Tests of planners.profiles.via_points: the ViaPoints planner, its profiles and its errors."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import InfeasibleError, InvalidInputError, UnknownNameError
from optraj.planners.profiles.via_points import PROFILES, ViaPoints

QUANTITIES = ("position", "velocity", "acceleration")


# -------------------------------------------------------------------------- errors


@pytest.mark.parametrize("profile", PROFILES)
def test_too_short_segment_durations_name_joint_segment_and_limit(profile):
    robot = get_robot("paddle4")
    points = [[0.1, 0, 0.1, 0], [0.5, 1, 0.5, 0.5], [0.9, -1, 0.2, 0], [0.3, 0.5, 0.6, 0.2]]
    problem = problems.Waypoints(robot, points, segment_durations=[0.5, 0.5, 0.5])
    with pytest.raises(InfeasibleError, match=r"(segment|via point) \d.*joint 'J\d'") as info:
        ViaPoints(profile).plan(problem)
    error = info.value
    assert error.joint in robot.joint_names
    assert error.required > error.allowed
    assert f"{error.allowed:.6g}" in str(error) and f"{error.required:.6g}" in str(error)


def test_unknown_profile_lists_the_valid_ones():
    with pytest.raises(UnknownNameError, match="known: lspb, quintic") as info:
        ViaPoints("cubic")
    assert info.value.known == PROFILES


def test_bad_arguments_and_problems():
    robot = get_robot("paddle4")
    with pytest.raises(InvalidInputError, match=r"plans a problems\.Waypoints, got PointToPoint"):
        ViaPoints().plan(problems.PointToPoint(robot, [0.1, 0, 0, 0], [0.2, 0, 0, 0]))
    with pytest.raises(InvalidInputError, match="blend_time applies to profile 'lspb' only"):
        ViaPoints("quintic", blend_time=0.2)
    with pytest.raises(InvalidInputError, match="blend_time must be >= 1e-06 s, got 0 s"):
        ViaPoints("lspb", blend_time=0.0)
    same = [[0.1, 0, 0, 0]] * 3
    for profile in PROFILES:
        with pytest.raises(InvalidInputError, match="give segment_durations to hold still"):
            ViaPoints(profile).plan(problems.Waypoints(robot, same))
        held = ViaPoints(profile).plan(problems.Waypoints(robot, same, segment_durations=[1, 2]))
        assert held.duration == pytest.approx(3.0)
        sample = held.sample(held.times(100))
        np.testing.assert_allclose(sample.q, np.broadcast_to(same[0], sample.q.shape), atol=1e-15)


def test_blend_time_is_a_duration():
    # issue 32, defect 6: float("0.2") took text for a number
    with pytest.raises(InvalidInputError, match="blend_time must be a numeric"):
        ViaPoints("lspb", blend_time="0.2")
    with pytest.raises(InvalidInputError, match="blend_time must be <= 86400 s"):
        ViaPoints("lspb", blend_time=1e200)


def test_waypoints_within_the_still_tolerance_are_refused_without_durations():
    # issue 32, defect 8: one rule with PointToPoint (exact equality was refused, 1e-13 not)
    robot = get_robot("paddle4")
    same = [[0.1, 0, 0, 0], [0.1 + 1e-13, 0, 0, 0], [0.1, 0, 0, 0]]
    for profile in PROFILES:
        with pytest.raises(InvalidInputError, match="every waypoint equals the first"):
            ViaPoints(profile).plan(problems.Waypoints(robot, same))
