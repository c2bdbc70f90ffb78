r"""The one face of every controller, and what it reads and returns.

A controller follows a planned :class:`planners.Trajectory`. At every control step it gets the
measured :class:`State`, the :class:`Reference` (the trajectory sampled at that time, with the
tool pose and twist) and the step length, and returns a :class:`Command`: a joint velocity,
and optionally a feed-forward joint torque that the plant adds to its servo torque.

>>> controller.reset(state)
>>> command = controller.step(state, reference, dt)
>>> command.qd    # joint velocity command [rad/s or m/s], shape (n,)
>>> command.tau   # feed-forward joint torque [N m or N], shape (n,), or None

:func:`sample_references` samples a trajectory once at every control time (batched forward
kinematics and inverse dynamics), so that neither is part of a controller's step time. The
plan's feed-forward torque is its inverse dynamics without gravity,

.. math:: \tau_{ff} = M(q_r) \ddot q_r + C(q_r, \dot q_r) \dot q_r
    = \mathrm{RNEA}(q_r, \dot q_r, \ddot q_r) - g(q_r),

since a plant compensates gravity at the measured configuration itself.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.planners.trajectory import TIME_TOLERANCE, Trajectory, fitted_to
from optraj.robots import Robot
from optraj.validation import as_array, as_vector, ndim_of

__all__ = [
    "Command",
    "Controller",
    "Reference",
    "References",
    "State",
    "as_gains",
    "cross3",
    "rotation_error",
    "sample_references",
]

FloatArray = NDArray[np.float64]


class State(NamedTuple):
    """What the controller measures at one instant.

    Attributes:
        t: Time [s].
        q: Joint positions [rad or m], shape (n,).
        qd: Joint velocities [rad/s or m/s], shape (n,).
    """

    t: float
    q: FloatArray
    qd: FloatArray


class Reference(NamedTuple):
    """The planned motion at one instant.

    Attributes:
        t: Time [s].
        q: Planned joint positions [rad or m], shape (n,).
        qd: Planned joint velocities [rad/s or m/s], shape (n,).
        qdd: Planned joint accelerations [rad/s^2 or m/s^2], shape (n,).
        T_world_tool: Planned tool pose, shape (4, 4).
        twist: Planned tool twist ``[v; omega]`` in world axes [m/s; rad/s], shape (6,);
            ``v`` is the velocity of the tool frame origin.
        phase: Name of the trajectory phase at ``t`` (``""`` when the trajectory has none).
        tau: Planned feed-forward joint torque [N m or N], shape (n,): the plan's inverse
            dynamics without gravity, ``rnea(q, qd, qdd) - g(q)``; None when not known (no
            feed-forward).
    """

    t: float
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    T_world_tool: FloatArray
    twist: FloatArray
    phase: str = ""
    tau: FloatArray | None = None


class Command(NamedTuple):
    """A controller's output for one step.

    Attributes:
        qd: Joint velocity command [rad/s or m/s], shape (n,).
        status: ``"ok"``, or ``"fallback: <reason>"`` when the controller could not compute
            its command and sent a safe one instead (held or decelerated).
        tau: Feed-forward joint torque [N m or N], shape (n,), that the plant adds to its
            servo torque on top of its own gravity compensation; None for none.
    """

    qd: FloatArray
    status: str = "ok"
    tau: FloatArray | None = None

    @property
    def fallback(self) -> bool:
        """Whether the command is a safe fallback rather than the controller's solution."""
        return self.status != "ok"


class Controller(ABC):
    """Base of every controller: ``reset(state)`` then ``step(state, reference, dt)``.

    Controllers keep their own memory (integrators, the last command, a warm start) and nothing
    global, so that one instance per simulation can be pickled and sent to a worker process.

    Attributes:
        robot: The robot being controlled.
    """

    robot: Robot

    @property
    def name(self) -> str:
        """Short name for tables and plots."""
        return type(self).__name__

    @abstractmethod
    def reset(self, state: State) -> None:
        """Forget the past: clear integrators and warm starts, take ``state`` as the start."""

    @abstractmethod
    def step(self, state: State, reference: Reference, dt: float) -> Command:
        """The joint velocity command for the next ``dt`` seconds.

        Args:
            state: The measured state now.
            reference: The planned motion now.
            dt: Control period [s], > 0.
        """


