"""Tests of planners.time_optimal.toppra_planner: TOPPRA retiming as exact trajectories."""

from __future__ import annotations

import dataclasses
import math
import pickle
import subprocess
import sys

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InfeasibleError, InvalidInputError, JointLimitError, OptrajError
from optraj.planners.checker import check
from optraj.planners.time_optimal.toppra_planner import (
    GeometricPath,
    Toppra,
    ToppraProblem,
    compose,
)
from optraj.planners.trajectory import Phase, Trajectory

KINEMATIC = ("position", "velocity", "acceleration")
#: Random cases of the stress test (each: plan, then the checker at 200 Hz).
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


# ------------------------------------------------------------------ stress test


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


# ----------------------------------------------------------- closed-form durations


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


# ------------------------------------------------------------------------- torque


def test_torque_limits_slow_the_motion_and_hold():
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    points = np.array([q0, q0 + np.array([0.5, -0.6, 0.3, 0.5, -0.4, 0.3, 0.2])])
    fast = _limits(robot, acceleration=robot.limits.acceleration * 4)
    free = Toppra().plan(problems.Waypoints(robot, points, limits=fast))
    held = np.abs(robot.gravity_torque(np.linspace(points[0], points[1], 50))).max(axis=0)
    limits = _limits(robot, acceleration=fast.acceleration, effort=np.maximum(1.3 * held, 1.0))
    problem = problems.Waypoints(robot, points, limits=limits)
    assert not check(free, problem, quantities=("torque",)).ok  # too fast for these torques
    slow = Toppra(torque=True).plan(problem)
    assert slow.duration > 1.2 * free.duration
    report = check(slow, problem, quantities=(*KINEMATIC, "torque"))
    assert report.ok, report.violations
    assert report["torque"].ratio > 0.99  # the torque limit binds
    assert slow.metadata["limit_ratio"]["torque"] <= 1.0


def test_gravity_alone_breaking_a_torque_limit_names_the_joint():
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    points = np.array([q0, q0 + np.array([0.5, -0.6, 0.3, 0.5, -0.4, 0.3, 0.2])])
    held = np.abs(robot.gravity_torque(np.linspace(points[0], points[1], 50))).max(axis=0)
    effort = robot.limits.effort.copy()
    effort[3] = 0.8 * held[3]
    problem = problems.Waypoints(robot, points, limits=_limits(robot, effort=effort))
    with pytest.raises(InfeasibleError) as info:
        Toppra(torque=True).plan(problem)
    error = info.value
    assert error.limit == "torque" and error.joint == robot.joint_names[3]
    assert error.required > error.allowed == pytest.approx(effort[3])
    assert "gravity" in str(error) and "s = " in str(error)
    Toppra().plan(problem)  # without torque limits the same path is fine


def test_torque_and_tool_speed_need_a_robot():
    limits = get_robot("paddle4").limits
    points = limits.sample(np.random.default_rng(1), 2)
    for planner in (Toppra(torque=True), Toppra(tool_speed=0.5)):
        with pytest.raises(InvalidInputError, match="robot"):
            planner.time_parametrize(points, limits)


# --------------------------------------------------------------------- tool speed


@pytest.mark.parametrize("cap", [0.6, 0.25])
def test_tool_speed_cap_holds(cap):
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    problem = problems.Waypoints(
        robot, [q0, q0 + np.array([0.5, -0.6, 0.3, 0.5, -0.4, 0.3, 0.2]), q0]
    )
    free = Toppra().plan(problem)
    capped = Toppra(tool_speed=cap).plan(problem)
    sample = capped.sample(capped.times(2000.0))
    J = robot.jacobian(sample.q)
    speed = np.linalg.norm(np.einsum("kij,kj->ki", J[:, :3], sample.qd), axis=1)
    assert speed.max() <= cap
    assert speed.max() >= 0.99 * cap  # and it binds
    assert capped.duration > free.duration
    assert check(capped, problem, quantities=KINEMATIC).ok


# --------------------------------------------------------------- boundary velocities


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


