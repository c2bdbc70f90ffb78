"""Tests of planners.ocp.guesses."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import (
    PathJumpError,
    UnreachableError,
)
from optraj.planners import Ruckig, check
from optraj.planners.ocp.guesses import quintic_guess, switch_times
from optraj.planners.ocp.optimal_control import (
    MIN_INTERVAL,
    OptimalControl,
)
from optraj.planners.time_optimal.lower_bound import joint_min_durations, lower_bound


@pytest.mark.parametrize(
    "raised", [PathJumpError(0.1, "right_j3", 0.2, 0.1), None], ids=["jumps", "unreachable"]
)
def test_a_pool_guess_without_its_line_starts_from_the_contact_choice(monkeypatch, raised):
    # When the guess's line cannot be followed (it jumps, or a pose with the contact's roll
    # has no solution), the guess joins the choice's entry, contact and exit by quintics.
    problem = problems.sawyer_pool_shot(1.0)
    failure = raised or UnreachableError(
        "no IK", position_error=0.1, orientation_error=0.0, attempts=1
    )

    def refused(*args, **kwargs):
        raise failure

    monkeypatch.setattr("optraj.planners.ocp.guesses.strike_line", refused)
    traj = OptimalControl("time").plan(problem)
    report = check(traj, problem)
    assert report.ok, report.summary()


def test_a_quintic_guess_joins_rest_to_the_given_end_state():
    q0, q1 = np.zeros(3), np.array([0.3, -0.2, 0.1])
    v1, a1 = np.array([0.1, 0.0, -0.1]), np.array([0.0, 0.5, 0.0])
    traj = quintic_guess(q0, q1, 2.0, v1, a1)
    start, end = traj.sample(np.array([0.0, 2.0])).q
    np.testing.assert_allclose(start, q0, atol=1e-12)
    np.testing.assert_allclose(end, q1, atol=1e-12)
    np.testing.assert_allclose(traj.sample(np.array([2.0])).qd[0], v1, atol=1e-12)
    np.testing.assert_allclose(traj.sample(np.array([2.0])).qdd[0], a1, atol=1e-12)
    np.testing.assert_allclose(traj.sample(np.array([0.0])).qd[0], 0.0, atol=1e-12)
    rest = quintic_guess(q0, q1, 1.0)
    np.testing.assert_allclose(rest.sample(np.array([1.0])).qd[0], 0.0, atol=1e-12)


def _panda_moves(count: int, seed: int = 35):
    """``count`` seeded rest-to-rest Panda moves within the middle 80 % of each range."""
    robot = get_robot("panda")
    limits = robot.limits
    rng = np.random.default_rng(seed)
    span = limits.upper - limits.lower
    for _ in range(count):
        q0 = limits.lower + span * rng.uniform(0.1, 0.9, limits.n)
        q1 = limits.lower + span * rng.uniform(0.1, 0.9, limits.n)
        yield problems.PointToPoint(robot, q0, q1)


def _jerk_switches(guess, joint):
    """The times where ``joint``'s jerk changes in a piecewise cubic ``guess`` [s]."""
    jerk = 6.0 * np.asarray(guess.coefficients)[:, 3, joint]
    steps = np.abs(np.diff(jerk)) > 1e-9 * np.max(np.abs(jerk))
    return np.asarray(guess.breakpoints)[1:-1][steps]


@pytest.mark.parametrize("extra", [0, 5, 20])
def test_switch_times_put_nodes_on_the_slowest_joints_jerk_switches(extra):
    planner = OptimalControl("time")
    for problem in _panda_moves(4, seed=extra):
        spec = planner._spec(problem)
        joint = spec.switch_joint
        assert joint == int(np.argmax(joint_min_durations(problem)))
        intervals = planner._grids(spec, 1)[0].intervals + extra
        times = switch_times(spec.guess, joint, intervals, 0.1)
        assert times is not None
        assert times.shape == (intervals + 1,)
        assert times[0] == 0.0 and times[-1] == spec.guess.duration
        steps = np.diff(times)
        assert np.all(steps >= MIN_INTERVAL) and np.all(steps <= 0.1 * (1 + 1e-12))
        switches = _jerk_switches(spec.guess, joint)
        # The first and last switch (the ends of the jerk ramps) are nodes whatever the count.
        for switch in (switches[0], switches[-1]):
            assert np.min(np.abs(times - switch)) < 1e-12


def test_switch_times_give_up_when_the_intervals_cannot_be_short_enough():
    problem = next(_panda_moves(1))
    spec = OptimalControl("time")._spec(problem)
    fewest = int(np.ceil(spec.guess.duration / 0.1))
    assert switch_times(spec.guess, spec.switch_joint, fewest - 1, 0.1) is None
    quintic = quintic_guess(problem.q_start, problem.q_goal, 1.0)
    assert switch_times(quintic, 0, 20, 0.1) is None  # not piecewise cubic


def test_a_free_move_starts_on_its_switch_grid_and_plans_within_the_limits():
    planner = OptimalControl("time")
    for problem in _panda_moves(3):
        built = planner.build(problem)
        spec = planner._spec(problem)
        K = built.compiled.layout.K
        expected = switch_times(spec.guess, spec.switch_joint, K, planner.max_interval)
        np.testing.assert_allclose(built.x0[:K], np.diff(expected), rtol=0, atol=1e-15)
        assert dict(built.compiled.structure.weights)["anchor"] > 0.0
        np.testing.assert_array_equal(built.parameter("anchor"), built.x0[:K])
        traj = planner.plan(problem)
        report = check(traj, problem)
        assert report.ok, report.summary()
        # A free grid on the switches: the motion is within 2 % of the shortest possible.
        assert traj.duration <= 1.02 * lower_bound(problem)


def test_a_fixed_duration_or_another_planners_warm_start_keeps_the_even_grid():
    planner = OptimalControl("time")
    problem = next(_panda_moves(1))
    fixed = problems.PointToPoint(problem.robot, problem.q_start, problem.q_goal, duration=3.0)
    built = planner.build(fixed)
    K = built.compiled.layout.K
    np.testing.assert_allclose(built.x0[:K], 3.0 / K, rtol=1e-12)
    assert "anchor" not in dict(built.compiled.structure.weights)
    ruckig = Ruckig().plan(problem)
    built = planner.build(problem, warm_start=ruckig)
    K = built.compiled.layout.K
    np.testing.assert_allclose(built.x0[:K], ruckig.duration / K, rtol=1e-12)
    assert "anchor" not in dict(built.compiled.structure.weights)
    assert dict(built.compiled.structure.options).get("ipopt.mu_init") is None
    traj = planner.plan(problem, warm_start=ruckig)
    report = check(traj, problem)
    assert report.ok, report.summary()
    # A previous solution on a switch grid lends its grid and multipliers.
    again = planner.plan(problem, warm_start=planner.plan(problem))
    assert again.metadata["warm_started"]
