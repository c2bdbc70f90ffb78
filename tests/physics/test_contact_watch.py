import mujoco
import numpy as np
import pytest

from optraj import physics, problems


@pytest.fixture(scope="module")
def world():
    shot = problems.sawyer_pool_shot(speed=1.0)
    return physics.scene_for(shot).as_kinematic().build()


def _placed(world, gap, speed):
    data = mujoco.MjData(world.model)
    ball = np.asarray(world.scene.ball)
    data.qpos[world.ball_qpos : world.ball_qpos + 3] = ball
    data.qpos[world.ball_qpos + 3 : world.ball_qpos + 7] = (1, 0, 0, 0)
    tip = ball - (world.scene.ball_radius + gap) * np.array([1.0, 0.0, 0.0])
    data.qpos[world.tool_qpos : world.tool_qpos + 3] = tip
    data.qpos[world.tool_qpos + 3 : world.tool_qpos + 7] = (0.5**0.5, 0, 0.5**0.5, 0)  # z -> +x
    data.qvel[world.tool_dof] = speed
    mujoco.mj_forward(world.model, data)
    return data


def test_fine_steps_start_within_the_lookahead(world):
    watch = physics.ContactWatch(world)
    speed = 1.0
    far = _placed(world, speed * physics.contact_watch.LOOKAHEAD + 0.01, speed)
    near = _placed(world, 0.5 * speed * physics.contact_watch.LOOKAHEAD, speed)
    assert not watch.near(far)
    assert watch.near(near)


def test_the_contact_is_recorded_once_with_the_launch(world):
    watch = physics.ContactWatch(world)
    data = _placed(world, 0.002, 1.0)
    watch.advance(data, 6e-3)
    record = watch.record()
    assert record["contacts"] == 1
    assert record["contact_end"] > record["contact_start"] > 0.0
    # Within 1e-4 (0.006 deg): the ball sinks into the soft cloth contact by a few microns.
    np.testing.assert_allclose(record["contact_normal"], [1.0, 0.0, 0.0], atol=1e-4)
    assert record["launch"][0] > 1.7
