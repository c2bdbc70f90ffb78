r"""Simulated robots that a controller's joint-velocity command drives.

A :class:`Plant` holds the true joint state of a simulated arm. ``reset(q)`` places it,
``step(command, dt)`` advances it by ``dt`` seconds under a joint velocity command held constant
over the step (zero-order hold), optionally with a feed-forward joint torque added to the
servo's and a force pushing on the tool, and returns the new :class:`PlantState`.

* :class:`KinematicPlant` (:mod:`controllers.kinematic_plant`): every joint velocity
  follows its command as a first-order lag (an ideal velocity servo with a time constant),
  integrated exactly; a feed-forward torque changes nothing (the ideal servo needs none).
  Torques are only reported, as the inverse dynamics of the realised motion.
* :class:`DynamicPlant` (:mod:`controllers.dynamic_plant`): rigid-body dynamics (Pinocchio's
  ABA) driven by a decentralised velocity servo per joint with gravity compensation and the
  feed-forward torque,

  .. math:: \tau = g(q) + \tau_{ff} + b \, \mathrm{diag}(M(q)) \, (u - \dot q),

  clipped to the effort limits.

>>> plant = KinematicPlant(robot)
>>> state = plant.reset(robot.home)
>>> state = plant.step(command_qd, dt=1e-3, torque=feedforward_tau)
>>> state.q, state.qd, state.tau

Plants that simulate more than the arm (a ball, contacts) hand it over in :meth:`Plant.record`,
which :func:`~controllers.simulation.simulate` stores in ``Result.record`` after the run.

This module holds what every plant shares (:class:`Plant`, :class:`PlantState`,
:func:`frozen_state`, the tool impulse response) and re-exports the two concrete plants.

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
from optraj.validation import as_array, as_positive, as_vector

__all__ = [
    "Plant",
    "PlantState",
    "frozen_state",
    "impulse_response",
    "tool_force_to_joint_velocity",
]

FloatArray = NDArray[np.float64]

_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


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
    return impulse_response(robot.model, robot.data, position, robot.tool_frame_id, p)


def impulse_response(
    model: pin.Model, data: pin.Data, q: FloatArray, frame_id: int, impulse: FloatArray
) -> FloatArray:
    """Joint velocity change ``M(q)^{-1} J_lin(q)^T impulse`` [rad/s or m/s], without checks.

    The core of :func:`tool_force_to_joint_velocity` for a plant's step, whose inputs are
    checked already.

    Args:
        model: The robot's Pinocchio model.
        data: Its Pinocchio data (overwritten).
        q: Joint positions [rad or m], finite, shape (n,).
        frame_id: Pinocchio id of the frame whose origin takes the impulse.
        impulse: Impulse [N s] in world axes, finite, shape (3,).

    Returns:
        The joint velocity change, shape (n,).
    """
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
