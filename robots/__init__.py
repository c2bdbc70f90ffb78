"""Robot models: URDF files, loading, limits, kinematics, IK, symbolic models, collision shapes.

>>> from optraj import robots
>>> robot = robots.load("sawyer")
>>> T_world_tool = robot.tool_pose(robot.home)
"""

from optraj.robots.collision import RobotCollision, collision_model
from optraj.robots.ik import IKSolution, solve_ik
from optraj.robots.limits import JointLimits
from optraj.robots.loading import known_robots, load
from optraj.robots.paddle_ik import PADDLE4_WORKSPACE, paddle4_ik
from optraj.robots.robot import Robot
from optraj.robots.symbolic import SymbolicModel

__all__ = [
    "PADDLE4_WORKSPACE",
    "IKSolution",
    "JointLimits",
    "Robot",
    "RobotCollision",
    "SymbolicModel",
    "collision_model",
    "known_robots",
    "load",
    "paddle4_ik",
    "solve_ik",
]
