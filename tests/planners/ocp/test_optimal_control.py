"""Tests of planners.ocp.optimal_control: every result judged by the independent checker."""

from __future__ import annotations

import dataclasses
import re
import time

import numpy as np
import pytest
from conftest import get_robot
from ocp_support import paddle_move, sawyer_shots

import optraj.planners.ocp.formulation as formulation
import optraj.planners.ocp.strike_search as strike_search
from optraj import problems, robots
from optraj.errors import (
    CONTACT_CHOICE,
    WINDOW_CHECK,
    InfeasibleError,
    InvalidInputError,
    MissingDependencyError,
    SolverError,
    UnknownNameError,
)
from optraj.planners import Quintic, Trajectory, check, lower_bound
from optraj.planners.ocp.optimal_control import (
    BUDGET_SPENT,
    INFEASIBLE_STATUSES,
    POSITION_SHRINKS,
    OptimalControl,
    WarmStart,
)
from optraj.planners.ocp.refinement import (
    position_excess,
)
from optraj.planners.strike.contact import BRANCH_SPREAD
from optraj.planners.strike.window_check import QUANTITIES


def _jerk_integral(traj) -> float:
    """Integral of the squared jerk over the motion, from dense samples [rad^2/s^5]."""
    times = np.linspace(0.0, traj.duration, 4001)
    jerk = traj.sample(times).jerk
    return float(np.trapezoid(np.sum(jerk**2, axis=1), times))


# ------------------------------------------------------------------------------ strikes


@pytest.mark.slow
def test_pool_strikes_at_1_m_s_pass_the_checker_or_say_why():
    planner = OptimalControl("time")
    solved = 0
    for problem in sawyer_shots(20, speed=1.0):
        try:
            traj = planner.plan(problem)
        except InfeasibleError as exc:
            assert exc.joint in problem.robot.joint_names and exc.required > exc.allowed
            continue
        report = check(traj, problem)  # every limit, torque and jerk included, and the strike
        assert report.ok, report.summary()
        assert [p.name for p in traj.phases] == ["approach", "strike", "stop"]
        assert traj.phase("strike").duration == pytest.approx(problem.window, abs=1e-9)
        solved += 1
    assert solved >= 19


@pytest.mark.parametrize("speed", [0.01, 0.03])
@pytest.mark.slow
def test_slow_pool_strikes_pass_the_checker(speed):
    # A window of 15 s or 5 s: without bounds on the strike nodes' velocities and
    # accelerations a minimum-time plan filled it with self-motion, and the cue left its
    # line between nodes however fine the strike grid (a SolverError after 8 rounds).
    planner = OptimalControl("time")
    for problem in sawyer_shots(2, speed=speed, seed=5):
        traj = planner.plan(problem)
        report = check(traj, problem)
        assert report.ok, report.summary()


@pytest.mark.slow
def test_a_contact_on_a_position_limit_plans_although_its_guess_line_jumps():
    # Found by a seeded random probe: the contact configuration has right_j4 on its lower
    # limit, which the IK of the guess's strike line then pins there, so right_j3 turns 0.14
    # rad between the last two of 10 samples; the plan ended in that PathJumpError.
    heading = float(np.degrees(np.arctan2(-0.84535494, 0.53420504)))
    problem = problems.sawyer_pool_shot(0.05, (1.06554361, -0.2979797, -0.09508575), heading)
    traj = OptimalControl("time").plan(problem)
    report = check(traj, problem)
    assert report.ok, report.summary()
    assert report["position"].joint == "right_j4"  # on its limit, within the tolerance


def test_the_contact_choice_keeps_the_planners_margin():
    # The default 1.3 m/s shot needs 0.88 of right_j0's velocity limit at its best contact:
    # a planner that keeps 20 % of the limits free refuses it at the contact choice (no NLP),
    # and so does a warm start's contact branch; the default margin plans it.
    problem = problems.sawyer_pool_shot(1.3)
    traj = OptimalControl("time").plan(problem)
    assert check(traj, problem).ok
    for warm_start in (None, traj):
        with pytest.raises(InfeasibleError, match=r"strike speed 1\.3 m/s needs") as info:
            OptimalControl("time", margin=0.2).plan(problem, warm_start=warm_start)
        assert info.value.limit == "velocity" and info.value.__cause__ is None


