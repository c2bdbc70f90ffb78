"""Tests of planners.checker.polynomials: exact extremes of piecewise polynomials, any rate."""

from __future__ import annotations

import numpy as np
import pytest
from checker_support import Q0, SQRT3, quintic

from optraj.planners.checker import QUANTITIES, check
from optraj.planners.checker.polynomials import (
    bernstein,
    critical_points,
    derivatives_of,
    evaluate_piecewise,
    horner,
    polyval,
    real_roots,
    segment_index,
    unit_roots,
)
from optraj.planners.trajectory import Trajectory
from optraj.robots import Robot


def test_peaks_between_samples_are_found_exactly(paddle):
    duration = 2.2  # at 3 Hz the samples miss T/2
    delta = np.array([0.1, 0.5, 0.3, -0.4])  # J3 nearest its limit: 0.3 m at 1.5 m/s
    trajectory = quintic(Q0, Q0 + delta, duration)
    assert not np.any(np.isclose(trajectory.times(3.0), duration / 2))
    velocity = check(trajectory, paddle, rate=3.0)["velocity"]
    assert velocity.value == pytest.approx(1.875 * 0.3 / duration, rel=1e-12)
    assert velocity.joint == "J3"
    assert velocity.time == pytest.approx(duration / 2, abs=1e-9)


def via_move(sawyer: Robot, h: float, peak_ratio: float) -> Trajectory:
    """Two rest-to-rest quintics of h seconds each: joint right_j1 out and back, peaking at
    ``peak_ratio`` of its velocity limit mid-segment, at rest (zero velocity and acceleration)
    at every breakpoint; joint right_j6 creeps on at 0.001 of its limit. Samples at the
    breakpoints see right_j1 still, so only exact bounds of every segment find its peak."""
    q0 = 0.5 * (sawyer.limits.lower + sawyer.limits.upper)
    rise = peak_ratio * sawyer.limits.velocity[1] * h / 1.875
    c = np.zeros((2, 6, sawyer.dof))
    c[:, 0] = q0
    for k, (start, move) in enumerate(((0.0, rise), (rise, -rise))):
        c[k, 0, 1] += start
        c[k, 3:, 1] = move * np.array([10.0, -15.0, 6.0]) / h ** np.arange(3, 6)
        c[k, 1, 6] = 1e-3 * sawyer.limits.velocity[6]
        c[k, 0, 6] += k * h * c[k, 1, 6]
    return Trajectory([0.0, h, 2.0 * h], c, joint_names=sawyer.joint_names)


@pytest.mark.parametrize(("h", "rate"), [(1.6e-3, 250.0), (0.4e-3, 1000.0), (1.6e-3, 1.0)])
def test_every_segment_is_bounded_exactly_whatever_the_rate(sawyer, h, rate):
    # A 3.2 ms (and a 0.8 ms) two-segment move whose joint right_j1 peaks at 1.077 of its
    # velocity limit between the samples fails at every rate, right_j6 creeping at 0.001.
    trajectory = via_move(sawyer, h, 1.077)
    report = check(trajectory, sawyer, rate=rate, quantities=["velocity", "acceleration"])
    velocity = report["velocity"]
    assert not velocity.ok
    assert velocity.joint == "right_j1"
    assert velocity.ratio == pytest.approx(1.077, rel=1e-9)
    assert min(abs(velocity.time - h / 2), abs(velocity.time - 1.5 * h)) < 1e-12
    rise = 1.077 * sawyer.limits.velocity[1] * h / 1.875
    acceleration = report["acceleration"]
    assert acceleration.joint == "right_j1"
    assert acceleration.value == pytest.approx(10.0 / SQRT3 * rise / h**2, rel=1e-9)


def test_many_segments_match_brute_force_sampling_at_a_coarse_rate(sawyer):
    # 400 random quintic pieces checked at 1 Hz (three samples and the breakpoints): every
    # polynomial quantity is still its exact worst, as dense sampling finds it.
    rng = np.random.default_rng(32)
    knots = np.concatenate([[0.0], np.cumsum(rng.uniform(0.002, 0.008, 400))])
    limits = sawyer.limits
    middle, half = 0.5 * (limits.lower + limits.upper), 0.5 * (limits.upper - limits.lower)
    shape = (len(knots), sawyer.dof)
    trajectory = Trajectory.from_hermite(
        knots,
        middle + 0.9 * half * rng.uniform(-1.0, 1.0, shape),
        rng.uniform(-300.0, 300.0, shape),
        rng.uniform(-1e5, 1e5, shape),
    )
    report = check(trajectory, sawyer, rate=1.0, quantities=QUANTITIES[:4])
    times = np.unique(np.concatenate([np.linspace(0.0, trajectory.duration, 400_001), knots]))
    sample = trajectory.sample(times)
    # The exact worst is at least the sampled one, and above it by no more than the samples'
    # spacing (5 us) can hide.
    score = np.maximum(limits.lower - sample.q, sample.q - limits.upper)
    assert score.max() - 1e-12 <= -report["position"].margin <= score.max() + 1e-5
    assert report["position"].joint == sawyer.joint_names[int(np.argmax(score.max(axis=0)))]
    for name, values, bound in (
        ("velocity", sample.qd, limits.velocity),
        ("acceleration", sample.qdd, limits.acceleration),
        ("jerk", sample.jerk, limits.jerk),
    ):
        ratio = np.abs(values) / bound
        finding = report[name]
        assert ratio.max() * (1 - 1e-12) <= finding.ratio <= ratio.max() * (1 + 1e-4), name
        assert finding.joint == sawyer.joint_names[int(np.argmax(ratio.max(axis=0)))], name


