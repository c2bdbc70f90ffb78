"""Tests of problems.point_to_point."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners
from optraj.errors import CollisionError, InvalidInputError, JointLimitError
from optraj.problems import BoundaryState, Box, PointToPoint, Scene
from optraj.problems.point_to_point import STILL_TOLERANCE, is_still


def test_defaults_are_rest_and_constraints_are_the_two_states():
    robot = get_robot("paddle4")
    problem = PointToPoint(robot, robot.home, [0.5, 0.1, 0.2, 0.0])
    np.testing.assert_array_equal(problem.qd_start, np.zeros(4))
    assert problem.qdd_start is None and problem.limits is robot.limits
    start, end = problem.constraints()
    assert isinstance(start, BoundaryState) and start.at == "start" and end.at == "end"
    np.testing.assert_array_equal(end.q, [0.5, 0.1, 0.2, 0.0])


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"q_goal": [0.5, 0.0, 1.2, 0.0]}, JointLimitError, r"q_goal: joint 'J3' position 1.2 m"),
        (
            {"qd_start": [0.0, 5.0, 0.0, 0.0]},
            JointLimitError,
            r"'J2' velocity 5 rad/s .* \[-3, 3\]",
        ),
        ({"qdd_goal": [9.0, 0, 0, 0]}, JointLimitError, r"'J1' acceleration 9 m/s\^2"),
        ({"q_goal": [0.5, np.nan, 0, 0]}, InvalidInputError, "finite"),
        ({"q_goal": [0.5, 0.0]}, InvalidInputError, r"shape \(4,\)"),
        ({"duration": 0.0}, InvalidInputError, "duration must be >= 1e-06 s, got 0 s"),
        # No text, no extreme durations, no missing positions.
        ({"duration": "2"}, InvalidInputError, "duration must be a numeric"),
        ({"duration": 1e200}, InvalidInputError, "duration must be <= 86400 s, got 1e[+]200 s"),
        ({"duration": 1e-200}, InvalidInputError, "duration must be >= 1e-06 s"),
        ({"q_start": None}, InvalidInputError, r"q_start must be a numeric array of shape \(4,\)"),
        ({"q_goal": None}, InvalidInputError, r"q_goal must be a numeric array of shape \(4,\)"),
        ({"q_goal": ["0.5", 0, 0, 0]}, InvalidInputError, "q_goal must be a numeric"),
        ({"tolerance": -1.0}, InvalidInputError, "tolerance must be >= 0, got -1"),
        ({"tolerance": True}, InvalidInputError, "tolerance must be a numeric"),
        ({"robot": "paddle4"}, InvalidInputError, "robots.Robot"),
    ],
)
def test_bad_values_name_the_value_and_the_bound(kwargs, error, match):
    robot = get_robot("paddle4")
    fields = {"robot": robot, "q_start": robot.home, "q_goal": robot.home}
    fields.update(kwargs)
    with pytest.raises(error, match=match):
        PointToPoint(**fields)


def test_limits_must_match_the_robot():
    with pytest.raises(InvalidInputError, match=r"limits must be a robots\.JointLimits"):
        PointToPoint(
            get_robot("paddle4"), np.zeros(4), np.zeros(4), limits=get_robot("youbot").limits
        )


# ------------------------------------------------- a move whose goal equals its start

#: The planners of a rest-to-rest PointToPoint, and the limits each keeps (for the checker).
_PLANNERS = {
    "cubic": (planners.Cubic, ("position", "velocity", "acceleration")),
    "quintic": (planners.Quintic, None),
    "lspb": (planners.LSPB, ("position", "velocity", "acceleration")),
    "toppra": (planners.Toppra, ("position", "velocity", "acceleration")),
    "ruckig": (planners.Ruckig, None),
    "optimal-control": (planners.OptimalControl, None),
}
_HOLDS = ("cubic", "quintic", "lspb", "ruckig")  # the planners that take a duration


@pytest.mark.parametrize("name", list(_PLANNERS))
@pytest.mark.parametrize("offset", [0.0, 1e-13, 0.9 * STILL_TOLERANCE])
def test_every_planner_refuses_a_still_move_without_a_duration(name, offset):
    # One rule for every planner, with one message: a still move needs a duration (no
    # trajectory of a vanishing length, and not only an exactly equal goal is still).
    robot = get_robot("sawyer")
    problem = PointToPoint(robot, robot.home, robot.home + offset)  # valid when built
    assert problem.still
    with pytest.raises(InvalidInputError, match="q_goal equals q_start") as info:
        _PLANNERS[name][0]().plan(problem)
    assert info.value.name == "q_goal"
    assert "give a duration to hold still" in str(info.value)


@pytest.mark.parametrize("name", _HOLDS)
def test_a_joint_profile_move_follows_the_same_rule(name):
    limits = get_robot("paddle4").limits
    q = np.array([0.5, 0.1, 0.2, 0.0])
    with pytest.raises(InvalidInputError, match="q_goal equals q_start") as info:
        _PLANNERS[name][0]().move(q, q, limits)
    assert info.value.name == "q_goal"
    held = _PLANNERS[name][0]().move(q, q, limits, 0.75)
    assert held.duration == 0.75


@pytest.mark.parametrize("name", _HOLDS)
def test_a_still_move_with_a_duration_is_a_hold(name):
    robot = get_robot("sawyer")
    problem = PointToPoint(robot, robot.home, robot.home + 1e-13, duration=0.5)
    traj = _PLANNERS[name][0]().plan(problem)
    assert traj.duration == pytest.approx(0.5, rel=1e-12)
    sample = traj.sample(traj.times(200.0))
    np.testing.assert_allclose(sample.q, np.broadcast_to(robot.home, sample.q.shape), atol=1e-12)
    assert planners.check(traj, problem, quantities=_PLANNERS[name][1]).ok


def test_a_planner_with_its_own_duration_holds_too():
    robot = get_robot("sawyer")
    problem = PointToPoint(robot, robot.home, robot.home)
    assert planners.Cubic(duration=0.3).plan(problem).duration == pytest.approx(0.3)


def test_a_still_move_with_boundary_velocities_is_no_hold():
    # Out and back (qd_start = -qd_goal) is a motion: the rule covers rest-to-rest moves only.
    robot = get_robot("paddle4")
    qd = np.array([0.2, 0.0, 0.0, 0.0])
    problem = PointToPoint(robot, [0.5, 0.1, 0.2, 0.0], [0.5, 0.1, 0.2, 0.0], qd, -qd)
    problem.require_motion("test")  # no error
    assert planners.Cubic().plan(problem).duration > 0.0


@pytest.mark.parametrize("robot_name", ["paddle4", "sawyer", "youbot"])
@pytest.mark.parametrize("name", [n for n in _PLANNERS if n != "optimal-control"])
def test_moves_just_above_the_tolerance_plan_and_pass_the_checker(robot_name, name):
    # Toppra called moves of 1e-11 to 1e-9 rad infeasible (an empty controllable set).
    robot = get_robot(robot_name)
    rng = np.random.default_rng(7)
    planner, quantities = _PLANNERS[name]
    for q0 in [robot.home, *robot.random_configurations(2, rng)]:
        for size in (2 * STILL_TOLERANCE, 1e-11, 1e-10, 1e-9):
            j = int(rng.integers(robot.dof))
            step = size if q0[j] + size <= robot.limits.upper[j] else -size
            q1 = q0.copy()
            q1[j] += step
            problem = PointToPoint(robot, q0, q1)
            assert not problem.still
            traj = planner().plan(problem)
            report = planners.check(traj, problem, quantities=quantities)
            assert report.ok, report
            assert traj.duration >= 1e-6  # no move is shorter than the shortest duration


def test_the_tolerance_is_one_constant():
    assert is_still([0.0, 1.0], [STILL_TOLERANCE, 1.0 - STILL_TOLERANCE])
    assert not is_still([0.0, 1.0], [2 * STILL_TOLERANCE, 1.0])


def test_is_still_is_the_largest_change_against_the_tolerance_on_seeded_random_pairs():
    rng = np.random.default_rng(3504)
    for _ in range(300):
        start = rng.normal(size=int(rng.integers(1, 9)))
        change = rng.choice([0.0, 0.5, 1.0, 1.5, 1e6], size=start.size) * STILL_TOLERANCE
        goal = start + change * rng.choice([-1.0, 1.0], size=start.size)
        if rng.random() < 0.1:
            goal[0] = np.nan
        wanted = float(np.max(np.abs(goal - start), initial=0.0)) <= STILL_TOLERANCE
        assert is_still(start, goal) == wanted
        assert is_still(start.tolist(), goal.tolist()) == wanted


def _construction(*args, **kwargs):
    """A PointToPoint's validated fields, or the type, message and name of its error."""
    try:
        problem = PointToPoint(*args, **kwargs)
    except (InvalidInputError, JointLimitError) as error:
        return type(error), str(error), getattr(error, "name", None)
    fields = ("q_start", "q_goal", "qd_start", "qd_goal", "qdd_start", "qdd_goal")
    return [None if getattr(problem, f) is None else getattr(problem, f).tolist() for f in fields]


