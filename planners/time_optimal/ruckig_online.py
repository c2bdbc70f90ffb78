"""Ruckig one control tick at a time, for controllers: :class:`OnlineRuckig`.

Each tick advances a jerk-limited motion towards a target state that may change between
ticks; Ruckig re-plans from the current state when it does. Start and target states are
checked as :func:`~planners.time_optimal.ruckig_move.state_to_state` checks them.
"""

from __future__ import annotations

import numpy as np
import ruckig
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, SolverError
from optraj.planners.time_optimal.ruckig_calculation import (
    USABLE_RESULTS,
    ruckig_error,
    ruckig_input,
)
from optraj.planners.time_optimal.ruckig_validation import (
    check_state,
    check_unsynchronised,
    checked_limits,
    state_or_zeros,
    synchronization_option,
)
from optraj.robots import JointLimits
from optraj.validation import as_duration, as_vector

__all__ = ["OnlineRuckig"]

FloatArray = NDArray[np.float64]


class OnlineRuckig:
    """Ruckig one control tick at a time: follow a (possibly changing) target state.

    Each :meth:`update` advances the jerk-limited motion by ``dt`` and returns the new
    commanded state; when the target changes, Ruckig re-plans from the current state.

    Example::

        online = OnlineRuckig(robot.limits, dt=1e-3)
        online.reset(q)
        while not online.finished:
            q, qd, qdd = online.update(q_target)

    Args:
        limits: Velocity, acceleration and jerk limits; targets are checked against all.
        dt: Control period [s], in [1e-6, 86400].
        synchronization: One of :data:`SYNCHRONIZATIONS`.

    Raises:
        InvalidInputError: Bad limits or period.
        UnknownNameError: An unknown synchronisation.
    """

    def __init__(self, limits: JointLimits, dt: float, *, synchronization: str = "time") -> None:
        self.limits = checked_limits(limits)
        self.dt = as_duration(dt, "dt")
        self.synchronization = synchronization
        self._sync = synchronization_option(synchronization)
        self._otg = ruckig.Ruckig(self.limits.n, self.dt)
        self._out = ruckig.OutputParameter(self.limits.n)
        self._inp: ruckig.InputParameter | None = None
        self._result: ruckig.Result | None = None

    def reset(
        self, q: ArrayLike, qd: ArrayLike | None = None, qdd: ArrayLike | None = None
    ) -> None:
        """Start from a joint state; rest when velocities and accelerations are not given.

        Args:
            q: Positions [rad or m], shape (n,).
            qd: Velocities [rad/s or m/s], shape (n,), or None.
            qdd: Accelerations [rad/s^2 or m/s^2], shape (n,), or None.

        Raises:
            InvalidInputError: Bad shapes or values.
            InfeasibleError: A state out of the limits.
            JointLimitError: A position outside the position limits.
        """
        n = self.limits.n
        position = as_vector(q, "q", n)
        self.limits.check_position(position, tolerance=1e-9, context="reset position")
        velocity, acceleration = state_or_zeros(qd, "qd", n), state_or_zeros(qdd, "qdd", n)
        check_state(velocity, acceleration, self.limits, "start", arriving=False)
        zeros = [0.0] * n
        self._inp = ruckig_input(
            self.limits,
            position,
            position,
            (velocity.tolist(), acceleration.tolist(), zeros, zeros),
            synchronization=self._sync,
            minimum_duration=None,
        )
        self._otg.reset()
        self._result = None

    def update(
        self,
        target_q: ArrayLike,
        target_qd: ArrayLike | None = None,
        target_qdd: ArrayLike | None = None,
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Advance one tick towards a target state.

        Args:
            target_q: Target positions [rad or m], shape (n,).
            target_qd: Target velocities [rad/s or m/s], shape (n,); rest when None.
            target_qdd: Target accelerations [rad/s^2 or m/s^2], shape (n,); zero when None.

        Returns:
            The new (q, qd, qdd) after ``dt``, each shape (n,).

        Raises:
            InvalidInputError: Bad shapes or values, :meth:`reset` was never called, or a
                moving target with synchronisation ``none``.
            InfeasibleError: A target state out of the limits or out of reach.
            JointLimitError: A target position outside the position limits.
            SolverError: Ruckig fails; carries its status.
        """
        if self._inp is None:
            raise InvalidInputError(
                "OnlineRuckig.update needs a start state: call reset(q) first", name="reset"
            )
        n = self.limits.n
        goal = as_vector(target_q, "target_q", n)
        self.limits.check_position(goal, tolerance=1e-9, context="target position")
        velocity = state_or_zeros(target_qd, "target_qd", n)
        acceleration = state_or_zeros(target_qdd, "target_qdd", n)
        check_unsynchronised(self.synchronization, velocity, acceleration)
        check_state(velocity, acceleration, self.limits, "target", arriving=True)
        self._inp.target_position = goal.tolist()
        self._inp.target_velocity = velocity.tolist()
        self._inp.target_acceleration = acceleration.tolist()
        try:
            result = self._otg.update(self._inp, self._out)
        except (ruckig.RuckigError, RuntimeError) as exc:
            raise ruckig_error(exc, self.limits) from exc
        if result not in USABLE_RESULTS:
            raise SolverError("ruckig", result.name, detail="online update failed")
        self._result = result
        self._out.pass_to_input(self._inp)
        return (
            np.array(self._out.new_position, dtype=float),
            np.array(self._out.new_velocity, dtype=float),
            np.array(self._out.new_acceleration, dtype=float),
        )

    @property
    def finished(self) -> bool:
        """Whether the last :meth:`update` reached the target state."""
        return self._result == ruckig.Result.Finished

    @property
    def time(self) -> float:
        """Time [s] along the current plan (reset when the target changes)."""
        return float(self._out.time)

    @property
    def duration(self) -> float:
        """Duration [s] of the current plan, from its last (re)calculation."""
        return float(self._out.trajectory.duration)
