r"""The joint-space baseline: PD on the joint error with the planned velocity fed forward.

.. math:: \dot q_{cmd} = \dot q_{ref} + K_P (q_{ref} - q) + K_D (\dot q_{ref} - \dot q)

It tracks the plan's joints, not the tool: errors in the tool pose come only through the
joints, with no Cartesian correction. No limit handling.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from controllers.controller import Command, Controller, Reference, State, as_gains
from robots import Robot

__all__ = ["JointPD"]

FloatArray = NDArray[np.float64]


class JointPD(Controller):
    """Joint PD with velocity feed-forward.

    Args:
        robot: The robot.
        kp: Position gain [1/s], scalar or per joint (n,).
        kd: Velocity-error gain [-], scalar or per joint (n,).

    Raises:
        InvalidInputError: A negative gain or one of the wrong size.
    """

    def __init__(self, robot: Robot, kp: ArrayLike = 20.0, kd: ArrayLike = 0.0) -> None:
        self.robot = robot
        self.kp = as_gains(kp, "kp", robot.dof, unit="[1/s]")
        self.kd = as_gains(kd, "kd", robot.dof, unit="[-]")

    @property
    def name(self) -> str:
        """Short name for tables and plots."""
        return "joint PD"

    def reset(self, state: State) -> None:
        """Nothing to forget: the law has no memory."""

    def step(self, state: State, reference: Reference, dt: float) -> Command:
        """``qd_ref + kp (q_ref - q) + kd (qd_ref - qd)``."""
        return Command(
            reference.qd + self.kp * (reference.q - state.q) + self.kd * (reference.qd - state.qd)
        )
