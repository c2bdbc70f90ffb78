"""Plain shapes of a 3-D scene: what the viewer draws besides the robot, as data.

A :class:`Shape` is a box, sphere, cylinder or capsule with a pose and a colour, and, when it
moves, one pose per animation frame. Cylinders and capsules run along their local z axis,
centred on their pose. Nothing here needs a viewer: the scene is built and inspected as data,
then handed to one (:mod:`optraj.viz.meshcat_viewer`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.robots.collision import along

__all__ = ["Kind", "Shape", "along", "box", "polyline", "segment", "sphere"]

FloatArray = NDArray[np.float64]
Kind = Literal["box", "sphere", "cylinder", "capsule"]
Rgba = tuple[float, float, float, float]

#: Segments shorter than this are not drawn [m].
MIN_LENGTH = 1e-6


@dataclass(frozen=True)
class Shape:
    """One solid of the scene.

    Attributes:
        name: Node name in the viewer, unique within a scene (e.g. ``"table/cloth"``).
        kind: ``"box"``, ``"sphere"``, ``"cylinder"`` or ``"capsule"``.
        size: Box: full lengths along x, y, z [m]; sphere: (radius,); cylinder and capsule:
            (radius, length) along local z [m] (a capsule's length excludes its end caps).
        pose: ``T_world_shape``, shape (4, 4).
        rgba: Colour and opacity, each in [0, 1].
        motion: Poses per animation frame, shape (m, 4, 4); ``None`` for a still shape.
    """

    name: str
    kind: Kind
    size: tuple[float, ...]
    pose: FloatArray
    rgba: Rgba
    motion: FloatArray | None = None


def _translation(point: ArrayLike) -> FloatArray:
    T = np.eye(4)
    T[:3, 3] = np.asarray(point, dtype=float)
    return T


def box(name: str, centre: ArrayLike, lengths: ArrayLike, rgba: Rgba) -> Shape:
    """An axis-aligned box, ``lengths`` [m] along x, y, z, centred at ``centre`` [m]."""
    size = tuple(float(v) for v in np.asarray(lengths, dtype=float))
    return Shape(name, "box", size, _translation(centre), rgba)


def sphere(name: str, centre: ArrayLike, radius: float, rgba: Rgba) -> Shape:
    """A sphere of ``radius`` [m] at ``centre`` [m]."""
    return Shape(name, "sphere", (float(radius),), _translation(centre), rgba)


def segment(
    name: str,
    start: ArrayLike,
    end: ArrayLike,
    radius: float,
    rgba: Rgba,
    kind: Kind = "cylinder",
) -> Shape | None:
    """A cylinder (or capsule) of ``radius`` [m] from ``start`` to ``end`` [m].

    None when shorter than :data:`MIN_LENGTH`.
    """
    a = np.asarray(start, dtype=float)
    b = np.asarray(end, dtype=float)
    length = float(np.linalg.norm(b - a))
    if length < MIN_LENGTH:
        return None
    T = _translation((a + b) / 2)
    T[:3, :3] = along(b - a)
    return Shape(name, kind, (float(radius), length), T, rgba)


def polyline(
    name: str, points: ArrayLike, radius: float, rgba: Rgba, most: int = 80
) -> list[Shape]:
    """A path drawn as thin cylinders through ``points`` [m], shape (k, 3).

    Points closer than the radius to the last kept one are dropped, then at most ``most``
    evenly spaced ones are kept (the first and last always), so a long roll-out stays a few
    dozen shapes. Segments are named ``name/0``, ``name/1``, ...
    """
    path = np.asarray(points, dtype=float).reshape(-1, 3)
    kept = [path[0]] if len(path) else []
    for point in path[1:]:
        if np.linalg.norm(point - kept[-1]) > radius:
            kept.append(point)
    if len(path) > 1 and len(kept) > 1 and np.linalg.norm(path[-1] - kept[-1]) > 0.0:
        kept[-1] = path[-1]
    if len(kept) > most:
        index = np.unique(np.linspace(0, len(kept) - 1, most).round().astype(int))
        kept = [kept[i] for i in index]
    shapes = [
        segment(f"{name}/{k}", kept[k], kept[k + 1], radius, rgba, "capsule")
        for k in range(len(kept) - 1)
    ]
    return [shape for shape in shapes if shape is not None]
