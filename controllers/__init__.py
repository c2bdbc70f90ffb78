"""How to follow a trajectory: pseudo-inverse + PID, the OSQP differential-IK QP, simulation.

Every controller has ``reset(state)`` and ``step(state, reference, dt) -> Command`` (a joint
velocity command, with the plan's feed-forward torque for the plant's servo); :func:`simulate`
runs one in closed loop on a simulated robot and measures how well it tracked.

>>> from optraj import controllers, planners, problems
>>> shot = problems.sawyer_pool_shot(speed=1.0)
>>> traj = planners.OptimalControl("time").plan(shot)
>>> result = controllers.simulate(shot.robot, traj, controllers.DiffIKQP(shot.robot, task="axis"))
>>> result.metrics.strike.speed_error_max   # relative speed error along the line
"""

from optraj.controllers.cartesian_pid import CartesianPID, tool_kinematics
from optraj.controllers.controller import (
    Command,
    Controller,
    Reference,
    References,
    State,
    rotation_error,
    sample_references,
)
from optraj.controllers.diff_ik_qp import DiffIKQP
from optraj.controllers.joint_pd import JointPD
from optraj.controllers.metrics import Metrics, StrikeMetrics, Violation, tracking_metrics
from optraj.controllers.plants import (
    DynamicPlant,
    KinematicPlant,
    Plant,
    PlantState,
    tool_force_to_joint_velocity,
)
from optraj.controllers.plot import plot_tracking
from optraj.controllers.pseudo_inverse_pid import PseudoInversePID
from optraj.controllers.qp_terms import QP, Bounds, Constraint, Objective, combine
from optraj.controllers.simulation import PLANTS, Impulse, Noise, Result, simulate

__all__ = [
    "PLANTS",
    "QP",
    "Bounds",
    "CartesianPID",
    "Command",
    "Constraint",
    "Controller",
    "DiffIKQP",
    "DynamicPlant",
    "Impulse",
    "JointPD",
    "KinematicPlant",
    "Metrics",
    "Noise",
    "Objective",
    "Plant",
    "PlantState",
    "PseudoInversePID",
    "Reference",
    "References",
    "Result",
    "State",
    "StrikeMetrics",
    "Violation",
    "combine",
    "plot_tracking",
    "rotation_error",
    "sample_references",
    "simulate",
    "tool_force_to_joint_velocity",
    "tool_kinematics",
    "tracking_metrics",
]
