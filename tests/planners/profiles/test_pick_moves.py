"""Tests of planners.profiles.pick_moves: vertical lines, their profile, the collision guard."""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

from optraj import problems
from optraj.errors import CollisionError
from optraj.planners.checker import check
from optraj.planners.profiles.lspb import LSPB
from optraj.planners.profiles.pick_moves import line_profile, require_clear, vertical_line
from optraj.planners.profiles.sequencer import PickAndPlacePlanner
from optraj.planners.profiles.time_scaling import Cubic, Quintic


def test_the_line_profile_follows_the_joint_profile():
    assert [line_profile(p) for p in (Cubic(), Quintic(), LSPB())] == ["cubic", "quintic", "lspb"]


def test_a_vertical_line_holds_the_orientation_and_ends_on_the_point():
    task = problems.youbot_two_blocks()
    robot = task.robot
    line = vertical_line(task, task.q_above_pick[1], task.picks[1], "quintic")
    start = robot.tool_pose(task.q_above_pick[1])
    times = np.linspace(0.0, line.duration, 51)
    poses = [robot.tool_pose(q) for q in line.sample(times).q]
    for pose in poses:
        np.testing.assert_allclose(pose[:2, 3], task.picks[1][:2], atol=1e-7)
        assert np.linalg.norm(pin.log3(start[:3, :3].T @ pose[:3, :3])) < 1e-6
    np.testing.assert_allclose(poses[-1][:3, 3], task.picks[1], atol=1e-9)
    assert check(line, task.robot).ok  # within the joint limits
    np.testing.assert_allclose(line.sample([0.0, line.duration]).qd, 0.0, atol=1e-12)


def test_without_a_scene_the_guard_has_nothing_to_check():
    task = problems.youbot_two_blocks()
    require_clear(PickAndPlacePlanner().plan(task), task)


def test_the_guard_names_the_finger_dragged_through_a_put_down_block():
    # The joint-space plan sweeps the left finger through block 0 on its way back to the
    # interim pose (phase interim_1): the guard refuses it, naming the pair and the phase.
    task = problems.youbot_two_blocks()
    traj = PickAndPlacePlanner(Quintic()).plan(task)
    task = dataclasses.replace(task, scene=problems.pick_and_place_scene(task))
    with pytest.raises(CollisionError, match="'tool/finger_left' overlaps 'block_0'") as caught:
        require_clear(traj, task)
    assert "(interim_1)" in caught.value.what
    assert caught.value.distance == pytest.approx(-0.0018, abs=3e-4)
