r"""The dynamic plant: rigid-body dynamics under a velocity servo per joint.

:class:`DynamicPlant` integrates Pinocchio's ABA by semi-implicit Euler substeps, with each
joint's actuator torque the servo law (gravity compensation, a feed-forward torque and a
velocity error gain scaled by the joint's own inertia), clipped to the effort limits.

>>> plant = DynamicPlant(robot, bandwidth=200.0)
>>> state = plant.reset(robot.home)
>>> state = plant.step(command_qd, dt=1e-3, torque=feedforward_tau)
>>> state.saturated
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike

from optraj.controllers.plant import Plant, PlantState, frozen_state
from optraj.errors import InvalidInputError
from optraj.robots import Robot
from optraj.validation import as_flag, as_positive

__all__ = ["DynamicPlant"]

_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

# Chosen default: more substeps than this in one step means dt is far too long for the plant
# (a step of minutes); refusing it keeps a typo from hanging the simulation.
_MAX_SUBSTEPS = 1_000_000


class DynamicPlant(Plant):
    r"""Rigid-body dynamics driven by a decentralised velocity servo per joint.

    Each joint's actuator applies, with gravity compensation and the feed-forward torque
    :math:`\tau_{ff}` of the step (zero when none is given),

    .. math:: \tau = g(q) + \tau_{ff} + b \, \mathrm{diag}(M(q)) \, (u - \dot q),

    clipped to the effort limits when ``saturate``; the arm then moves by Pinocchio's ABA,
    :math:`\ddot q = M^{-1}(\tau + J_{lin}^T F - C \dot q - g)`, integrated with equal
    substeps of semi-implicit Euler (:math:`\dot q \mathrel{+}= \ddot q h`, then
    :math:`q \mathrel{+}= \dot q h`). Coriolis forces and the inertia coupling between joints
    are not compensated by the servo: they disturb it as they would on a real arm, unless the
    feed-forward carries them (a plan's :math:`M \ddot q + C \dot q`, its inverse dynamics
    without gravity, makes a servo commanded with the plan's velocity follow it closely).

    On a single joint the loop is a first-order lag with time constant :math:`1/b`; on the arm
    the coupled modes settle with rates :math:`b \lambda_i`, with :math:`\lambda_i` the
    eigenvalues of :math:`M^{-1} \mathrm{diag}(M)` (between about 0.26 and 24 for Sawyer, by
    sampling 2000 random configurations). Semi-implicit Euler is stable while
    :math:`b \lambda_{max} h < 2`; the defaults give 200 * 24 * 2.5e-4 = 1.2.

    Attributes:
        robot: The simulated robot.
        bandwidth: Servo bandwidth :math:`b` [rad/s], > 0.
        max_substep: Longest integration substep [s], > 0.
        saturate: Whether actuator torques are clipped to ``robot.limits.effort``.
    """

    def __init__(
        self,
        robot: Robot,
        bandwidth: float = 200.0,
        max_substep: float = 2.5e-4,
        saturate: bool = True,
    ) -> None:
        """Build the plant.

        Args:
            robot: The robot to simulate.
            bandwidth: Servo bandwidth [rad/s], > 0. The default 200 rad/s is a chosen
                default: the 5 ms time constant of :class:`KinematicPlant`, so that both plants
                agree closely on smooth motions that do not saturate (least on a light joint
                that the inertia coupling with a heavy one disturbs, such as paddle4's last).
            max_substep: Longest integration substep [s], > 0 (chosen default 0.25 ms: four
                substeps per 1 ms control step, stable for the default bandwidth).
            saturate: Clip the actuator torques to the robot's effort limits.

        Raises:
            InvalidInputError: ``bandwidth`` or ``max_substep`` not finite and positive.
        """
        super().__init__(robot)
        self.bandwidth = as_positive(bandwidth, "bandwidth", "rad/s")
        self.max_substep = as_positive(max_substep, "max_substep", "s")
        self.saturate = as_flag(saturate, "saturate")

    @property
    def name(self) -> str:
        """Short name for tables and plots."""
        return "dynamic"

    def step(
        self,
        command: ArrayLike,
        dt: float,
        tool_force: ArrayLike | None = None,
        torque: ArrayLike | None = None,
    ) -> PlantState:
        """Advance by ``dt`` [s] under the joint velocity ``command``; see :meth:`Plant.step`.

        ``torque`` is added to the servo torque before it is clipped to the effort limits.
        """
        state, u, dt, force, feedforward = self._begin_step(command, dt, tool_force, torque)
        ratio = dt / self.max_substep
        if ratio > _MAX_SUBSTEPS:
            raise InvalidInputError(
                f"dt = {dt:.6g} s would need {math.ceil(ratio)} substeps of at most "
                f"{self.max_substep:.6g} s (limit {_MAX_SUBSTEPS}); take shorter steps",
                name="dt",
                value=dt,
            )
        # The tiny shrink keeps rounding (1e-3 / 2.5e-4 = 4.000...01) from adding a substep.
        substeps = max(1, math.ceil(ratio * (1.0 - 1e-12)))
        h = dt / substeps
        model, data = self.robot.model, self.robot.data
        effort = self.robot.limits.effort
        fid = self.robot.tool_frame_id
        gain = self.bandwidth
        q, qd = state.q, state.qd
        tau_sum = np.zeros_like(q)
        saturated = False
        for _ in range(substeps):
            tau = pin.computeGeneralizedGravity(model, data, q) + gain * np.diag(
                pin.crba(model, data, q)
            ) * (u - qd)
            if feedforward is not None:
                tau += feedforward
            if self.saturate:
                clipped = np.clip(tau, -effort, effort)
                saturated = saturated or bool((clipped != tau).any())
                tau = clipped
            tau_sum += tau
            if force is not None:
                jac = pin.computeFrameJacobian(model, data, q, fid, _WORLD_ALIGNED)
                tau = tau + jac[:3].T @ force
            qdd = pin.aba(model, data, q, qd, tau)
            qd = qd + h * qdd
            q = q + h * qd
        if not (np.isfinite(q).all() and np.isfinite(qd).all()):
            raise InvalidInputError(
                f"the dynamic simulation diverged with dt = {dt:.6g} s in {substeps} substeps "
                f"of {h:.6g} s (bandwidth {gain:.6g} rad/s); use a shorter max_substep or a "
                "lower bandwidth",
                name="dt",
                value=dt,
            )
        qdd_mean = (qd - state.qd) / dt
        self._state = frozen_state(q, qd, qdd_mean, tau_sum / substeps, saturated)
        return self._state
