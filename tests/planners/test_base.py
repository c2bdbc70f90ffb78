"""Tests of planners.base: the shared planner face."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import InvalidInputError
from optraj.planners.base import JointProfile, Planner
from optraj.planners.profiles.time_scaling import Cubic, Quintic


def test_profiles_are_planners_and_stamp_metadata():
    robot = get_robot("paddle4")
    problem = problems.PointToPoint(robot, robot.home, [0.6, 0.2, 0.3, 0.1])
    for profile in (Cubic(), Quintic()):
        assert isinstance(profile, Planner) and isinstance(profile, JointProfile)
        traj = profile.plan(problem)
        assert traj.metadata["planner"] == profile.name
        assert traj.metadata["status"] == "ok" and traj.metadata["solve_time"] > 0.0
        assert traj.joint_names == robot.joint_names
        assert [p.name for p in traj.phases] == ["move"]


def test_move_validates_its_inputs():
    limits = get_robot("paddle4").limits
    with pytest.raises(InvalidInputError, match=r"q_goal must have shape \(4,\)"):
        Cubic().move(np.zeros(4), np.zeros(3), limits)
    with pytest.raises(InvalidInputError, match=r"duration must be >= 1e-06 s, got -1 s"):
        Cubic().move(np.zeros(4), np.zeros(4), limits, duration=-1.0)
