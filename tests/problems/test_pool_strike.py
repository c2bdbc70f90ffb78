"""Tests of problems.pool_strike."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import CollisionError, InvalidInputError, UnreachableError
from optraj.problems import POOL_BALL_RADIUS, PoolStrike, StrikeLine
from optraj.problems.pool_strike import MAX_WINDOW


def test_geometry_and_timing_of_the_strike():
    robot = get_robot("sawyer")
    problem = PoolStrike(robot, ball=(0.75, 0.15, -0.05), direction=(2.0, 0.0, 0.0), speed=1.2)
    np.testing.assert_allclose(problem.direction, [1.0, 0.0, 0.0])
    np.testing.assert_allclose(problem.contact_point, [0.75 - POOL_BALL_RADIUS, 0.15, -0.05])
    np.testing.assert_allclose(
        problem.entry_point - problem.contact_point, [-0.10, 0, 0], atol=1e-15
    )
    np.testing.assert_allclose(problem.exit_point - problem.contact_point, [0.05, 0, 0], atol=1e-15)
    assert problem.window == pytest.approx(0.15 / 1.2)
    assert problem.contact_delay == pytest.approx(0.10 / 1.2)
    # The IK hint puts the cue tip on the contact point along the direction.
    T = robot.tool_pose(problem.q_contact)
    np.testing.assert_allclose(T[:3, 3], problem.contact_point, atol=1e-8)
    np.testing.assert_allclose(T[:3, 2], problem.direction, atol=1e-8)
    line = problem.constraints()[1]
    assert isinstance(line, StrikeLine) and line.phase == "strike"
    assert line.position_tolerance == 1e-5 and line.speed_tolerance == 1e-3
    np.testing.assert_array_equal(line.entry_point, problem.entry_point)  # to the last bit


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"speed": 0.0}, InvalidInputError, "speed must be > 0 m/s"),
        # A speed of 1e308 m/s is refused before it overflows the maths; text is no number.
        ({"speed": 1e308}, InvalidInputError, "speed must be <= 343 m/s, got 1e[+]308 m/s"),
        ({"speed": "1.0"}, InvalidInputError, "speed must be a numeric"),
        ({"speed": True}, InvalidInputError, "speed must be a numeric"),
        ({"speed": 1e-300}, InvalidInputError, r"last 1\.5e\+299 s, .* speed must be >= 0\.0025"),
        ({"direction": (0.0, 0.0, 0.0)}, InvalidInputError, "non-zero direction"),
        ({"ball": (0.7, np.inf, 0.0)}, InvalidInputError, "finite"),
        ({"run_up": 0.0, "follow_through": 0.0}, InvalidInputError, "needs a window"),
        ({"run_up": -0.1}, InvalidInputError, "run_up must be >= 0 m"),
        ({"run_up": 1e308}, InvalidInputError, "run_up must be <= 20580 m"),
        (
            {"run_up": 2e4, "follow_through": 2e4},
            InvalidInputError,
            "run_up [+] follow_through = 40000 m must be <= 20580 m",
        ),
        ({"position_tolerance": np.nan}, InvalidInputError, "position_tolerance must be finite"),
        ({"speed_tolerance": 0.0}, InvalidInputError, "speed_tolerance must be > 0"),
        ({"angle_tolerance": "x"}, InvalidInputError, "angle_tolerance must be a numeric"),
        ({"ball": (3.0, 0.0, 0.0)}, UnreachableError, "no configuration"),
    ],
)
def test_bad_strikes_raise_typed_errors(kwargs, error, match):
    fields = {
        "robot": get_robot("sawyer"),
        "ball": (0.75, 0.15, -0.05),
        "direction": (1, 0, 0),
        "speed": 1.0,
    }
    fields.update(kwargs)
    with pytest.raises(error, match=match):
        PoolStrike(**fields)


def test_the_slowest_speed_a_refusal_names_is_accepted():
    # The refusal of a slower strike names 0.0025 m/s (0.15 m / MAX_WINDOW); at that speed the
    # window, 0.15000000000000002 / 0.0025, comes out a rounding above MAX_WINDOW.
    sawyer = get_robot("sawyer")
    with pytest.raises(InvalidInputError, match=r"speed must be >= 0\.0025 m/s"):
        PoolStrike(sawyer, ball=(0.75, 0.15, -0.05), direction=(1, 0, 0), speed=0.0024)
    problem = PoolStrike(sawyer, ball=(0.75, 0.15, -0.05), direction=(1, 0, 0), speed=0.0025)
    assert problem.window == pytest.approx(MAX_WINDOW, rel=1e-12)


def test_a_cue_in_the_table_is_refused_and_a_level_cue_keeps_no_arm_clear_of_it():
    shot = problems.sawyer_pool_shot()
    assert shot.scene is None
    table = problems.pool_table(shot.ball, shot.ball_radius)
    # A cue rising 30 deg through the ball: its butt is under the cloth on every IK branch.
    rising = (np.cos(np.radians(30.0)), 0.0, np.sin(np.radians(30.0)))
    with pytest.raises(CollisionError, match="strike contact") as caught:
        dataclasses.replace(shot, direction=rising, scene=table)
    assert caught.value.first.startswith("tool/") and caught.value.second == "cloth"
    # A level cue at the ball's height holds the wrist (capsules of 3 to 3.5 cm radius) 2.9
    # cm above the cloth: the cue is clear, every contact configuration's arm is not.
    level = dataclasses.replace(shot, scene=table)
    with pytest.raises(CollisionError, match="every contact configuration") as caught:
        planners.choose_contact(level)
    assert caught.value.first.startswith("link_") and caught.value.distance < 0.0
    assert caught.value.second in ("cloth", "cushion_near")
    # Raised 4 deg (the table scenario's default), a clear one is found.
    raised = problems.sawyer_pool_shot(with_table=True)
    assert raised.direction[2] == pytest.approx(-np.sin(np.radians(4.0)))
    choice = planners.choose_contact(raised)
    shapes = problems.SceneCollision(raised.robot, raised.scene)
    for q in (choice.q, choice.q_entry, choice.q_exit):
        assert shapes.distances(q)[0].distance >= raised.scene.margin == 0.01
    floor_only = problems.Scene((problems.floor(-0.914),))
    assert dataclasses.replace(shot, scene=floor_only).scene is floor_only
