"""Tests of planners.time_optimal.toppra_grid: gridpoints, their refinement, short paths."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj.planners.time_optimal.toppra_grid import grid_for, refined, stretch_factor
from optraj.planners.time_optimal.toppra_path import GeometricPath
from optraj.planners.time_optimal.toppra_planner import Toppra


def test_every_knot_is_a_gridpoint_and_the_count_is_kept():
    path = GeometricPath.spline(np.array([[0.0, 0.0], [0.1, 0.05], [0.9, 0.4], [1.0, 1.0]]))
    grid = grid_for(path, 50)
    assert grid.size == 51 and np.all(np.diff(grid) > 0.0)
    assert set(path.knots) <= set(grid)
    assert grid[0] == path.knots[0] and grid[-1] == path.knots[-1]
    assert 100 <= grid_for(path, None).size - 1 <= 400  # by default: one per 0.02 rad
    np.testing.assert_array_equal(grid_for(path, 2), path.knots)  # one per segment at least
    line = GeometricPath.line(np.zeros(2), np.array([3.0, 4.0]))
    np.testing.assert_allclose(grid_for(line, 10), np.linspace(0.0, 5.0, 11))


def test_refined_splits_the_given_intervals_into_four():
    robot = get_robot("paddle4")
    points = robot.random_configurations(3, np.random.default_rng(2))
    problem = Toppra(gridpoints=10).build(points, robot.limits)
    finer = refined(problem, np.array([0, 3]))
    assert finer.grid.size == problem.grid.size + 6 and finer.segment.size == finer.grid.size - 1
    step = problem.grid[1] - problem.grid[0]
    np.testing.assert_allclose(np.diff(finer.grid[:5]), np.full(4, step / 4.0), rtol=1e-12)
    assert set(problem.grid) <= set(finer.grid)
    assert finer.path is problem.path


@pytest.mark.parametrize(("length", "factor"), [(0.25, 2.0), (1e-6, 1e3), (1.0, 1.0), (4.0, 1.0)])
def test_short_paths_are_solved_in_a_stretched_parameter(length, factor):
    path = GeometricPath.line(np.zeros(2), np.array([0.0, length]))
    assert stretch_factor(path) == pytest.approx(factor, rel=1e-12)
