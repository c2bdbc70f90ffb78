"""Robot models: URDF files, loading, limits, kinematics, inverse kinematics, symbolic models.

>>> import robots
>>> robot = robots.load("sawyer")
>>> T_world_tool = robot.tool_pose(robot.home)
"""

from robots.ik import IKSolution, solve_ik
from robots.limits import JointLimits
from robots.loading import known_robots, load
from robots.paddle_ik import PADDLE4_WORKSPACE, paddle4_ik
from robots.robot import Robot
from robots.symbolic import SymbolicModel

__all__ = [
    "PADDLE4_WORKSPACE",
    "IKSolution",
    "JointLimits",
    "Robot",
    "SymbolicModel",
    "known_robots",
    "load",
    "paddle4_ik",
    "solve_ik",
]