def test_a_strike_faster_than_any_contact_allows_is_named_within_a_second():
    planner = OptimalControl("time")
    with pytest.raises(InfeasibleError):  # warm-up: loads the LP plugin
        planner.plan(problems.sawyer_pool_shot(3.0))
    for problem in sawyer_shots(3, speed=2.5, seed=11):
        started = time.perf_counter()
        with pytest.raises(InfeasibleError, match=r"strike speed 2\.5 m/s needs") as info:
            planner.plan(problem)
        assert time.perf_counter() - started < 1.0
        error = info.value
        assert error.limit == "velocity" and error.joint in problem.robot.joint_names
        assert error.required > error.allowed
        assert 0.0 < error.max_speed < 2.5  # the best reachable speed, in the message too
        assert f"{error.max_speed:.3g} m/s" in str(error)


@pytest.mark.parametrize(
    "ball, heading",
    [
        # Strike benchmark ball 3: every contact found needs more than 0.99 of right_j0's
        # velocity limit at contact (the contact choice, which checks velocities at three
        # configurations only, lets it through).
        ((0.7009739175308249, 0.10577670705892629, -0.04954517410420467), 2.1398940829796977),
        # Ball 0: its windows alone keep within 0.997 of the limits; the approach into them
        # and the stop after them do not.
        ((0.7750190933209333, 0.2640248303393514, -0.022431430975480643), -10.991712400376326),
    ],
    ids=["ball 3", "ball 0"],
)
def test_a_strike_whose_window_needs_more_than_the_limits_is_refused_with_the_window_named(
    ball, heading
):
    # At 1.5 m/s the solver finds the strike infeasible, and the window check finds every
    # contact's strike window past the limits.
    problem = problems.sawyer_pool_shot(1.5, ball, heading)
    with pytest.raises(InfeasibleError) as info:
        OptimalControl("time").plan(problem)
    error = info.value
    assert isinstance(error.__cause__, SolverError)
    assert error.__cause__.status in INFEASIBLE_STATUSES
    assert error.limit in QUANTITIES and error.joint in problem.limits.names
    assert error.required > error.allowed
    assert error.joint in str(error) and f"{error.allowed:.4g}" in str(error)
    assert "with the approach into it and the stop after it, needs more than the" in str(error)
    slower = float(re.search(r"run at ([0-9.]+) m/s", str(error))[1])
    assert 1.0 < slower < 1.5
    assert str(error).endswith("a slower strike or looser limits may plan")
    assert re.search(r"or at this speed with limits [0-9.]+ times as large", str(error))
    # The finding is marked as the window check's, with the slower speed it names.
    assert error.found_by == WINDOW_CHECK
    assert error.max_speed == pytest.approx(slower, rel=1e-3)


def _paddle_problems(count: int, seed: int = 3):
    robot = get_robot("paddle4")
    rng = np.random.default_rng(seed)
    made = 0
    while made < count:
        ball = (rng.uniform(0.5, 1.1), rng.uniform(-0.6, 0.6), rng.uniform(0.1, 0.7))
        speed = 0.0 if made % 2 == 0 else rng.uniform(0.2, 0.8)
        yield problems.PaddleStrike(
            robot, ball=ball, contact_angle=rng.uniform(-1.0, 1.0), speed=speed
        )
        made += 1


@pytest.mark.slow
def test_paddle_strikes_pass_the_checker():
    planner = OptimalControl("time")
    for problem in _paddle_problems(20):
        try:
            traj = planner.plan(problem)
        except InfeasibleError as exc:  # a contact speed beyond the joints
            assert exc.joint in problem.robot.joint_names
            continue
        report = check(traj, problem)
        assert report.ok, report.summary()
        if problem.speed == 0.0:  # the ECE486 task: at the ball at rest after exactly T
            assert traj.duration == pytest.approx(problem.contact_time, abs=1e-9)


def test_a_paddle_strike_without_room_at_contact_is_refused_before_the_solve():
    # J3 is 29 mm from its upper limit at contact: the NLP found this strike infeasible after
    # 77 iterations and named only "dynamics". Now the contact choice refuses it with J3's
    # room; a strike 5 % under the speed it names plans (the jerk limit takes some room too).
    robot = get_robot("paddle4")
    ball, angle = (1.08197713, -0.72308109, 0.24624905), 0.5057469237104932
    problem = problems.PaddleStrike(robot, ball=ball, contact_angle=angle, speed=1.5)
    planner = OptimalControl("time")
    with pytest.raises(InfeasibleError, match=r"J3 is 0\.02909 m from its upper limit") as info:
        planner.plan(problem)
    assert info.value.found_by == CONTACT_CHOICE and info.value.__cause__ is None
    slower = dataclasses.replace(problem, speed=0.95 * info.value.max_speed)
    report = check(planner.plan(slower), slower)
    assert report.ok, report.summary()


