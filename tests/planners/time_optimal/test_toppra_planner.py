"""Tests of planners.time_optimal.toppra_planner: the Toppra planner, its faces and options."""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import InvalidInputError, OptrajError
from optraj.planners.checker import check
from optraj.planners.time_optimal import toppra_planner
from optraj.planners.time_optimal.toppra_planner import GeometricPath, Toppra
from optraj.planners.trajectory import Phase, Trajectory

KINEMATIC = ("position", "velocity", "acceleration")


CASES = 1000


def _limits(robot, velocity=None, acceleration=None, effort=None):
    limits = robot.limits
    return dataclasses.replace(
        limits,
        velocity=limits.velocity if velocity is None else velocity,
        acceleration=limits.acceleration if acceleration is None else acceleration,
        effort=limits.effort if effort is None else effort,
    )


def _path_position(traj, t):
    """s(t) of a Toppra result, from its grid, grid times and path velocities."""
    grid = traj.metadata["grid"]
    times = traj.metadata["grid_times"]
    sd = traj.metadata["path_velocity"]
    i = np.clip(np.searchsorted(times, t, side="right") - 1, 0, grid.size - 2)
    u = (sd[i + 1] ** 2 - sd[i] ** 2) / (2.0 * (grid[i + 1] - grid[i]))
    tau = t - times[i]
    return grid[i] + sd[i] * tau + 0.5 * u * tau**2


def _rest_to_rest_time(distance, velocity, acceleration):
    """Closed-form minimum time of a 1-D rest-to-rest move (trapezoid or triangle) [s]."""
    if distance > velocity**2 / acceleration:
        return distance / velocity + velocity / acceleration
    return 2.0 * math.sqrt(distance / acceleration)


def _phase_plane_time(distance, velocity, acceleration, samples=200_001):
    """Brute force: the fastest path speed min(v, sqrt(2 a s), sqrt(2 a (L - s))), integrated."""
    s = np.linspace(0.0, distance, samples)
    speed = np.minimum(velocity, np.sqrt(2 * acceleration * np.minimum(s, distance - s)) + 1e-300)
    midpoint = 0.5 * (speed[1:] + speed[:-1])
    return float(np.sum(np.diff(s) / midpoint))


def _random_waypoints(rng):
    robot = get_robot("sawyer" if rng.random() < 0.5 else "paddle4")
    n = robot.dof
    limits = _limits(robot, rng.uniform(0.2, 3.0, n), rng.uniform(0.5, 20.0, n))
    points = robot.random_configurations(int(rng.integers(2, 6)), rng)
    return problems.Waypoints(robot, points, limits=limits)


