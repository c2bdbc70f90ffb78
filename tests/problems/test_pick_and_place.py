"""Tests of problems.pick_and_place."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import CollisionError, InvalidInputError, UnreachableError
from optraj.problems import PickAndPlace, ToolContact, youbot_two_blocks
from optraj.problems.scene_shapes import translation


def test_ik_solutions_put_the_gripper_on_each_block_and_the_pile():
    problem = youbot_two_blocks()
    robot = problem.robot
    for k in range(problem.count):
        for q, point in (
            (problem.q_pick[k], problem.picks[k]),
            (problem.q_place[k], problem.place_point(k)),
            (problem.q_above_pick[k], problem.picks[k] + [0, 0, problem.clearance]),
        ):
            T = robot.tool_pose(q)
            np.testing.assert_allclose(T[:3, 3], point, atol=1e-8)
            np.testing.assert_allclose(T[:3, 2], [0.0, 0.0, -1.0], atol=1e-8)
    np.testing.assert_allclose(problem.place_point(1) - problem.place_point(0), [0, 0, 0.03])
    contacts = [c for c in problem.constraints() if isinstance(c, ToolContact)]
    assert [c.label for c in contacts[:3]] == [
        "grasp 0 (start)",
        "grasp 0 (end)",
        "release 0 (end)",
    ]


def test_unreachable_block_names_it():
    message = r"above pick 1 at \(0.9, 0, 0.02\) m is out of reach"
    with pytest.raises(UnreachableError, match=message):
        PickAndPlace(
            get_robot("youbot"),
            picks=[(0.22, 0.1, -0.03), (0.9, 0.0, -0.03)],
            pile=(0.12, 0.14, -0.03),
        )


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"picks": np.zeros((0, 3))}, "at least one block"),
        ({"block_height": 0.0}, "block_height must be > 0 m"),
        ({"block_height": "0.05"}, "block_height must be a numeric"),
        ({"grasp_time": 1e200}, "grasp_time must be <= 86400 s, got 1e[+]200 s"),
        ({"grasp_time": 1e-200}, "grasp_time must be >= 1e-06 s"),
        ({"approach": (0, 0, 0)}, "non-zero direction"),
        ({"pile": (0.1, 0.1)}, r"shape \(3,\)"),
    ],
)
def test_bad_values(kwargs, match):
    fields = {
        "robot": get_robot("youbot"),
        "picks": [(0.22, 0.1, -0.03)],
        "pile": (0.12, 0.14, -0.03),
    }
    fields.update(kwargs)
    with pytest.raises(InvalidInputError, match=match):
        PickAndPlace(**fields)


def test_a_scene_is_optional_and_a_clear_one_is_kept():
    task = problems.youbot_two_blocks()
    assert task.scene is None
    scene = problems.pick_and_place_scene(task)
    assert dataclasses.replace(task, scene=scene).scene is scene


def test_a_grip_inside_an_obstacle_is_refused_naming_the_pair():
    task = problems.youbot_two_blocks()
    post = problems.Box("post", (0.02, 0.02, 0.05), translation(task.picks[1]))
    scene = problems.Scene((post,))
    with pytest.raises(CollisionError, match="'post'") as caught:
        dataclasses.replace(task, scene=scene)
    assert caught.value.what == "above pick 1" and caught.value.second == "post"
