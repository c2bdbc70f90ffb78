"""Tests of optraj.cli_problems: the command line's problems built from JSON-able options."""

from __future__ import annotations

import numpy as np
import pytest

from optraj import problems
from optraj.cli_problems import PROBLEMS, build_problem, check_fit, joint_words
from optraj.errors import InvalidInputError, UnknownNameError


def test_each_problem_is_built_for_its_robot_with_the_options_given():
    shot = build_problem("sawyer", "pool-shot", {"speed": 0.5, "heading": 10.0})
    assert isinstance(shot, problems.PoolStrike) and shot.speed == 0.5
    assert np.degrees(np.arctan2(shot.direction[1], shot.direction[0])) == pytest.approx(10.0)
    paddle = build_problem("paddle4", "paddle-strike", {"ball": [1.1, -0.8, 0.7]})
    assert np.allclose(paddle.ball, [1.1, -0.8, 0.7])
    assert isinstance(build_problem("youbot", "pick-and-place", {}), problems.PickAndPlace)
    move = build_problem("paddle4", "point-to-point", {"q_goal": [0.5, 0.1, 0.2, 0.0]})
    assert np.allclose(move.q_goal, [0.5, 0.1, 0.2, 0.0]) and move.duration is None


def test_a_limit_scale_scales_every_limit_and_none_means_the_default():
    move = build_problem(
        "paddle4", "point-to-point", {"q_goal": [0.5, 0.1, 0.2, 0.0], "limit_scale": 0.5}
    )
    assert np.allclose(move.limits.velocity, 0.5 * move.robot.limits.velocity)
    shot = build_problem("sawyer", "pool-shot", {"speed": None})
    assert shot.speed == 1.0


def test_pose_names_and_numbers_are_joint_positions():
    assert joint_words(["home"], "--q-goal") == "home"
    assert joint_words(["0.5", "1"], "--q-goal") == [0.5, 1.0]
    assert joint_words(["0.5,1", "2"], "--q-goal") == [0.5, 1.0, 2.0]
    assert joint_words(["0.5 1"], "--q-goal") == [0.5, 1.0]
    with pytest.raises(InvalidInputError, match="one pose name"):
        joint_words(["a", "b"], "--q-goal")
    move = build_problem("sawyer", "point-to-point", {"q_goal": "home", "duration": 1.0})
    assert np.allclose(move.q_goal, move.robot.home)


def test_bad_names_robots_and_options_are_refused_with_what_fits():
    with pytest.raises(UnknownNameError, match="pool-shot"):
        check_fit("sawyer", "pool")
    with pytest.raises(InvalidInputError, match=r"is for robot 'sawyer'.*point-to-point"):
        check_fit("paddle4", "pool-shot")
    with pytest.raises(InvalidInputError, match="--speed"):
        build_problem("sawyer", "pool-shot", {"speed": "fast"})
    with pytest.raises(InvalidInputError, match="goal equals the start"):
        build_problem("sawyer", "point-to-point", {})
    with pytest.raises(InvalidInputError, match="needs 4 values"):
        build_problem("paddle4", "point-to-point", {"q_goal": [0.1]})
    with pytest.raises(InvalidInputError, match="mapping"):
        build_problem("sawyer", "pool-shot", [("speed", 1.0)])
    assert set(PROBLEMS) == {"pool-shot", "paddle-strike", "pick-and-place", "point-to-point"}
