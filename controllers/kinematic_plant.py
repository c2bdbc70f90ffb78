r"""The kinematic plant: ideal velocity servos, each joint a first-order lag.

:class:`KinematicPlant` integrates the lag exactly, so its motion does not depend on how it is
cut into steps; it reports torques as the inverse dynamics of the realised motion.

>>> plant = KinematicPlant(robot, time_constant=0.005)
>>> state = plant.reset(robot.home)
>>> state = plant.step(command_qd, dt=1e-3)
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from optraj.controllers.plant import (
    FloatArray,
    Plant,
    PlantState,
    frozen_state,
    impulse_response,
)
from optraj.errors import InvalidInputError
from optraj.robots import Robot
from optraj.validation import as_number

__all__ = ["KinematicPlant"]


class KinematicPlant(Plant):
    r"""Ideal velocity servos: each joint velocity follows its command as a first-order lag.

    With the command :math:`u` held over a step of length :math:`\Delta t` and the time constant
    :math:`T`, the exact solution from :math:`(q_0, \dot q_0)` is

    .. math::

        \dot q(t) = u + (\dot q_0 - u) e^{-t/T}, \qquad
        q(\Delta t) = q_0 + u \Delta t + (\dot q_0 - u) T (1 - e^{-\Delta t/T}),

    so the result does not depend on how a motion is cut into steps. A tool force :math:`F`
    acts as the impulse :math:`F \Delta t` at the start of the step
    (:func:`tool_force_to_joint_velocity`); the servo then pulls the velocity back to the
    command. A feed-forward ``torque`` is checked and otherwise ignored: the ideal servo
    realises the commanded velocity whatever the torque it takes. Torques are reported as the
    inverse dynamics of the realised motion.

    Attributes:
        robot: The simulated robot.
        time_constant: Velocity servo time constant [s], >= 0; 0 makes the joint velocity equal
            the command exactly (and makes tool forces have no effect).
    """

    def __init__(self, robot: Robot, time_constant: float = 0.005) -> None:
        """Build the plant.

        Args:
            robot: The robot to simulate.
            time_constant: Velocity servo time constant [s], finite and >= 0. The default
                5 ms is a chosen default: an assumed stiff industrial velocity loop, not a
                value measured on any of the robots.

        Raises:
            InvalidInputError: ``time_constant`` negative or not finite.
        """
        super().__init__(robot)
        self.time_constant = as_number(time_constant, "time_constant", "s", minimum=0.0)

    @property
    def name(self) -> str:
        """Short name for tables and plots."""
        return "kinematic"

    def step(
        self,
        command: ArrayLike,
        dt: float,
        tool_force: ArrayLike | None = None,
        torque: ArrayLike | None = None,
    ) -> PlantState:
        """Advance by ``dt`` [s] under the joint velocity ``command``; see :meth:`Plant.step`.

        ``torque`` is validated but does not change the motion (an ideal velocity servo).
        """
        state, u, dt, force, _ = self._begin_step(command, dt, tool_force, torque)
        model, data = self.robot.model, self.robot.data
        qd0 = state.qd
        if force is not None:
            qd0 = qd0 + impulse_response(model, data, state.q, self.robot.tool_frame_id, force * dt)
        T = self.time_constant
        if T > 0.0:
            alpha = -math.expm1(-dt / T)  # 1 - exp(-dt/T), accurate for dt << T
            qd = qd0 + alpha * (u - qd0)
            q = state.q + u * dt + (qd0 - u) * (T * alpha)
        else:
            qd = u.copy()
            q = state.q + u * dt
        qdd = (qd - state.qd) / dt
        tau = np.array(pin.rnea(model, data, q, qd, qdd))  # = robot.inverse_dynamics(q, qd, qdd)
        if not (np.isfinite(q).all() and np.isfinite(tau).all()):
            raise InvalidInputError(
                f"the kinematic simulation overflowed with dt = {dt:.6g} s; the command "
                f"{_describe(u)} is far beyond anything physical",
                name="command",
                value=u,
            )
        self._state = frozen_state(q, qd, qdd, tau, False)
        return self._state


def _describe(values: FloatArray) -> str:
    return np.array2string(values, precision=4, threshold=12)
