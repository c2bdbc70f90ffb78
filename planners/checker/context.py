"""The context of one check: the trajectory's polynomials, sampling grid, limits and tool.

:func:`planners.checker.check` builds one :class:`CheckContext` and hands it to every finding
maker: the exact state at an instant, the sampled instants of a window, the exact peak joint
speed, and the shared :class:`~planners.checker.kinematics.ToolKinematics`.

Example::

    times = ctx.window(phase.t_start, phase.t_end)   # samples, both ends, the end from the left
    q, qd, qdd, jerk = ctx.state(ctx.duration)
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.planners.checker.kinematics import ToolKinematics
from optraj.planners.checker.polynomials import evaluate_piecewise, exact_candidates
from optraj.planners.trajectory import TIME_TOLERANCE, Phase, Trajectory
from optraj.robots import JointLimits

__all__ = ["CheckContext"]

FloatArray = NDArray[np.float64]


@dataclass
class CheckContext:
    """Everything a finding maker needs.

    Attributes:
        trajectory: The trajectory under check.
        limits: The joint limits to judge against.
        names: The joint names, shape (n,).
        knots: Breakpoints [s], shape (K + 1,).
        derivatives: Position, velocity, acceleration, jerk and snap polynomials
            (:func:`~planners.checker.polynomials.derivatives_of`).
        grid: The sampled instants [s]: the rate, every breakpoint and the instant before.
        spacing: Largest gap between two samples [s].
        kinematics: Tool poses and twists at the instants the constraints need.
    """

    trajectory: Trajectory
    limits: JointLimits
    names: tuple[str, ...]
    knots: FloatArray
    derivatives: list[FloatArray]
    grid: FloatArray
    spacing: float
    kinematics: ToolKinematics

    @property
    def duration(self) -> float:
        """The trajectory's duration [s]."""
        return self.trajectory.duration

    def phase(self, name: str) -> Phase | None:
        """The trajectory's phase ``name``, or None."""
        for phase in self.trajectory.phases:
            if phase.name == name:
                return phase
        return None

    def left_of(self, time: float) -> float:
        """The instant just before ``time`` (the largest float below it), unless at the end.

        Sampling is right-continuous; a window or phase that ends at a breakpoint must be
        judged by the segment that ends there, not by the one that starts there.
        """
        return time if time >= self.duration else float(np.nextafter(time, -np.inf))

    def window(self, start: float, end: float) -> FloatArray:
        """Sampled instants in [start, end], with both ends (the end from the left) [s]."""
        inside = self.grid[(self.grid >= start) & (self.grid < end)]
        last = self.left_of(end) if end > start else end
        return np.unique(np.concatenate([inside, [start, last]]))

    @functools.cached_property
    def peak_speed(self) -> float:
        """The fastest any joint moves [rad/s or m/s], exact on every segment."""
        speed = exact_candidates(self.knots, self.derivatives[1], lambda x, j: np.abs(x), math.inf)
        return float(np.max(np.abs(speed.value)))

    def state(self, time: float) -> list[FloatArray]:
        """Exact q, qd, qdd and jerk at one time, each shape (n,)."""
        at = np.array([min(max(time, 0.0), self.duration)])
        return [evaluate_piecewise(self.derivatives[r], self.knots, at)[0] for r in range(4)]

    def instant(self, time: float) -> float | None:
        """``time`` clipped onto [0, duration] if within round-off of it, else None."""
        if time < -TIME_TOLERANCE or time > self.duration + TIME_TOLERANCE:
            return None
        return min(max(float(time), 0.0), self.duration)