@pytest.mark.parametrize("chunk", range(10))
def test_random_waypoints_pass_the_checker(chunk):
    """1000 seeded random cases (10 chunks), 100 grid intervals: every limit holds."""
    rng = np.random.default_rng([2026, chunk])
    planner = Toppra(gridpoints=100)
    failures = []
    for _ in range(CASES // 10):
        problem = _random_waypoints(rng)
        traj = planner.plan(problem)
        assert traj is not None
        report = check(traj, problem, quantities=KINEMATIC, rate=200.0)
        if not report.ok:
            failures.append((traj.metadata["path"], report.violations))
        assert traj.metadata["planner"] == "toppra"
        assert traj.metadata["limit_ratio"]["velocity"] <= 1.0
        assert traj.metadata["limit_ratio"]["acceleration"] <= 1.0
    assert failures == []


def test_metadata_and_phases_of_a_waypoints_plan():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(7)
    problem = problems.Waypoints(robot, robot.random_configurations(4, rng), via_tolerance=1e-9)
    traj = Toppra(gridpoints=150).plan(problem)
    meta = traj.metadata
    assert meta["planner"] == "toppra" and meta["status"] == "ok"
    assert meta["gridpoints"] == 150 and meta["solve_time"] > 0.0
    assert meta["native"].duration == pytest.approx(traj.duration, rel=1e-12)
    assert [p.name for p in traj.phases] == ["segment 1", "segment 2", "segment 3"]
    # each phase starts on its waypoint, at rest at both ends
    for k, phase in enumerate(traj.phases):
        np.testing.assert_allclose(
            traj.sample(phase.t_start).q, problem.waypoints[k], rtol=0, atol=1e-12
        )
    np.testing.assert_allclose(traj.sample(0.0).qd, 0.0, atol=1e-12)
    np.testing.assert_allclose(traj.sample(traj.duration).qd, 0.0, atol=1e-12)
    assert check(traj, problem, quantities=KINEMATIC).ok
    assert traj.to_dict()["metadata"]["planner"] == "toppra"  # native objects left out


@pytest.mark.parametrize("distance", [0.02, 0.3, 1.5])
def test_single_joint_line_matches_the_closed_form(distance):
    robot = get_robot("sawyer")
    limits = robot.limits
    q0 = robot.home.copy()
    q1 = q0.copy()
    q1[3] += distance if q0[3] + distance <= limits.upper[3] else -distance
    traj = Toppra().plan(problems.PointToPoint(robot, q0, q1))
    v, a = limits.velocity[3], limits.acceleration[3]
    exact = _rest_to_rest_time(distance, v, a)
    assert exact == pytest.approx(_phase_plane_time(distance, v, a), rel=1e-4)
    assert exact * (1 - 1e-9) <= traj.duration <= exact * 1.01
    np.testing.assert_allclose(traj.sample(traj.duration).q, q1, atol=1e-12)
    assert [p.name for p in traj.phases] == ["move"]


def test_proportional_line_matches_the_slowest_joints_closed_form():
    robot = get_robot("sawyer")
    limits = _limits(
        robot,
        velocity=np.array([1.0, 0.8, 1.5, 2.0, 0.6, 3.0, 1.2]),
        acceleration=np.array([4.0, 2.0, 6.0, 1.5, 8.0, 3.0, 5.0]),
    )
    q0 = robot.home.copy()
    delta = np.array([0.4, -0.3, 0.6, 0.2, -0.5, 0.7, 0.3])
    traj = Toppra().plan(problems.PointToPoint(robot, q0, q0 + delta, limits=limits))
    # joint j alone needs T_j(|delta_j|); all moving proportionally, the slowest decides,
    # with the scaled limits of the line parameter: min_j v_j / |delta_j| (and a alike)
    length = float(np.linalg.norm(delta))
    v = float(np.min(limits.velocity * length / np.abs(delta)))
    a = float(np.min(limits.acceleration * length / np.abs(delta)))
    exact = _rest_to_rest_time(length, v, a)
    assert exact * (1 - 1e-9) <= traj.duration <= exact * 1.01
    assert check(traj, robot, quantities=KINEMATIC).ok


def test_torque_and_tool_speed_need_a_robot():
    limits = get_robot("paddle4").limits
    points = limits.sample(np.random.default_rng(1), 2)
    for planner in (Toppra(torque=True), Toppra(tool_speed=0.5)):
        with pytest.raises(InvalidInputError, match="robot"):
            planner.time_parametrize(points, limits)


def test_start_and_end_path_velocities_are_honoured():
    robot = get_robot("paddle4")
    rng = np.random.default_rng(11)
    points = robot.random_configurations(3, rng)
    traj = Toppra(start_path_velocity=0.3, end_path_velocity=0.2).time_parametrize(
        points, robot.limits
    )
    spline = GeometricPath.spline(points)
    first = Trajectory(spline.knots, spline.derivatives[0])
    np.testing.assert_allclose(traj.sample(0.0).qd, 0.3 * first.sample(0.0).q, atol=1e-12)
    end = traj.sample(traj.duration).qd
    np.testing.assert_allclose(end, 0.2 * first.sample(first.duration).q, atol=1e-9)
    assert check(traj, robot, quantities=KINEMATIC).ok


def test_point_to_point_enters_and_leaves_along_the_line():
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    q1 = q0 + np.array([0.3, -0.2, 0.1, 0.4, -0.3, 0.2, 0.1])
    direction = (q1 - q0) / np.linalg.norm(q1 - q0)
    problem = problems.PointToPoint(
        robot, q0, q1, qd_start=0.3 * direction, qd_goal=0.5 * direction
    )
    traj = Toppra().plan(problem)
    np.testing.assert_allclose(traj.sample(0.0).qd, 0.3 * direction, atol=1e-12)
    np.testing.assert_allclose(traj.sample(traj.duration).qd, 0.5 * direction, atol=1e-9)
    assert check(traj, problem, quantities=KINEMATIC).ok


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"duration": 2.0}, "fixed duration"),
        ({"qdd_start": np.full(4, 0.1)}, "accelerations"),
    ],
)
def test_point_to_point_it_cannot_honour(kwargs, match):
    robot = get_robot("paddle4")
    q0 = robot.home.copy()
    problem = problems.PointToPoint(robot, q0, q0 + 0.2, **kwargs)
    with pytest.raises(InvalidInputError, match=match):
        Toppra().plan(problem)