def test_too_fast_start_path_velocity_is_infeasible():
    robot = get_robot("sawyer")
    limits = robot.limits
    q0 = robot.home.copy()
    q1 = q0.copy()
    q1[3] += 0.8  # s = chord length: joint 3 moves at the path velocity
    with pytest.raises(InfeasibleError) as info:
        Toppra().time_parametrize(np.array([q0, q1]), limits, sd_start=2 * limits.velocity[3])
    error = info.value
    assert error.limit == "path velocity"
    assert error.required == pytest.approx(2 * limits.velocity[3])
    assert error.allowed == pytest.approx(limits.velocity[3], rel=2e-3)
    assert "start path velocity" in str(error)
    traj = Toppra().time_parametrize(np.array([q0, q1]), limits, sd_start=0.99 * error.allowed)
    assert traj.sample(0.0).qd[3] == pytest.approx(0.99 * error.allowed)


def test_start_too_fast_to_stop_in_time_is_infeasible():
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    q1 = q0.copy()
    q1[3] += 0.01
    with pytest.raises(InfeasibleError, match="largest feasible start path velocity"):
        Toppra().time_parametrize(np.array([q0, q1]), robot.limits, sd_start=1.5)


def test_too_fast_end_path_velocity_names_the_joint():
    robot = get_robot("sawyer")
    limits = robot.limits
    q0 = robot.home.copy()
    q1 = q0.copy()
    q1[3] += 0.8
    with pytest.raises(InfeasibleError) as info:
        Toppra().time_parametrize(np.array([q0, q1]), limits, sd_end=2 * limits.velocity[3])
    assert info.value.joint == robot.joint_names[3]
    assert info.value.allowed == pytest.approx(limits.velocity[3], rel=2e-3)


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


# ---------------------------------------------------------------- infeasible inputs


def test_waypoint_outside_the_joint_limits_is_a_typed_error():
    robot = get_robot("sawyer")
    limits = robot.limits
    q0 = robot.home.copy()
    bad = q0.copy()
    bad[1] = limits.upper[1] + 0.1
    with pytest.raises(JointLimitError) as info:
        Toppra().time_parametrize(np.array([q0, bad]), limits)
    assert info.value.joint == robot.joint_names[1]
    with pytest.raises(JointLimitError):
        problems.Waypoints(robot, [q0, bad])


def test_trajectory_path_through_a_joint_limit_names_the_joint():
    robot = get_robot("paddle4")
    limits = robot.limits
    q0 = robot.home.copy()
    q1 = q0.copy()
    q1[2] = limits.upper[2] - 0.01
    # a cubic that overshoots past q1 (and the limit) before coming back to it
    path = Trajectory.from_hermite([0.0, 1.0], [q0, q1], [2.0 * (q1 - q0), -(q1 - q0)])
    with pytest.raises(JointLimitError) as info:
        Toppra().time_parametrize(path, limits)
    assert info.value.joint == robot.joint_names[2]
    assert "s = " in str(info.value)


def test_spline_leaving_the_limits_falls_back_to_a_shape_preserving_path():
    robot = get_robot("paddle4")
    limits = robot.limits
    rng = np.random.default_rng(5)
    for _ in range(50):
        points = robot.random_configurations(5, rng)
        traj = Toppra(gridpoints=60).time_parametrize(points, limits)
        assert check(traj, robot, quantities=KINEMATIC).ok
        if traj.metadata["path"].startswith("pchip"):
            with pytest.raises(JointLimitError):  # the spline would have left the limits
                Toppra().time_parametrize(Trajectory(*_spline_as_trajectory(points)), limits)
            break
    else:
        pytest.fail("no random case needed the fallback")


def _spline_as_trajectory(points):
    spline = GeometricPath.spline(points)
    return spline.knots, spline.coefficients


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


# ------------------------------------------------------------ trajectories as paths


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


def test_path_with_stops_and_a_dwell_is_retimed_without_a_large_slowdown():
    robot = get_robot("sawyer")
    q0 = robot.home.copy()
    q1 = q0 + 0.3
    go = planners.Quintic().plan(problems.PointToPoint(robot, q0, q1))
    back = planners.Quintic().plan(problems.PointToPoint(robot, q1, q0))
    single = Toppra().time_parametrize(go, robot.limits).duration
    for path in (go.then(Trajectory.constant(q1, 0.5), back), go.then(back)):
        traj = Toppra().time_parametrize(path, robot.limits)
        assert check(traj, robot, quantities=KINEMATIC).ok
        # both moves as fast as alone (within the grid's resolution); the dwell takes ~0 s
        assert traj.duration < 2.0 * single * 1.08
        assert traj.metadata["slowdown"] < 1.01