def test_random_polynomials_match_brute_force_sampling(paddle):
    rng = np.random.default_rng(20240611)
    for _ in range(6):
        segments = int(rng.integers(1, 5))
        knots = np.concatenate([[0.0], np.cumsum(rng.uniform(0.2, 0.8, segments))])
        shape = (segments + 1, 4)
        trajectory = Trajectory.from_hermite(
            knots,
            rng.uniform(-1.0, 1.0, shape),
            rng.uniform(-2.0, 2.0, shape),
            rng.uniform(-10.0, 10.0, shape),
        )
        report = check(trajectory, paddle, quantities=["velocity", "acceleration"])
        assert report.names == ("velocity", "acceleration")
        times = np.linspace(0.0, trajectory.duration, int(trajectory.duration * 1e5) + 1)
        sample = trajectory.sample(times)
        for name, values, bound in (
            ("velocity", sample.qd, paddle.limits.velocity),
            ("acceleration", sample.qdd, paddle.limits.acceleration),
        ):
            ratio = np.abs(values) / bound
            i, j = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
            finding = report[name]
            assert finding.value == pytest.approx(abs(values[i, j]), rel=1e-3)
            assert finding.joint == paddle.joint_names[j]
            assert ratio.max() - 1e-12 <= finding.ratio <= ratio.max() * (1 + 1e-3)


def test_piecewise_evaluation_matches_the_trajectory_samples():
    rng = np.random.default_rng(7)
    knots = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 0.5, 5))])
    shape = (len(knots), 3)
    trajectory = Trajectory.from_hermite(
        knots, rng.normal(size=shape), rng.normal(size=shape), rng.normal(size=shape)
    )
    times = np.concatenate([knots, rng.uniform(0.0, knots[-1], 50)])
    table = derivatives_of(trajectory.coefficients, 4)
    assert [c.shape[1] for c in table] == [6, 5, 4, 3, 2]
    sample = trajectory.sample(times)
    for order, expected in enumerate((sample.q, sample.qd, sample.qdd, sample.jerk)):
        np.testing.assert_allclose(
            evaluate_piecewise(table[order], knots, times), expected, rtol=1e-12, atol=1e-9
        )
    np.testing.assert_array_equal(segment_index(knots, knots), [0, 1, 2, 3, 4, 4])


def test_roots_and_critical_points_of_one_polynomial():
    # (t - 0.2)(t - 0.7)(t - 1.5), ascending coefficients.
    cubic = np.polynomial.polynomial.polyfromroots([0.2, 0.7, 1.5])
    np.testing.assert_allclose(np.sort(real_roots(cubic, 1.0)), [0.2, 0.7], atol=1e-12)
    assert real_roots(np.zeros(4), 1.0).size == 0
    tau = np.linspace(0.0, 1.0, 11)
    np.testing.assert_allclose(polyval(cubic, tau), np.polyval(cubic[::-1], tau), atol=1e-15)
    value, slope = horner(cubic[None], tau[None])
    np.testing.assert_allclose(value[0], polyval(cubic, tau), atol=1e-15)
    derivative = np.polynomial.polynomial.polyder(cubic)
    np.testing.assert_allclose(slope[0], polyval(derivative, tau), atol=1e-14)
    stationary = np.polynomial.polynomial.polyroots(derivative)
    inside = np.sort(stationary[(stationary >= 0.0) & (stationary <= 1.0)])
    points = np.sort(critical_points(cubic, 1.0))
    np.testing.assert_allclose(points, np.sort(np.concatenate([[0.0, 1.0], inside])), atol=1e-12)
    found = unit_roots(derivative[None])[0]
    assert np.min(np.abs(found - inside[0])) < 1e-12


def test_bernstein_coefficients_enclose_the_polynomial_on_the_unit_interval():
    rng = np.random.default_rng(11)
    u = np.linspace(0.0, 1.0, 2001)
    for degree in (1, 3, 5):
        coefficients = rng.normal(size=degree + 1)
        enclosure = coefficients @ bernstein(degree)
        values = polyval(coefficients, u)
        assert enclosure.min() <= values.min() + 1e-12
        assert values.max() <= enclosure.max() + 1e-12
        # The end coefficients are the values at the ends.
        assert enclosure[0] == pytest.approx(values[0]) and enclosure[-1] == pytest.approx(
            values[-1]
        )
