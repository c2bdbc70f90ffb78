"""What is to be done: strike, pick-and-place and waypoint problems, and ready-made scenarios.

Problems are frozen dataclasses validated when built; ``constraints()`` lists what a
trajectory must satisfy besides the joint limits, for the independent checker.
"""

from problems.cartesian_line import CartesianLine
from problems.constraints import (
    BoundaryState,
    Constraint,
    StrikeLine,
    ToolContact,
    ToolPath,
    ViaPoint,
)
from problems.paddle_strike import PaddleStrike
from problems.pick_and_place import PickAndPlace
from problems.point_to_point import PointToPoint
from problems.pool_strike import POOL_BALL_RADIUS, PoolStrike
from problems.scenarios import sawyer_pool_shot, seed_paddle_strike, youbot_two_blocks
from problems.waypoints import Waypoints

__all__ = [
    "POOL_BALL_RADIUS",
    "BoundaryState",
    "CartesianLine",
    "Constraint",
    "PaddleStrike",
    "PickAndPlace",
    "PointToPoint",
    "PoolStrike",
    "StrikeLine",
    "ToolContact",
    "ToolPath",
    "ViaPoint",
    "Waypoints",
    "sawyer_pool_shot",
    "seed_paddle_strike",
    "youbot_two_blocks",
]
