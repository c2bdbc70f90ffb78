r"""The Cartesian PID law that both Cartesian controllers share: pose error to a tool twist.

.. math::

    e = \begin{bmatrix} p_d - p \\ \log(R_d R^T)^\vee \end{bmatrix}, \qquad
    v_{cmd} = v_d + K_P e + K_I \int e \, dt + K_D (v_d - J \dot q)

in world axes, ``[linear [m/s]; angular [rad/s]]``. The integral is clamped per axis
(anti-windup). For a tool whose roll about its own z axis is free (a cue), ``task="axis"``
corrects only the direction of that axis.

Also here: :func:`tool_kinematics`, the tool pose and Jacobian in one Pinocchio pass.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.controllers.controller import Reference, as_gains, cross3, rotation_error
from optraj.robots import Robot
from optraj.validation import as_choice, as_vector

__all__ = ["AXIS_SINE", "TASKS", "CartesianPID", "tool_kinematics"]

FloatArray = NDArray[np.float64]

#: Task kinds: the full pose (6-D), or position plus tool axis with free roll (5-D).
TASKS: tuple[str, ...] = ("pose", "axis")
#: Smallest ``|z x z_d|`` [-] with a defined correction axis in the 5-D task; below it the
#: axes are parallel (or opposite) and the raw cross product is used.
AXIS_SINE = 1e-12
_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_HALVES = ("linear", "angular")


def tool_kinematics(robot: Robot, q: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Tool pose and world-aligned Jacobian from one forward pass.

    Args:
        robot: The robot.
        q: Joint positions [rad or m], shape (n,); not validated (hot path).

    Returns:
        ``T_world_tool`` shape (4, 4) and ``J`` shape (6, n), rows [linear; angular].
    """
    model, data, fid = robot.model, robot.data, robot.tool_frame_id
    pin.computeJointJacobians(model, data, q)
    T = pin.updateFramePlacement(model, data, fid).homogeneous
    J = pin.getFrameJacobian(model, data, fid, _WORLD_ALIGNED)
    return T, J


def check_task(task: str) -> str:
    """Validate a task name (``"pose"`` or ``"axis"``)."""
    return as_choice(task, "task", TASKS)


class CartesianPID:
    """Pose error to commanded tool twist, with feed-forward and a clamped integral.

    Args:
        kp: Proportional gain [1/s]: scalar, [linear, angular] or per axis (6,).
        ki: Integral gain [1/s^2], same forms; 0 turns the integral off.
        kd: Derivative gain on the twist error [-], same forms.
        integral_limit: Largest magnitude of each integrated error component, as
            [linear [m s], angular [rad s]] or per axis (6,).
        task: ``"pose"`` (6-D) or ``"axis"``: only the tool z axis is corrected, not the roll
            about it.

    Raises:
        InvalidInputError: A negative or malformed gain.
        UnknownNameError: An unknown task.
    """

    def __init__(
        self,
        kp: ArrayLike = 20.0,
        ki: ArrayLike = 0.0,
        kd: ArrayLike = 0.0,
        integral_limit: ArrayLike = (0.01, 0.05),
        task: Literal["pose", "axis"] = "pose",
    ) -> None:
        self.kp = as_gains(kp, "kp", 6, unit="[1/s]", halves=_HALVES)
        self.ki = as_gains(ki, "ki", 6, unit="[1/s^2]", halves=_HALVES)
        self.kd = as_gains(kd, "kd", 6, unit="[-]", halves=_HALVES)
        self.integral_limit = as_gains(
            integral_limit, "integral_limit", 6, unit="[m s or rad s]", halves=_HALVES
        )
        self.task = check_task(task)
        self._integrate = bool(self.ki.any())
        self._derivative = bool(self.kd.any())
        self._integral_floor = -self.integral_limit
        self._integral = np.zeros(6)

    def reset(self, integral: ArrayLike | None = None) -> None:
        """Clear the integral, or start it from ``integral``.

        Args:
            integral: The integrated pose error to continue from [m s; rad s], shape (6,)
                (taken as given, not clamped); None for zeros.

        Raises:
            InvalidInputError: ``integral`` of another shape or not finite.
        """
        self._integral = np.zeros(6) if integral is None else as_vector(integral, "integral", 6)

    @property
    def integral(self) -> FloatArray:
        """The clamped integral of the pose error [m s; rad s], shape (6,) (a copy)."""
        return self._integral.copy()

    def error(self, T_world_tool: FloatArray, reference: Reference) -> FloatArray:
        """Pose error ``[p_d - p; log(R_d R^T)]`` in world axes [m; rad], shape (6,).

        With ``task="axis"`` the angular part is the rotation that turns the tool z axis onto
        the planned one about their common normal, ``(z x z_d) angle / |z x z_d|``; it does
        not depend on either roll.
        """
        error = np.empty(6)
        error[:3] = reference.T_world_tool[:3, 3] - T_world_tool[:3, 3]
        if self.task == "axis":
            z, z_d = T_world_tool[:3, 2], reference.T_world_tool[:3, 2]
            normal = cross3(z, z_d)
            sine = math.sqrt(float(normal @ normal))
            angle = math.atan2(sine, float(z @ z_d))
            error[3:] = normal * (angle / sine) if sine > AXIS_SINE else normal
        else:
            error[3:] = rotation_error(reference.T_world_tool[:3, :3], T_world_tool[:3, :3])
        return error

    def twist(
        self,
        T_world_tool: FloatArray,
        J: FloatArray,
        qd: FloatArray,
        reference: Reference,
        dt: float,
    ) -> FloatArray:
        """Commanded tool twist ``[v; omega]`` in world axes [m/s; rad/s], shape (6,).

        Args:
            T_world_tool: Measured tool pose, shape (4, 4).
            J: Jacobian at the measured configuration, shape (6, n).
            qd: Measured joint velocities, shape (n,) (used by the derivative term only).
            reference: The planned motion now.
            dt: Control period [s] (integration step of the integral).
        """
        error = self.error(T_world_tool, reference)
        command = reference.twist + self.kp * error
        if self._integrate:
            integral = np.maximum(self._integral + error * dt, self._integral_floor)
            self._integral = np.minimum(integral, self.integral_limit, out=integral)
            command += self.ki * self._integral
        if self._derivative:
            command += self.kd * (reference.twist - J @ qd)
        return command
