r"""Simulated robots that a controller's joint-velocity command drives.

A :class:`Plant` holds the true joint state of a simulated arm. ``reset(q)`` places it,
``step(command, dt)`` advances it by ``dt`` seconds under a joint velocity command held constant
over the step (zero-order hold), optionally with a feed-forward joint torque added to the
servo's and a force pushing on the tool, and returns the new :class:`PlantState`.

* :class:`KinematicPlant`: every joint velocity follows its command as a first-order lag (an
  ideal velocity servo with a time constant), integrated exactly; a feed-forward torque
  changes nothing (the ideal servo needs none). Torques are only reported, as the inverse
  dynamics of the realised motion.
* :class:`DynamicPlant`: rigid-body dynamics (Pinocchio's ABA) driven by a decentralised
  velocity servo per joint with gravity compensation and the feed-forward torque,

  .. math:: \tau = g(q) + \tau_{ff} + b \, \mathrm{diag}(M(q)) \, (u - \dot q),

  clipped to the effort limits.

>>> plant = KinematicPlant(robot)
>>> state = plant.reset(robot.home)
>>> state = plant.step(command_qd, dt=1e-3, torque=feedforward_tau)
>>> state.q, state.qd, state.tau

Plants that simulate more than the arm (a ball, contacts) hand it over in :meth:`Plant.record`,
which :func:`~controllers.simulation.simulate` stores in ``Result.record`` after the run.

Plants keep their own state and nothing global; they pickle with their robot, so one plant per
simulation can be sent to a worker process.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import Any, NamedTuple

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.robots import Robot
from optraj.validation import as_array, as_flag, as_number, as_positive, as_vector

__all__ = [
    "DynamicPlant",
    "KinematicPlant",
    "Plant",
    "PlantState",
    "frozen_state",
    "tool_force_to_joint_velocity",
]

FloatArray = NDArray[np.float64]

_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

# Chosen default: more substeps than this in one step means dt is far too long for the plant
# (a step of minutes); refusing it keeps a typo from hanging the simulation.
_MAX_SUBSTEPS = 1_000_000


class PlantState(NamedTuple):
    """The true state of a simulated arm after a step (or a reset).

    The arrays are read-only: they are the plant's own state.

    Attributes:
        q: Joint positions [rad or m], shape (n,).
        qd: Joint velocities [rad/s or m/s], shape (n,).
        qdd: Mean joint acceleration over the last step, ``(qd_new - qd_old) / dt``
            [rad/s^2 or m/s^2], shape (n,); zeros after a reset.
        tau: Joint torques [N m] / forces [N] over the last step, shape (n,): the mean applied
            actuator torque for :class:`DynamicPlant`; for :class:`KinematicPlant` the inverse
            dynamics of the realised motion (what the motion needs). Zeros after a reset.
        saturated: Whether any joint torque was clipped to its effort limit during the step
            (always False for :class:`KinematicPlant`).
    """

    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    tau: FloatArray
    saturated: bool


class Plant(ABC):
    """Base of every simulated robot: ``reset(q)`` then ``step(command, dt)``.

    Attributes:
        robot: The simulated robot.
    """

    robot: Robot

    def __init__(self, robot: Robot) -> None:
        if not isinstance(robot, Robot):
            raise InvalidInputError(
                f"robot must be a robots.Robot, got {type(robot).__name__}", name="robot"
            )
        self.robot = robot
        self._state: PlantState | None = None

    @property
    def name(self) -> str:
        """Short name for tables and plots."""
        return type(self).__name__

    @property
    def state(self) -> PlantState:
        """The current state.

        Raises:
            InvalidInputError: The plant has not been reset yet.
        """
        if self._state is None:
            raise InvalidInputError(
                f"{self.name} has no state yet: call reset(q) before step or state",
                name="state",
            )
        return self._state

    def reset(self, q: ArrayLike, qd: ArrayLike | None = None) -> PlantState:
        """Place the arm at ``q`` moving at ``qd``, and forget the last step.

        Args:
            q: Joint positions [rad or m], shape (n,).
            qd: Joint velocities [rad/s or m/s], shape (n,); zeros when None.

        Returns:
            The new state, with zero acceleration and torque.

        Raises:
            InvalidInputError: Wrong shapes or non-finite entries.
        """
        n = self.robot.dof
        position = as_vector(q, "q", n)
        velocity = np.zeros(n) if qd is None else as_vector(qd, "qd", n)
        self._state = frozen_state(position, velocity, np.zeros(n), np.zeros(n), False)
        return self._state

    @abstractmethod
    def step(
        self,
        command: ArrayLike,
        dt: float,
        tool_force: ArrayLike | None = None,
        torque: ArrayLike | None = None,
    ) -> PlantState:
        """Advance the simulation by ``dt`` under a constant joint velocity command.

        Args:
            command: Joint velocity command [rad/s or m/s], shape (n,), held over the step.
            dt: Step length [s], > 0.
            tool_force: Force [N] in world axes applied at the tool frame origin during the
                whole step, shape (3,); None for no force.
            torque: Feed-forward joint torque [N m or N], shape (n,), held over the step and
                added to the servo's torque (on top of its gravity compensation); None for
                none.

        Returns:
            The state at the end of the step.

        Raises:
            InvalidInputError: Bad input, ``step`` before ``reset``, or a diverged simulation.
        """

    def record(self) -> dict[str, Any]:
        """What the plant simulates beyond the joint state, for ``Result.record``.

        :func:`~controllers.simulation.simulate` calls it once at the end of a run. A plant
        that simulates more than the arm (a ball it hits, contacts) returns it here by name;
        the base plants have nothing more and return an empty dict.
        """
        return {}

    def _begin_step(
        self,
        command: ArrayLike,
        dt: float,
        tool_force: ArrayLike | None,
        torque: ArrayLike | None = None,
    ) -> tuple[PlantState, FloatArray, float, FloatArray | None, FloatArray | None]:
        """Check a step's inputs cheaply; return the state, command, dt, force and torque."""
        state = self.state
        n = self.robot.dof
        command = _checked_vector(command, "command", n)
        if not (
            type(dt) is float and math.isfinite(dt) and dt > 0.0  # fast path for plain floats
        ):
            dt = as_positive(dt, "dt", "s")
        force = None if tool_force is None else as_array(tool_force, "tool_force", (3,))
        feedforward = None if torque is None else _checked_vector(torque, "torque", n)
        return state, command, dt, force, feedforward


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
            qd0 = qd0 + _impulse_response(
                model, data, state.q, self.robot.tool_frame_id, force * dt
            )
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


