"""The still solids of a MuJoCo strike world, built from a :class:`problems.Scene`.

The planners, the checker and the viewer read one scene description (:mod:`problems.scene`:
boxes, spheres, cylinders and half-spaces with names and world poses); this module turns its
objects into MuJoCo geoms on the world body:

* :class:`~problems.Box` -> a box geom with the box's half extents,
* :class:`~problems.Sphere` -> a sphere geom,
* :class:`~problems.Cylinder` -> a cylinder geom (radius, half length) along the pose's z axis,
* :class:`~problems.Plane` -> a plane geom (MuJoCo's plane is solid below its z = 0, as the
  scene's half-space is behind its normal).

The object named ``ball`` is left out: the world's ball is a free body of its own. Every other
object touches the ball through an explicit contact pair, and nothing else (the arm carries no
geometry, the tool touches only the ball). The ball rolls on ``cloth`` and on planes with the
cloth's contact, and rebounds from every other object with the cushion's (see
:mod:`optraj.physics.scene` for the values and their sources).
"""

from __future__ import annotations

import fnmatch

import mujoco
import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.problems import Box, Cylinder, Plane, Scene, Sphere
from optraj.problems.pool_strike import POOL_BALL_RADIUS

__all__ = [
    "CLOTH_FRICTION",
    "CLOTH_SOLREF",
    "CUSHION_FRICTION",
    "CUSHION_SOLREF",
    "Contact",
    "add_objects",
    "add_pair",
    "inert",
]

FloatArray = NDArray[np.float64]

#: Ball on cloth: sliding friction 0.2, spin friction 0.005 R, rolling resistance 0.01 R
#: (a length in MuJoCo), critically damped with a 4 ms time constant.
CLOTH_FRICTION = (
    0.2,
    0.2,
    0.005 * POOL_BALL_RADIUS,
    0.01 * POOL_BALL_RADIUS,
    0.01 * POOL_BALL_RADIUS,
)
CLOTH_SOLREF = (0.004, 1.0)
#: Ball on cushion: restitution about 0.75 (damping ratio 0.09), friction 0.2.
CUSHION_SOLREF = (0.004, 0.09)
CUSHION_FRICTION = (0.2, 0.2, 0.005, 0.0001, 0.0001)

#: Colours of the objects by name pattern (first match), and of any other object.
COLOURS = (
    ("cloth", (0.05, 0.45, 0.2, 1.0)),
    ("cushion_*", (0.3, 0.15, 0.05, 1.0)),
    ("floor", (0.5, 0.5, 0.5, 1.0)),
)
OTHER_COLOUR = (0.6, 0.6, 0.65, 1.0)
#: The scene object that is the world's free ball, not a still solid.
BALL_NAME = "ball"

#: A contact pair's parameters: ``(condim, solref, friction)``.
Contact = tuple[int, tuple[float, float], tuple[float, ...]]
ROLLING: Contact = (6, CLOTH_SOLREF, CLOTH_FRICTION)
REBOUND: Contact = (3, CUSHION_SOLREF, CUSHION_FRICTION)


def inert(geom: mujoco.MjsGeom) -> None:
    """Make a geom collide only through the explicit contact pairs."""
    geom.contype = 0
    geom.conaffinity = 0


def add_pair(
    spec: mujoco.MjSpec,
    geom1: str,
    geom2: str,
    condim: int,
    solref: tuple[float, float],
    solimp: tuple[float, ...] | None,
    friction: tuple[float, ...] | None = None,
) -> None:
    """An explicit contact pair ``geom1-geom2`` with its own parameters."""
    pair = spec.add_pair(name=f"{geom1}-{geom2}")
    pair.geomname1, pair.geomname2 = geom1, geom2
    pair.condim = condim
    pair.solref = list(solref)
    if solimp is not None:
        pair.solimp = list(solimp)
    if friction is not None:
        pair.friction = list(friction)


def colour_of(name: str) -> tuple[float, float, float, float]:
    """The drawing colour of the object called ``name`` (rgba, each in [0, 1])."""
    for pattern, rgba in COLOURS:
        if fnmatch.fnmatchcase(name, pattern):
            return rgba
    return OTHER_COLOUR


def contact_of(item: Box | Sphere | Cylinder | Plane) -> Contact:
    """The ball's contact with ``item``: rolling on the cloth and planes, else a rebound."""
    return ROLLING if item.name == "cloth" or isinstance(item, Plane) else REBOUND


def add_objects(spec: mujoco.MjSpec, scene: Scene, ball: str) -> list[str]:
    """Add the scene's still objects to the world body, each in contact with ``ball``.

    Args:
        spec: The world being built.
        scene: The scene description; its object ``ball`` is skipped.
        ball: Name of the ball's geom.

    Returns:
        The names of the geoms added, in the scene's order.

    Raises:
        InvalidInputError: The scene carries objects (attachments): a strike world's objects
            stand still.
    """
    if scene.attachments:
        carried = ", ".join(repr(a.object) for a in scene.attachments)
        raise InvalidInputError(
            f"a strike world's objects stand still; the scene attaches {carried} to the robot",
            name="scene",
        )
    added = []
    for item in scene.objects:
        if item.name == BALL_NAME:
            continue
        geom = spec.worldbody.add_geom(name=item.name, type=_TYPES[type(item)])
        geom.size = _size(item)
        pose = np.asarray(item.pose)
        geom.pos = list(pose[:3, 3])
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, np.ascontiguousarray(pose[:3, :3]).ravel())
        geom.quat = list(quat)
        geom.rgba = list(colour_of(item.name))
        inert(geom)
        condim, solref, friction = contact_of(item)
        add_pair(spec, item.name, ball, condim, solref, None, friction)
        added.append(item.name)
    return added


_TYPES = {
    Box: mujoco.mjtGeom.mjGEOM_BOX,
    Sphere: mujoco.mjtGeom.mjGEOM_SPHERE,
    Cylinder: mujoco.mjtGeom.mjGEOM_CYLINDER,
    Plane: mujoco.mjtGeom.mjGEOM_PLANE,
}


def _size(item: Box | Sphere | Cylinder | Plane) -> list[float]:
    """MuJoCo's size of a geom [m]: half extents, radius, radius and half length."""
    if isinstance(item, Box):
        return [float(v) for v in np.asarray(item.half_extents)]
    if isinstance(item, Sphere):
        return [float(item.radius), 0.0, 0.0]
    if isinstance(item, Cylinder):
        return [float(item.radius), float(item.half_length), 0.0]
    # A plane is infinite in MuJoCo's collisions; its size only draws it (half lengths and
    # the grid spacing).
    return [0.0, 0.0, 1.0]