# ----------------------------------------------------------------------------- joint moves


@pytest.mark.slow
def test_min_time_moves_come_within_0_2_percent_of_the_lower_bound():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(5)
    planner = OptimalControl("time")
    for _ in range(20):
        q = robot.random_configurations(2, rng)
        problem = problems.PointToPoint(robot, q[0], q[1])
        traj = planner.plan(problem)
        bound = lower_bound(problem)
        assert bound * (1.0 - 1e-9) <= traj.duration <= 1.002 * bound
        report = check(traj, problem)
        assert report.ok, report.summary()


def test_min_jerk_with_a_fixed_duration_approaches_the_quintic():
    # The minimum-jerk rest-to-rest motion of a fixed duration is the quintic (Flash & Hogan
    # 1985); with piecewise-constant jerk the optimum can only come close to it from above.
    robot = get_robot("youbot")
    q0 = robot.home
    q1 = q0 + 0.3 * (robot.limits.upper - q0)
    problem = problems.PointToPoint(robot, q0, q1, duration=3.0)
    traj = OptimalControl("jerk", regularization=0.0, intervals=60).plan(problem)
    quintic = Quintic(duration=3.0).plan(problem)
    assert check(traj, problem).ok
    assert traj.duration == pytest.approx(3.0, abs=1e-9)
    ours, best = _jerk_integral(traj), _jerk_integral(quintic)
    assert best <= ours <= 1.05 * best
    times = np.linspace(0.0, 3.0, 301)
    gap = np.abs(traj.sample(times).q - quintic.sample(times).q)
    assert gap.max() < 0.02 * np.abs(q1 - q0).max()


@pytest.mark.slow
def test_min_effort_needs_less_torque_than_min_jerk():
    robot = get_robot("youbot")
    q0 = robot.home
    q1 = q0 + 0.4 * (robot.limits.upper - q0)
    problem = problems.PointToPoint(robot, q0, q1, duration=2.5)

    def effort(traj) -> float:  # integral of squared torques over the effort limits
        times = np.linspace(0.0, traj.duration, 2001)
        s = traj.sample(times)
        tau = robot.inverse_dynamics(s.q, s.qd, s.qdd) / robot.limits.effort
        return float(np.trapezoid(np.sum(tau**2, axis=1), times))

    smooth = OptimalControl("jerk").plan(problem)
    strong = OptimalControl("effort").plan(problem)
    assert check(strong, problem).ok
    assert effort(strong) < effort(smooth)


def test_any_start_and_goal_state():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(8)
    q = robot.random_configurations(2, rng)
    qd_goal = 0.3 * robot.limits.velocity * rng.uniform(-1.0, 1.0, robot.dof)
    problem = problems.PointToPoint(robot, q[0], q[1], qd_goal=qd_goal)
    traj = OptimalControl("time").plan(problem)
    report = check(traj, problem)
    assert report.ok, report.summary()
    np.testing.assert_allclose(traj.sample(traj.duration).qd, qd_goal, atol=1e-6)


def test_waypoints_are_passed_through():
    robot = get_robot("youbot")
    rng = np.random.default_rng(4)
    points = robot.random_configurations(4, rng)
    problem = problems.Waypoints(robot, points, via_tolerance=1e-6)
    traj = OptimalControl("time").plan(problem)
    report = check(traj, problem)
    assert report.ok, report.summary()
    assert [p.name for p in traj.phases] == ["segment 1", "segment 2", "segment 3"]


@pytest.mark.slow
def test_a_via_point_plan_warm_starts_a_waypoint_problem_and_a_mismatch_says_so():
    # ViaPoints and Toppra named their phases "segment 0..", the NLP "segment 1..": the warm
    # start was dropped without a word. One naming, and a warm start that cannot be used raises.
    from optraj.planners import ViaPoints

    robot = get_robot("youbot")
    points = robot.random_configurations(4, np.random.default_rng(4))
    problem = problems.Waypoints(robot, points, via_tolerance=1e-6)
    guess = ViaPoints().plan(problem)
    cold = OptimalControl("time").plan(problem)
    warm = OptimalControl("time").plan(problem, warm_start=guess)
    assert check(warm, problem).ok
    assert warm.metadata["iterations"] != cold.metadata["iterations"]  # the guess was used
    other = Quintic().plan(problems.PointToPoint(robot, q_start=points[0], q_goal=points[-1]))
    with pytest.raises(InvalidInputError, match=r"warm_start has the phases \['move'\]"):
        OptimalControl("time").plan(problem, warm_start=other)


