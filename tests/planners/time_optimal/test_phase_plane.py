"""Tests of planners.time_optimal.phase_plane: TOPPRA's plan and its bounds in (s, s-dot)."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot
from scipy.optimize import linprog

from optraj import planners, problems
from optraj.errors import InvalidInputError
from optraj.planners.time_optimal.phase_plane import PhasePlane, phase_plane
from optraj.planners.time_optimal.toppra_problem import MARGIN


def _solved(waypoints, robot, **options):
    toppra = planners.Toppra(**options)
    problem = toppra.build(np.asarray(waypoints), robot.limits, robot=robot)
    return problem, toppra.solve(problem)


@pytest.fixture(scope="module")
def line():
    """paddle4's slide J1 alone over 0.5 m: a path shorter than 1 m, solved stretched."""
    robot = get_robot("paddle4")
    goal = robot.home.copy()
    goal[0] = 0.95
    problem, traj = _solved([robot.home, goal], robot)
    return robot, problem, traj, phase_plane(problem, traj)


@pytest.fixture(scope="module")
def curve():
    """A Sawyer spline through four seeded waypoints."""
    robot = get_robot("sawyer")
    rng = np.random.default_rng(36)
    steps = rng.uniform(-0.5, 0.5, size=(3, robot.dof))
    waypoints = robot.home + np.vstack([np.zeros(robot.dof), np.cumsum(steps, axis=0)])
    problem, traj = _solved(waypoints, robot)
    return robot, problem, traj, phase_plane(problem, traj)


def test_a_straight_line_is_bounded_by_its_velocity_limit_alone(line):
    robot, _, traj, plane = line
    speed = robot.limits.velocity[0]  # s is the distance J1 moves [m]: s-dot is its speed
    assert isinstance(plane, PhasePlane)
    assert plane.unit == "rad"
    np.testing.assert_allclose(plane.s, traj.metadata["grid"], rtol=0, atol=0)
    np.testing.assert_allclose(plane.sd_max, speed, rtol=1e-9)
    np.testing.assert_allclose(plane.bounds["velocity"], speed, rtol=1e-9)
    assert np.all(np.isinf(plane.bounds["acceleration"]))  # q'' = 0 on a line
    assert set(plane.binding) == {"velocity"}
    # time-optimal: it cruises at the velocity limit the planner keeps (shrunk by MARGIN)
    assert np.max(plane.sd) == pytest.approx(speed * (1.0 - MARGIN), rel=1e-6)
    # from rest at the acceleration limit: s-dot = sqrt(2 a s) at the first gridpoints
    acceleration = robot.limits.acceleration[0] * (1.0 - MARGIN)
    np.testing.assert_allclose(plane.sd[1:4], np.sqrt(2 * acceleration * plane.s[1:4]), rtol=1e-6)


def test_the_plan_is_the_trajectory_s_path_velocity(curve):
    _, problem, traj, plane = curve
    times = traj.metadata["grid_times"]
    tangent = problem.path.native(plane.s, 1)  # q'(s) [rad/rad]
    np.testing.assert_allclose(
        traj.sample(times).qd, tangent * plane.sd[:, None], rtol=0, atol=1e-9
    )


def test_the_plan_stays_under_every_bound_and_reaches_the_limits(curve):
    _, _, _, plane = curve
    assert plane.sd[0] == 0.0 and plane.sd[-1] == 0.0
    assert np.all(plane.sd <= plane.sd_controllable * (1 + 1e-9) + 1e-12)
    assert np.all(plane.sd_controllable <= plane.sd_max * (1 + 1e-9))
    lowest = np.min(np.stack(list(plane.bounds.values())), axis=0)
    assert np.all(plane.sd_max <= lowest * (1 + 1e-9))
    # velocity and acceleration only: the joint bound is the lower of the two
    np.testing.assert_allclose(plane.sd_max, lowest, rtol=1e-9)
    assert np.max(plane.sd / np.maximum(plane.sd_max, 1e-300)) > 0.99  # time-optimal
    assert set(plane.binding) <= {"velocity", "acceleration"}


