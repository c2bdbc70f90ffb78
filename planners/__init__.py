"""How to do it in time: the Trajectory type, time scalings, Cartesian paths, the checker.

Every planner has ``plan(problem) -> Trajectory``; :func:`check` judges any trajectory
against a robot's limits and a problem's constraints, independently of the planner.

>>> import planners, problems
>>> problem = problems.seed_paddle_strike()
>>> traj = planners.Cubic().plan(problem)
>>> planners.check(traj, problem, quantities=("position", "velocity", "acceleration")).ok
True
"""

from planners.base import JointProfile, Planner
from planners.cartesian import CartesianStraightLine, LinearTrajectory, follow_tool_path
from planners.checker import Finding, Report, check
from planners.lspb import LSPB
from planners.seed_strike import SeedStrike
from planners.sequencer import PickAndPlacePlanner
from planners.time_scaling import Cubic, Quintic
from planners.trajectory import Phase, Trajectory, TrajectorySample
from planners.via_points import ViaPoints

__all__ = [
    "LSPB",
    "CartesianStraightLine",
    "Cubic",
    "Finding",
    "JointProfile",
    "LinearTrajectory",
    "Phase",
    "PickAndPlacePlanner",
    "Planner",
    "Quintic",
    "Report",
    "SeedStrike",
    "Trajectory",
    "TrajectorySample",
    "ViaPoints",
    "check",
    "follow_tool_path",
]