@pytest.mark.slow
def test_a_strike_that_passes_a_position_limit_between_nodes_is_solved_again_within():
    # Benchmark shot 95 (seed 7): the first solve takes right_j0 past its lower limit
    # between two nodes; with their bounds moved in, the warm re-solve stays within.
    problem = problems.sawyer_pool_shot(
        1.0,
        (0.6915635334246808, 0.12726660566584574, -0.05026149557804848),
        heading_deg=16.598236109553604,
    )
    planner = OptimalControl("time")
    first = planner.solve(planner.build(problem))
    assert not check(first, problem, quantities=("position",))["position"].ok
    traj = planner.plan(problem)
    report = check(traj, problem)
    assert report.ok, report.summary()
    assert traj.metadata["rounds"] == 2 and traj.metadata["position_rows"] is False
    assert traj.duration == pytest.approx(first.duration, rel=0.01)
    # The statistics count both solves: the first one's iterations, then the re-solve's.
    rounds = traj.metadata["round_iterations"]
    assert len(rounds) == 2 and rounds[0] == first.metadata["iterations"]
    assert traj.metadata["iterations"] == sum(rounds)
    assert traj.metadata["warm_started"] is False  # the first solve was cold


def test_positions_between_nodes_get_rows_when_moving_node_bounds_cannot_help():
    # A via point with a joint at its upper limit: bounded at the nodes only, the fastest
    # motion passes the via node still moving and leaves the range just after it. The via
    # node is pinned there, so moving node bounds in cannot settle it: rows come in.
    robot = get_robot("paddle4")
    limits = robot.limits
    middle = 0.5 * (limits.lower + limits.upper)
    via, end = middle.copy(), middle.copy()
    via[0] = limits.upper[0]
    end[1] = 0.5 * (middle[1] + limits.lower[1])
    problem = problems.Waypoints(robot, np.array([middle, via, end]))
    planner = OptimalControl("time")
    first = planner.solve(planner.build(problem))  # the first round: no position rows
    assert not check(first, problem, quantities=("position",))["position"].ok
    assert position_excess(first, limits).any()
    traj = planner.plan(problem)
    assert traj.metadata["position_rows"] and traj.metadata["rounds"] == 2 + POSITION_SHRINKS
    report = check(traj, problem, quantities=("position", "velocity", "acceleration", "jerk"))
    assert report.ok, report.summary()
    always = OptimalControl("time", position_rows=True).plan(problem)
    assert always.metadata["rounds"] == 1
    assert always.duration == pytest.approx(traj.duration, rel=5e-3)


@pytest.mark.parametrize("rows", ["linear", "rnea"])
def test_a_torque_limit_that_binds_gets_rows_and_holds(rows):
    robot = get_robot("youbot")
    q0 = robot.home
    q1 = q0 + 0.6 * (robot.limits.upper - q0)
    unlimited = OptimalControl("time").plan(problems.PointToPoint(robot, q0, q1))
    times = np.linspace(0.0, unlimited.duration, 2001)
    s = unlimited.sample(times)
    peak = np.max(np.abs(robot.inverse_dynamics(s.q, s.qd, s.qdd)), axis=0)
    gravity = np.max(
        np.abs(robot.inverse_dynamics(s.q, np.zeros_like(s.q), np.zeros_like(s.q))), axis=0
    )
    # Gravity plus 30 % of the torque the fastest move adds on top: the move must slow down.
    effort = np.minimum(
        robot.limits.effort, np.maximum(1.05 * gravity, gravity + 0.3 * (peak - gravity))
    )
    limits = dataclasses.replace(robot.limits, effort=effort)
    problem = problems.PointToPoint(robot, q0, q1, limits=limits)
    assert [f.name for f in check(unlimited, problem).violations] == ["torque"]
    traj = OptimalControl("time", torque_rows=rows).plan(problem)
    report = check(traj, problem)
    assert report.ok, report.summary()
    assert traj.metadata["torque_rows"] > 0
    assert traj.duration > 1.05 * unlimited.duration


