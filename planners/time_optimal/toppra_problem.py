"""A TOPPRA problem, validated and ready to solve: the path, its grid, limits and end speeds.

:meth:`Toppra.build <planners.time_optimal.toppra_planner.Toppra.build>` makes a
:class:`ToppraProblem`; :meth:`ToppraProblem.constraints` gives the toppra constraints it is
solved under, with every rate limit shrunk by :data:`MARGIN` unless told otherwise.

Example::

    problem = Toppra().build(waypoints, robot.limits)
    problem.grid                 # gridpoints [path units], every knot of the path among them
    problem.constraints()        # toppra constraint objects (imports toppra)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.planners.time_optimal.toppra_constraints import (
    joint_speed_rates,
    tool_speed_rates,
    torque_constraint,
)
from optraj.planners.time_optimal.toppra_path import GeometricPath, toppra_classes
from optraj.robots import JointLimits, Robot

__all__ = ["MARGIN", "ToppraProblem", "initial_scale"]

FloatArray = NDArray[np.float64]

#: Fraction by which every rate limit (velocity, acceleration, torque, tool speed) is shrunk
#: before solving, to absorb toppra's small excess between gridpoints [-].
MARGIN = 1e-3


@dataclass(frozen=True, eq=False)
class ToppraProblem:
    """A validated TOPPRA problem, ready for :meth:`Toppra.solve` and open to inspection.

    Attributes:
        path: The geometric path.
        limits: The limits the result must respect.
        grid: Gridpoints [path units], shape (N + 1,); every knot of the path is one.
        sd_start: Path velocity at the start [path units/s], >= 0.
        sd_end: Path velocity at the end [path units/s], >= 0.
        robot: The robot (torque limits, tool speed cap), or None.
        torque: Whether the joint torque limits (``limits.effort``) apply.
        tool_speed: Cap on the tool frame origin's speed [m/s], or None.
        phases: Named windows of the result as path positions (name, s_start, s_end).
        segment: The path segment of each grid interval, shape (N,).
    """

    path: GeometricPath
    limits: JointLimits
    grid: FloatArray
    sd_start: float
    sd_end: float
    robot: Robot | None
    torque: bool
    tool_speed: float | None
    phases: tuple[tuple[str, float, float], ...]
    segment: NDArray[np.intp]

    @property
    def moving(self) -> bool:
        """Whether the motion starts or ends with a non-zero path velocity."""
        return self.sd_start > 0.0 or self.sd_end > 0.0

    def constraints(self, scale: dict[str, float] | None = None) -> list[Any]:
        """The toppra constraints, each rate limit multiplied by its factor in ``scale``.

        Args:
            scale: Factor per quantity (``"velocity"``, ``"acceleration"``, ``"torque"``,
                ``"tool speed"``); 1 - :data:`MARGIN` for those not given.
        """
        factor = initial_scale(self)
        factor.update(scale or {})
        lib = toppra_classes()

        limits = self.limits
        constraints = [
            lib.SpeedConstraint(joint_speed_rates(limits.velocity * factor["velocity"]), limits.n),
            lib.AccelerationConstraint(limits.acceleration * factor["acceleration"]),
        ]
        if self.torque and self.robot is not None:
            constraints.append(torque_constraint(self.robot, limits.effort * factor["torque"]))
        if self.tool_speed is not None and self.robot is not None:
            cap = self.tool_speed * factor["tool speed"]
            constraints.append(lib.SpeedConstraint(tool_speed_rates(self.robot, cap), limits.n))
        return constraints


def initial_scale(problem: ToppraProblem) -> dict[str, float]:
    """Every limited quantity of the problem with the factor 1 - MARGIN."""
    names = ["velocity", "acceleration"]
    if problem.torque:
        names.append("torque")
    if problem.tool_speed is not None:
        names.append("tool speed")
    return dict.fromkeys(names, 1.0 - MARGIN)
