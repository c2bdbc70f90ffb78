import dataclasses

import numpy as np
import pytest

from optraj import controllers, physics, planners, problems
from optraj.errors import InvalidInputError
from optraj.planners.ocp.clearance import Clearance


def _track(shot, plan, scene=None, **options):
    robot = shot.robot
    plant = physics.MujocoPlant(scene or physics.scene_for(shot))
    result = controllers.simulate(robot, plan, controllers.DiffIKQP(robot), plant=plant, **options)
    return physics.outcome(result, shot)


def test_a_tracked_pool_shot_sends_the_ball_on_its_line(pool_shot, pool_plan):
    outcome = _track(pool_shot, pool_plan)
    assert outcome.hit and outcome.contacts == 1
    assert outcome.within
    assert abs(outcome.heading_error) < 0.1
    assert 1.5 < outcome.effective_mass < 3.0  # Sawyer's cue tip, about 2 kg
    # the ball rolls out along +x and stays on the table
    assert outcome.rest_position[0] > pool_shot.ball[0]
    assert abs(outcome.rest_position[2] - pool_shot.ball[2]) < 1e-3
    # the roll-out ends where the ball rests, from where the run left it
    np.testing.assert_array_equal(outcome.roll[-1], outcome.rest_position)
    np.testing.assert_allclose(outcome.roll[0], outcome.path[-1])
    np.testing.assert_array_equal(outcome.start, pool_shot.ball)
    np.testing.assert_array_equal(outcome.direction, pool_shot.direction)


@pytest.mark.slow
def test_outcomes_are_deterministic_for_a_seed(pool_shot, pool_plan):
    a = _track(pool_shot, pool_plan, noise=controllers.Noise(seed=4))
    b = _track(pool_shot, pool_plan, noise=controllers.Noise(seed=4))
    assert a.heading_error == b.heading_error
    np.testing.assert_array_equal(a.launch_velocity, b.launch_velocity)


def test_a_ball_that_is_never_touched_is_a_miss(pool_shot, pool_plan):
    elsewhere = physics.scene_for(pool_shot).with_ball(
        np.asarray(pool_shot.ball) + np.array([0.0, 0.2, 0.0])
    )
    outcome = _track(pool_shot, pool_plan, scene=elsewhere)
    assert not outcome.hit and not outcome.within
    assert outcome.heading_error == np.inf
    assert "missed" in outcome.summary()
    np.testing.assert_array_equal(outcome.roll, [outcome.start])  # it never moved


def test_outcome_needs_a_mujoco_record(pool_shot, pool_plan):
    result = controllers.simulate(pool_shot.robot, pool_plan, controllers.DiffIKQP(pool_shot.robot))
    with pytest.raises(InvalidInputError, match="MujocoPlant"):
        physics.outcome(result, pool_shot)


def test_a_paddle_strike_leaves_along_the_paddle_normal():
    paddle = problems.PaddleStrike(
        problems.ece486_paddle_strike().robot, ball=(0.8, 0.2, 0.3), speed=0.5
    )
    plan = planners.OptimalControl("time").plan(
        dataclasses.replace(paddle, limits=paddle.robot.limits.scaled(0.8))
    )
    result = controllers.simulate(
        paddle.robot,
        plan,
        controllers.DiffIKQP(paddle.robot),
        plant=physics.MujocoPlant(physics.scene_for(paddle)),
    )
    outcome = physics.outcome(result, paddle)
    assert outcome.hit
    assert outcome.heading_error < 0.5


@pytest.mark.slow
@pytest.mark.parametrize("elevation", [4.0, 8.0])
def test_a_raised_cue_over_the_table_sends_the_ball_along_its_heading(elevation):
    # The cue tilted down through the ball's centre: the cloth takes the downward push, the
    # ball leaves along the heading at the ideal speed of a cue coasting down the same line
    # (measured: heading 0.000 deg; speed +0.4 % at 4 deg, +1.0 % at 8 deg).
    shot = problems.sawyer_pool_shot(1.0, with_table=True, elevation_deg=elevation)
    plan = planners.OptimalControl(clearance=Clearance(shoulder=False)).plan(shot)
    result = physics.outcome(physics.replay(physics.scene_for(shot), plan), shot)
    assert result.hit and result.within, result
    assert abs(result.heading_error) < 0.05
    assert planners.check(plan, shot)["clearance"].ok  # the arm 1 cm clear of the whole table