def test_other_bad_inputs_are_typed_errors():
    robot = get_robot("paddle4")
    q0 = robot.home.copy()
    with pytest.raises(InvalidInputError, match="does not point forwards"):
        Toppra().plan(problems.PointToPoint(robot, q0, q0 + 0.2, qd_start=np.array([1, 0, 0, 0])))
    with pytest.raises(InvalidInputError, match="q_goal equals q_start"):
        Toppra().plan(problems.PointToPoint(robot, q0, q0))
    with pytest.raises(InvalidInputError, match="no path"):
        Toppra().time_parametrize(np.array([q0, q0, q0]), robot.limits)
    with pytest.raises(InvalidInputError, match="segment_durations"):
        Toppra().plan(problems.Waypoints(robot, [q0, q0 + 0.2], segment_durations=[1.0]))
    with pytest.raises(InvalidInputError, match="time_parametrize only"):
        Toppra(start_path_velocity=0.1).plan(problems.Waypoints(robot, [q0, q0 + 0.2]))
    with pytest.raises(InvalidInputError):
        Toppra(start_path_velocity=-1.0)
    with pytest.raises(InvalidInputError):
        Toppra(gridpoints=1)
    with pytest.raises(InvalidInputError):
        Toppra().plan(robot)
    corner = Trajectory(
        [0.0, 1.0, 2.0],
        np.array([[q0, np.full(4, 0.1)], [q0 + 0.1, np.array([0.1, -0.1, 0.1, 0.1])]]),
    )
    with pytest.raises(InvalidInputError, match="corner"):
        Toppra().time_parametrize(corner, robot.limits)
    with pytest.raises(OptrajError):  # never None
        Toppra().time_parametrize(np.array([q0]), robot.limits)


def test_trajectory_path_keeps_its_geometry_and_phases():
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    t = np.linspace(0.0, 2.0, 9)
    direction = np.array([0.3, -0.2, 0.1, 0.4, -0.3, 0.2, 0.1])
    path = Trajectory.from_hermite(
        t,
        q0 + np.outer(np.sin(t), direction),
        np.outer(np.cos(t), direction),
        -np.outer(np.sin(t), direction),
        phases=[Phase("approach", 0.0, 0.5), Phase("strike", 0.5, 1.6), Phase("stop", 1.6, 2.0)],
    )
    traj = Toppra().time_parametrize(path, robot.limits, robot=robot)
    assert [p.name for p in traj.phases] == ["approach", "strike", "stop"]
    times = np.linspace(0.0, traj.duration, 1001)
    s = np.clip(_path_position(traj, times), 0.0, path.duration)
    np.testing.assert_allclose(traj.sample(times).q, path.sample(s).q, rtol=0, atol=1e-6)
    for old, new in zip(path.phases, traj.phases, strict=True):
        np.testing.assert_allclose(
            traj.sample(new.t_start).q, path.sample(old.t_start).q, atol=1e-6
        )
        np.testing.assert_allclose(traj.sample(new.t_end).q, path.sample(old.t_end).q, atol=1e-6)
    assert traj.metadata["path_unit"] == "s"
    assert check(traj, robot, quantities=KINEMATIC).ok


