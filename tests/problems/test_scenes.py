"""Ready-made scenes: the pool table from the MuJoCo scene's numbers, the youBot's blocks."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from optraj import problems
from optraj.problems import scenes
from optraj.problems.scene_distances import SceneCollision


def test_the_cloth_top_is_the_ball_bottom_and_the_tip_may_touch_the_ball():
    ball = np.array([0.75, 0.15, -0.05])
    table = problems.pool_table(ball, 0.028575)
    cloth = table.object("cloth")
    top = cloth.pose[2, 3] + cloth.half_extents[2]
    assert top == pytest.approx(-0.05 - 0.028575, abs=1e-12)
    near = table.object("cushion_near")
    assert near.pose[0, 3] + near.half_extents[0] == pytest.approx(0.75 - 0.635)  # head string
    assert near.half_extents[2] * 2 == pytest.approx(scenes.CUSHION_HEIGHT)
    np.testing.assert_allclose(table.object("ball").pose[:3, 3], ball)
    assert table.always_allowed("tool/tip", "ball") and table.always_allowed("tool/cue", "ball")
    assert not table.always_allowed("link_7", "ball")
    assert table.object("floor").point[2] == scenes.SAWYER_FLOOR


def test_the_blocks_stand_on_the_work_surface_where_they_are_gripped():
    task = problems.youbot_two_blocks()
    scene = problems.pick_and_place_scene(task)
    assert scene.names == ("block_0", "block_1", "work_surface")
    for k in range(2):
        block = scene.object(f"block_{k}")
        np.testing.assert_allclose(block.pose[:3, 3], task.picks[k])
        bottom = task.picks[k][2] - task.block_height / 2
        assert scene.object("work_surface").point[2] == pytest.approx(bottom)
        assert scene.attachments[k].start == f"grasp_{k}"
        assert scene.sometimes_allowed("tool/palm", f"block_{k}")[0] == f"descend_{k}"
    # at the grip the fingers straddle the block, clear of it (1.5 mm each side)
    shapes = SceneCollision(task.robot, dataclasses.replace(scene, allowed=()))
    found = [d for d in shapes.distances(task.q_pick[0]) if d.second == "block_0"]
    assert min(d.distance for d in found) == pytest.approx(0.0015, abs=2e-4)


def test_the_floor_is_a_half_space_below_the_base():
    plane = problems.floor(scenes.YOUBOT_FLOOR)
    assert plane.point[2] == pytest.approx(-0.1275) and plane.normal[2] == 1.0
