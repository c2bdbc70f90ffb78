"""Tests of planners.arrays.joint: jtraj and mtraj, judged by closed forms and the checker."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners
from optraj.errors import InvalidInputError
from optraj.planners.arrays.joint import jtraj, mtraj
from optraj.planners.arrays.scalar import quintic, trapezoidal

Q1 = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])


def test_jtraj_documented_example_over_normalised_time():
    tg = jtraj(Q1, -Q1, 50)
    assert tg.q.shape == tg.qd.shape == tg.qdd.shape == (50, 6)
    np.testing.assert_array_equal(tg.t, np.linspace(0.0, 1.0, 50))
    np.testing.assert_array_equal(tg.q[0], Q1)
    np.testing.assert_allclose(tg.q[-1], -Q1, rtol=0, atol=1e-12)
    np.testing.assert_allclose(tg.qd[[0, -1]], 0.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(tg.qdd[[0, -1]], 0.0, rtol=0, atol=1e-12)
    # Velocities per unit of normalised time: the rest-to-rest peak is 15/8 of the move.
    peak = np.abs(tg.trajectory.sample(0.5).qd)
    np.testing.assert_allclose(peak, 15.0 / 8.0 * 2.0 * Q1, rtol=1e-12)
    assert tg.trajectory.metadata["time_unit"] == "normalised"


def test_jtraj_over_a_time_vector_scales_the_rates():
    t = np.linspace(0.0, 2.0, 21)
    tg = jtraj(Q1, -Q1, t)
    x = t / 2.0
    shape = 10 * x**3 - 15 * x**4 + 6 * x**5
    rate = (30 * x**2 - 60 * x**3 + 30 * x**4) / 2.0
    np.testing.assert_allclose(tg.q, Q1 - 2.0 * Q1 * shape[:, None], rtol=0, atol=1e-12)
    np.testing.assert_allclose(tg.qd, -2.0 * Q1 * rate[:, None], rtol=0, atol=1e-12)
    assert tg.istime is True


def test_jtraj_meets_given_end_velocities():
    rng = np.random.default_rng(11)
    for _ in range(20):
        q0, qf, v0, v1 = rng.uniform(-2.0, 2.0, (4, 3))
        t = np.linspace(0.0, rng.uniform(0.2, 4.0), 9)
        tg = jtraj(q0, qf, t, v0, v1)
        np.testing.assert_allclose(tg.q[[0, -1]], [q0, qf], rtol=0, atol=1e-12)
        np.testing.assert_allclose(tg.qd[[0, -1]], [v0, v1], rtol=0, atol=1e-10)
        np.testing.assert_allclose(tg.qdd[[0, -1]], 0.0, rtol=0, atol=1e-9)


def test_jtraj_judged_by_the_checker_has_the_closed_form_peaks():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(36)
    for _ in range(5):
        q0, qf = robot.limits.sample(rng, 2)
        dist = np.abs(qf - q0)
        T = 1.2 * max(np.max(15 / 8 * dist / robot.limits.velocity), 1.0)
        tg = jtraj(q0, qf, np.linspace(0.0, T, 11))
        report = planners.check(tg.trajectory, robot)
        assert report["position"].ok and report["velocity"].ok
        # The checker reports the joint nearest its limit: the worst ratio peak / limit.
        limits = robot.limits
        velocity, acceleration = 15 / 8 * dist / T, 10 / np.sqrt(3) * dist / T**2
        np.testing.assert_allclose(
            report["velocity"].ratio, np.max(velocity / limits.velocity), rtol=1e-9
        )
        np.testing.assert_allclose(
            report["acceleration"].ratio, np.max(acceleration / limits.acceleration), rtol=1e-9
        )


@pytest.mark.parametrize("tfunc", [quintic, trapezoidal])
def test_mtraj_documented_example(tfunc):
    tg = mtraj(tfunc, Q1, -Q1, 11)
    assert tg.q.shape == tg.qd.shape == tg.qdd.shape == (11, 6)
    np.testing.assert_array_equal(tg.q[0], Q1)
    np.testing.assert_allclose(tg.q[[5, -1]], [np.zeros(6), -Q1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(tg.qd[[0, -1]], 0.0, rtol=0, atol=1e-12)
    if tfunc is quintic:
        np.testing.assert_allclose(tg.qdd[[0, 5, -1]], 0.0, rtol=0, atol=1e-12)
    assert tg.trajectory.metadata["profile"] == tfunc.__name__
    assert tg.istime is False


def test_mtraj_of_quintic_is_jtraj_on_a_time_vector():
    t = np.linspace(0.0, 3.0, 31)
    ours, theirs = mtraj(quintic, Q1, -Q1, t), jtraj(Q1, -Q1, t)
    for field in ("q", "qd", "qdd"):
        np.testing.assert_allclose(getattr(ours, field), getattr(theirs, field), atol=1e-12)


def test_mtraj_stacks_joints_of_different_timings_into_one_trajectory():
    rng = np.random.default_rng(3)
    q0, qf = rng.uniform(-2.0, 2.0, (2, 5))
    speeds = rng.uniform(1.1, 2.0, 5)
    t = np.linspace(0.0, 2.0, 41)
    speed_of = dict(zip(q0.tolist(), speeds, strict=True))
    tg = mtraj(lambda a, b, t: trapezoidal(a, b, t, speed_of[a] * abs(b - a) / 2.0), q0, qf, t)
    np.testing.assert_allclose(np.max(np.abs(tg.qd), axis=0), speeds * np.abs(qf - q0) / 2.0)
    sample = tg.trajectory.sample(t)
    for got, want in ((sample.q, tg.q), (sample.qd, tg.qd)):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_mtraj_of_trapezoidal_judged_by_the_checker():
    robot = get_robot("sawyer")
    q0, qf = robot.limits.sample(np.random.default_rng(1), 2)
    dist = np.abs(qf - q0)
    T = 10.0
    tg = mtraj(trapezoidal, q0, qf, np.linspace(0.0, T, 6))
    report = planners.check(tg.trajectory, robot)
    limits = robot.limits
    np.testing.assert_allclose(
        report["velocity"].ratio, np.max(1.5 * dist / T / limits.velocity), rtol=1e-9
    )
    np.testing.assert_allclose(
        report["acceleration"].ratio, np.max(4.5 * dist / T**2 / limits.acceleration), rtol=1e-9
    )
    assert report["jerk"].value == np.inf  # the blends switch acceleration at once


def test_bad_joint_inputs_are_refused_naming_them():
    with pytest.raises(InvalidInputError, match=r"qf must have shape \(6,\)"):
        jtraj(Q1, [1.0, 2.0], 10)
    with pytest.raises(InvalidInputError, match=r"qd1 must have shape \(6,\)"):
        jtraj(Q1, -Q1, 10, qd1=[0.0])
    with pytest.raises(InvalidInputError, match="q0 must be finite"):
        jtraj([np.nan], [0.0], 10)
    with pytest.raises(InvalidInputError, match="tfunc must be a scalar profile function"):
        mtraj("quintic", Q1, -Q1, 10)
    with pytest.raises(InvalidInputError, match="tfunc must return a scalar SampledProfile"):
        mtraj(lambda a, b, t: (a, b, t), Q1, -Q1, 10)
    with pytest.raises(InvalidInputError, match=r"V = .* is too large"):
        mtraj(lambda a, b, t: trapezoidal(a, b, t, V=100.0), Q1, -Q1, 10)


@pytest.mark.slow
def test_joint_profiles_agree_with_the_robotics_toolbox(rtb):
    rng = np.random.default_rng(8)
    for _ in range(10):
        q0, qf, v0, v1 = rng.uniform(-2.0, 2.0, (4, 4))
        t = np.linspace(0.0, rng.uniform(0.5, 5.0), 25)
        for args in ((q0, qf, 25, v0, v1), (q0, qf, t, v0, v1)):
            ours, theirs = jtraj(*args), rtb.jtraj(*args)
            for got, want in zip(
                (ours.q, ours.qd, ours.qdd), (theirs.q, theirs.qd, theirs.qdd), strict=True
            ):
                np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9)
        for ours_f, theirs_f in ((quintic, rtb.quintic), (trapezoidal, rtb.trapezoidal)):
            ours, theirs = mtraj(ours_f, q0, qf, t), rtb.mtraj(theirs_f, q0, qf, t)
            np.testing.assert_allclose(ours.q, theirs.q, rtol=1e-9, atol=1e-9)
            np.testing.assert_allclose(ours.qd, theirs.qd, rtol=1e-9, atol=1e-9)
