"""Signed distances between a robot and its scene, through Pinocchio and coal.

:class:`SceneCollision` joins the robot's collision shapes (:mod:`robots.collision`) and the
scene's objects in one :class:`pinocchio.GeometryModel`, with one collision pair for every two
shapes that may not touch: robot against object, robot against itself where
:mod:`robots.collision` does not allow it, and a carried object against the objects that are
not carried; objects that stay put are not checked against each other. Pairs
the scene allows at every time are left out; pairs it allows only during some phases are kept
and switched off by the checker in those phases (:meth:`SceneCollision.set_active`).
Distances are signed (negative: how deep the shapes overlap) with a witness point on each.

Example::

    shapes = SceneCollision(problem.robot, problem.scene)
    nearest = shapes.distances(q)[0]   # PairDistance(first, second, distance, points)
    shapes.require_clear(q, "the goal")  # CollisionError naming the pair if they overlap
"""

from __future__ import annotations

import fnmatch
from typing import NamedTuple

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import CollisionError, InvalidInputError, UnknownNameError
from optraj.problems.scene import Scene
from optraj.robots import Robot
from optraj.robots.collision import collision_model
from optraj.validation import as_vector

__all__ = ["PairDistance", "SceneCollision"]

FloatArray = NDArray[np.float64]


class PairDistance(NamedTuple):
    """The signed distance of two shapes.

    Attributes:
        first: A robot shape's name (``link_3``, ``tool/tip``), or a carried object's.
        second: The other shape's name: a robot shape or a scene object.
        distance: Signed distance [m]; negative when they overlap, by how much.
        point_first: Witness point on ``first``, world frame [m], shape (3,).
        point_second: Witness point on ``second``, world frame [m], shape (3,).
    """

    first: str
    second: str
    distance: float
    point_first: FloatArray
    point_second: FloatArray


