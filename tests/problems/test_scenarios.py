"""Tests of problems.scenarios: the ready-made problems build and are what they say."""

from __future__ import annotations

import numpy as np
import pytest

from optraj import problems
from optraj.errors import InvalidInputError
from optraj.problems import scenarios
from optraj.problems.scenarios import block_clearance_scene


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


def test_two_blocks_with_their_scene():
    problem = problems.youbot_two_blocks(with_scene=True, margin=0.001)
    scene = problem.scene
    assert scene is not None and scene.margin == 0.001
    assert scene.names == ("block_0", "block_1", "work_surface")
    # The interim pose is the scene's, not the start pose, and the blocks are turned as the
    # gripper grips them in this very problem.
    assert not np.allclose(problem.q_interim, problem.q_start)
    for k in range(problem.count):
        block = scene.object(f"block_{k}").pose
        np.testing.assert_allclose(block[:3, 3], problem.picks[k], atol=1e-12)
        tool = problem.robot.tool_pose(problem.q_pick[k])
        np.testing.assert_allclose(block[:3, :3], tool[:3, :3], atol=1e-9)


def test_the_block_clearance_scene_allows_the_gripper_only_at_its_blocks():
    problem = problems.youbot_two_blocks(with_scene=True)
    blocks = block_clearance_scene(problem)
    assert blocks.margin == 0.02 and blocks.names == ("block_0", "block_1")
    assert [a.object for a in blocks.attachments] == ["block_0", "block_1"]
    assert blocks.always_allowed("link_3", "tool/palm")  # the robot itself: the problem's
    assert blocks.always_allowed("block_0", "block_1")
    assert not blocks.always_allowed("link_5", "block_0")
    assert blocks.sometimes_allowed("link_5", "block_0") is None
    held = ("descend", "grasp", "back_to_interim", "turn_to_target", "release", "retreat")
    under = ("release_1", "retreat_1")  # block 1 is put on block 0
    expected = (*(f"{p}_0" for p in held), *under)
    assert blocks.sometimes_allowed("tool/finger_left", "block_0") == expected
    with pytest.raises(InvalidInputError, match="needs a problem with a scene"):
        block_clearance_scene(problems.youbot_two_blocks())


def test_a_shot_over_a_table_raises_the_cue_and_starts_cue_up():
    shot = problems.sawyer_pool_shot(with_table=True)
    assert shot.scene is not None and shot.scene.margin == 0.01
    assert shot.direction[2] == pytest.approx(-np.sin(np.radians(scenarios.CUE_ELEVATION)))
    np.testing.assert_allclose(shot.q_start, scenarios.SAWYER_CUE_UP)
    level = problems.sawyer_pool_shot(with_table=True, elevation_deg=0.0)
    assert level.direction[2] == 0.0
    steep = problems.sawyer_pool_shot(elevation_deg=10.0)
    assert steep.scene is None and steep.direction[2] == pytest.approx(-np.sin(np.radians(10)))
    with pytest.raises(InvalidInputError, match="with_table must be a bool"):
        problems.sawyer_pool_shot(with_table=1)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="elevation_deg"):
        problems.sawyer_pool_shot(elevation_deg=75.0)
    with pytest.raises(InvalidInputError, match="margin"):
        problems.sawyer_pool_shot(with_table=True, margin=-0.01)
