"""How to do it in time: Trajectory, classic, time-optimal and optimal-control plans, the checker.

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
from planners.classic_strike import ClassicStrike
from planners.contact import ContactChoice, choose_contact, contact_choices, contact_near
from planners.lower_bound import lower_bound
from planners.lspb import LSPB
from planners.optimal_control import OptimalControl, OptimalControlProblem
from planners.ruckig_planner import OnlineRuckig, Ruckig
from planners.seed_strike import SeedStrike
from planners.sequencer import PickAndPlacePlanner
from planners.strike import TimeOptimalStrike
from planners.time_scaling import Cubic, Quintic
from planners.toppra_planner import Toppra
from planners.trajectory import Phase, Trajectory, TrajectorySample
from planners.via_points import ViaPoints
from planners.window_check import WindowCheck, WindowRatio

__all__ = [
    "LSPB",
    "CartesianStraightLine",
    "ClassicStrike",
    "ContactChoice",
    "Cubic",
    "Finding",
    "JointProfile",
    "LinearTrajectory",
    "OnlineRuckig",
    "OptimalControl",
    "OptimalControlProblem",
    "Phase",
    "PickAndPlacePlanner",
    "Planner",
    "Quintic",
    "Report",
    "Ruckig",
    "SeedStrike",
    "TimeOptimalStrike",
    "Toppra",
    "Trajectory",
    "TrajectorySample",
    "ViaPoints",
    "WindowCheck",
    "WindowRatio",
    "check",
    "choose_contact",
    "contact_choices",
    "contact_near",
    "follow_tool_path",
    "lower_bound",
]
