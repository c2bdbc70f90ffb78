import dataclasses

import numpy as np
import pytest
from viz_support import paddle_case, pool_case, youbot_case

from optraj import physics, problems
from optraj.problems.scene_shapes import translation
from optraj.viz.tasks import (
    ball_shape,
    paddle_shapes,
    pile_shape,
    pool_shapes,
    static_scene,
    task_objects,
)


def _names(shapes):
    return {shape.name for shape in shapes}


@pytest.fixture(scope="module")
def pool():
    return pool_case()


@pytest.fixture(scope="module")
def youbot():
    return youbot_case()


def test_pool_table_cloth_is_under_the_ball_and_the_strike_line_is_the_shot(pool):
    shot, traj = pool
    times = np.linspace(0.0, traj.duration, 5)
    shapes = task_objects(shot, shot.robot, traj, times, -0.914) + pool_shapes(shot, -0.914)
    assert {"table/cloth", "table/cushion_near", "strike_line", "table/leg_0"} <= _names(shapes)
    assert "floor" not in _names(shapes) and "ball" not in _names(shapes)  # drawn elsewhere
    cloth = next(s for s in shapes if s.name == "table/cloth")
    np.testing.assert_allclose(
        cloth.pose[2, 3] + cloth.size[2] / 2, shot.ball[2] - shot.ball_radius, atol=1e-12
    )
    line = next(s for s in shapes if s.name == "strike_line")
    length = line.size[1]
    start = line.pose @ np.array([0.0, 0.0, -length / 2, 1.0])
    np.testing.assert_allclose(start[:3], shot.entry_point, atol=1e-12)
    np.testing.assert_allclose(line.pose[:3, 2], shot.direction, atol=1e-12)
    legs = [s for s in shapes if s.name.startswith("table/leg_")]
    for leg in legs:  # legs stand on the floor
        np.testing.assert_allclose(leg.pose[2, 3] - leg.size[2] / 2, -0.914, atol=1e-12)


def test_the_viewer_draws_the_mujoco_worlds_table(pool):
    shot, traj = pool
    drawn = {s.name: s for s in task_objects(shot, shot.robot, traj, np.zeros(1), -0.914)}
    model = physics.scene_for(shot).build().model
    for name in ("cloth", "cushion_far", "cushion_near", "cushion_left", "cushion_right"):
        shape = drawn[f"table/{name}"]
        np.testing.assert_array_equal(np.asarray(shape.size), 2 * model.geom(name).size)
        np.testing.assert_array_equal(shape.pose[:3, 3], model.geom(name).pos)


def test_a_problems_own_scene_replaces_the_ready_made_table(pool):
    shot, traj = pool
    post = problems.Cylinder("post", 0.03, 0.2, translation((1.5, -0.4, 0.0)))
    mine = dataclasses.replace(shot, scene=problems.Scene((post,)))
    (shape,) = task_objects(mine, mine.robot, traj, np.zeros(1), -0.914)
    assert shape.name == "post"
    assert pool_shapes(mine, -0.914)[0].name == "strike_line"  # no cloth: no apron


def test_paddle_heading_and_ball():
    problem, traj = paddle_case()
    (heading,) = paddle_shapes(problem)
    np.testing.assert_allclose(heading.pose[:3, 2], problem.normal, atol=1e-12)
    ball = ball_shape(problem, None)
    np.testing.assert_allclose(ball.pose[:3, 3], problem.ball)
    assert ball.motion is None
    assert static_scene(problem) is None
    assert task_objects(problem, problem.robot, traj, np.zeros(1), -0.35) == []


def test_blocks_wait_ride_with_the_gripper_and_land_on_the_pile(youbot):
    problem, traj = youbot
    times = np.linspace(0.0, traj.duration, 400)
    shapes = {s.name: s for s in task_objects(problem, problem.robot, traj, times, -0.2)}
    assert {"block_0", "block_1", "work_surface"} <= set(shapes)
    assert pile_shape(problem).name == "pile"
    scene = problems.pick_and_place_scene(problem)
    for k in range(problem.count):
        block = scene.object(f"block_{k}")
        assert shapes[f"block_{k}"].size == tuple(2 * block.half_extents)
        motion = shapes[f"block_{k}"].motion
        assert motion is not None and motion.shape == (len(times), 4, 4)
        grasp = traj.phase(f"grasp_{k}")
        release = traj.phase(f"release_{k}")
        before = times < grasp.t_start
        np.testing.assert_array_equal(
            motion[before], np.broadcast_to(block.pose, (sum(before), 4, 4))
        )
        np.testing.assert_allclose(motion[-1][:3, 3], problem.place_point(k), atol=1e-5)
        during = (times > grasp.t_end) & (times < release.t_start)
        tool = problem.robot.tool_pose(traj.sample(times[during]).q)
        held = np.linalg.solve(tool, motion[during])  # the block in the tool frame
        np.testing.assert_allclose(held, np.broadcast_to(held[0], held.shape), atol=1e-9)
        assert np.ptp(motion[during][:, 0, 3]) > 0.01  # and carried
