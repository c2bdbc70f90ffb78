import numpy as np
import pinocchio as pin
import pytest
from conftest import SHIPPED, get_robot

from optraj.robots.collision import CUE_TIP_RADIUS, PADDLE_RADIUS
from optraj.viz.robot_geometry import LINK_COLOURS, robot_geometry, sizes_of


def _placements(robot, q):
    geometry = robot_geometry(robot)
    data = robot.model.createData()
    placements = pin.GeometryData(geometry)
    pin.forwardKinematics(robot.model, data, q)
    pin.updateGeometryPlacements(robot.model, data, geometry, placements)
    poses = {
        item.name: placements.oMg[i].homogeneous for i, item in enumerate(geometry.geometryObjects)
    }
    return geometry, data, poses


@pytest.mark.parametrize("name", SHIPPED)
def test_links_join_consecutive_joints_at_any_configuration(name):
    robot = get_robot(name)
    rng = np.random.default_rng(5)
    for q in robot.random_configurations(3, rng):
        geometry, data, poses = _placements(robot, q)
        model = robot.model
        for j in range(1, model.njoints):
            if f"link_{j}" not in poses:
                continue
            item = geometry.geometryObjects[geometry.getGeometryId(f"link_{j}")]
            half = item.geometry.halfLength
            assert (type(item.geometry).__name__ == "Capsule") == (model.parents[j] > 0)
            T = poses[f"link_{j}"]
            ends = [T @ np.array([0.0, 0.0, s * half, 1.0]) for s in (-1.0, 1.0)]
            parent = data.oMi[int(model.parents[j])].translation
            np.testing.assert_allclose(ends[0][:3], parent, atol=1e-9)
            np.testing.assert_allclose(ends[1][:3], data.oMi[j].translation, atol=1e-9)


@pytest.mark.parametrize("name", SHIPPED)
def test_moving_links_have_distinct_colours_and_the_robot_has_a_tool(name):
    robot = get_robot(name)
    geometry = robot_geometry(robot)
    colours = {
        tuple(item.meshColor)
        for item in geometry.geometryObjects
        if item.name.startswith("link_") and item.parentJoint > 0
    }
    assert len(colours) >= 2
    assert colours <= {tuple(c) for c in LINK_COLOURS}
    assert any(item.name.startswith("tool/") for item in geometry.geometryObjects)
    assert sizes_of(robot).links[0] > 0.0


def test_cue_tip_sits_just_behind_the_tool_frame():
    robot = get_robot("sawyer")
    _, _, poses = _placements(robot, robot.home)
    T_tool = robot.tool_pose(robot.home)
    expected = T_tool[:3, 3] - CUE_TIP_RADIUS * T_tool[:3, 2]
    np.testing.assert_allclose(poses["tool/tip"][:3, 3], expected, atol=1e-12)
    # The cue's axis is the tool's z axis.
    np.testing.assert_allclose(abs(poses["tool/cue"][:3, 2] @ T_tool[:3, 2]), 1.0, atol=1e-12)


def test_paddle_blade_faces_along_the_paddle_normal():
    robot = get_robot("paddle4")
    geometry, _, poses = _placements(robot, robot.home)
    T_tool = robot.tool_pose(robot.home)
    blade = poses["tool/blade"]
    np.testing.assert_allclose(blade[:3, 2], T_tool[:3, 2], atol=1e-12)
    item = geometry.geometryObjects[geometry.getGeometryId("tool/blade")]
    assert item.geometry.radius == PADDLE_RADIUS
    assert np.linalg.norm(blade[:3, 3] - T_tool[:3, 3]) < 0.02


def test_youbot_fingers_straddle_the_tool_point():
    robot = get_robot("youbot")
    _, _, poses = _placements(robot, robot.home)
    T_tool = robot.tool_pose(robot.home)
    left = poses["tool/finger_left"][:3, 3]
    right = poses["tool/finger_right"][:3, 3]
    middle = (left + right) / 2
    # Halfway between the fingers, on the tool axis, near the tool point.
    offset = middle - T_tool[:3, 3]
    along_axis = offset @ T_tool[:3, 2]
    np.testing.assert_allclose(offset - along_axis * T_tool[:3, 2], 0.0, atol=1e-12)
    assert abs(along_axis) < 0.02
