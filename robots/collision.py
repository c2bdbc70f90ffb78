"""Collision geometry for robots whose URDFs carry none: capsule links and the tool.

Our URDFs hold kinematics and dynamics only. :func:`collision_model` builds a
:class:`pinocchio.GeometryModel` of coal shapes: each link a capsule from its joint to the next
joint's origin (the base's link a flat-ended cylinder, standing on its mount), with the radii of
:data:`SIZES` (one table, also used by the viewer, :mod:`optraj.viz.robot_geometry`), and the
tool: Sawyer's pool cue (a capsule shaft and a sphere tip), paddle4's blade (a cylinder), the
youBot's gripper (a palm box and two finger boxes, opened fully), or a small sphere at the tool
frame of any other robot.

Geometry names: ``link_<j>`` (from joint j's parent to joint j, carried by the parent),
``link_tool`` (last joint to the tool mount) and ``tool/<part>``. Pairs of geometries carried by
the same joint or by a joint and its parent are adjacent; they, and the pairs that already touch
at the robot's home pose (capsules that overlap around a short offset between two joints), are
the robot's allowed pairs: MoveIt's setup assistant disables the same two kinds.

Example::

    robot_shapes = collision_model(robots.load("youbot"))
    robot_shapes.geometry.ngeoms, sorted(robot_shapes.allowed)[:2]
"""

from __future__ import annotations

from dataclasses import dataclass

import coal
import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.robots.loading import SAWYER_CUE_RADIUS
from optraj.robots.paddle_ik import BALL_OFFSET
from optraj.robots.robot import Robot

__all__ = [
    "CUE_TIP_RADIUS",
    "DEFAULT_SIZES",
    "FINGER_GAP",
    "FINGER_SIZE",
    "FINGER_START",
    "PADDLE_BALL_RADIUS",
    "PADDLE_RADIUS",
    "PADDLE_THICKNESS",
    "PALM_SIZE",
    "SIZES",
    "RobotCollision",
    "Sizes",
    "collision_geometry",
    "collision_model",
    "sizes_of",
]

FloatArray = NDArray[np.float64]

#: Segments shorter than this carry no shape [m].
MIN_LENGTH = 1e-6

#: Cue tip radius [m] (physics.scene's CUE_TIP_RADIUS, a rounded tip of our choice).
CUE_TIP_RADIUS = 0.006
#: Paddle blade radius and thickness [m] (physics.scene's: a 150 mm blade, the ECE486 paddle
#: thickness w_p = 0.01 m).
PADDLE_RADIUS = 0.075
PADDLE_THICKNESS = 0.01
#: Table-tennis ball radius [m] (ITTF: 40 mm diameter): the blade face sits this far short of
#: where the paddle plans put the ball centre.
PADDLE_BALL_RADIUS = 0.02
#: youBot gripper: palm (x, y, z lengths [m]) on arm_link_5; fingers 0.046 m out, each open
#: 0.0115 m at most (robots.md); finger lengths [m]. Our drawing of the published numbers.
PALM_SIZE = (0.03, 0.1, 0.046)
FINGER_SIZE = (0.015, 0.01, 0.05)
FINGER_START = 0.046
FINGER_GAP = 0.0115


@dataclass(frozen=True)
class Sizes:
    """Radii of a robot's links [m].

    Attributes:
        links: Capsule radius per link, the base first; the last one repeats.
        joint: Radius of a revolute joint's housing in the viewer, as a multiple of its
            link's radius.
        rail: Radius of a prismatic joint's rail in the viewer [m].
    """

    links: tuple[float, ...]
    joint: float = 1.1
    rail: float = 0.015

    def radius(self, index: int) -> float:
        """Radius of the link carried by joint ``index`` (0: the base) [m]."""
        return self.links[min(index, len(self.links) - 1)]


#: Our choices, close to the arms' real girth: Sawyer's upper arm is about 0.13 m across,
#: the youBot's links about 0.07 m.
SIZES = {
    "sawyer": Sizes((0.07, 0.065, 0.055, 0.05, 0.045, 0.04, 0.035, 0.03, 0.03)),
    "youbot": Sizes((0.05, 0.04, 0.035, 0.03, 0.028, 0.025)),
    "paddle4": Sizes((0.03, 0.03, 0.025, 0.025, 0.018), rail=0.02),
}
DEFAULT_SIZES = Sizes((0.05, 0.045, 0.04, 0.035, 0.03, 0.025))


