import math

import numpy as np
import pytest

from optraj import physics, problems
from optraj.errors import InvalidInputError
from optraj.physics.scene import POOL_BALL_MASS, POOL_BALL_RADIUS
from optraj.robots.collision import CUE_TIP_RADIUS


@pytest.fixture(scope="module")
def shot(pool_shot):
    return pool_shot


@pytest.fixture(scope="module")
def scene(shot):
    return physics.scene_for(shot)


def _speed(record):
    return float(np.linalg.norm(record["launch"][:2]))


@pytest.mark.parametrize("lead", [2.3e-3, 3.7e-3, 6.1e-3])
def test_a_straight_cue_sends_the_ball_at_the_calibrated_ideal_speed(shot, scene, lead):
    # The ideal comes from a cue started 5 ms out; other run-ups start the contact at other
    # phases of the steps, and coarse steps hand over to fine ones at other points.
    outcome = physics.outcome(
        physics.straight_cue(scene, shot.direction, 1.0, run_up_time=lead), shot
    )
    assert outcome.hit and outcome.contacts == 1
    assert abs(outcome.speed_error) < 0.01
    assert abs(outcome.heading_error) < 0.05


@pytest.mark.parametrize("heading", [-35.0, 20.0])
def test_an_oblique_straight_cue_sends_the_ball_straight_along_its_line(heading):
    # With MuJoCo's default pyramidal friction cone the cloth pulled a sliding ball towards the
    # pyramid's edges: 0.09 deg off at 20 deg, then a curve 0.7 m wide. Elliptic cones: none.
    shot = problems.sawyer_pool_shot(1.0, heading_deg=heading)
    scene = physics.scene_for(shot)
    outcome = physics.outcome(physics.straight_cue(scene, shot.direction, 1.0), shot)
    assert abs(outcome.heading_error) < 0.005
    d = np.asarray(shot.direction)[:2]
    rel = outcome.roll[:, :2] - np.asarray(shot.ball)[:2]
    along, across = rel @ d, rel @ np.array([-d[1], d[0]])
    assert along.max() > 0.8
    first = int(np.argmax(along > 0.8))  # the first 0.8 m, short of any cushion
    assert first > 10
    assert np.abs(across[:first]).max() < 1e-4  # [m]


def test_a_lateral_offset_turns_the_ball_by_the_contact_geometry(shot, scene):
    offset = 1e-3
    record = physics.straight_cue(scene, shot.direction, 1.0, offset=(0.0, offset, 0.0))
    heading = physics.outcome(record, shot).heading_error
    expected = -math.degrees(math.asin(offset / (POOL_BALL_RADIUS + CUE_TIP_RADIUS)))
    assert heading == pytest.approx(expected, rel=0.05)


def test_a_lighter_cue_follows_the_effective_mass_law(shot, scene):
    # Newton's impact law: v_ball = (1 + e) m / (m + m_ball) v; e drops out of the ratio.
    heavy = _speed(physics.straight_cue(scene, shot.direction, 1.0, tool_mass=1000.0))
    light = _speed(physics.straight_cue(scene, shot.direction, 1.0, tool_mass=2.0))
    expected = (2.0 / (2.0 + POOL_BALL_MASS)) / (1000.0 / (1000.0 + POOL_BALL_MASS))
    assert light / heavy == pytest.approx(expected, rel=5e-3)
    assert 1.75 < heavy < 1.87  # restitution about 0.8


def test_the_plan_alone_puts_the_ball_on_its_line(shot, scene, pool_plan):
    outcome = physics.outcome(physics.replay(scene, pool_plan), shot)
    assert outcome.within
    assert abs(outcome.heading_error) < 0.05


def test_replay_checks_its_trajectory(scene):
    with pytest.raises(InvalidInputError, match=r"planners\.Trajectory"):
        physics.replay(scene, "plan")


def test_straight_cue_checks_its_input(scene):
    with pytest.raises(InvalidInputError, match="direction"):
        physics.straight_cue(scene, (0.0, 0.0, 0.0), 1.0)
    with pytest.raises(InvalidInputError, match="speed"):
        physics.straight_cue(scene, (1.0, 0.0, 0.0), -1.0)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda scene, shot: physics.replay(scene, None, settle="0.1"), "settle must be a numeric"),
        (lambda scene, shot: physics.replay(scene, None, settle=1e300), r"settle must be <= 10 s"),
        (lambda scene, shot: physics.straight_cue(scene, shot.direction, 1e308),
         r"speed must be <= 100 m/s"),
        (lambda scene, shot: physics.straight_cue(scene, shot.direction, 1.0, run_up_time=1e300),
         r"run_up_time must be <= 1 s"),
    ],
)  # fmt: skip
def test_extreme_times_and_speeds_are_refused(shot, scene, call, match):
    with pytest.raises(InvalidInputError, match=match):
        call(scene, shot)
