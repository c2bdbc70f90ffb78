"""Tests of planners.checker.context: windows, instants, exact states and the peak speed."""

from __future__ import annotations

import numpy as np
import pytest
from checker_support import DELTA, Q0, T, quintic

from optraj.planners.checker.context import CheckContext
from optraj.planners.checker.kinematics import ToolKinematics
from optraj.planners.checker.polynomials import derivatives_of
from optraj.planners.trajectory import Phase, Trajectory
from optraj.robots import Robot


def context_of(trajectory: Trajectory, robot: Robot, rate: float) -> CheckContext:
    grid = trajectory.times(rate)
    knots = np.asarray(trajectory.breakpoints, dtype=float)
    derivatives = derivatives_of(np.asarray(trajectory.coefficients, dtype=float), 4)
    return CheckContext(
        trajectory=trajectory,
        limits=robot.limits,
        names=robot.limits.names,
        knots=knots,
        derivatives=derivatives,
        grid=grid,
        spacing=float(np.max(np.diff(grid))),
        kinematics=ToolKinematics(robot, derivatives, knots),
    )


def test_windows_hold_their_samples_and_both_ends_the_end_from_the_left(paddle):
    trajectory = quintic(Q0, Q0 + DELTA, T, phases=[Phase("move", 0.0, 1.25)])
    ctx = context_of(trajectory, paddle, 4.0)
    assert ctx.duration == T and ctx.spacing == pytest.approx(0.25)
    assert ctx.phase("move") == Phase("move", 0.0, 1.25) and ctx.phase("strike") is None
    window = ctx.window(0.3, 1.0)
    np.testing.assert_array_equal(window, [0.3, 0.5, 0.75, np.nextafter(1.0, 0.0)])
    assert ctx.left_of(1.0) < 1.0 and ctx.left_of(T) == T  # the end is the end
    np.testing.assert_array_equal(ctx.window(0.5, 0.5), [0.5])


def test_instants_states_and_the_exact_peak_speed(paddle):
    trajectory = quintic(Q0, Q0 + DELTA, T)
    ctx = context_of(trajectory, paddle, 1.0)
    assert ctx.instant(-1e-10) == 0.0 and ctx.instant(T + 1e-10) == T
    assert ctx.instant(-1e-6) is None and ctx.instant(T + 1e-6) is None
    assert ctx.instant(0.7) == 0.7
    sample = trajectory.sample(np.array([0.7]))
    q, qd, qdd, jerk = ctx.state(0.7)
    np.testing.assert_allclose(q, sample.q[0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(qd, sample.qd[0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(qdd, sample.qdd[0], rtol=0, atol=1e-14)
    np.testing.assert_allclose(jerk, sample.jerk[0], rtol=0, atol=1e-13)
    np.testing.assert_allclose(ctx.state(-1.0)[0], Q0)  # clipped onto the trajectory
    assert ctx.peak_speed == pytest.approx(1.875 * np.max(np.abs(DELTA)) / T, rel=1e-12)
