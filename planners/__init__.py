"""How to do it in time: Trajectory, classic, time-optimal and optimal-control plans, the checker.

Every planner has ``plan(problem) -> Trajectory``; :func:`check` judges any trajectory
against a robot's limits and a problem's constraints, independently of the planner.

>>> from optraj import planners, problems
>>> problem = problems.ece486_paddle_strike()
>>> traj = planners.Cubic().plan(problem)
>>> planners.check(traj, problem, quantities=("position", "velocity", "acceleration")).ok
True
"""

from optraj.planners import arrays as arrays
from optraj.planners.base import JointProfile, Planner
from optraj.planners.checker import Finding, Report, check
from optraj.planners.ocp.clearance import Clearance
from optraj.planners.ocp.optimal_control import OptimalControl, OptimalControlProblem
from optraj.planners.profiles.cartesian import (
    CartesianStraightLine,
    LinearTrajectory,
    follow_tool_path,
)
from optraj.planners.profiles.lspb import LSPB
from optraj.planners.profiles.sequencer import PickAndPlacePlanner
from optraj.planners.profiles.time_scaling import Cubic, Quintic
from optraj.planners.profiles.via_points import ViaPoints
from optraj.planners.registry import make_planner, planner_names, register_planner
from optraj.planners.solve_stats import SolveStats
from optraj.planners.strike.classic_strike import ClassicStrike
from optraj.planners.strike.contact import (
    ContactChoice,
    choose_contact,
    contact_choices,
    contact_near,
)
from optraj.planners.strike.pull_back_strike import PullBackStrike
from optraj.planners.strike.time_optimal_strike import TimeOptimalStrike
from optraj.planners.strike.window_check import WindowCheck, WindowRatio
from optraj.planners.time_optimal.lower_bound import lower_bound
from optraj.planners.time_optimal.ruckig_planner import OnlineRuckig, Ruckig
from optraj.planners.time_optimal.toppra_planner import Toppra
from optraj.planners.trajectory import Phase, Trajectory, TrajectorySample

__all__ = [
    "LSPB",
    "CartesianStraightLine",
    "ClassicStrike",
    "Clearance",
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
    "PullBackStrike",
    "Quintic",
    "Report",
    "Ruckig",
    "SolveStats",
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
    "make_planner",
    "planner_names",
    "register_planner",
]
