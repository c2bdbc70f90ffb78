"""The solids of a :class:`problems.Scene` as viewer shapes; carried ones ride with a frame.

The viewer draws the same scene description that the checker measures and that the MuJoCo
world is built from (:mod:`optraj.physics.static_objects`): boxes, spheres and cylinders at
their poses, and half-spaces as a thin tile whose top is the plane (a horizontal plane at the
drawn floor's height is the floor itself, not drawn twice). An object with an
:class:`~problems.Attachment` keeps its offset from the attachment's robot frame from the
attachment's start to its end, and stays where the frame leaves it. The object called
``ball`` is the ball's, drawn with its roll (:func:`optraj.viz.tasks.ball_shape`).

The pool table's objects (``cloth``, ``cushion_*``) are drawn as ``table/<name>``; every other
object under its own name.
"""

from __future__ import annotations

import fnmatch
import re

import numpy as np
from numpy.typing import NDArray

from optraj.physics.static_objects import BALL_NAME, colour_of
from optraj.planners import Trajectory
from optraj.problems import Attachment, Box, Cylinder, Plane, Scene, Sphere
from optraj.robots import Robot
from optraj.viz.shapes import Rgba, Shape

__all__ = ["BLOCK_COLOURS", "drawn_name", "object_shapes"]

FloatArray = NDArray[np.float64]

#: Colours of ``block_<k>``, by k.
BLOCK_COLOURS: tuple[Rgba, ...] = (
    (0.9, 0.3, 0.3, 1.0),
    (0.3, 0.5, 0.95, 1.0),
    (0.95, 0.75, 0.2, 1.0),
)
#: A plane's tile: half its side [m], its thickness [m] and its colour (translucent).
PLANE_HALF_SIDE = 0.6
PLANE_THICKNESS = 0.002
PLANE_COLOUR: Rgba = (0.55, 0.55, 0.6, 0.35)
#: A horizontal plane this close to the drawn floor [m] is the floor.
FLOOR_TOLERANCE = 1e-3
#: Objects drawn as parts of the pool table.
TABLE_PARTS = ("cloth", "cushion_*")
_BLOCK = re.compile(r"block_(\d+)$")


def drawn_name(name: str) -> str:
    """The viewer's name of the scene object ``name`` (``table/cloth``, ``block_0``, ...)."""
    table = any(fnmatch.fnmatchcase(name, pattern) for pattern in TABLE_PARTS)
    return f"table/{name}" if table else name


def _colour(name: str) -> Rgba:
    block = _BLOCK.match(name)
    if block is not None:
        return BLOCK_COLOURS[int(block.group(1)) % len(BLOCK_COLOURS)]
    return colour_of(name)


def _still(item: Box | Sphere | Cylinder | Plane, floor: float) -> Shape | None:
    """One object at its scene pose; None for the floor plane."""
    name, rgba, pose = drawn_name(item.name), _colour(item.name), np.asarray(item.pose)
    if isinstance(item, Box):
        size = tuple(2.0 * float(v) for v in np.asarray(item.half_extents))
        return Shape(name, "box", size, pose, rgba)
    if isinstance(item, Sphere):
        return Shape(name, "sphere", (float(item.radius),), pose, rgba)
    if isinstance(item, Cylinder):
        size = (float(item.radius), 2.0 * float(item.half_length))
        return Shape(name, "cylinder", size, pose, rgba)
    normal = np.asarray(item.normal)
    if normal[2] > 1.0 - 1e-9 and abs(float(item.point[2]) - floor) < FLOOR_TOLERANCE:
        return None
    tile = pose.copy()
    tile[:3, 3] -= (PLANE_THICKNESS / 2) * normal  # its top face on the plane
    side = 2.0 * PLANE_HALF_SIDE
    return Shape(name, "box", (side, side, PLANE_THICKNESS), tile, PLANE_COLOUR)


def _instant(trajectory: Trajectory, when: float | str, *, first: bool) -> float | None:
    """A time [s] within the trajectory, or a phase's start (end); None: no such phase."""
    if isinstance(when, str):
        phase = next((p for p in trajectory.phases if p.name == when), None)
        if phase is None:
            return None
        return phase.t_start if first else phase.t_end
    return min(float(when), trajectory.duration)


def _motion(
    start: FloatArray,
    attachments: list[Attachment],
    robot: Robot,
    trajectory: Trajectory,
    times: FloatArray,
) -> FloatArray | None:
    """The object's pose per frame, shape (m, 4, 4); None when it is never carried.

    An attachment whose phases the trajectory lacks leaves the object where it is.
    """
    spans = []
    for attachment in attachments:
        t0 = _instant(trajectory, attachment.start, first=True)
        t1 = _instant(trajectory, attachment.end, first=False)
        if t0 is not None and t1 is not None:
            spans.append((t0, max(t0, t1), attachment.frame))
    if not spans:
        return None
    motion = np.broadcast_to(start, (len(times), 4, 4)).copy()
    q = trajectory.sample(np.clip(times, 0.0, trajectory.duration)).q
    still = start
    for t0, t1, frame in sorted(spans, key=lambda span: span[0]):
        ends = robot.frame_pose(trajectory.sample(np.array([t0, t1])).q, frame)
        held = np.linalg.solve(ends[0], still)  # the object in the frame when taken
        motion[times >= t0] = robot.frame_pose(q[times >= t0], frame) @ held
        still = ends[1] @ held
        motion[times > t1] = still
    return motion


def object_shapes(
    scene: Scene, robot: Robot, trajectory: Trajectory, times: FloatArray, floor: float
) -> list[Shape]:
    """The scene's solids as viewer shapes, the carried ones moving frame by frame.

    Args:
        scene: The scene description.
        robot: The robot whose frames carry the attached objects.
        trajectory: Its motion.
        times: Frame times [s], shape (m,).
        floor: Height of the drawn floor [m] (a plane there is not drawn again).
    """
    shapes = []
    for item in scene.objects:
        if item.name == BALL_NAME:
            continue
        shape = _still(item, floor)
        if shape is None:
            continue
        attached = [a for a in scene.attachments if a.object == item.name]
        motion = _motion(shape.pose, attached, robot, trajectory, times) if attached else None
        if motion is not None:
            shape = Shape(shape.name, shape.kind, shape.size, motion[0], shape.rgba, motion)
        shapes.append(shape)
    return shapes