@dataclass(frozen=True)
class References:
    """A trajectory sampled at every control time, with the tool pose and twist.

    Attributes:
        t: Times [s], shape (m,).
        q: Joint positions, shape (m, n).
        qd: Joint velocities, shape (m, n).
        qdd: Joint accelerations, shape (m, n).
        T_world_tool: Tool poses, shape (m, 4, 4).
        twist: Tool twists ``[v; omega]`` in world axes, shape (m, 6).
        phase: Phase name at each time, length m.
        tau: Feed-forward joint torques [N m or N], shape (m, n): the plan's inverse dynamics
            without gravity (see :class:`Reference`); None when not known.
    """

    t: FloatArray
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    T_world_tool: FloatArray
    twist: FloatArray
    phase: tuple[str, ...]
    tau: FloatArray | None = None

    def __len__(self) -> int:
        return int(self.t.size)

    def __getitem__(self, k: int) -> Reference:
        return Reference(
            float(self.t[k]),
            self.q[k],
            self.qd[k],
            self.qdd[k],
            self.T_world_tool[k],
            self.twist[k],
            self.phase[k],
            None if self.tau is None else self.tau[k],
        )


def as_gains(
    value: ArrayLike,
    name: str,
    size: int,
    *,
    unit: str = "",
    halves: tuple[str, str] | None = None,
) -> FloatArray:
    """Non-negative gains, one per joint or axis, shape (size,).

    Args:
        value: A scalar (the same for all), ``size`` values, or with ``halves`` two values,
            one for each half of the axes (e.g. ``("linear", "angular")``).
        name: Argument name for the error message.
        size: How many gains.
        unit: Unit for the error message, e.g. ``"[1/s]"``.
        halves: Names of the two halves, to accept the two-value form.

    Raises:
        InvalidInputError: Another number of values, negative or non-finite entries.
    """
    shape: tuple[None, ...] = () if ndim_of(value) == 0 else (None,)
    array = np.atleast_1d(as_array(value, name, shape))
    if array.size == 1:
        array = np.full(size, array[0])
    elif halves is not None and array.size == 2:
        array = np.repeat(array, size // 2)
    if array.size != size:
        forms = (
            f"a scalar, [{halves[0]}, {halves[1]}] or {size} values"
            if halves is not None
            else f"a scalar or one gain per joint ({size})"
        )
        raise InvalidInputError(f"{name} must be {forms}, got {array.size} values", name=name)
    if np.any(array < 0.0):
        text = np.array2string(array, precision=4)
        raise InvalidInputError(f"{name} must be >= 0 {unit}, got {text}".strip(), name=name)
    return array


def sample_references(robot: Robot, trajectory: Trajectory, times: ArrayLike) -> References:
    """Sample a trajectory with its tool pose, twist and feed-forward torque at the given times.

    Args:
        robot: The robot the trajectory is for.
        trajectory: The planned trajectory.
        times: Times [s], within [0, duration], shape (m,).

    Raises:
        InvalidInputError: The trajectory's joint count differs from the robot's, a time
            lies outside the trajectory, or the inverse dynamics overflowed.
    """
    fitted_to(trajectory, robot)
    t = as_vector(times, "times")
    sample = trajectory.sample(t)
    poses = robot.tool_pose(sample.q)
    jacobians = robot.jacobian(sample.q)
    twists = np.einsum("mij,mj->mi", jacobians, sample.qd)
    torques = robot.inverse_dynamics(sample.q, sample.qd, sample.qdd) - robot.gravity_torque(
        sample.q
    )
    names = [""] * t.size
    for phase in trajectory.phases:  # later phases win at shared boundaries
        inside = np.flatnonzero(
            (t >= phase.t_start - TIME_TOLERANCE) & (t <= phase.t_end + TIME_TOLERANCE)
        )
        for k in inside:
            names[k] = phase.name
    return References(
        t=np.asarray(sample.t, dtype=float),
        q=sample.q,
        qd=sample.qd,
        qdd=sample.qdd,
        T_world_tool=poses,
        twist=twists,
        phase=tuple(names),
        tau=torques,
    )


def rotation_error(R_desired: FloatArray, R: FloatArray) -> FloatArray:
    r"""Rotation vector that turns ``R`` into ``R_desired``, in world axes [rad], shape (3,).

    .. math:: e_R = \log(R_d R^T)^\vee

    Its norm is the angle between the two orientations (Pinocchio's ``log3``, exact near 0
    and pi).
    """
    return np.asarray(pin.log3(R_desired @ R.T))


def cross3(a: FloatArray, b: FloatArray) -> FloatArray:
    """Cross product of two 3-vectors, shape (3,); a tenth of ``np.cross``'s time on one pair."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])