def test_float_arrays_and_lists_give_the_same_problem_or_error_on_seeded_random_states():
    # Float64 arrays within the limits take a path of their own, lists the general checks.
    robot = get_robot("panda")
    limits = robot.limits
    rng = np.random.default_rng(3505)
    span = limits.upper - limits.lower

    def near(bound):
        step = rng.choice([0.0, 1e-9, 2e-9, 1e-3], size=limits.n) * rng.choice([-1, 1], limits.n)
        return np.where(
            rng.random(limits.n) < 0.8, bound * rng.uniform(-1, 1, limits.n), bound + step
        )

    for _ in range(300):
        states = {
            "q_start": limits.lower + span * rng.uniform(-0.001, 1.001, limits.n),
            "q_goal": limits.lower + span * rng.uniform(-0.001, 1.001, limits.n),
            "qd_start": near(limits.velocity) if rng.random() < 0.5 else None,
            "qd_goal": near(limits.velocity) if rng.random() < 0.5 else None,
            "qdd_start": near(limits.acceleration) if rng.random() < 0.5 else None,
            "qdd_goal": near(limits.acceleration) if rng.random() < 0.5 else None,
        }
        if rng.random() < 0.1:
            states["q_goal"][rng.integers(limits.n)] = np.nan
        arrays = _construction(robot, **states)
        lists = {k: None if v is None else v.tolist() for k, v in states.items()}
        assert arrays == _construction(robot, **lists)


