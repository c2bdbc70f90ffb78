"""Visual geometry for robots whose URDFs carry none: links, joints and the tool.

Our URDFs hold kinematics and dynamics only. :func:`robot_geometry` draws each link as a
capsule from its joint to the next joint's origin, each revolute joint as a short dark
cylinder along its axis, each prismatic joint as a grey rail over its travel, and the tool:
Sawyer's pool cue, paddle4's paddle, the youBot's gripper, or a small sphere at the tool
frame of any other robot. Links and tool are the collision model's own shapes
(:func:`optraj.robots.collision.collision_geometry`, which the checker and the MuJoCo scene
use too), coloured here. Each moving link has its own colour. The result is a
:class:`pinocchio.GeometryModel`, placed by Pinocchio at any configuration.
"""

from __future__ import annotations

import coal
import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from optraj.robots import Robot
from optraj.robots.collision import Sizes, collision_geometry, sizes_of
from optraj.viz.shapes import MIN_LENGTH, along

__all__ = ["LINK_COLOURS", "Sizes", "robot_geometry", "sizes_of"]

FloatArray = NDArray[np.float64]

#: One colour per moving link, in joint order (then repeated) [rgba].
LINK_COLOURS = (
    (0.12, 0.47, 0.71, 1.0),
    (1.00, 0.50, 0.05, 1.0),
    (0.17, 0.63, 0.17, 1.0),
    (0.84, 0.15, 0.16, 1.0),
    (0.58, 0.40, 0.74, 1.0),
    (0.55, 0.34, 0.29, 1.0),
    (0.89, 0.47, 0.76, 1.0),
    (0.09, 0.75, 0.81, 1.0),
)
BASE_COLOUR = (0.35, 0.35, 0.38, 1.0)
JOINT_COLOUR = (0.22, 0.22, 0.25, 1.0)
RAIL_COLOUR = (0.62, 0.62, 0.66, 1.0)
#: Cue colours: the MuJoCo scene's (light wood shaft, blue tip).
CUE_COLOUR = (0.8, 0.65, 0.4, 1.0)
CUE_TIP_COLOUR = (0.2, 0.4, 0.8, 1.0)
#: Paddle blade colour: the MuJoCo scene's red.
PADDLE_COLOUR = (0.75, 0.1, 0.1, 1.0)
GRIPPER_COLOUR = (0.25, 0.25, 0.28, 1.0)


#: Colours of the tools' parts, by name; any other robot's ``tool/tip`` is JOINT_COLOUR.
TOOL_COLOURS = {
    "tool/cue": CUE_COLOUR,
    "tool/blade": PADDLE_COLOUR,
    "tool/palm": GRIPPER_COLOUR,
    "tool/finger_left": GRIPPER_COLOUR,
    "tool/finger_right": GRIPPER_COLOUR,
}


def robot_geometry(robot: Robot) -> pin.GeometryModel:
    """Capsule links, joint housings, rails and the tool of ``robot``, as visual geometry.

    Names: ``link_<j>`` (from joint j's parent to joint j; a cylinder on the base, capsules
    above), ``link_tool`` (last joint to the tool) and ``tool/...`` for the tool's parts (the
    collision model's shapes), then ``joint_<j>`` and ``rail_<j>``.
    """
    geometry = collision_geometry(robot)
    for item in geometry.geometryObjects:
        item.meshColor = np.asarray(_colour(robot, item), dtype=float)
    model = robot.model
    sizes = sizes_of(robot)
    for j in range(1, model.njoints):
        kind, axis = _axis(model, j)
        if kind == "revolute":
            housing = sizes.radius(j) * sizes.joint
            T = pin.SE3(along(axis), np.zeros(3))
            _add(geometry, f"joint_{j}", j, T, coal.Cylinder(housing, 1.8 * housing), JOINT_COLOUR)
        else:
            placement = model.jointPlacements[j]
            lower, upper = model.lowerPositionLimit[j - 1], model.upperPositionLimit[j - 1]
            start = placement.act(lower * axis)
            end = placement.act(upper * axis)
            _rail(geometry, f"rail_{j}", int(model.parents[j]), start, end, sizes.rail)
    return geometry


def _colour(robot: Robot, item: pin.GeometryObject) -> tuple[float, ...]:
    """A shape's colour: links by the joint that carries them, tools by part."""
    if item.name in TOOL_COLOURS:
        return TOOL_COLOURS[item.name]
    if item.name == "tool/tip":
        return CUE_TIP_COLOUR if robot.name == "sawyer" else JOINT_COLOUR
    joint = int(item.parentJoint)
    return BASE_COLOUR if joint == 0 else LINK_COLOURS[(joint - 1) % len(LINK_COLOURS)]


def _axis(model: pin.Model, joint: int) -> tuple[str, FloatArray]:
    """``("revolute" | "prismatic", axis)`` of a one-DOF joint, axis in the joint frame."""
    jmodel = model.joints[joint]
    jdata = jmodel.createData()
    jmodel.calc(jdata, pin.neutral(model))
    S = np.asarray(jdata.S).ravel()
    if np.linalg.norm(S[3:]) > 0.5:
        return "revolute", S[3:] / np.linalg.norm(S[3:])
    return "prismatic", S[:3] / np.linalg.norm(S[:3])


def _add(
    geometry: pin.GeometryModel,
    name: str,
    joint: int,
    placement: pin.SE3,
    shape: coal.ShapeBase,
    rgba: tuple[float, ...],
) -> None:
    item = pin.GeometryObject(name, int(joint), placement, shape)
    item.meshColor = np.asarray(rgba, dtype=float)
    geometry.addGeometryObject(item)


def _rail(
    geometry: pin.GeometryModel,
    name: str,
    joint: int,
    start: FloatArray,
    end: FloatArray,
    radius: float,
) -> None:
    """A cylinder between two points of a joint's frame; nothing if too short."""
    a, b = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    length = float(np.linalg.norm(b - a))
    if length < MIN_LENGTH:
        return
    shape = coal.Cylinder(radius, length)
    _add(geometry, name, joint, pin.SE3(along(b - a), (a + b) / 2), shape, RAIL_COLOUR)
