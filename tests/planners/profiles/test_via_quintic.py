"""Tests of planners.profiles.via_quintic: quintics through every via point."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.planners.profiles.via_points import ViaPoints
from optraj.planners.profiles.via_quintic import (
    MONOTONE_SLOPE_RATIO,
    plan_quintic,
    quintic_fit,
    quintic_segments,
    via_velocities,
)

QUANTITIES = ("position", "velocity", "acceleration")


@pytest.mark.slow
def test_quintic_passes_every_via_point_and_is_c2(via):
    rng = np.random.default_rng(99)
    robots_ = [get_robot("sawyer"), get_robot("paddle4")]
    for trial in range(60):
        problem = via.random_waypoints(rng, robots_[trial % 2])
        traj = ViaPoints("quintic").plan(problem)
        points, limits = problem.waypoints, problem.limits
        assert traj.degree == 5
        via.at_rest_on_the_ends(traj, points)
        times = traj.metadata["via_times"]
        np.testing.assert_allclose(traj.sample(times).q, points, rtol=0, atol=1e-9)
        # C2: position, velocity and acceleration agree on both sides of every breakpoint.
        for order, (left, right) in enumerate(via.sides(traj, 2)):
            scale = (1.0, np.max(limits.velocity), np.max(limits.acceleration))[order]
            np.testing.assert_allclose(left, right, rtol=0, atol=1e-9 * scale)
        np.testing.assert_allclose(traj.sample(traj.duration).qdd, 0.0, atol=1e-9)
        # Monotone segments: each joint stays between the waypoints it moves between.
        for i, phase in enumerate(traj.phases):
            q = traj.sample(np.linspace(phase.t_start, phase.t_end, 200)).q
            low = np.minimum(points[i], points[i + 1])
            high = np.maximum(points[i], points[i + 1])
            assert np.all((q >= low - 1e-12) & (q <= high + 1e-12))
        via.within_limits(traj, limits, 20_000.0 if trial % 20 == 0 else 500.0 / traj.duration)
        report = planners.check(traj, problem, rate=200.0, quantities=QUANTITIES)
        assert report.ok, report


def test_quintic_uses_craigs_via_velocities():
    robot = get_robot("paddle4")
    points = np.array(
        [[0.1, 0.0, 0.1, 0.0], [0.3, 1.0, 0.2, 0.5], [0.5, -1.0, 0.6, 0.5], [0.6, -0.5, 0.7, 0.2]]
    )
    problem = problems.Waypoints(robot, points, segment_durations=[2.0, 2.0, 2.0])
    traj = ViaPoints("quintic").plan(problem)
    slopes = np.diff(points, axis=0) / 2.0
    qd = traj.sample(traj.metadata["via_times"]).qd
    np.testing.assert_allclose(qd[0], 0.0, atol=1e-12)
    np.testing.assert_allclose(qd[-1], 0.0, atol=1e-12)
    # J1 keeps its direction: mean of the slopes; J2 turns back at both inner points: 0;
    # J4 stops at point 1 (slope 0 after it): 0.
    np.testing.assert_allclose(qd[1:3, 0], 0.5 * (slopes[:-1, 0] + slopes[1:, 0]), atol=1e-12)
    np.testing.assert_allclose(qd[1:3, 1], 0.0, atol=1e-12)
    assert qd[1, 3] == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(traj.sample(traj.metadata["via_times"]).qdd, 0.0, atol=1e-9)
    np.testing.assert_allclose([p.duration for p in traj.phases], 2.0, rtol=1e-12)
    # Slopes 0.05 then 0.35 m/s: the mean 0.2 is capped at 15/7 x 0.05 to stay monotone.
    points[:, 2] = [0.1, 0.2, 0.9, 0.95]
    problem = problems.Waypoints(robot, points, segment_durations=[2.0, 2.0, 2.0])
    traj = ViaPoints("quintic").plan(problem)
    assert traj.sample(2.0).qd[2] == pytest.approx(15.0 / 7.0 * 0.05, rel=1e-12)
    assert planners.check(traj, problem, quantities=QUANTITIES).ok


def test_quintic_given_durations_are_honoured_and_checked():
    robot = get_robot("paddle4")
    points = [[0.1, 0, 0.1, 0], [0.5, 1, 0.5, 0.5], [0.9, -1, 0.2, 0], [0.3, 0.5, 0.6, 0.2]]
    problem = problems.Waypoints(robot, points, segment_durations=[2.0, 2.5, 2.0])
    traj = ViaPoints("quintic").plan(problem)
    np.testing.assert_allclose([p.duration for p in traj.phases], [2.0, 2.5, 2.0], rtol=1e-12)
    assert traj.metadata["durations_from"] == "problem"
    assert planners.check(traj, problem, quantities=QUANTITIES).ok


# ---------------------------------------------------------- segments and fit


def test_segments_meet_the_via_points_and_velocities_with_zero_acceleration():
    rng = np.random.default_rng(4)
    points = rng.uniform(-1.0, 1.0, (5, 3))
    h = rng.uniform(0.5, 2.0, 4)
    b = quintic_segments(points, h)  # b[i, p]: u^p coefficient, u = (t - s_i) / h_i
    velocity = via_velocities(points, h)
    powers = np.arange(6)
    np.testing.assert_allclose(b[:, 0], points[:-1], atol=1e-15)
    np.testing.assert_allclose(np.einsum("ipn->in", b), points[1:], atol=1e-12)
    np.testing.assert_allclose(b[:, 1], velocity[:-1] * h[:, None], atol=1e-15)
    end_slope = np.einsum("p,ipn->in", powers, b)
    np.testing.assert_allclose(end_slope, velocity[1:] * h[:, None], atol=1e-12)
    np.testing.assert_array_equal(b[:, 2], 0.0)
    end_curve = np.einsum("p,ipn->in", powers * (powers - 1), b)
    np.testing.assert_allclose(end_curve, 0.0, atol=1e-11)


def test_via_velocities_are_capped_to_keep_segments_monotone():
    points = np.array([[0.0], [0.1], [0.8]])  # slopes 0.1 then 0.7 at h = 1
    velocity = via_velocities(points, np.array([1.0, 1.0]))
    assert velocity[1, 0] == pytest.approx(MONOTONE_SLOPE_RATIO * 0.1, rel=1e-15)
    # At the cap, both end velocities c times the slope: the quintic just stays monotone.
    u = np.linspace(0.0, 1.0, 10_001)
    c = MONOTONE_SLOPE_RATIO
    assert np.min(c - 30.0 * (c - 1.0) * u**2 * (1.0 - u) ** 2) >= -1e-12


def test_fit_puts_the_worst_peak_on_its_limit():
    robot = get_robot("paddle4")
    points = np.array([[0.1, 0, 0.1, 0], [0.5, 1, 0.5, 0.5], [0.9, -1, 0.2, 0]])
    h = quintic_fit(points, robot.limits)
    traj = plan_quintic(points, None, robot.limits)
    np.testing.assert_array_equal(traj.metadata["segment_durations"], h)
    sample = traj.sample(traj.times(20_000.0))
    ratio = max(
        np.max(np.abs(sample.qd) / robot.limits.velocity),
        np.max(np.abs(sample.qdd) / robot.limits.acceleration),
    )
    assert ratio == pytest.approx(1.0, rel=1e-6)