# ---------------------------------------------------------------------- internals


def test_built_problem_can_be_inspected_before_solving():
    robot = get_robot("paddle4")
    points = robot.random_configurations(3, np.random.default_rng(2))
    planner = Toppra(gridpoints=50)
    built = planner.build(points, robot.limits)
    assert isinstance(built, ToppraProblem)
    assert built.grid.size == 51 and built.grid[0] == 0.0
    assert set(built.path.knots) <= set(built.grid)  # every knot is a gridpoint
    assert len(built.constraints()) == 2
    traj = planner.solve(built)
    assert traj.metadata["gridpoints"] == 50


def test_importing_the_module_does_not_import_toppra():
    code = (
        "import sys, planners.time_optimal.toppra_planner; "
        "assert 'toppra' not in sys.modules and 'matplotlib' not in sys.modules"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr


def test_results_pickle_with_toppras_object():
    robot = get_robot("paddle4")
    problem = problems.Waypoints(robot, robot.random_configurations(3, np.random.default_rng(4)))
    traj = Toppra().plan(problem)
    clone = pickle.loads(pickle.dumps(traj))
    t = np.linspace(0.0, traj.duration, 50)
    np.testing.assert_array_equal(clone.sample(t).q, traj.sample(t).q)
    np.testing.assert_allclose(clone.metadata["native"](t), traj.sample(t).q, atol=1e-9)
    assert clone.metadata["controllable_sets"].shape == (traj.metadata["gridpoints"] + 1, 2)
    # a fresh interpreter finds the toppra-derived classes too
    code = (
        "import pickle, sys; traj = pickle.loads(sys.stdin.buffer.read()); "
        "print(traj.metadata['native'].duration)"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], input=pickle.dumps(traj), capture_output=True, check=False
    )
    assert done.returncode == 0, done.stderr.decode()
    assert float(done.stdout) == pytest.approx(traj.duration)


@pytest.mark.parametrize("size", [2e-12, 1e-11, 1e-10, 1e-9, 3e-9, 1e-7])
def test_tiny_moves_are_feasible(size):
    # issue 32, defect 8: toppra's absolute tolerances called the controllable set of these
    # moves empty; the path is now solved in a parameter at least one unit long.
    robot = get_robot("sawyer")
    q1 = robot.home.copy()
    q1[0] += size
    problem = problems.PointToPoint(robot, robot.home, q1)
    traj = Toppra().plan(problem)
    assert check(traj, problem, quantities=KINEMATIC).ok
    # One joint moves: the optimum is the bang-bang (LSPB) minimum time, within MARGIN.
    fastest = planners.LSPB().plan(problem).duration
    assert traj.duration == pytest.approx(
        fastest, rel=2 * planners.time_optimal.toppra_planner.MARGIN
    )


def test_a_stretched_path_is_the_same_path():
    path = GeometricPath.spline(np.array([[0.0, 0.0], [1e-3, 2e-3], [3e-3, 1e-3]]))
    stretched = path.stretched(500.0)
    s = np.linspace(0.0, path.knots[-1], 7)
    for order in range(3):
        np.testing.assert_allclose(
            stretched.native(500.0 * s, order) * 500.0**order, path.native(s, order), rtol=1e-12
        )


def test_numbers_in_range():
    # issue 32, defect 6: a tool speed or path velocity of 1e308 overflowed the solve
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


def test_pchip_slopes_near_zero_stay_finite_without_overflow_warnings():
    import warnings

    from optraj.planners.time_optimal.toppra_planner import GeometricPath

    waypoints = np.array([[0.0, 0.0], [1.0, 1e-310], [2.0, 2e-310], [3.0, 0.5]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the overflow in the slopes' mean was a RuntimeWarning
        path = GeometricPath.pchip(waypoints)
    assert np.all(np.isfinite(path.coefficients))