def test_a_pool_strike_with_a_weak_shoulder_keeps_its_torque_limit():
    # right_j0 carries no gravity; a tenth of its rating binds while the arm swings round.
    shot = problems.sawyer_pool_shot()
    effort = shot.limits.effort.copy()
    effort[0] *= 0.1
    weak = dataclasses.replace(shot, limits=dataclasses.replace(shot.limits, effort=effort))
    free = OptimalControl("time").plan(shot)
    assert [f.name for f in check(free, weak).violations] == ["torque"]
    traj = OptimalControl("time").plan(weak)
    report = check(traj, weak)
    assert report.ok, report.summary()
    assert traj.metadata["torque_rows"] > 0 and traj.metadata["rounds"] > 1
    # Rounds for the torques leave the position rows out while positions hold between nodes.
    assert traj.metadata["position_rows"] is False


def test_a_torque_limit_gravity_alone_breaks_is_infeasible():
    # The goal at rest needs its gravity torques, twice the limits: refused before any solve,
    # with the joint and the factor on the effort limits a plan needs at least.
    robot = get_robot("youbot")
    q0 = robot.home
    q1 = q0 + 0.5 * (robot.limits.upper - q0)
    gravity = np.abs(robot.gravity_torque(q1))
    limits = dataclasses.replace(robot.limits, effort=np.maximum(0.5 * gravity, 1e-3))
    problem = problems.PointToPoint(robot, q0, q1, limits=limits)
    with pytest.raises(InfeasibleError, match=r"the goal state \(at rest\) needs joint") as info:
        OptimalControl("time").plan(problem)
    joint = robot.limits.names.index(info.value.joint)
    assert info.value.limit == "effort"
    assert info.value.required == pytest.approx(gravity[joint], rel=1e-9)
    assert "times as large" in str(info.value)


def _overloaded_pool_shot() -> problems.PoolStrike:
    """Issue 32's shot: 0.07 m/s on Sawyer with acceleration, jerk and effort limits at 5 %."""
    shot = problems.sawyer_pool_shot(0.07)
    limits = shot.robot.limits.scaled(0.05, ("acceleration", "jerk", "effort"))
    return problems.PoolStrike(shot.robot, shot.ball, shot.direction, 0.07, limits=limits)


def test_a_strike_whose_start_gravity_overloads_is_refused_before_any_search(monkeypatch):
    # At rest at home Sawyer's shoulder holds 16.7 N m against gravity, 4.2 times its 5 %
    # effort limit: no motion from there keeps the limits, so neither a contact search nor a
    # solve runs (the search and the solves took 84 s to a SolverError naming only a group).
    def searched(*args, **kwargs):
        raise AssertionError("the contact search ran")

    monkeypatch.setattr(strike_search, "contact_choices", searched)
    monkeypatch.setattr(formulation, "choose_contact", searched)
    problem = _overloaded_pool_shot()
    gravity = np.abs(problem.robot.gravity_torque(problem.q_start))
    with pytest.raises(
        InfeasibleError, match=r"start state \(at rest\) needs joint 'right_j1'"
    ) as info:
        OptimalControl().plan(problem)
    error = info.value
    assert (error.limit, error.joint, error.allowed) == ("effort", "right_j1", pytest.approx(4.0))
    assert error.required == pytest.approx(gravity[1], rel=1e-9)
    assert f"effort limits at least {gravity[1] / 4.0:.4g} times as large" in str(error)
    with pytest.raises(InfeasibleError, match="start state"):  # build() says the same
        OptimalControl().build(problem)


@pytest.mark.slow
def test_a_strike_whose_windows_need_more_torque_than_the_limits_is_refused_naming_effort():
    # From the arm held up (little gravity torque at the start) to a ball held out over the
    # table with effort limits at 15 %: the first solve is infeasible, and every contact's
    # window needs more of right_j1's effort than the limits give, at any slower speed too.
    robot = get_robot("sawyer")
    up = np.array([0.0, -np.pi / 2, 0.0, 0.0, 0.0, 0.0, 3.3161])
    shot = problems.sawyer_pool_shot(0.5)
    limits = robot.limits.scaled(0.15, ("effort",))
    problem = problems.PoolStrike(robot, shot.ball, shot.direction, 0.5, q_start=up, limits=limits)
    with pytest.raises(InfeasibleError) as info:
        OptimalControl().plan(problem)
    error = info.value
    assert error.found_by == WINDOW_CHECK
    assert (error.limit, error.joint) == ("effort", "right_j1")
    assert error.required > error.allowed == pytest.approx(limits.effort[1])
    assert error.max_speed == 0.0 and str(error).endswith("looser limits may plan")
    assert re.search(r"at this speed with limits 1\.\d+ times as large", str(error))


