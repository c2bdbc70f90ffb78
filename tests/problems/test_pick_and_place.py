"""Tests of problems.pick_and_place."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import CollisionError, InvalidInputError, UnreachableError
from optraj.problems import PickAndPlace, ToolContact, youbot_two_blocks
from optraj.problems.pick_and_place import highest_point
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


def test_without_a_scene_the_interim_pose_is_the_start_pose():
    task = problems.youbot_two_blocks()
    np.testing.assert_array_equal(task.q_interim, task.q_start)


def test_with_a_scene_the_interim_pose_clears_the_tallest_object_by_the_clearance():
    task = problems.youbot_two_blocks()
    scene = problems.pick_and_place_scene(task)
    chosen = dataclasses.replace(task, scene=scene, q_interim=None)
    # The pile under the last block tops out at -0.03 - 0.015 + 0.03 = -0.015 m, as high as
    # the blocks where they stand; a carried block hangs 0.015 m below the TCP, which passes
    # the clearance (0.05 m) above that.
    assert chosen.interim_height() == pytest.approx(-0.015 + 0.015 + 0.05, abs=1e-12)
    tcp = chosen.robot.tool_pose(chosen.q_interim)
    middle = np.mean([*task.picks, task.pile], axis=0)
    np.testing.assert_allclose(tcp[:3, 3], [*middle[:2], 0.05], atol=1e-6)
    np.testing.assert_allclose(tcp[:3, 2], task.approach, atol=1e-6)
    # A taller object raises it; replace keeps the resolved pose unless told to choose again.
    post = problems.Box("post", (0.01, 0.01, 0.02), translation((0.0, 0.3, -0.025)))
    taller = dataclasses.replace(scene, objects=(*scene.objects, post))
    kept = dataclasses.replace(chosen, scene=taller)
    np.testing.assert_array_equal(kept.q_interim, chosen.q_interim)
    again = dataclasses.replace(chosen, scene=taller, q_interim=None)
    assert again.interim_height() == pytest.approx(-0.005 + 0.015 + 0.05, abs=1e-12)


def test_an_interim_pose_out_of_reach_is_named():
    task = problems.youbot_two_blocks()
    tower = problems.Box("tower", (0.01, 0.01, 0.2), translation((0.0, 0.3, 0.0)))
    scene = problems.Scene((tower,))
    with pytest.raises(UnreachableError, match="the interim pose at"):
        dataclasses.replace(task, scene=scene, q_interim=None)


@pytest.mark.parametrize(("item", "top"), [
    (problems.Box("b", (0.1, 0.2, 0.3), translation((0, 0, 1.0))), 1.3),
    # Turned 90 deg about x: its y half-extent stands up.
    (problems.Box("b", (0.1, 0.2, 0.3), np.array(
        [[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 1.0], [0, 0, 0, 1]], dtype=float)), 1.2),
    (problems.Sphere("s", 0.25, translation((1, 2, 3))), 3.25),
    (problems.Cylinder("c", 0.1, 0.5, translation((0, 0, 1.0))), 1.5),
    # Lying along x: its radius is its top.
    (problems.Cylinder("c", 0.1, 0.5, np.array(
        [[0, 0, 1, 0], [0, 1, 0, 0], [-1, 0, 0, 1.0], [0, 0, 0, 1]], dtype=float)), 1.1),
])  # fmt: skip
def test_highest_point_of_each_shape(item, top):
    assert highest_point(item) == pytest.approx(top, abs=1e-12)
