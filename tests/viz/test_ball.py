import dataclasses

import numpy as np
import pytest
from viz_support import pool_case, rolled_outcome

from optraj import physics
from optraj.viz.ball import ball_motion, ball_path, path_shapes, path_times
from optraj.viz.scene import build_scene


def test_ball_rests_until_contact_then_follows_the_roll():
    shot, _ = pool_case()
    outcome = rolled_outcome(shot, contact_time=1.0)
    _, times = path_times(outcome)
    assert np.all(np.diff(times) > 0.0)
    poses = ball_motion(outcome, np.array([0.0, 0.99, 1.0, times[-1], times[-1] + 5.0]))
    np.testing.assert_allclose(poses[:3, :3, 3], np.broadcast_to(shot.ball, (3, 3)))
    np.testing.assert_allclose(poses[3:, :3, 3], np.broadcast_to(outcome.roll[-1], (2, 3)))
    # The first roll-out point is reached at the launch speed (1 m/s over 0.02 m).
    np.testing.assert_allclose(times[1], 1.0 + 0.02, atol=1e-6)


def test_path_is_drawn_from_the_start_to_rest():
    shot, _ = pool_case()
    outcome = rolled_outcome(shot, contact_time=1.0)
    path = ball_path(outcome)
    np.testing.assert_allclose(path[0], shot.ball)
    np.testing.assert_allclose(path[-1], outcome.roll[-1])
    shapes = path_shapes(outcome)
    assert shapes and all(s.name.startswith("ball_path/") for s in shapes)


def test_a_missed_ball_stays_and_draws_no_path():
    shot, _ = pool_case()
    missed = dataclasses.replace(rolled_outcome(shot, 1.0), hit=False, contact_time=np.inf)
    assert path_shapes(missed) == []
    poses = ball_motion(missed, np.array([0.0, 10.0]))
    np.testing.assert_allclose(poses[:, :3, 3], np.broadcast_to(shot.ball, (2, 3)))


@pytest.mark.slow
def test_a_strike_run_through_mujoco_draws_the_ball_path_along_the_shot():
    shot, traj = pool_case()
    outcome = physics.outcome(physics.replay(physics.scene_for(shot), traj), shot)
    assert outcome.hit
    scene = build_scene(shot.robot, traj, shot, outcome, fps=10.0)
    path = [shape for shape in scene.shapes if shape.name.startswith("ball_path/")]
    assert path
    heading = shot.direction[:2] / np.linalg.norm(shot.direction[:2])
    for piece in path:  # every piece runs along the commanded heading (out and back off the
        # far cushion, where the ball hops a little), on the cloth
        across = piece.pose[:2, 2] / np.linalg.norm(piece.pose[:2, 2])
        np.testing.assert_allclose(abs(across @ heading), 1.0, atol=1e-3)
        np.testing.assert_allclose(piece.pose[2, 3], shot.ball[2], atol=1e-3)
    ball = scene.shape("ball")
    np.testing.assert_allclose(ball.motion[0][:3, 3], shot.ball, atol=1e-12)
    travelled = ball.motion[-1][:3, 3] - shot.ball
    assert travelled @ shot.direction > 0.1