@pytest.mark.parametrize("torque", ["auto", True])
def test_a_start_holding_nearly_its_effort_limit_keeps_no_torque_margin_there(torque):
    # The start holds 99 % of right_j1's effort limit against gravity, more than the 3 %
    # torque margin leaves: the rows at the start node keep the room the state leaves, and
    # the rounds settle once the other torques are within the margin.
    robot = get_robot("sawyer")
    q0 = robot.home
    effort = robot.limits.effort.copy()
    effort[1] = abs(robot.gravity_torque(q0)[1]) / 0.99
    limits = dataclasses.replace(robot.limits, effort=effort)
    q1 = q0.copy()
    q1[0] += 0.3  # a turn about the vertical base joint: right_j1's gravity torque stays
    problem = problems.PointToPoint(robot, q0, q1, limits=limits)
    traj = OptimalControl(torque=torque).plan(problem)
    assert check(traj, problem).ok


def test_a_plan_past_its_time_budget_raises_a_solver_error_that_names_it():
    with pytest.raises(SolverError, match=r"time_budget of 1e-06 s") as info:
        OptimalControl(time_budget=1e-6).plan(paddle_move())
    assert info.value.status == BUDGET_SPENT


# ------------------------------------------------------------- build, solve, warm starts


def test_solve_statistics_split_the_plan_time():
    problem = problems.sawyer_pool_shot(1.0, ball=(0.75, 0.15, -0.05))
    traj = OptimalControl("jerk").plan(problem)  # min time first, then min jerk: two solves
    meta = traj.metadata
    assert len(meta["round_iterations"]) >= 2
    # Evaluating the NLP's functions is part of the solves' time, the contact choice is not,
    # and both lie within the plan's.
    assert 0.0 < meta["evaluation_time"] < meta["nlp_time"]
    assert meta["contact_time"] > 0.0
    assert meta["contact_time"] + meta["nlp_time"] < meta["solve_time"]
    youbot = get_robot("youbot")
    move = problems.PointToPoint(youbot, youbot.home, youbot.home + 0.2)
    assert OptimalControl("time").plan(move).metadata["contact_time"] == 0.0


@pytest.mark.slow
def test_warm_start_from_a_previous_solution_and_from_another_planner():
    first, second = (
        problems.sawyer_pool_shot(1.0, ball=ball)
        for ball in ((0.75, 0.15, -0.05), (0.75, 0.17, -0.05))
    )
    planner = OptimalControl("time")
    previous = planner.plan(first)
    assert isinstance(previous.metadata["warm_start"], WarmStart)
    cold = planner.plan(second)
    warm = planner.plan(second, warm_start=previous)
    assert check(warm, second).ok
    assert warm.metadata["warm_started"] is True
    assert warm.metadata["iterations"] <= cold.metadata["iterations"]
    # The multipliers fit the previous solve's objective: its time scale is kept.
    kept = warm.metadata["warm_start"].time_scale
    assert kept == previous.metadata["warm_start"].time_scale
    assert kept != cold.metadata["warm_start"].time_scale
    # The previous contact branch still has room: no contact search this time.
    assert warm.metadata["contact_from_warm_start"] is True
    assert cold.metadata["contact_from_warm_start"] is False
    assert (
        np.abs(
            warm.metadata["contact_configuration"] - previous.metadata["contact_configuration"]
        ).max()
        < 0.1
    )
    plain = Trajectory(cold.breakpoints, cold.coefficients, phases=cold.phases)  # no duals
    seeded = planner.plan(second, warm_start=plain)
    assert seeded.metadata["warm_started"] is False and check(seeded, second).ok