class SceneCollision:
    """A robot and a scene as one geometry model with the pairs that may not touch.

    Attributes:
        robot: The robot.
        scene: The scene.
        geometry: Robot shapes first (on their joints), then the scene's objects (on the
            world), with the collision pairs.
        windows: Per collision pair, the phases during which the scene allows it (empty: never).
        attached: Per attachment, the index of its object's shape and its frame's id.
    """

    def __init__(self, robot: Robot, scene: Scene) -> None:
        if not isinstance(scene, Scene):
            raise InvalidInputError(
                f"scene must be a problems.Scene, got {type(scene).__name__}", name="scene"
            )
        shapes = collision_model(robot)
        self.robot = robot
        self.scene = scene
        geometry = shapes.geometry.copy()
        robot_count = geometry.ngeoms
        for item in scene.objects:
            if geometry.existGeometryName(item.name):
                raise InvalidInputError(
                    f"scene object {item.name!r} has the name of one of the robot's shapes",
                    name="objects",
                )
            placement = pin.SE3(np.asarray(item.pose, dtype=float))
            geometry.addGeometryObject(pin.GeometryObject(item.name, 0, placement, item.shape()))
        names = [g.name for g in geometry.geometryObjects]
        candidates = shapes.self_pairs() + [
            (a, b) for a in range(robot_count) for b in range(robot_count, len(names))
        ]
        carried = [geometry.getGeometryId(a.object) for a in scene.attachments]
        candidates += [
            (a, b) for a in carried for b in range(robot_count, len(names)) if b not in carried
        ]
        self.windows: list[tuple[str, ...]] = []
        for a, b in candidates:
            if scene.always_allowed(names[a], names[b]):
                continue
            geometry.addCollisionPair(pin.CollisionPair(a, b))
            self.windows.append(scene.sometimes_allowed(names[a], names[b]) or ())
        self.geometry = geometry
        self.names = tuple(names)
        self.robot_count = robot_count
        self._model = robot.model
        self._data = robot.model.createData()
        self._geometry_data = pin.GeometryData(geometry)
        self._active: bytes | None = None
        self.attached = [self._attachment(a.object, a.frame) for a in scene.attachments]

    def _attachment(self, name: str, frame: str) -> tuple[int, int]:
        if not self._model.existFrame(frame):
            known = [f.name for f in self._model.frames]
            raise UnknownNameError("frame", frame, known)
        return self.geometry.getGeometryId(name), int(self._model.getFrameId(frame))

    @property
    def pair_count(self) -> int:
        """Number of collision pairs."""
        return len(self.windows)

    def pair_names(self, index: int) -> tuple[str, str]:
        """The names of collision pair ``index``: the robot's (or a carried object's) first."""
        pair = self.geometry.collisionPairs[index]
        return self.names[pair.first], self.names[pair.second]

    def set_active(self, active: NDArray[np.bool_] | None) -> None:
        """Switch collision pairs on (True) and off; None: every pair on."""
        key = None if active is None else np.asarray(active, dtype=bool).tobytes()
        if key == self._active and key is not None:
            return
        self._active = key
        data = self._geometry_data
        for k in range(self.pair_count):
            if active is None or active[k]:
                data.activateCollisionPair(k)
            else:
                data.deactivateCollisionPair(k)

    def frame_pose(self, q: ArrayLike, frame: int) -> FloatArray:
        """World pose of robot frame ``frame`` (an id) at ``q``, shape (4, 4)."""
        q = np.asarray(q, dtype=float)
        pin.framesForwardKinematics(self._model, self._data, q)
        return np.asarray(self._data.oMf[frame].homogeneous)

    def compute(self, q: ArrayLike, poses: dict[int, FloatArray] | None = None) -> int:
        """Place every shape at ``q`` and measure every active pair.

        ``poses`` moves objects (by shape index) to other world poses, shape (4, 4) each.
        Returns the index of the nearest active pair (Pinocchio's), or an index out of range
        when no pair is active.
        """
        model, data, geometry_data = self._model, self._data, self._geometry_data
        pin.updateGeometryPlacements(model, data, self.geometry, geometry_data, q)
        for index, pose in (poses or {}).items():
            geometry_data.oMg[index] = pin.SE3(pose)
        return int(pin.computeDistances(self.geometry, geometry_data))

    def pair_distance(self, index: int) -> PairDistance:
        """The last :meth:`compute`'s result for pair ``index``."""
        result = self._geometry_data.distanceResults[index]
        first, second = self.pair_names(index)
        return PairDistance(
            first,
            second,
            float(result.min_distance),
            np.array(result.getNearestPoint1(), dtype=float),
            np.array(result.getNearestPoint2(), dtype=float),
        )

    def smallest(self, active: NDArray[np.bool_] | None = None) -> tuple[int, float]:
        """(pair index, distance [m]) of the nearest active pair of the last compute.

        (-1, inf) when no pair is active.
        """
        results = self._geometry_data.distanceResults
        best, where = np.inf, -1
        for k in range(self.pair_count):
            if active is None or active[k]:
                value = results[k].min_distance
                if value < best:
                    best, where = value, k
        return where, float(best)

    def static_mask(self) -> NDArray[np.bool_]:
        """The pairs checked without times: those the scene never allows."""
        return np.array([not phases for phases in self.windows], dtype=bool)

    def distances(self, q: ArrayLike, shapes: str = "*") -> list[PairDistance]:
        """Every pair checked at one configuration, nearest first.

        Objects are where the scene puts them; pairs allowed at some time are left out.

        Args:
            q: Configuration [rad or m], shape (n,).
            shapes: Only the pairs whose first shape's name matches this shell pattern
                (e.g. ``"tool/*"``); every pair by default.

        Raises:
            InvalidInputError: ``q`` is not a finite vector of the robot's size.
        """
        q = as_vector(q, "q", self.robot.dof)
        mask = self.static_mask()
        if shapes != "*":
            first = [fnmatch.fnmatchcase(self.pair_names(k)[0], shapes) for k in range(mask.size)]
            mask &= np.array(first, dtype=bool)
        self.set_active(mask)
        self.compute(q)
        found = [self.pair_distance(k) for k in range(self.pair_count) if mask[k]]
        return sorted(found, key=lambda item: item.distance)

    def require_clear(self, q: ArrayLike, what: str, shapes: str = "*") -> None:
        """Refuse a configuration in which two shapes that may not touch overlap.

        Args:
            q: Configuration [rad or m], shape (n,).
            what: What ``q`` is, for the message (e.g. ``"pick 0"``).
            shapes: Only the pairs whose first shape matches this pattern (:meth:`distances`).

        Raises:
            CollisionError: The deepest overlapping pair, its depth and ``what``.
        """
        found = self.distances(q, shapes)
        if found and found[0].distance < 0.0:
            nearest = found[0]
            raise CollisionError(
                nearest.first,
                nearest.second,
                nearest.distance,
                what=what,
                point=tuple(float(v) for v in nearest.point_first),
            )
