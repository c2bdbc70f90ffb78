"""How to do it in time: Trajectory, classic, time-optimal and optimal-control plans, the checker.

Every planner has ``plan(problem) -> Trajectory``; :func:`check` judges any trajectory
against a robot's limits and a problem's constraints, independently of the planner.

>>> from optraj import planners, problems
>>> problem = problems.seed_paddle_strike()
>>> traj = planners.Cubic().plan(problem)
>>> planners.check(traj, problem, quantities=("position", "velocity", "acceleration")).ok
True
"""

from optraj.planners.base import JointProfile, Planner
from optraj.planners.cartesian import CartesianStraightLine, LinearTrajectory, follow_tool_path
from optraj.planners.checker import Finding, Report, check
from optraj.planners.classic_strike import ClassicStrike
from optraj.planners.contact import ContactChoice, choose_contact, contact_choices, contact_near
from optraj.planners.lower_bound import lower_bound
from optraj.planners.lspb import LSPB
from optraj.planners.optimal_control import OptimalControl, OptimalControlProblem
from optraj.planners.ruckig_planner import OnlineRuckig, Ruckig
from optraj.planners.seed_strike import SeedStrike
from optraj.planners.sequencer import PickAndPlacePlanner
from optraj.planners.strike import TimeOptimalStrike
from optraj.planners.time_scaling import Cubic, Quintic
from optraj.planners.toppra_planner import Toppra
from optraj.planners.trajectory import Phase, Trajectory, TrajectorySample
from optraj.planners.via_points import ViaPoints
from optraj.planners.window_check import WindowCheck, WindowRatio

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
