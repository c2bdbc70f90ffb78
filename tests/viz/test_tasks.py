import numpy as np
from viz_support import paddle_case, pool_case, youbot_case

from optraj.viz.tasks import ball_shape, block_shapes, paddle_shapes, pool_shapes


def _names(shapes):
    return {shape.name for shape in shapes}


def test_pool_table_cloth_is_under_the_ball_and_the_strike_line_is_the_shot():
    shot, _ = pool_case()
    shapes = pool_shapes(shot, floor=-0.914)
    assert {"table/cloth", "table/cushion_near", "strike_line", "table/leg_0"} <= _names(shapes)
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


def test_paddle_heading_and_ball():
    problem, _ = paddle_case()
    (heading,) = paddle_shapes(problem)
    np.testing.assert_allclose(heading.pose[:3, 2], problem.normal, atol=1e-12)
    ball = ball_shape(problem, None)
    np.testing.assert_allclose(ball.pose[:3, 3], problem.ball)
    assert ball.motion is None


def test_blocks_wait_ride_with_the_gripper_and_land_on_the_pile():
    problem, traj = youbot_case()
    times = np.linspace(0.0, traj.duration, 400)
    shapes = {s.name: s for s in block_shapes(problem, problem.robot, traj, times)}
    assert {"block_0", "block_1", "pile"} <= set(shapes)
    for k in range(problem.count):
        motion = shapes[f"block_{k}"].motion
        assert motion is not None and motion.shape == (len(times), 4, 4)
        grasp = traj.phase(f"grasp_{k}")
        release = traj.phase(f"release_{k}")
        np.testing.assert_allclose(
            motion[times < grasp.t_start][:, :3, 3],
            np.broadcast_to(problem.picks[k], (np.sum(times < grasp.t_start), 3)),
        )
        np.testing.assert_allclose(motion[-1][:3, 3], problem.place_point(k), atol=1e-5)
        during = (times > grasp.t_end) & (times < release.t_start)
        tool = problem.robot.tool_position(traj.sample(times[during]).q)
        gap = np.linalg.norm(motion[during][:, :3, 3] - tool, axis=1)
        np.testing.assert_allclose(gap, gap[0], atol=1e-5)  # rigidly held
        assert np.ptp(motion[during][:, 0, 3]) > 0.01  # and carried
