"""Signed distances robot-to-scene: analytic cases, coal itself, and refused configurations."""

from __future__ import annotations

import coal
import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from optraj.errors import CollisionError, InvalidInputError
from optraj.problems import AllowedPair, Box, Plane, Scene, SceneCollision, Sphere
from optraj.problems.scene_shapes import translation
from optraj.robots.collision import collision_model


def _placement(robot, name, q):
    """World placement of a robot shape: forward kinematics and its joint placement."""
    shapes = collision_model(robot)
    g = shapes.geometry.geometryObjects[shapes.geometry.getGeometryId(name)]
    data = robot.model.createData()
    pin.forwardKinematics(robot.model, data, np.asarray(q, dtype=float))
    return data.oMi[g.parentJoint] * g.placement, g.geometry


def _pair(found, first, second):
    return next(d for d in found if {d.first, d.second} == {first, second})


def test_sphere_to_plane_is_the_centre_height_less_the_radius():
    robot = get_robot("sawyer")
    M, tip = _placement(robot, "tool/tip", robot.home)
    normal = np.array([0.0, 0.6, 0.8])
    for gap in (0.03, -0.002):  # clear, then overlapping by 2 mm
        point = M.translation - (tip.radius + gap) * normal
        scene = Scene((Plane("wall", point, normal),))
        found = _pair(SceneCollision(robot, scene).distances(robot.home), "tool/tip", "wall")
        assert found.distance == pytest.approx(gap, abs=1e-9)
        witness = M.translation - tip.radius * normal
        np.testing.assert_allclose(found.point_first, witness, atol=1e-9)


def test_box_to_box_is_the_gap_between_parallel_faces():
    robot = get_robot("youbot")
    q = robot.home
    M, palm = _placement(robot, "tool/palm", q)
    half = palm.halfSide
    box_half = np.array([0.02, 0.03, 0.01])
    for gap in (0.015, 0.004):
        pose = np.eye(4)
        pose[:3, :3] = M.rotation
        pose[:3, 3] = M.translation + (half[0] + gap + box_half[0]) * M.rotation[:, 0]
        scene = Scene((Box("crate", box_half, pose),))
        found = _pair(SceneCollision(robot, scene).distances(q), "tool/palm", "crate")
        assert found.distance == pytest.approx(gap, abs=1e-7)


def test_capsule_to_sphere_beside_and_beyond_its_end():
    robot = get_robot("sawyer")
    q = robot.home
    M, capsule = _placement(robot, "link_4", q)
    axis, side = M.rotation[:, 2], M.rotation[:, 0]
    radius = 0.04
    beside = M.translation + (capsule.radius + 0.05 + radius) * side
    end = M.translation + capsule.halfLength * axis
    beyond = end + (capsule.radius + 0.02 + radius) * (0.6 * axis + 0.8 * side)
    for centre, expected in ((beside, 0.05), (beyond, 0.02)):
        scene = Scene((Sphere("ball", radius, translation(centre)),))
        found = _pair(SceneCollision(robot, scene).distances(q), "link_4", "ball")
        assert found.distance == pytest.approx(expected, abs=1e-9)


def test_every_pair_agrees_with_coal_on_random_configurations():
    robot = get_robot("youbot")
    scene = Scene(
        (
            Box("crate", (0.05, 0.04, 0.03), translation((0.25, 0.05, 0.1))),
            Sphere("ball", 0.03, translation((0.1, -0.2, 0.3))),
            Plane("ground", (0.0, 0.0, -0.04)),
        )
    )
    shapes = SceneCollision(robot, scene)
    objects = {item.name: item for item in scene.objects}
    rng = np.random.default_rng(7)
    lower, upper = robot.limits.lower, robot.limits.upper
    for _ in range(5):
        q = rng.uniform(lower, upper)
        for found in shapes.distances(q):
            M1, shape1 = _placement(robot, found.first, q)
            if found.second in objects:
                item = objects[found.second]
                M2, shape2 = pin.SE3(item.pose), item.shape()
            else:
                M2, shape2 = _placement(robot, found.second, q)
            request, result = coal.DistanceRequest(), coal.DistanceResult()
            expected = coal.distance(
                shape1,
                coal.Transform3s(M1.rotation, M1.translation),
                shape2,
                coal.Transform3s(M2.rotation, M2.translation),
                request,
                result,
            )
            # GJK pairs (cylinder, box) stop within coal's default tolerance, 1e-6
            assert found.distance == pytest.approx(expected, abs=1e-5), found[:2]


def test_a_configuration_inside_an_obstacle_is_refused_naming_the_pair():
    robot = get_robot("sawyer")
    M, _ = _placement(robot, "tool/tip", robot.home)
    scene = Scene((Sphere("post", 0.05, translation(M.translation)),))
    shapes = SceneCollision(robot, scene)
    with pytest.raises(CollisionError, match="goal is in collision") as caught:
        shapes.require_clear(robot.home, "goal")
    assert caught.value.second == "post" and caught.value.first.startswith("tool/")
    assert caught.value.distance < -0.04
    allowed = Scene(scene.objects, allowed=(AllowedPair("tool/*", "post"),))
    SceneCollision(robot, allowed).require_clear(robot.home, "goal")  # may touch: no error


def test_names_must_not_clash_and_q_must_fit():
    robot = get_robot("paddle4")
    with pytest.raises(InvalidInputError, match="link_2"):
        SceneCollision(robot, Scene((Sphere("link_2", 0.1),)))
    with pytest.raises(InvalidInputError, match="q"):
        SceneCollision(robot, Scene((Sphere("s", 0.1),))).distances([0.0, 0.0])
    with pytest.raises(InvalidInputError, match=r"problems\.Scene"):
        SceneCollision(robot, "table")
