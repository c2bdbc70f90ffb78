r"""The Sawyer exercise's tracking controller: Cartesian PID through the Jacobian pseudo-inverse.

.. math:: \dot q_{cmd} = J^{+} v_{cmd}, \qquad
          J^{+} = J^T (J J^T + \lambda^2 I)^{-1}

with :math:`v_{cmd}` from :class:`~controllers.cartesian_pid.CartesianPID` and
:math:`\lambda = 0` the plain Moore-Penrose pseudo-inverse. The command carries the plan's
feed-forward torque (its inverse dynamics without gravity) for the plant's servo. It knows
no joint limits, as in the Sawyer exercise: near a singularity or with a plan that already runs at a
limit it commands whatever the inverse gives. :class:`~controllers.diff_ik_qp.DiffIKQP` is its
limit-aware replacement.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.controllers.cartesian_pid import CartesianPID, tool_kinematics
from optraj.controllers.controller import Command, Controller, Reference, State, cross3
from optraj.errors import InvalidInputError
from optraj.problems.common import check_robot
from optraj.robots import Robot
from optraj.validation import as_flag, as_number

__all__ = ["PseudoInversePID"]

FloatArray = NDArray[np.float64]

#: Range of a non-zero damping [-]. Below 1e-6 the added ``lambda^2 = 1e-12`` is lost in
#: round-off against ``J J^T`` (entries of order 1 m^2), so a rank-deficient task is solved
#: as singular; above 1e3 ``lambda^2`` outweighs ``J J^T`` a million-fold and the command is
#: all but zero. 0 is the plain pseudo-inverse, which handles rank deficiency by its SVD.
MIN_DAMPING = 1e-6
MAX_DAMPING = 1e3


class PseudoInversePID(Controller):
    """Cartesian PID on the pose error plus feed-forward twist, mapped by ``J^+``.

    Args:
        robot: The robot.
        kp: Proportional gain [1/s]: scalar, [linear, angular] or per axis (6,).
        ki: Integral gain [1/s^2], same forms.
        kd: Derivative gain on the twist error [-], same forms.
        integral_limit: Anti-windup clamp of the integrated error [m s, rad s].
        damping: Damping ``lambda`` of the damped least-squares inverse [-], 0 or in
            [MIN_DAMPING, MAX_DAMPING]; 0 is the plain pseudo-inverse of the Sawyer exercise.
        task: ``"pose"`` (6-D) or ``"axis"`` (5-D: roll about the tool z axis is free; the
            Jacobian's angular rows are projected on the plane normal to the axis).
        feedforward: Whether the command carries the plan's feed-forward torque
            (``reference.tau``); False: ``Command.tau`` is None.

    Raises:
        InvalidInputError: A robot that is not a robots.Robot, a negative gain, a damping
            outside 0 or [MIN_DAMPING, MAX_DAMPING], or a switch that is not a bool.
        UnknownNameError: An unknown task.
    """

    def __init__(
        self,
        robot: Robot,
        kp: ArrayLike = 20.0,
        ki: ArrayLike = 5.0,
        kd: ArrayLike = 0.0,
        integral_limit: ArrayLike = (0.01, 0.05),
        damping: float = 0.0,
        task: Literal["pose", "axis"] = "pose",
        feedforward: bool = True,
    ) -> None:
        self.robot = check_robot(robot)
        self.pid = CartesianPID(kp, ki, kd, integral_limit, task)
        self.damping = as_number(damping, "damping", minimum=0.0, maximum=MAX_DAMPING)
        if 0.0 < self.damping < MIN_DAMPING:
            raise InvalidInputError(
                f"damping must be 0 (the plain pseudo-inverse) or >= {MIN_DAMPING:g}, got "
                f"{self.damping:.6g}",
                name="damping",
                value=damping,
            )
        self.feedforward = as_flag(feedforward, "feedforward")

    @property
    def name(self) -> str:
        """Short name for tables and plots."""
        return "pseudo-inverse PID" if self.damping == 0.0 else "damped pseudo-inverse PID"

    def reset(self, state: State) -> None:
        """Clear the PID integral."""
        self.pid.reset()

    def step(self, state: State, reference: Reference, dt: float) -> Command:
        """``qd = J^+ v_cmd``, with ``reference.tau`` fed forward; see the module docstring."""
        T, J = tool_kinematics(self.robot, state.q)
        v = self.pid.twist(T, J, state.qd, reference, dt)
        if self.pid.task == "axis":
            basis = _normal_basis(T[:3, 2])  # (2, 3): the two axes normal to the tool axis
            J = np.vstack([J[:3], basis @ J[3:]])
            v = np.concatenate([v[:3], basis @ v[3:]])
        if self.damping == 0.0:
            qd = np.linalg.pinv(J) @ v
        else:
            rows = J.shape[0]
            qd = J.T @ np.linalg.solve(J @ J.T + self.damping**2 * np.eye(rows), v)
        return Command(qd, tau=reference.tau if self.feedforward else None)


def _normal_basis(axis: FloatArray) -> FloatArray:
    """Two orthonormal vectors normal to a unit ``axis``, as rows, shape (2, 3)."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    first = cross3(axis, helper)
    first /= np.linalg.norm(first)
    return np.vstack([first, cross3(axis, first)])