def test_a_warm_re_plan_whose_kept_contact_fails_runs_the_search(monkeypatch):
    first, second = (
        problems.sawyer_pool_shot(1.0, ball=ball)
        for ball in ((0.75, 0.15, -0.05), (0.75, 0.17, -0.05))
    )
    planner = OptimalControl("time")
    previous = planner.plan(first)
    # A warm start read back from JSON keeps the contact configuration (as a list).
    restored = Trajectory.from_json(previous.to_json())
    assert planner.plan(second, warm_start=restored).metadata["contact_from_warm_start"]
    calls = []
    original = OptimalControl._plan

    def fail_first(self, problem, spec, warm_start):
        calls.append(warm_start)
        if len(calls) == 1:
            raise SolverError("ipopt", "Maximum_Iterations_Exceeded")
        return original(self, problem, spec, warm_start)

    monkeypatch.setattr(OptimalControl, "_plan", fail_first)
    traj = planner.plan(second, warm_start=previous)
    assert calls[0] is previous and calls[1] is None  # the search's choice solved cold
    assert traj.metadata["contact_from_warm_start"] is False
    assert traj.metadata["contact_attempts"] == 2 and check(traj, second).ok
    monkeypatch.setattr(OptimalControl, "_plan", original)
    kept = OptimalControl("time", reuse_contact=False).plan(second, warm_start=previous)
    assert kept.metadata["contact_from_warm_start"] is False


def _moved_2_cm(ball, heading_deg):
    """A benchmark shot (1 m/s) and the same shot with its ball 2 cm further along y."""
    return tuple(
        problems.sawyer_pool_shot(1.0, (ball[0], ball[1] + dy, ball[2]), heading_deg)
        for dy in (0.0, 0.02)
    )


@pytest.mark.slow
def test_a_warm_start_through_another_contact_branch_is_not_lent():
    # Strike benchmark shot 35 of seed 11: the kept branch has no room after the ball moved,
    # and the search chooses another; warm from the old branch this took 634 iterations.
    first, moved = _moved_2_cm(
        (0.6787860478501857, 0.11273030410957995, -0.0950677344620466), 12.075038611385985
    )
    planner = OptimalControl("time")
    previous = planner.plan(first)
    traj = planner.plan(moved, warm_start=previous)
    meta = traj.metadata
    assert meta["contact_from_warm_start"] is False
    jump = np.abs(meta["contact_configuration"] - previous.metadata["contact_configuration"])
    assert jump.max() > BRANCH_SPREAD
    assert meta["warm_started"] is False and meta["iterations"] < 100
    assert check(traj, moved).ok


@pytest.mark.slow
def test_a_failed_solve_is_retried_from_the_next_contact_branch():
    # Shot 42 of benchmarks/strike.py: IPOPT finds the problem infeasible from the chosen
    # contact configuration, whose window the window check finds past the limits too, and
    # solves it from the next IK branch.
    problem = problems.sawyer_pool_shot(
        1.0, (0.770755805063373, 0.11771877321136866, -0.04053151295117215), 6.371000264362529
    )
    with pytest.raises(SolverError, match="Infeasible_Problem_Detected") as info:
        OptimalControl("time", contact_retries=0).plan(problem)
    # One contact tried: not a refusal of the strike, which another contact makes.
    assert "from this contact configuration the window check's best strike window" in str(
        info.value
    )
    assert str(info.value).endswith("other contact configurations (contact_retries > 0) may plan")
    traj = OptimalControl("time").plan(problem)
    assert traj.metadata["contact_attempts"] == 2
    report = check(traj, problem)
    assert report.ok, report.summary()


# ---------------------------------------------------------------------- errors and inputs


def test_solver_failure_carries_status_and_most_violated_group():
    problem = next(sawyer_shots(1, speed=1.0))
    with pytest.raises(SolverError, match=r"Maximum_Iterations_Exceeded.*most violated") as info:
        OptimalControl("time", max_iterations=2).plan(problem)
    assert info.value.solver == "ipopt" and info.value.iterations == 2
    # The row's place, never only its group; the joint limits the point holds, if any.
    assert re.search(
        r"most violated: [\w ()]+ at (node|interval) \d+ of the \w+ phase", str(info.value)
    )
    assert "binding at the solver's point" in str(info.value) or "no joint limit" in str(info.value)


