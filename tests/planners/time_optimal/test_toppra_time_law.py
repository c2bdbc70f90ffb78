"""Tests of planners.time_optimal.toppra_time_law: toppra's answer as exact polynomials."""

from __future__ import annotations

import numpy as np
from conftest import get_robot

from optraj import problems
from optraj.planners.time_optimal.toppra_planner import Toppra
from optraj.planners.time_optimal.toppra_time_law import TimeLaw, compose
from optraj.planners.trajectory import Trajectory


def test_exact_conversion_matches_toppras_own_output():
    robot = get_robot("sawyer")
    problem = problems.Waypoints(robot, robot.random_configurations(5, np.random.default_rng(3)))
    traj = Toppra(gridpoints=100).plan(problem)
    native = traj.metadata["native"]  # toppra's ParametrizeConstAccel
    t = np.linspace(0.0, traj.duration, 1234)
    sample = traj.sample(t)
    np.testing.assert_allclose(sample.q, native(t), rtol=0, atol=1e-9)
    np.testing.assert_allclose(sample.qd, native(t, 1), rtol=0, atol=1e-9)
    np.testing.assert_allclose(sample.qdd, native(t, 2), rtol=0, atol=1e-7)
    assert traj.degree == 6  # cubic path, quadratic s(t)


def test_compose_splits_pieces_where_knots_fall_between_gridpoints():
    knots = np.array([0.0, 0.3, 1.0])
    coefficients = np.array([[[0.0], [1.0], [0.5], [-0.2]], [[0.3448], [1.1760], [0.32], [0.1]]])
    grid = np.linspace(0.0, 1.0, 5)  # 0.3 is not a gridpoint
    sd = np.array([0.0, 0.8, 1.0, 0.7, 0.0])
    breakpoints, coeffs = compose(knots, coefficients, grid, sd)
    assert breakpoints.size == 6 and coeffs.shape == (5, 7, 1)
    traj = Trajectory(breakpoints, coeffs)
    path = Trajectory(knots, coefficients)
    t = np.linspace(0.0, traj.duration, 501)
    x = sd**2
    times = np.concatenate([[0.0], np.cumsum(2 * np.diff(grid) / (sd[:-1] + sd[1:]))])
    i = np.clip(np.searchsorted(times, t, side="right") - 1, 0, 3)
    u = (x[i + 1] - x[i]) / (2 * (grid[i + 1] - grid[i]))
    s = grid[i] + sd[i] * (t - times[i]) + 0.5 * u * (t - times[i]) ** 2
    np.testing.assert_allclose(traj.sample(t).q, path.sample(np.clip(s, 0, 1)).q, atol=1e-12)


def test_the_time_law_reaches_each_position_when_its_quadratic_does():
    grid = np.array([0.0, 0.5, 1.5, 2.0])
    sd = np.array([0.0, 1.0, 2.0, 0.0])
    law = TimeLaw(grid, sd)
    np.testing.assert_allclose(law.u, [1.0, 1.5, -4.0], rtol=1e-15)
    np.testing.assert_allclose(law.t, [0.0, 1.0, 1.0 + 2.0 / 3.0, 1.0 + 2.0 / 3.0 + 0.5])
    np.testing.assert_array_equal(law.time_at(grid), law.t)  # gridpoints: their own times
    # s = 0.5 t^2 on the first interval: s = 0.125 at t = 0.5
    np.testing.assert_allclose(law.time_at(np.array([0.125])), [0.5], rtol=1e-12)
    i, tau = law.locate(np.array([0.125, 1.0]))
    np.testing.assert_array_equal(i, [0, 1])
    s = grid[i] + sd[i] * tau + 0.5 * law.u[i] * tau**2
    np.testing.assert_allclose(s, [0.125, 1.0], rtol=1e-12)
