"""Tests of planners.time_optimal.toppra_verify: bounds on every limit between gridpoints."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj.planners.time_optimal.toppra_path import segment_of
from optraj.planners.time_optimal.toppra_planner import Toppra
from optraj.planners.time_optimal.toppra_time_law import TimeLaw
from optraj.planners.time_optimal.toppra_verify import TARGET, verify


def test_the_bounds_cover_the_sampled_peaks_and_come_close_to_them():
    robot = get_robot("sawyer")
    points = robot.random_configurations(4, np.random.default_rng(12))
    planner = Toppra(gridpoints=60, tool_speed=1.0)
    built = planner.build(points, robot.limits, robot=robot)
    traj = planner.solve(built)
    grid = traj.metadata["grid"]  # refined where the first solve exceeded a limit
    problem = dataclasses.replace(built, grid=grid, segment=segment_of(built.path.knots, grid[:-1]))
    found = verify(problem, TimeLaw(grid, traj.metadata["path_velocity"]))
    assert set(found.ratios) == {"velocity", "acceleration", "tool speed"}
    assert max(found.ratios.values()) <= 1.0 and found.slowdown <= 1.0
    sample = traj.sample(np.linspace(0.0, traj.duration, 20_001))
    limits = robot.limits
    velocity = float(np.max(np.abs(sample.qd) / limits.velocity))
    acceleration = float(np.max(np.abs(sample.qdd) / limits.acceleration))
    assert velocity <= found.ratios["velocity"] + 1e-12
    assert acceleration <= found.ratios["acceleration"] + 1e-12
    assert found.ratios["velocity"] <= 1.01 * velocity  # a bound, close to the peak
    assert found.ratios["acceleration"] <= 1.01 * acceleration
    if max(found.ratios.values()) <= TARGET:
        assert found.slowdown == 1.0 and found.over.size == 0


def test_a_slowdown_scales_speeds_by_c_and_accelerations_by_c_squared():
    robot = get_robot("paddle4")
    points = robot.random_configurations(3, np.random.default_rng(3))
    problem = Toppra(gridpoints=40).build(points, robot.limits)
    law = TimeLaw(problem.grid, np.full(problem.grid.size, 0.05))  # slow: within every limit
    slow = verify(problem, law)
    assert max(slow.ratios.values()) <= TARGET
    assert slow.slowdown == 1.0 and slow.over.size == 0 and slow.after == slow.ratios
    fast = verify(problem, TimeLaw(problem.grid, law.sd * 0.5))
    np.testing.assert_allclose(fast.ratios["velocity"], 0.5 * slow.ratios["velocity"], rtol=1e-9)
    np.testing.assert_allclose(
        fast.ratios["acceleration"], 0.25 * slow.ratios["acceleration"], rtol=1e-9
    )
    # far too fast: the slow-down brings the binding bound to TARGET exactly
    over = verify(problem, TimeLaw(problem.grid, np.full(problem.grid.size, 100.0)))
    assert over.slowdown < 1.0 and over.over.size > 0
    assert max(over.after.values()) == pytest.approx(TARGET, rel=1e-12)
    assert over.after["velocity"] == pytest.approx(over.ratios["velocity"] * over.slowdown)
