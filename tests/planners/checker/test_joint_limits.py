"""Tests of planners.checker.joint_limits: each joint quantity's worst value, located."""

from __future__ import annotations

import numpy as np
import pytest
from checker_support import DELTA, Q0, SQRT3, T, limits_of, peaks, quintic

from optraj.planners.checker import QUANTITIES, check
from optraj.planners.trajectory import Trajectory
from optraj.problems import PointToPoint


def test_known_good_quintic_passes_with_the_analytic_peaks(paddle):
    peak = peaks(DELTA, T)
    factors = np.array([1.5, 1.3, 1.01, 1.2])  # joint J3 comes nearest its limits
    limits = limits_of(
        paddle,
        velocity=factors * peak["velocity"],
        acceleration=factors * peak["acceleration"],
        jerk=factors * peak["jerk"],
    )
    problem = PointToPoint(paddle, Q0, Q0 + DELTA, limits=limits)
    report = check(quintic(Q0, Q0 + DELTA, T), problem)
    assert report.ok, report.summary()
    assert report.violations == ()
    assert report.names == (*QUANTITIES, "start state", "end state")

    velocity = report["velocity"]
    assert velocity.joint == "J3"
    assert velocity.value == pytest.approx(1.875 * 0.3 / T, rel=1e-9)
    assert velocity.time == pytest.approx(T / 2, abs=1e-9)
    assert velocity.ratio == pytest.approx(1 / 1.01, rel=1e-9)
    assert velocity.margin == pytest.approx(velocity.limit - velocity.value, rel=1e-12)

    acceleration = report["acceleration"]
    assert acceleration.value == pytest.approx(10 / SQRT3 * 0.3 / T**2, rel=1e-9)
    expected = T * (0.5 + np.array([-1.0, 1.0]) * SQRT3 / 6)  # either side of the middle
    assert np.min(np.abs(acceleration.time - expected)) < 1e-9

    jerk = report["jerk"]
    assert jerk.value == pytest.approx(60 * 0.3 / T**3, rel=1e-9)
    assert min(jerk.time, T - jerk.time) < 1e-9  # the jerk peaks at both ends

    # J3 starts 0.3 m above its lower limit 0: the smallest position margin.
    position = report["position"]
    assert (position.joint, position.value, position.limit) == ("J3", 0.3, 0.0)
    assert position.margin == pytest.approx(0.3)
    assert position.time == 0.0

    # Torque against an independent, denser sampling of inverse dynamics.
    times = np.linspace(0.0, T, 8001)
    sample = quintic(Q0, Q0 + DELTA, T).sample(times)
    torque = np.abs(paddle.inverse_dynamics(sample.q, sample.qd, sample.qdd)) / paddle.limits.effort
    assert report["torque"].ratio == pytest.approx(torque.max(), rel=1e-3)
    assert report["torque"].joint == paddle.joint_names[int(np.argmax(torque.max(axis=0)))]


def test_position_overshoot_between_samples_is_caught(paddle):
    upper = paddle.limits.upper[1]
    # J2 rises to 1e-6 rad above its limit at 0.4995 s, midway between two 1 kHz samples.
    c = np.zeros((1, 3, 4))
    c[0, 0] = Q0
    c[0, :, 1] = [upper + 1e-6 - 10 * 0.4995**2, 2 * 10 * 0.4995, -10.0]
    trajectory = Trajectory([0.0, 1.0], c)
    sampled = trajectory.sample(trajectory.times(1000.0)).q[:, 1]
    assert sampled.max() < upper  # no sample is outside
    position = check(trajectory, paddle)["position"]
    assert not position.ok
    assert position.joint == "J2"
    assert position.limit == upper
    assert position.margin == pytest.approx(-1e-6, rel=1e-6)
    assert position.time == pytest.approx(0.4995, abs=1e-9)


@pytest.mark.parametrize(
    ("quantity", "times"),
    [
        ("velocity", (T / 2,)),
        ("acceleration", (T * (0.5 - SQRT3 / 6), T * (0.5 + SQRT3 / 6))),
        ("jerk", (0.0, T)),
    ],
)
def test_joint_limit_violations_are_located(paddle, quantity, times):
    peak = peaks(DELTA, T)[quantity]
    bound = 2.0 * peak
    bound[1] = 0.9 * peak[1]  # only J2 breaks its limit, by 10 %
    problem = PointToPoint(paddle, Q0, Q0 + DELTA, limits=limits_of(paddle, **{quantity: bound}))
    report = check(quintic(Q0, Q0 + DELTA, T), problem)
    assert [f.name for f in report.violations] == [quantity]
    finding = report[quantity]
    assert finding.joint == "J2"
    assert finding.value == pytest.approx(peak[1], rel=1e-9)
    assert finding.limit == pytest.approx(0.9 * peak[1])
    assert finding.margin == pytest.approx(-0.1 * peak[1], rel=1e-6)
    assert finding.ratio == pytest.approx(1 / 0.9, rel=1e-9)
    assert min(abs(finding.time - t) for t in times) < 1e-9
    assert (
        finding.unit
        == {"velocity": "rad/s", "acceleration": "rad/s^2", "jerk": "rad/s^3"}[quantity]
    )
    assert not report.ok and not report.passed(quantity) and report.passed("position")


def test_torque_limit_violation_is_located(paddle):
    # Standing still at home, J1 (lifting along z) holds the arm's weight.
    weight = float(paddle.gravity_torque(paddle.home)[0])
    effort = paddle.limits.effort.copy()
    effort[0] = 0.5 * weight
    problem = PointToPoint(
        paddle, paddle.home, paddle.home, limits=limits_of(paddle, effort=effort)
    )
    report = check(Trajectory.constant(paddle.home, 1.0), problem)
    assert [f.name for f in report.violations] == ["torque"]
    torque = report["torque"]
    assert torque.joint == "J1"
    assert torque.unit == "N"
    assert torque.value == pytest.approx(weight, rel=1e-9)
    assert torque.ratio == pytest.approx(2.0, rel=1e-9)


def test_position_outside_the_range(paddle):
    q1 = Q0.copy()
    q1[1] = paddle.limits.upper[1] + 0.05
    position = check(quintic(Q0, q1, T), paddle)["position"]
    assert not position.ok
    assert position.joint == "J2"
    assert position.value == pytest.approx(q1[1])
    assert position.limit == paddle.limits.upper[1]
    assert position.margin == pytest.approx(-0.05)
    assert position.time == pytest.approx(T)
    assert "beyond its upper limit" in position.detail
