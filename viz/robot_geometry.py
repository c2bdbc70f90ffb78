"""Visual geometry for robots whose URDFs carry none: links, joints and the tool.

Our URDFs hold kinematics and dynamics only. :func:`robot_geometry` draws each link as a
capsule from its joint to the next joint's origin, each revolute joint as a short dark
cylinder along its axis, each prismatic joint as a grey rail over its travel, and the tool:
Sawyer's pool cue, paddle4's paddle, the youBot's gripper (the sizes of the collision model,
:mod:`optraj.robots.collision`, which the MuJoCo scene uses too), or a small sphere at the
tool frame of any other robot. Each moving link has its own colour. The result is a
:class:`pinocchio.GeometryModel`, placed by Pinocchio at any configuration.
"""

from __future__ import annotations

import coal
import numpy as np
import pinocchio as pin
from numpy.typing import NDArray

from optraj.robots import Robot
from optraj.robots.collision import (
    CUE_TIP_RADIUS,
    FINGER_GAP,
    FINGER_SIZE,
    FINGER_START,
    PADDLE_BALL_RADIUS,
    PADDLE_RADIUS,
    PADDLE_THICKNESS,
    PALM_SIZE,
    Sizes,
    sizes_of,
    tool_mount,
)
from optraj.robots.loading import SAWYER_CUE_RADIUS as CUE_SHAFT_RADIUS
from optraj.robots.paddle_ik import BALL_OFFSET
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


def robot_geometry(robot: Robot) -> pin.GeometryModel:
    """Capsule links, joint housings, rails and the tool of ``robot``, as visual geometry.

    Names: ``link_<j>`` (from joint j's parent to joint j; a cylinder on the base, capsules
    above), ``joint_<j>``, ``rail_<j>``,
    ``link_tool`` (last joint to the tool) and ``tool/...`` for the tool's parts.
    """
    model = robot.model
    sizes = sizes_of(robot)
    geometry = pin.GeometryModel()

    def radius(index: int) -> float:
        return sizes.links[min(index, len(sizes.links) - 1)]

    def colour(joint: int) -> tuple[float, ...]:
        return BASE_COLOUR if joint == 0 else LINK_COLOURS[(joint - 1) % len(LINK_COLOURS)]

    for j in range(1, model.njoints):
        parent = int(model.parents[j])
        placement = model.jointPlacements[j]
        end = placement.translation
        # The base's link is a flat-ended cylinder: it stands on the pedestal.
        _rod(
            geometry,
            f"link_{j}",
            parent,
            np.zeros(3),
            end,
            radius(parent),
            colour(parent),
            capsule=parent > 0,
        )
        kind, axis = _axis(model, j)
        if kind == "revolute":
            housing = radius(j) * sizes.joint
            T = pin.SE3(along(axis), np.zeros(3))
            _add(geometry, f"joint_{j}", j, T, coal.Cylinder(housing, 1.8 * housing), JOINT_COLOUR)
        else:
            lower, upper = model.lowerPositionLimit[j - 1], model.upperPositionLimit[j - 1]
            start = placement.act(lower * axis)
            end = placement.act(upper * axis)
            _rod(geometry, f"rail_{j}", parent, start, end, sizes.rail, RAIL_COLOUR, capsule=False)
    last = model.njoints - 1
    tool = model.frames[robot.tool_frame_id]
    mount = tool_mount(robot)
    _rod(geometry, "link_tool", last, np.zeros(3), mount.translation, radius(last), colour(last))
    tool_parts = {"sawyer": _cue, "paddle4": _paddle, "youbot": _gripper}.get(robot.name)
    if tool_parts is None:
        _add(
            geometry, "tool/tip", tool.parentJoint, tool.placement, coal.Sphere(0.02), JOINT_COLOUR
        )
    else:
        tool_parts(geometry, tool.parentJoint, mount, tool.placement)
    return geometry


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


def _rod(
    geometry: pin.GeometryModel,
    name: str,
    joint: int,
    start: FloatArray,
    end: FloatArray,
    radius: float,
    rgba: tuple[float, ...] = BASE_COLOUR,
    *,
    capsule: bool = True,
) -> None:
    """A capsule (or cylinder) between two points of a joint's frame; nothing if too short."""
    a, b = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    length = float(np.linalg.norm(b - a))
    if length < MIN_LENGTH:
        return
    shape = coal.Capsule(radius, length) if capsule else coal.Cylinder(radius, length)
    _add(geometry, name, joint, pin.SE3(along(b - a), (a + b) / 2), shape, rgba)


def _cue(geometry: pin.GeometryModel, joint: int, mount: pin.SE3, tool: pin.SE3) -> None:
    """The cue from the hand to the tip (the tool frame is the front of the tip)."""
    tip = tool.translation
    axis = tool.rotation[:, 2]
    centre = tip - CUE_TIP_RADIUS * axis
    _rod(geometry, "tool/cue", joint, mount.translation, centre, CUE_SHAFT_RADIUS, CUE_COLOUR)
    placement = pin.SE3(np.eye(3), centre)
    _add(geometry, "tool/tip", joint, placement, coal.Sphere(CUE_TIP_RADIUS), CUE_TIP_COLOUR)


def _paddle(geometry: pin.GeometryModel, joint: int, mount: pin.SE3, tool: pin.SE3) -> None:
    """The blade, placed as the MuJoCo scene places it.

    Its face is one ball radius short of where the plans put the ball centre.
    """
    normal = tool.rotation[:, 2]
    face = tool.translation + (BALL_OFFSET - PADDLE_BALL_RADIUS) * normal
    centre = face - (PADDLE_THICKNESS / 2) * normal
    blade = coal.Cylinder(PADDLE_RADIUS, PADDLE_THICKNESS)
    _add(geometry, "tool/blade", joint, pin.SE3(tool.rotation, centre), blade, PADDLE_COLOUR)


def _gripper(geometry: pin.GeometryModel, joint: int, mount: pin.SE3, tool: pin.SE3) -> None:
    """Palm and two fingers, opened fully, along the palm's y axis."""
    R = mount.rotation
    palm_centre = mount.act(np.array([0.0, 0.0, PALM_SIZE[2] / 2]))
    palm = coal.Box(*PALM_SIZE)
    _add(geometry, "tool/palm", joint, pin.SE3(R, palm_centre), palm, GRIPPER_COLOUR)
    for side, sign in (("left", 1.0), ("right", -1.0)):
        y = sign * (FINGER_GAP + FINGER_SIZE[1] / 2)
        centre = mount.act(np.array([0.0, y, FINGER_START + FINGER_SIZE[2] / 2]))
        finger = coal.Box(*FINGER_SIZE)
        _add(geometry, f"tool/finger_{side}", joint, pin.SE3(R, centre), finger, GRIPPER_COLOUR)