def test_the_acceleration_bound_is_the_largest_s_dot_of_an_independent_lp():
    # three waypoints: one parabola, so q'' is constant and no knot makes a jump row
    robot = get_robot("sawyer")
    rng = np.random.default_rng(7)
    waypoints = robot.home + np.vstack(
        [np.zeros(robot.dof), rng.uniform(-0.6, 0.6, (2, robot.dof))]
    )
    problem, traj = _solved(waypoints, robot, gridpoints=40)
    plane = phase_plane(problem, traj)
    s = plane.s
    first, second = problem.path.native(s, 1), problem.path.native(s, 2)
    limit = robot.limits.acceleration
    for i in range(s.size - 1):
        # toppra's interpolation: |q' u + q'' x| <= a at s_i and, with x + 2 ds u, at s_i+1
        ds = s[i + 1] - s[i]
        u_terms = np.concatenate([first[i], first[i + 1] + 2 * ds * second[i + 1]])
        rows = np.column_stack([u_terms, np.concatenate([second[i], second[i + 1]])])
        bound = np.tile(limit, 2)
        result = linprog(
            c=[0.0, -1.0],
            A_ub=np.vstack([rows, -rows]),
            b_ub=np.concatenate([bound, bound]),
            bounds=[(None, None), (0.0, None)],
        )
        assert result.status == 0
        assert plane.bounds["acceleration"][i] == pytest.approx(np.sqrt(result.x[1]), rel=1e-6)


def test_torque_limits_add_their_own_bound():
    robot = get_robot("sawyer")
    problem, traj = _solved([robot.home, robot.home + 0.3], robot, torque=True, gridpoints=50)
    plane = phase_plane(problem, traj)
    assert tuple(plane.bounds) == ("velocity", "acceleration", "torque")
    assert np.all(plane.sd_max <= plane.bounds["torque"] * (1 + 1e-9))
    assert np.all(np.isfinite(plane.bounds["torque"]))


def test_a_trajectory_used_as_a_path_sets_no_bound_where_it_rests():
    robot = get_robot("sawyer")
    move = problems.PointToPoint(robot, q_start=robot.home, q_goal=robot.home + 0.5)
    quintic = planners.Quintic().plan(move)  # q'(s) = 0 at its rest ends (s is its time)
    toppra = planners.Toppra(gridpoints=60)
    problem = toppra.build(quintic, robot.limits)
    plane = phase_plane(problem, toppra.solve(problem))
    assert plane.unit == "s"
    for bound in (plane.sd_max, plane.bounds["velocity"], plane.bounds["acceleration"]):
        assert np.isinf(bound[0]) and np.isinf(bound[-1])
        middle = bound[bound.size // 4 : 3 * bound.size // 4]
        assert np.all(np.isfinite(middle))
    assert plane.sd[0] == 0.0 and plane.sd[-1] == 0.0
    assert np.all(plane.sd <= plane.sd_max)


def test_a_plan_of_another_kind_or_path_is_refused(line, curve):
    robot, problem, traj, _ = line
    move = problems.PointToPoint(robot, q_start=robot.home, q_goal=[0.95, 0.0, 0.0, 0.0])
    with pytest.raises(InvalidInputError, match=r"not retimed by planners\.Toppra.*'grid'"):
        phase_plane(problem, planners.Quintic().plan(move))
    with pytest.raises(InvalidInputError, match="retimed along another path"):
        phase_plane(curve[1], traj)
    with pytest.raises(InvalidInputError, match="problem must be a ToppraProblem"):
        phase_plane(move, traj)
    with pytest.raises(InvalidInputError, match=r"trajectory must be a planners\.Trajectory"):
        phase_plane(problem, traj.metadata)