def sizes_of(robot: Robot) -> Sizes:
    """The radii used for a robot (by name; a default for the others)."""
    return SIZES.get(robot.name, DEFAULT_SIZES)


@dataclass(frozen=True)
class RobotCollision:
    """A robot's collision shapes and the pairs of them that may touch.

    Attributes:
        robot: The robot.
        geometry: Its shapes (coal, placed on the model's joints), no collision pairs.
        allowed: Pairs of geometry names that may touch, each pair sorted.
    """

    robot: Robot
    geometry: pin.GeometryModel
    allowed: frozenset[tuple[str, str]]

    @property
    def names(self) -> tuple[str, ...]:
        """Names of the robot's shapes, in order."""
        return tuple(g.name for g in self.geometry.geometryObjects)

    def self_pairs(self) -> list[tuple[int, int]]:
        """Index pairs of the robot's own shapes that may not touch."""
        names = self.names
        return [
            (a, b)
            for a in range(len(names))
            for b in range(a + 1, len(names))
            if _pair(names[a], names[b]) not in self.allowed
        ]


def _pair(a: str, b: str) -> tuple[str, str]:
    return (a, b) if a <= b else (b, a)


def collision_model(robot: Robot) -> RobotCollision:
    """The collision shapes of ``robot`` and its allowed pairs (see the module docstring).

    Raises:
        InvalidInputError: ``robot`` is not a :class:`robots.Robot`.
    """
    geometry = collision_geometry(robot)
    return RobotCollision(robot, geometry, _allowed(robot, geometry))


def collision_geometry(robot: Robot) -> pin.GeometryModel:
    """The shapes of ``robot``, in a new model each call.

    ``link_<j>`` capsules from joint j's parent to joint j (a cylinder on the base),
    ``link_tool`` to the tool mount, and ``tool/...`` for the tool's parts.

    Raises:
        InvalidInputError: ``robot`` is not a :class:`robots.Robot`.
    """
    if not isinstance(robot, Robot):
        raise InvalidInputError(
            f"robot must be a robots.Robot, got {type(robot).__name__}", name="robot"
        )
    model = robot.model
    sizes = sizes_of(robot)
    geometry = pin.GeometryModel()
    for j in range(1, model.njoints):
        parent = int(model.parents[j])
        end = model.jointPlacements[j].translation
        radius = sizes.radius(parent)
        _rod(geometry, f"link_{j}", parent, np.zeros(3), end, radius, capsule=parent > 0)
    last = model.njoints - 1
    tool = model.frames[robot.tool_frame_id]
    mount = tool_mount(robot)
    _rod(geometry, "link_tool", last, np.zeros(3), mount.translation, sizes.radius(last))
    parts = {"sawyer": _cue, "paddle4": _paddle, "youbot": _gripper}.get(robot.name)
    if parts is None:
        _add(geometry, "tool/tip", tool.parentJoint, tool.placement, coal.Sphere(0.02))
    else:
        parts(geometry, tool.parentJoint, mount, tool.placement)
    return geometry


def _allowed(robot: Robot, geometry: pin.GeometryModel) -> frozenset[tuple[str, str]]:
    """Adjacent pairs, and the pairs that touch at the robot's home pose."""
    model = robot.model
    objects = list(geometry.geometryObjects)
    allowed: set[tuple[str, str]] = set()
    for a, first in enumerate(objects):
        for second in objects[a + 1 :]:
            ja, jb = int(first.parentJoint), int(second.parentJoint)
            if ja == jb or int(model.parents[ja]) == jb or int(model.parents[jb]) == ja:
                allowed.add(_pair(first.name, second.name))
    probe = geometry.copy()
    for a in range(len(objects)):
        for b in range(a + 1, len(objects)):
            if _pair(objects[a].name, objects[b].name) not in allowed:
                probe.addCollisionPair(pin.CollisionPair(a, b))
    data = model.createData()
    probe_data = pin.GeometryData(probe)
    pin.computeDistances(model, data, probe, probe_data, np.asarray(robot.home, dtype=float))
    for pair, result in zip(probe.collisionPairs, probe_data.distanceResults, strict=True):
        if result.min_distance <= 0.0:
            allowed.add(_pair(objects[pair.first].name, objects[pair.second].name))
    return frozenset(allowed)


