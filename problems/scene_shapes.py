"""The solids of a scene: boxes, half-spaces, spheres and cylinders with names and poses.

Each shape has a unique ``name`` and a world pose ``T_world_shape`` (4x4, metres); boxes,
spheres and cylinders are centred on their pose, cylinders run along their local z axis. A
:class:`Plane` is a half-space: the solid lies behind ``point`` against the outward ``normal``
(a floor, a table top seen from above). :meth:`~Box.shape` gives the coal shape that
:mod:`problems.scene_distances` measures with.

Example::

    block = Box("block_0", half_extents=(0.01, 0.01, 0.015), pose=translation((0.22, 0.1, -0.03)))
    floor = Plane("floor", point=(0, 0, -0.914), normal=(0, 0, 1))
"""

from __future__ import annotations

from dataclasses import dataclass

import coal
import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.problems.common import unit_vector
from optraj.validation import as_positive, as_transform, as_vector

__all__ = ["Box", "Cylinder", "Plane", "Shape", "Sphere", "translation"]

FloatArray = NDArray[np.float64]


def translation(point: ArrayLike) -> FloatArray:
    """The pose of a shape at ``point`` [m] with the world's axes, shape (4, 4)."""
    T = np.eye(4)
    T[:3, 3] = as_vector(point, "point", 3)
    return T


def _name(value: object) -> str:
    if not isinstance(value, str) or not value.strip():
        raise InvalidInputError(
            f"a scene shape's name must be a non-empty str, got {value!r}", name="name"
        )
    return value


def _pose(shape: Box | Sphere | Cylinder) -> None:
    raw = shape.pose
    pose = np.eye(4) if raw is None else as_transform(raw, f"{shape.name}.pose")
    object.__setattr__(shape, "pose", pose)


@dataclass(frozen=True, eq=False)
class Box:
    """A box centred on its pose.

    Attributes:
        name: Unique name in its scene.
        half_extents: Half lengths along the box's x, y, z [m], each > 0.
        pose: ``T_world_box``, shape (4, 4); identity when None.
    """

    name: str
    half_extents: FloatArray
    pose: FloatArray = None  # type: ignore[assignment]  # None: identity (__post_init__)

    def __post_init__(self) -> None:
        object.__setattr__(self, "name", _name(self.name))
        half = as_vector(self.half_extents, f"{self.name}.half_extents", 3)
        for value in half:
            as_positive(float(value), f"{self.name}.half_extents", "m")
        object.__setattr__(self, "half_extents", half)
        _pose(self)

    def shape(self) -> coal.ShapeBase:
        """The coal box (full side lengths)."""
        return coal.Box(*(2.0 * np.asarray(self.half_extents)))


@dataclass(frozen=True, eq=False)
class Sphere:
    """A sphere centred on its pose.

    Attributes:
        name: Unique name in its scene.
        radius: [m], > 0.
        pose: ``T_world_sphere``, shape (4, 4); identity when None.
    """

    name: str
    radius: float
    pose: FloatArray = None  # type: ignore[assignment]  # None: identity (__post_init__)

    def __post_init__(self) -> None:
        object.__setattr__(self, "name", _name(self.name))
        object.__setattr__(self, "radius", as_positive(self.radius, f"{self.name}.radius", "m"))
        _pose(self)

    def shape(self) -> coal.ShapeBase:
        """The coal sphere."""
        return coal.Sphere(float(self.radius))


@dataclass(frozen=True, eq=False)
class Cylinder:
    """A cylinder along its pose's z axis, centred on the pose.

    Attributes:
        name: Unique name in its scene.
        radius: [m], > 0.
        half_length: Half its length along z [m], > 0.
        pose: ``T_world_cylinder``, shape (4, 4); identity when None.
    """

    name: str
    radius: float
    half_length: float
    pose: FloatArray = None  # type: ignore[assignment]  # None: identity (__post_init__)

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "name", _name(self.name))
        set_(self, "radius", as_positive(self.radius, f"{self.name}.radius", "m"))
        set_(self, "half_length", as_positive(self.half_length, f"{self.name}.half_length", "m"))
        _pose(self)

    def shape(self) -> coal.ShapeBase:
        """The coal cylinder (full length)."""
        return coal.Cylinder(float(self.radius), 2.0 * float(self.half_length))


@dataclass(frozen=True, eq=False)
class Plane:
    """A half-space: everything behind ``point`` against the outward ``normal`` is solid.

    Attributes:
        name: Unique name in its scene.
        point: A point of the boundary plane [m], shape (3,).
        normal: Outward normal (normalised here), shape (3,).

    Derived: ``pose``, the plane's frame (origin ``point``, z axis ``normal``), shape (4, 4).
    """

    name: str
    point: FloatArray
    normal: FloatArray = (0.0, 0.0, 1.0)  # type: ignore[assignment]  # made an array

    def __post_init__(self) -> None:
        object.__setattr__(self, "name", _name(self.name))
        object.__setattr__(self, "point", as_vector(self.point, f"{self.name}.point", 3))
        object.__setattr__(self, "normal", unit_vector(self.normal, f"{self.name}.normal"))

    @property
    def pose(self) -> FloatArray:
        """The plane's frame: origin at ``point``, z axis along ``normal``, shape (4, 4)."""
        z = np.asarray(self.normal)
        helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        x = np.cross(helper, z)
        x /= np.linalg.norm(x)
        T = np.eye(4)
        T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
        T[:3, 3] = self.point
        return T

    def shape(self) -> coal.ShapeBase:
        """The coal half-space in the plane's own frame (z <= 0 is solid)."""
        return coal.Halfspace(np.array([0.0, 0.0, 1.0]), 0.0)


#: Any solid of a scene.
Shape = Box | Sphere | Cylinder | Plane