def test_solvers_by_name():
    with pytest.raises(UnknownNameError, match="ipopt"):
        OptimalControl(solver="ipotp")
    with pytest.raises(MissingDependencyError, match="knitro"):
        OptimalControl(solver="knitro")
    with pytest.raises(UnknownNameError, match="sqpmethod"):  # left out: see SOLVERS
        OptimalControl(solver="fatrop")


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"objective": "speed"}, "objective"),
        ({"objective": {"time": -1.0}}, "objective"),
        ({"objective": {}}, "objective"),
        ({"margin": 0.7}, "margin"),
        ({"torque": "sometimes"}, "torque"),
        ({"torque_rows": "exact"}, "torque rows"),
        ({"position_rows": False}, "position_rows"),
        ({"stretch": 0.5}, "stretch"),
        ({"intervals": 0}, "intervals"),
        ({"step": -0.1}, "step"),
        ({"objective": {"time": "abc"}}, "objective weight 'time'"),
        ({"objective": {"time": True}}, "objective weight 'time'"),
        ({"margin": False}, "margin"),
        ({"torque": 0.0}, "torque"),
        ({"position_rows": 1}, "position_rows"),
        ({"regularization": None}, "regularization"),
        ({"free_grid": "no"}, "free_grid"),
        ({"solver_options": 5}, "solver_options"),
        ({"max_interval": 1e-6}, "max_interval must be > 0.0001 s"),
        ({"intervals": {"bogus": 5}}, "intervals names a phase 'bogus'"),
        ({"intervals": {"segment 0": 5}}, "intervals names a phase 'segment 0'"),
        ({"intervals": 10**6}, "intervals must be an integer <= 400"),
        ({"time_budget": "5"}, "time_budget"),
        ({"time_budget": True}, "time_budget"),
        ({"time_budget": -1.0}, "time_budget must be >= 1e-06 s"),
        ({"time_budget": 1e9}, "time_budget must be <= 86400 s"),
        ({"margin": "0.1"}, "margin"),
        ({"margin": 0.5}, "margin must be < 0.5"),
        ({"stretch": True}, "stretch"),
        ({"stretch": 0.5}, "stretch must be >= 1"),
        ({"tolerance": 10.0}, "tolerance must be <= 1"),
        ({"step": 1e300}, "step must be <= 86400 s"),
        ({"objective": {"time": -1.0}}, "objective weight 'time' must be >= 0"),
    ],
)
def test_bad_options_raise_typed_errors(kwargs, name):
    with pytest.raises((InvalidInputError, UnknownNameError), match=name):
        OptimalControl(**kwargs)


def test_bad_plan_inputs_are_named_before_any_solve():
    move = paddle_move()
    sawyer = get_robot("sawyer")
    other = OptimalControl().plan(problems.PointToPoint(sawyer, sawyer.home, sawyer.home + 0.1))
    with pytest.raises(InvalidInputError, match=r"warm_start must be a planners\.Trajectory"):
        OptimalControl().plan(move, warm_start="abc")
    with pytest.raises(InvalidInputError, match=r"warm_start moves 7 joints; .* has 4"):
        OptimalControl().plan(move, warm_start=other)
    with pytest.raises(InvalidInputError, match="OptimalControlProblem of build"):
        OptimalControl().solve(None)
    with pytest.raises(InvalidInputError, match=r"solver_options .* No such IPOPT option: bogus"):
        OptimalControl(solver_options={"ipopt.bogus": 1}).plan(move)
    # A grid finer than any solve can take is refused, not built.
    with pytest.raises(InvalidInputError, match=r"phase 'move' would need \d+ intervals"):
        OptimalControl(max_interval=2e-4).plan(move)


def test_an_unsupported_problem_is_named():
    with pytest.raises(InvalidInputError, match="PickAndPlace"):
        OptimalControl().plan(problems.youbot_two_blocks())


def test_one_planner_plans_two_models_of_sawyer_each_with_its_own_kinematics():
    # Its compiled NLPs were keyed by the robot's name: after the default cue, a Sawyer with
    # a 0.45 m cue reused the other kinematics and ended at IPOPT's iteration limit.
    planner = OptimalControl("time")
    shot = problems.sawyer_pool_shot(1.0)
    longer = robots.load("sawyer", cue_length=0.45)
    other = dataclasses.replace(shot, robot=longer, limits=longer.limits, q_start=longer.home)
    for problem in (shot, other):
        traj = planner.plan(problem)
        report = check(traj, problem)
        assert report.ok, report.summary()


def test_a_goal_on_a_position_limit_ends_on_it_not_past_it():
    # Found by the fuzz suite: the jerks integrated from the first node ended joint J3
    # (prismatic, start and goal on its lower limit 0 m) 3.95e-9 m past the limit, as the
    # solver meets its integration rows only to its tolerance; the checker failed position.
    robot = get_robot("paddle4")
    problem = problems.PointToPoint(robot, np.zeros(4), [0.0, 2.0, 0.0, 0.0])
    traj = OptimalControl("time").plan(problem)
    report = check(traj, problem)
    assert report.ok, report.violations
    end = traj.sample(traj.duration)
    np.testing.assert_allclose(end.q, problem.q_goal, rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(end.qd, 0.0, rtol=0.0, atol=1e-12)
