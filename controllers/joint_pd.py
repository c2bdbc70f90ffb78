r"""The joint-space baseline: PD on the joint error with the planned velocity fed forward.

.. math:: \dot q_{cmd} = \dot q_{ref} + K_P (q_{ref} - q) + K_D (\dot q_{ref} - \dot q),
    \qquad \tau_{ff} = \tau_{ref}

with the plan's feed-forward torque :math:`\tau_{ref}` (its inverse dynamics without gravity)
passed on to the plant. It tracks the plan's joints, not the tool: errors in the tool pose
come only through the joints, with no Cartesian correction. No limit handling.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.controllers.controller import Command, Controller, Reference, State, as_gains
from optraj.problems.common import check_robot
from optraj.robots import Robot
from optraj.validation import as_flag

__all__ = ["JointPD"]

FloatArray = NDArray[np.float64]


class JointPD(Controller):
    """Joint PD with velocity feed-forward.

    Args:
        robot: The robot.
        kp: Position gain [1/s], scalar or per joint (n,).
        kd: Velocity-error gain [-], scalar or per joint (n,).
        feedforward: Whether the command carries the plan's feed-forward torque
            (``reference.tau``); False: ``Command.tau`` is None.

    Raises:
        InvalidInputError: A robot that is not a robots.Robot, a negative gain or one of the
            wrong size, or a switch that is not a bool.
    """

    def __init__(
        self,
        robot: Robot,
        kp: ArrayLike = 20.0,
        kd: ArrayLike = 0.0,
        feedforward: bool = True,
    ) -> None:
        self.robot = check_robot(robot)
        self.kp = as_gains(kp, "kp", robot.dof, unit="[1/s]")
        self.kd = as_gains(kd, "kd", robot.dof, unit="[-]")
        self.feedforward = as_flag(feedforward, "feedforward")

    @property
    def name(self) -> str:
        """Short name for tables and plots."""
        return "joint PD"

    def reset(self, state: State) -> None:
        """Nothing to forget: the law has no memory."""

    def step(self, state: State, reference: Reference, dt: float) -> Command:
        """``qd_ref + kp (q_ref - q) + kd (qd_ref - qd)``, with ``reference.tau`` fed forward."""
        return Command(
            reference.qd + self.kp * (reference.q - state.q) + self.kd * (reference.qd - state.qd),
            tau=reference.tau if self.feedforward else None,
        )
