"""Collision shapes of the shipped robots: names, radii shared with the viewer, allowed pairs."""

from __future__ import annotations

import coal
import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from optraj.errors import InvalidInputError
from optraj.robots import collision as rc


@pytest.mark.parametrize(
    ("name", "tool"),
    [
        ("sawyer", {"tool/cue", "tool/tip"}),
        ("youbot", {"tool/palm", "tool/finger_left", "tool/finger_right"}),
        ("paddle4", {"tool/blade"}),
    ],
)
def test_every_robot_has_capsule_links_and_its_tool(name, tool):
    robot = get_robot(name)
    shapes = rc.collision_model(robot)
    names = set(shapes.names)
    assert tool <= names
    sizes = rc.sizes_of(robot)
    for g in shapes.geometry.geometryObjects:
        if g.name.startswith("link_") and g.name != "link_1" and g.name != "link_tool":
            assert isinstance(g.geometry, coal.Capsule), g.name
            assert g.geometry.radius == sizes.radius(int(g.parentJoint)), g.name


def test_adjacent_links_are_allowed_and_distant_ones_are_not():
    shapes = rc.collision_model(get_robot("sawyer"))
    assert ("link_2", "link_3") in shapes.allowed
    assert ("link_7", "tool/tip") in shapes.allowed
    assert ("link_2", "tool/tip") not in shapes.allowed
    names = shapes.names
    pairs = {(names[a], names[b]) for a, b in shapes.self_pairs()}
    assert ("link_2", "tool/tip") in pairs and ("link_2", "link_3") not in pairs


def test_no_pair_that_may_not_touch_overlaps_at_home():
    for name in ("sawyer", "youbot", "paddle4"):
        robot = get_robot(name)
        shapes = rc.collision_model(robot)
        geometry = shapes.geometry.copy()
        for a, b in shapes.self_pairs():
            geometry.addCollisionPair(pin.CollisionPair(a, b))
        data = pin.GeometryData(geometry)
        pin.computeDistances(robot.model, robot.model.createData(), geometry, data, robot.home)
        assert all(r.min_distance > 0.0 for r in data.distanceResults), name


def test_the_cue_tip_is_its_front_and_the_shaft_stays_behind_it():
    robot = get_robot("sawyer")
    shapes = rc.collision_model(robot)
    model, data = robot.model, robot.model.createData()
    geometry_data = pin.GeometryData(shapes.geometry)
    pin.updateGeometryPlacements(model, data, shapes.geometry, geometry_data, robot.home)
    T = robot.tool_pose(robot.home)
    tip = geometry_data.oMg[shapes.geometry.getGeometryId("tool/tip")]
    front = tip.translation + rc.CUE_TIP_RADIUS * T[:3, 2]
    np.testing.assert_allclose(front, T[:3, 3], atol=1e-12)
    cue = shapes.geometry.geometryObjects[shapes.geometry.getGeometryId("tool/cue")].geometry
    shaft = geometry_data.oMg[shapes.geometry.getGeometryId("tool/cue")]
    shaft_front = shaft.translation + (cue.halfLength + cue.radius) * shaft.rotation[:, 2]
    assert float(np.dot(T[:3, 3] - shaft_front, T[:3, 2])) > rc.CUE_TIP_RADIUS


def test_the_viewer_uses_the_collision_sizes():
    import importlib

    robot_geometry = importlib.import_module("optraj.viz.robot_geometry")

    assert robot_geometry.sizes_of is rc.sizes_of


def test_a_robot_is_required():
    with pytest.raises(InvalidInputError, match=r"robots\.Robot"):
        rc.collision_model("sawyer")
