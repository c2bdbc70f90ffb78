"""Tests of planners.checker.allowance: the one round-off rule and the boundary allowance."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest
from checker_support import DELTA, Q0, T, limits_of, quintic

from optraj.planners.checker import check
from optraj.planners.checker.allowance import (
    ABSOLUTE_SLACK,
    RELATIVE_SLACK,
    TIME_ROUND_OFF,
    round_off,
    state_allowance,
    thresholds,
)
from optraj.planners.trajectory import Trajectory
from optraj.problems import PointToPoint
from optraj.robots import JointLimits, Robot


@dataclass
class Limited:
    """A duck-typed problem with limits of its own and no constraints."""

    robot: Robot
    limits: JointLimits

    def constraints(self) -> tuple:
        return ()


def late_ramp(jerk: float, tau: float, step: float = 0.0) -> Trajectory:
    """J1 at rest until 574.297 s, then jerk +jerk and -jerk for tau each, then cruising.

    Each phase starts from the exact end state of the one before, as Ruckig reports it, so
    the two sides of a breakpoint differ only by the round-off of its time (about 1e-13 s
    there); ``step`` adds a real acceleration jump [m/s^2] to the second phase.
    """
    t1 = 574.2970347063706
    knots = np.array([0.0, t1, t1 + tau, t1 + 2.0 * tau, t1 + 3.0])
    c = np.zeros((4, 4, 4))
    c[:, 0, :] = Q0
    c[1, 3, 0] = jerk / 6.0
    c[2, :3, 0] = [Q0[0] + jerk * tau**3 / 6.0, jerk * tau**2 / 2.0, (jerk * tau + step) / 2.0]
    c[2, 3, 0] = -jerk / 6.0
    powers = tau ** np.arange(4)
    c[3, 0, 0] = c[2, :, 0] @ powers
    c[3, 1, 0] = (c[2, 1:, 0] * np.arange(1, 4)) @ powers[:3]
    return Trajectory(knots, c)


def test_round_off_at_a_late_breakpoint_is_not_a_jump(paddle):
    # At t = 574 s a breakpoint is known to 1e-13 s, over which a 1e6 m/s^3 jerk changes the
    # acceleration by 4.5e-8 m/s^2: that is no jump.
    limits = limits_of(
        paddle, acceleration=np.array([0.4, 6.0, 8.0, 30.0]), jerk=np.array([2e6, 120, 160, 600])
    )
    problem = Limited(paddle, limits)
    report = check(late_ramp(1e6, 2e-7), problem, rate=1.0)
    assert report.ok, report.summary()
    assert report["acceleration"].value == pytest.approx(0.2, rel=1e-6)
    # A real jump of 1e-3 m/s^2 is still one.
    jumped = check(late_ramp(1e6, 2e-7, step=1e-3), problem, rate=1.0)
    assert jumped["jerk"].value == math.inf
    assert "acceleration jumps by -0.001 m/s^2 at t = 574.297 s" in jumped["jerk"].detail


@pytest.mark.parametrize("miss", [0.5, 1.0, 1.0 + 1e-7, 1.001, 1.1, 2.0])
def test_end_state_finding_and_boundary_jump_follow_one_rule(paddle, miss):
    # The end acceleration misses its prescription by ``miss`` tolerances: the end state
    # passes exactly when there is no jump. Round-off, 1e-9 of the 8 m/s^2 limit, is allowed
    # on top of the tolerance.
    tolerance = 1e-6
    trajectory = quintic(Q0, Q0 + DELTA, T)
    qdd1 = np.array([0.0, 0.0, miss * tolerance, 0.0])
    problem = PointToPoint(paddle, Q0, Q0 + DELTA, qdd_goal=qdd1, tolerance=tolerance)
    report = check(trajectory, problem, quantities=["jerk"])
    assert report["end state"].ok == report["jerk"].ok == (miss < 1.05)
    assert report["end state"].value == pytest.approx(miss * tolerance)
    if miss > 1.05:
        assert "from the prescribed end state" in report["jerk"].detail


def test_round_off_is_relative_absolute_and_time_parts():
    assert float(round_off(2.0)) == pytest.approx(RELATIVE_SLACK * 2.0 + ABSOLUTE_SLACK, rel=1e-15)
    # The time part grows with the slope and with the duration beyond 1 s.
    assert float(round_off(0.0, slope=-3.0, duration=0.5)) == pytest.approx(
        ABSOLUTE_SLACK + 3.0 * TIME_ROUND_OFF, rel=1e-12
    )
    assert float(round_off(0.0, slope=3.0, duration=100.0)) == pytest.approx(
        ABSOLUTE_SLACK + 300.0 * TIME_ROUND_OFF, rel=1e-12
    )
    np.testing.assert_allclose(
        round_off(np.array([1.0, -4.0])), RELATIVE_SLACK * np.array([1.0, 4.0]) + ABSOLUTE_SLACK
    )


def test_state_allowance_is_the_tolerance_plus_round_off_where_prescribed(paddle):
    limits = paddle.limits
    qd = np.array([0.0, 0.1, 0.0, 0.0])
    slopes = [qd, np.ones(4), np.zeros(4)]
    allowed = state_allowance([None, qd, None], slopes, 1e-6, limits, 2.0)
    assert allowed[0] is None and allowed[2] is None
    scale = limits.velocity + np.abs(qd)
    np.testing.assert_allclose(allowed[1], 1e-6 + round_off(scale, slopes[1], 2.0), rtol=1e-15)
    np.testing.assert_array_equal(thresholds(limits)[0], limits.upper - limits.lower)
