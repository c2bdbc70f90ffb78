"""What is to be done: strike, pick-and-place and waypoint problems, and ready-made scenarios.

A :class:`Scene` (boxes, half-spaces, spheres, cylinders, carried objects, allowed pairs)
describes a robot's surroundings; :class:`SceneCollision` measures the distances to it.
Problems are frozen dataclasses validated when built; ``constraints()`` lists what a
trajectory must satisfy besides the joint limits, for the independent checker.
"""

from optraj.problems.cartesian_line import CartesianLine
from optraj.problems.constraints import (
    BoundaryState,
    Constraint,
    StrikeLine,
    ToolContact,
    ToolPath,
    ViaPoint,
)
from optraj.problems.paddle_strike import PaddleStrike
from optraj.problems.pick_and_place import PickAndPlace
from optraj.problems.point_to_point import PointToPoint
from optraj.problems.pool_strike import POOL_BALL_RADIUS, PoolStrike
from optraj.problems.scenarios import (
    block_clearance_scene,
    ece486_paddle_strike,
    sawyer_pool_shot,
    youbot_two_blocks,
)
from optraj.problems.scene import AllowedPair, Attachment, Scene
from optraj.problems.scene_distances import PairDistance, SceneCollision
from optraj.problems.scene_shapes import Box, Cylinder, Plane, Sphere
from optraj.problems.scenes import floor, pick_and_place_scene, pool_table
from optraj.problems.waypoints import Waypoints

__all__ = [
    "POOL_BALL_RADIUS",
    "AllowedPair",
    "Attachment",
    "BoundaryState",
    "Box",
    "CartesianLine",
    "Constraint",
    "Cylinder",
    "PaddleStrike",
    "PairDistance",
    "PickAndPlace",
    "Plane",
    "PointToPoint",
    "PoolStrike",
    "Scene",
    "SceneCollision",
    "Sphere",
    "StrikeLine",
    "ToolContact",
    "ToolPath",
    "ViaPoint",
    "Waypoints",
    "block_clearance_scene",
    "ece486_paddle_strike",
    "floor",
    "pick_and_place_scene",
    "pool_table",
    "sawyer_pool_shot",
    "youbot_two_blocks",
]
