"""Tests of planners.checker.jumps: jumps at breakpoints and against boundary states."""

from __future__ import annotations

import math

import numpy as np
import pytest
from checker_support import DELTA, Q0, T, no_nan, quintic, two_segments

from optraj.planners.checker import check
from optraj.planners.checker.jumps import boundary_jumps, breakpoint_jumps
from optraj.planners.checker.polynomials import derivatives_of
from optraj.planners.trajectory import Trajectory
from optraj.problems import BoundaryState, PointToPoint


def test_smooth_breakpoints_are_not_jumps(paddle):
    # The quintic cut into 200 quintic Hermite pieces is the same C-infinity motion.
    whole = quintic(Q0, Q0 + DELTA, T)
    knots = np.linspace(0.0, T, 201)
    s = whole.sample(knots)
    pieces = Trajectory.from_hermite(knots, s.q, s.qd, s.qdd)
    report = check(pieces, paddle)
    assert report.ok, report.summary()
    for name in ("velocity", "acceleration", "jerk"):
        # (the Hermite coefficients carry round-off of about 1e-8 in the jerk; the ratio, as
        # joints J1 and J3 tie in velocity by design)
        assert report[name].ratio == pytest.approx(check(whole, paddle)[name].ratio, rel=1e-6)


def test_velocity_jump_at_a_breakpoint_makes_acceleration_unbounded(paddle):
    rest = np.stack([Q0, np.zeros(4)])
    moving = np.stack([Q0, [0.0, 0.0, 0.2, 0.0]])  # J3 starts at 0.2 m/s at t = 1 s
    report = check(two_segments(rest, moving), paddle)
    no_nan(report)
    assert [f.name for f in report.violations] == ["acceleration", "jerk", "torque"]
    acceleration = report["acceleration"]
    assert (acceleration.value, acceleration.margin, acceleration.ratio) == (
        math.inf,
        -math.inf,
        math.inf,
    )
    assert (acceleration.time, acceleration.joint) == (1.0, "J3")
    assert "velocity jumps by 0.2 m/s at t = 1 s (joint 'J3')" in acceleration.detail
    assert "unbounded acceleration" in acceleration.detail
    assert "unbounded torque" in report["torque"].detail
    assert report["velocity"].ok and report["velocity"].value == pytest.approx(0.2)
    text = report.summary()
    assert "inf" in text and "FAIL" in text and text == str(report)


def test_position_jump_makes_velocity_unbounded(paddle):
    shifted = Q0 + np.array([0.0, 0.0, 0.01, 0.0])
    report = check(two_segments(Q0[None], shifted[None]), paddle)
    no_nan(report)
    velocity = report["velocity"]
    assert velocity.value == math.inf and not velocity.ok
    assert "position jumps by 0.01 m at t = 1 s (joint 'J3')" in velocity.detail
    assert {"velocity", "acceleration", "jerk", "torque"} == {f.name for f in report.violations}


def test_acceleration_jump_makes_only_jerk_unbounded(paddle):
    accelerating = np.stack([Q0, np.zeros(4), [0.0, 0.0, 0.2, 0.0]])  # 0.4 m/s^2
    cruising = np.stack([Q0 + np.array([0, 0, 0.2, 0]), [0.0, 0.0, 0.4, 0.0], np.zeros(4)])
    report = check(two_segments(accelerating, cruising), paddle)
    assert [f.name for f in report.violations] == ["jerk"]
    assert "acceleration jumps by -0.4 m/s^2 at t = 1 s" in report["jerk"].detail
    assert report["acceleration"].value == pytest.approx(0.4)


def test_start_state_mismatch_is_a_jump_and_a_failed_start(paddle):
    qd0 = np.array([0.0, 0.0, 0.2, 0.0])  # the trajectory starts moving, the robot is at rest
    trajectory = Trajectory.from_hermite(
        [0.0, T], [Q0, Q0 + DELTA], [qd0, np.zeros(4)], [np.zeros(4), np.zeros(4)]
    )
    report = check(trajectory, PointToPoint(paddle, Q0, Q0 + DELTA))
    no_nan(report)
    start = report["start state"]
    assert not start.ok
    assert (start.joint, start.unit, start.time) == ("J3", "m/s", 0.0)
    assert start.value == pytest.approx(0.2)
    assert "qd of joint 'J3'" in start.detail
    acceleration = report["acceleration"]
    assert acceleration.value == math.inf and acceleration.time == 0.0
    assert "from the prescribed start state" in acceleration.detail
    assert report["end state"].ok
    # Against the robot alone there is no start state, hence no jump.
    assert check(trajectory, paddle)["acceleration"].ok


def test_end_velocity_mismatch_is_a_jump(paddle):
    qd1 = np.array([0.0, 0.3, 0.0, 0.0])  # still turning at the end, the goal is rest
    trajectory = Trajectory.from_hermite([0.0, T], [Q0, Q0 + DELTA], [np.zeros(4), qd1])
    report = check(trajectory, PointToPoint(paddle, Q0, Q0 + DELTA))
    assert report["end state"].value == pytest.approx(0.3)
    acceleration = report["acceleration"]
    assert acceleration.value == math.inf and acceleration.time == T
    assert "velocity jumps by -0.3 rad/s at t = 2 s (joint 'J2') from the prescribed end state" in (
        acceleration.detail
    )


def test_jumps_are_measured_exactly_at_breakpoints_and_against_states(paddle):
    rest = np.stack([Q0, np.zeros(4)])
    moving = np.stack([Q0, [0.0, 0.0, 0.2, 0.0]])  # J3 starts at 0.2 m/s at t = 1 s
    trajectory = two_segments(rest, moving)
    knots = np.asarray(trajectory.breakpoints)
    table = derivatives_of(trajectory.coefficients, 4)
    (jump,) = breakpoint_jumps(table, knots, paddle.limits)
    assert (jump.order, jump.time, jump.joint, jump.source) == (1, 1.0, 2, "")
    assert jump.delta == pytest.approx(0.2) and jump.size > 1.0
    assert breakpoint_jumps(table[:1] + table[:1], knots[:2], paddle.limits) == []

    # A prescribed end velocity missed by more than the tolerance is a jump, within it none.
    end = [np.zeros(4), np.array([0.0, 0.0, 0.2, 0.0]), np.zeros(4), np.zeros(4)]
    state = BoundaryState("end", None, np.array([0.0, 0.0, 0.2 + 1e-3, 0.0]), tolerance=1e-4)
    wanted = [None, np.asarray(state.qd), None]
    (jump,) = boundary_jumps(state, wanted, end, 2.0, paddle.limits, 2.0)
    assert (jump.order, jump.time, jump.joint, jump.source) == (1, 2.0, 2, "end state")
    assert jump.delta == pytest.approx(1e-3)  # prescribed minus actual at the end
    loose = BoundaryState("end", None, state.qd, tolerance=2e-3)
    assert boundary_jumps(loose, wanted, end, 2.0, paddle.limits, 2.0) == []