def tool_force_to_joint_velocity(robot: Robot, q: ArrayLike, impulse: ArrayLike) -> FloatArray:
    r"""Joint velocity change caused by an impulse on the tool frame origin.

    A rigid arm hit by the impulse :math:`p` at the tool frame origin changes its joint
    velocity by

    .. math:: \Delta \dot q = M(q)^{-1} J_{lin}(q)^T p,

    with :math:`M` the joint-space inertia matrix and :math:`J_{lin}` the world-aligned linear
    rows of the tool Jacobian (all other forces are finite, so they add nothing over an
    instant).

    Args:
        robot: The robot.
        q: Joint positions [rad or m], shape (n,).
        impulse: Impulse [N s] in world axes, shape (3,).

    Returns:
        The joint velocity change [rad/s or m/s], shape (n,).

    Raises:
        InvalidInputError: Wrong shapes or non-finite entries.
    """
    position = as_vector(q, "q", robot.dof)
    p = as_array(impulse, "impulse", (3,))
    return _impulse_response(robot.model, robot.data, position, robot.tool_frame_id, p)


def _impulse_response(
    model: pin.Model, data: pin.Data, q: FloatArray, frame_id: int, impulse: FloatArray
) -> FloatArray:
    """``M(q)^{-1} J_lin(q)^T impulse`` without input checks, shape (n,)."""
    upper = pin.crba(model, data, q)
    inertia = np.triu(upper) + np.triu(upper, 1).T  # some Pinocchio versions fill only triu
    jac = pin.computeFrameJacobian(model, data, q, frame_id, _WORLD_ALIGNED)
    return np.linalg.solve(inertia, jac[:3].T @ impulse)


def _checked_vector(value: ArrayLike, name: str, n: int) -> FloatArray:
    """``value`` as a finite float64 vector of shape (n,); a fast path for one already."""
    if (
        isinstance(value, np.ndarray)
        and value.dtype == np.float64
        and value.shape == (n,)
        and np.isfinite(value).all()
    ):
        return value
    return as_vector(value, name, n)


def frozen_state(
    q: FloatArray, qd: FloatArray, qdd: FloatArray, tau: FloatArray, saturated: bool
) -> PlantState:
    """A PlantState owning read-only copies of the arrays it is given."""
    arrays = [np.array(a, dtype=float) for a in (q, qd, qdd, tau)]
    for a in arrays:
        a.setflags(write=False)
    return PlantState(arrays[0], arrays[1], arrays[2], arrays[3], bool(saturated))


def _describe(values: FloatArray) -> str:
    return np.array2string(values, precision=4, threshold=12)