def _crate_at_the_tool(robot, q):
    """A 10 cm crate around the tool point of ``q``."""
    pose = np.eye(4)
    pose[:3, 3] = robot.tool_pose(q)[:3, 3]
    return Scene(objects=(Box("crate", [0.05, 0.05, 0.05], pose),))


def test_a_goal_inside_an_obstacle_is_refused_naming_the_pair():
    robot = get_robot("sawyer")
    goal = robot.home + 0.3
    scene = _crate_at_the_tool(robot, goal)
    with pytest.raises(CollisionError, match="crate") as caught:
        PointToPoint(robot, robot.home, goal, scene=scene)
    assert "q_goal" in str(caught.value)
    # The same crate around the start's tool point: the goal is clear, the problem is made,
    # and the checker measures a trajectory that starts inside the crate.
    problem = PointToPoint(robot, goal, robot.home, scene=scene)
    traj = planners.Quintic().plan(problem)
    clearance = planners.check(traj, problem)["clearance"]
    assert not clearance.ok and clearance.time == pytest.approx(0.0, abs=1e-3)
    assert "crate" in clearance.detail


def test_a_scene_must_be_a_scene():
    robot = get_robot("sawyer")
    with pytest.raises(InvalidInputError, match=r"scene must be a problems\.Scene"):
        PointToPoint(robot, robot.home, robot.home + 0.1, scene="table")