def test_retiming_a_toppra_result_under_tighter_limits():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(3)
    problem = problems.Waypoints(robot, robot.random_configurations(4, rng))
    first = Toppra().plan(problem)
    slower = _limits(robot, robot.limits.velocity * 0.5, robot.limits.acceleration * 0.3)
    second = Toppra().time_parametrize(first, slower)  # a path that starts and ends at rest
    assert second.duration > first.duration
    assert [p.name for p in second.phases] == [p.name for p in first.phases]
    slow_problem = problems.Waypoints(robot, problem.waypoints, limits=slower)
    assert check(second, slow_problem, quantities=KINEMATIC).ok


def test_importing_the_module_does_not_import_toppra():
    code = (
        "import sys, planners.time_optimal.toppra_planner; "
        "assert 'toppra' not in sys.modules and 'matplotlib' not in sys.modules"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr


def test_numbers_in_range():
    # a tool speed or path velocity of 1e308 would overflow the solve
    with pytest.raises(InvalidInputError, match="tool_speed must be <= 343 m/s"):
        Toppra(tool_speed=1e308)
    with pytest.raises(InvalidInputError, match=r"start_path_velocity must be <= 1e\+08"):
        Toppra(start_path_velocity=1e200)
    with pytest.raises(InvalidInputError, match="tool_speed must be a numeric"):
        Toppra(tool_speed="1")
    with pytest.raises(InvalidInputError, match="torque must be True or False"):
        Toppra(torque=1)
    with pytest.raises(InvalidInputError, match="gridpoints must be an integer <= 100000"):
        Toppra(gridpoints=10**7)


def test_a_still_move_with_a_boundary_velocity_has_no_line_to_follow():
    robot = get_robot("paddle4")
    q = np.array([0.5, 0.1, 0.2, 0.0])
    qd = np.array([0.2, 0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match="no straight line to move along") as info:
        Toppra().plan(problems.PointToPoint(robot, q, q, qd, qd))
    assert info.value.name == "q_goal"
    with pytest.raises(InvalidInputError, match="every waypoint equals the first"):
        Toppra().plan(problems.Waypoints(robot, [q, q + 1e-13]))


def test_the_names_of_the_pieces_are_importable_from_here_as_before():
    from optraj.planners.time_optimal import (
        toppra_constraints,
        toppra_path,
        toppra_problem,
        toppra_solve,
        toppra_time_law,
    )

    assert toppra_planner.GeometricPath is toppra_path.GeometricPath
    assert toppra_planner.curvature_jumps is toppra_path.curvature_jumps
    assert toppra_planner.ToppraProblem is toppra_problem.ToppraProblem
    assert toppra_planner.MARGIN == toppra_problem.MARGIN
    assert toppra_planner.RETRIES == toppra_solve.RETRIES
    assert toppra_planner.compose is toppra_time_law.compose
    for name in ("chord_safe_bound", "jump_rows", "normalised_rows"):
        assert getattr(toppra_planner, name) is getattr(toppra_constraints, name)
    assert all(hasattr(toppra_planner, name) for name in toppra_planner.__all__)


def test_time_parametrize_passes_its_keyword_options_to_build():
    robot = get_robot("paddle4")
    points = robot.random_configurations(3, np.random.default_rng(6))
    planner = Toppra(gridpoints=40)
    built = planner.build(points, robot.limits, robot=robot, sd_start=0.1, sd_end=0.05)
    assert (built.sd_start, built.sd_end, built.robot) == (0.1, 0.05, robot)
    traj = planner.time_parametrize(points, robot.limits, robot=robot, sd_start=0.1, sd_end=0.05)
    assert traj.metadata["sd_start"] == 0.1 and traj.metadata["sd_end"] == 0.05
    with pytest.raises(TypeError, match=r"time_parametrize\(\) got an unexpected .*'sd_begin'"):
        planner.time_parametrize(points, robot.limits, sd_begin=0.1)