def tool_mount(robot: Robot) -> pin.SE3:
    """Where the tool is held, in the last joint's frame.

    The link that carries the tool frame (Sawyer's right_hand, the youBot's gripper palm),
    or the tool frame itself.
    """
    model = robot.model
    frames = {"sawyer": "right_hand", "youbot": "gripper_palm_link"}
    name = frames.get(robot.name)
    if name is not None and model.existFrame(name):
        return model.frames[model.getFrameId(name)].placement
    return model.frames[robot.tool_frame_id].placement


def along(axis: ArrayLike) -> FloatArray:
    """A rotation whose z axis is ``axis`` (normalised), shape (3, 3).

    Raises:
        InvalidInputError: An axis shorter than 1e-12 (no direction).
    """
    z = np.asarray(axis, dtype=float)
    norm = float(np.linalg.norm(z))
    if norm < 1e-12:
        raise InvalidInputError(f"axis {z.tolist()} has no direction", name="axis")
    z = z / norm
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def _add(
    geometry: pin.GeometryModel, name: str, joint: int, placement: pin.SE3, shape: coal.ShapeBase
) -> None:
    geometry.addGeometryObject(pin.GeometryObject(name, int(joint), placement, shape))


def _rod(
    geometry: pin.GeometryModel,
    name: str,
    joint: int,
    start: FloatArray,
    end: FloatArray,
    radius: float,
    *,
    capsule: bool = True,
) -> None:
    """A capsule (or cylinder) between two points of a joint's frame; nothing if too short."""
    a, b = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    length = float(np.linalg.norm(b - a))
    if length < MIN_LENGTH:
        return
    shape = coal.Capsule(radius, length) if capsule else coal.Cylinder(radius, length)
    _add(geometry, name, joint, pin.SE3(along(b - a), (a + b) / 2), shape)


def _cue(geometry: pin.GeometryModel, joint: int, mount: pin.SE3, tool: pin.SE3) -> None:
    """The cue from the hand to the tip (the tool frame is the front of the tip).

    The shaft's round end stops one shaft radius behind the tip's centre, so that only the tip
    reaches the front.
    """
    tip = tool.translation
    axis = tool.rotation[:, 2]
    centre = tip - CUE_TIP_RADIUS * axis
    shaft_end = centre - SAWYER_CUE_RADIUS * axis
    _rod(geometry, "tool/cue", joint, mount.translation, shaft_end, SAWYER_CUE_RADIUS)
    _add(geometry, "tool/tip", joint, pin.SE3(np.eye(3), centre), coal.Sphere(CUE_TIP_RADIUS))


def _paddle(geometry: pin.GeometryModel, joint: int, mount: pin.SE3, tool: pin.SE3) -> None:
    """The blade, placed as the MuJoCo scene places it.

    Its face is one ball radius short of where the plans put the ball centre.
    """
    normal = tool.rotation[:, 2]
    face = tool.translation + (BALL_OFFSET - PADDLE_BALL_RADIUS) * normal
    centre = face - (PADDLE_THICKNESS / 2) * normal
    blade = coal.Cylinder(PADDLE_RADIUS, PADDLE_THICKNESS)
    _add(geometry, "tool/blade", joint, pin.SE3(tool.rotation, centre), blade)


def _gripper(geometry: pin.GeometryModel, joint: int, mount: pin.SE3, tool: pin.SE3) -> None:
    """Palm and two fingers, opened fully, along the palm's y axis."""
    R = mount.rotation
    palm_centre = mount.act(np.array([0.0, 0.0, PALM_SIZE[2] / 2]))
    _add(geometry, "tool/palm", joint, pin.SE3(R, palm_centre), coal.Box(*PALM_SIZE))
    for side, sign in (("left", 1.0), ("right", -1.0)):
        y = sign * (FINGER_GAP + FINGER_SIZE[1] / 2)
        centre = mount.act(np.array([0.0, y, FINGER_START + FINGER_SIZE[2] / 2]))
        _add(geometry, f"tool/finger_{side}", joint, pin.SE3(R, centre), coal.Box(*FINGER_SIZE))
