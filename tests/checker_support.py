"""Hand-made trajectories and problems of the checker tests, with their analytic peaks.

Every trajectory here is made by hand (polynomials, Hermite interpolation), so the expected
worst values are known analytically or by brute-force sampling, independently of the checker.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from optraj.planners.checker import Report
from optraj.planners.trajectory import Trajectory
from optraj.robots import JointLimits, Robot

SQRT3 = math.sqrt(3.0)
#: Start and move of the paddle4 quintic [m, rad, m, rad]; joint J3 is index 2.
Q0 = np.array([0.45, 0.0, 0.3, 0.0])
DELTA = np.array([0.2, 0.5, 0.3, -0.4])
T = 2.0


def quintic(q0: np.ndarray, q1: np.ndarray, duration: float, **kwargs) -> Trajectory:
    """Rest-to-rest quintic q0 -> q1: peak |qd| 1.875 d/T at T/2, |qdd| 10/sqrt(3) d/T^2."""
    d = np.asarray(q1, dtype=float) - q0
    c = np.zeros((1, 6, len(q0)))
    c[0, 0] = q0
    c[0, 3] = 10 * d / duration**3
    c[0, 4] = -15 * d / duration**4
    c[0, 5] = 6 * d / duration**5
    return Trajectory([0.0, duration], c, **kwargs)


def peaks(delta: np.ndarray, duration: float) -> dict[str, np.ndarray]:
    """Analytic peak magnitudes of the quintic, per joint."""
    d = np.abs(delta)
    return {
        "velocity": 1.875 * d / duration,
        "acceleration": 10 / SQRT3 * d / duration**2,
        "jerk": 60 * d / duration**3,
    }


def limits_of(robot: Robot, **fields: np.ndarray) -> JointLimits:
    base = robot.limits
    names = ("lower", "upper", "velocity", "acceleration", "jerk", "effort")
    values = {name: getattr(base, name) for name in names}
    values.update(fields)
    return JointLimits(base.names, base.kinds, **values)


def no_nan(report: Report) -> None:
    for f in report.findings:
        for value in (f.value, f.limit, f.margin, f.ratio):
            assert not math.isnan(value), f
        assert f.time is None or math.isfinite(f.time)


def two_segments(first: np.ndarray, second: np.ndarray) -> Trajectory:
    """Segments [0, 1] and [1, 2] s with coefficient rows (d + 1, n) given per segment."""
    return Trajectory([0.0, 1.0, 2.0], np.stack([first, second]))


@dataclass
class Task:
    """A duck-typed problem: anything with robot, limits and constraints() is checkable."""

    robot: Robot
    items: tuple

    @property
    def limits(self) -> JointLimits:
        return self.robot.limits

    def constraints(self) -> tuple:
        return self.items
