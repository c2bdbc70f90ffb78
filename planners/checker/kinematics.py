"""Tool poses and twists at the instants the task constraints ask for, in one batched call.

Each constraint evaluator calls :meth:`ToolKinematics.need` with its instants while it is
prepared; :func:`planners.checker.check` then calls :meth:`ToolKinematics.compute` once (one
forward-kinematics call and one Jacobian call over every instant), and the evaluations read
:meth:`ToolKinematics.pose` and :meth:`ToolKinematics.twist` at the instants they asked for.

Example::

    kinematics = ToolKinematics(robot, derivatives_of(trajectory.coefficients, 1), knots)
    kinematics.need(times, twist=True)
    kinematics.compute()
    speed = np.linalg.norm(kinematics.twist(times)[:, :3], axis=1)   # [m/s]
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.planners.checker.polynomials import evaluate_piecewise
from optraj.robots import Robot

__all__ = ["ToolKinematics"]

FloatArray = NDArray[np.float64]


class ToolKinematics:
    """Tool poses and twists at every instant any constraint asks for, in one batched call."""

    def __init__(self, robot: Robot, derivatives: list[FloatArray], knots: FloatArray) -> None:
        self._robot = robot
        self._derivatives = derivatives
        self._knots = knots
        self._pose_requests: list[FloatArray] = [np.empty(0)]
        self._twist_requests: list[FloatArray] = [np.empty(0)]
        self._times = np.empty(0)
        self._poses = np.empty((0, 4, 4))
        self._twist_times = np.empty(0)
        self._twists = np.empty((0, 6))

    def need(self, times: ArrayLike, *, twist: bool = False) -> None:
        """Ask for the tool pose (and twist) at these times [s]."""
        values = np.atleast_1d(np.asarray(times, dtype=float))
        self._pose_requests.append(values)
        if twist:
            self._twist_requests.append(values)

    def compute(self) -> None:
        """Evaluate every requested pose and twist (one batched robot call each)."""
        self._times = np.unique(np.concatenate(self._pose_requests))
        if self._times.size:
            q = evaluate_piecewise(self._derivatives[0], self._knots, self._times)
            self._poses = self._robot.tool_pose(q)
        self._twist_times = np.unique(np.concatenate(self._twist_requests))
        if self._twist_times.size:
            q = evaluate_piecewise(self._derivatives[0], self._knots, self._twist_times)
            qd = evaluate_piecewise(self._derivatives[1], self._knots, self._twist_times)
            jac = self._robot.jacobian(q)
            self._twists = np.einsum("mij,mj->mi", jac, qd)

    @staticmethod
    def _index(table: FloatArray, times: ArrayLike) -> NDArray[np.intp]:
        values = np.atleast_1d(np.asarray(times, dtype=float))
        index = np.searchsorted(table, values)
        if np.any(index >= table.size) or np.any(
            table[np.minimum(index, table.size - 1)] != values
        ):
            raise RuntimeError("kinematics asked at an instant that was not requested")
        return index

    def pose(self, times: ArrayLike) -> FloatArray:
        """Tool poses ``T_world_tool`` at requested times, shape (m, 4, 4)."""
        return self._poses[self._index(self._times, times)]

    def twist(self, times: ArrayLike) -> FloatArray:
        """Tool twists ``[v; w]`` (origin velocity [m/s], angular velocity [rad/s]), (m, 6)."""
        return self._twists[self._index(self._twist_times, times)]
