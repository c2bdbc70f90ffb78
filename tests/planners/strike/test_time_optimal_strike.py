"""Tests of planners.strike.time_optimal_strike: approach, constant-speed strike and stop."""

from __future__ import annotations

import numpy as np
import pytest

from optraj import problems
from optraj.errors import InfeasibleError, InvalidInputError, UnknownNameError
from optraj.planners.checker import check
from optraj.planners.strike.classic_strike import ClassicStrike
from optraj.planners.strike.contact import choose_contact
from optraj.planners.strike.time_optimal_strike import TimeOptimalStrike, strike_line

ALL = ("position", "velocity", "acceleration", "jerk", "torque")
STRIKE = ("strike window", "strike position", "strike speed", "strike axis", "contact")


def _shots(count: int, speed: float):
    rng = np.random.default_rng(7)
    for _ in range(count):
        ball = (rng.uniform(0.65, 0.85), rng.uniform(-0.05, 0.3), rng.uniform(-0.1, 0.0))
        yield problems.sawyer_pool_shot(speed, ball, heading_deg=rng.uniform(-20.0, 20.0))


def test_ruckig_pool_strikes_pass_the_checker_or_say_why():
    planned = 0
    for problem in _shots(8, speed=0.5):
        try:
            traj = TimeOptimalStrike("ruckig").plan(problem)
        except InfeasibleError as exc:
            assert exc.joint is not None or exc.limit  # names what binds
            continue
        planned += 1
        report = check(traj, problem, quantities=ALL)
        assert report.ok, report.summary()
        assert [p.name for p in traj.phases] == ["approach", "strike", "stop"]
        # The joint-space approach meets the line only at the entry: reported, not hidden.
        assert traj.metadata["approach_line_gap"] >= 0.0
    assert planned >= 4


@pytest.mark.parametrize("approach", ["ruckig", "toppra"])
def test_pool_approach_keeps_the_tool_off_the_ball_until_the_strike_line(approach):
    retreated = planned = 0
    quantities = ALL if approach == "ruckig" else ("position", "velocity", "acceleration")
    for problem in _shots(8, speed=0.5):
        try:
            traj = TimeOptimalStrike(approach).plan(problem)
        except InfeasibleError:
            continue
        planned += 1
        retreated += bool(traj.metadata["approach_retreat"])
        report = check(traj, problem, quantities=quantities)
        assert report.ok, report.summary()
        t = np.arange(0.0, traj.phase("strike").t_start, 1e-3)
        points = problem.robot.tool_position(traj.sample(t).q)
        gap = np.linalg.norm(points - np.asarray(problem.ball), axis=1) - problem.ball_radius
        assert gap.min() >= 0.0199, f"the tool comes {gap.min() * 1e3:.1f} mm off the ball"
    # Some of these balls lie in the way of Ruckig's direct joint-space move (the first
    # does); TOPPRA's path comes in along the line's tangent and needs no detour here.
    assert planned >= 4
    assert retreated >= (1 if approach == "ruckig" else 0)


def test_toppra_approach_enters_at_speed_with_an_acceleration_step():
    problem = next(_shots(1, speed=0.5))
    traj = TimeOptimalStrike("toppra").plan(problem)
    report = check(traj, problem, quantities=("position", "velocity", "acceleration"))
    assert report.ok, report.summary()
    assert all(report[name].ok for name in STRIKE)
    # TOPPRA matches the entry velocity, not the acceleration: the jerk is unbounded there.
    assert check(traj, problem, quantities=("jerk",))["jerk"].value == np.inf


@pytest.mark.parametrize("approach", ["ruckig", "toppra"])
def test_paddle_strike_at_speed_meets_ball_on_time(approach):
    problem = problems.PaddleStrike(
        problems.ece486_paddle_strike().robot, ball=(1.0, 0.3, 0.4), speed=0.5, contact_time=2.0
    )
    traj = TimeOptimalStrike(approach).plan(problem)
    quantities = ALL if approach == "ruckig" else ("position", "velocity", "acceleration")
    report = check(traj, problem, quantities=quantities)
    assert report.ok, report.summary()
    assert traj.phase("approach").t_end == pytest.approx(2.0)


def test_ece486_paddle_strike_with_toppra_waits_then_arrives_at_rest():
    problem = problems.ece486_paddle_strike()
    traj = TimeOptimalStrike("toppra").plan(problem)
    report = check(traj, problem, quantities=("position", "velocity", "acceleration"))
    assert report.ok, report.summary()
    assert traj.phase("wait").duration > 0.0


def test_contact_time_too_short_is_infeasible():
    problem = problems.PaddleStrike(
        problems.ece486_paddle_strike().robot, ball=(1.1, 0.8, 0.7), contact_time=0.1
    )
    with pytest.raises(InfeasibleError, match="longer than the contact time"):
        TimeOptimalStrike("ruckig").plan(problem)


def test_the_chosen_contact_plans_shots_the_nearest_branch_cannot():
    # Shots 2 and 3 of the 1 m/s draw: from the IK solution nearest the start the line needs
    # more than a joint's velocity or acceleration limit; choose_contact's branch has room.
    shots = list(_shots(3, speed=1.0))[1:]
    for problem in shots:
        with pytest.raises(InfeasibleError):
            TimeOptimalStrike("ruckig").plan(problem)
        chosen = choose_contact(problem).q
        traj = TimeOptimalStrike("ruckig", contact="choose").plan(problem)
        report = check(traj, problem, quantities=ALL)
        assert report.ok, report.summary()
        assert np.allclose(traj.metadata["contact_configuration"], chosen)
        assert 0.0 < traj.metadata["contact_speed_ratio"] <= 1.0
        # The cubic profile from the same branch: within the velocity and acceleration
        # limits (its jerk jumps at the entry), on the line.
        cubic = ClassicStrike("cubic", contact="choose").plan(problem)
        report = check(cubic, problem, quantities=("position", "velocity", "acceleration"))
        assert report.ok, report.summary()
        assert np.allclose(cubic.metadata["contact_configuration"], chosen)


@pytest.mark.parametrize("approach", ["ruckig", "toppra"])
def test_a_line_that_pins_a_joint_on_its_limit_is_refused(approach):
    # Shot 0 of the 1 m/s draw: from the chosen contact, the inverse kinematics along the line
    # pins right_j4 on its lower limit part-way, and the line kinks there (the other joints
    # change course at once), so the spline through it passes the limit.
    problem = next(_shots(1, speed=1.0))
    with pytest.raises(InfeasibleError, match="takes joint 'right_j4' to") as info:
        TimeOptimalStrike(approach, contact="choose").plan(problem)
    assert (info.value.limit, info.value.joint) == ("position", "right_j4")
    # The line itself, judged apart: it does leave the box.
    line = strike_line(problem, q_contact=choose_contact(problem).q)
    q = line.sample(np.linspace(0.0, line.duration, 20001)).q
    j = problem.limits.names.index("right_j4")
    assert q[:, j].min() < problem.limits.lower[j] - 1e-6
    assert info.value.allowed == problem.limits.lower[j]


def test_bad_arguments():
    with pytest.raises(UnknownNameError, match="unknown approach 'rrt'"):
        TimeOptimalStrike("rrt")  # type: ignore[arg-type]
    for make in (TimeOptimalStrike, ClassicStrike):
        with pytest.raises(UnknownNameError, match="unknown contact 'nearest'"):
            make(contact="nearest")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="PoolStrike or a PaddleStrike"):
        TimeOptimalStrike().plan(problems.youbot_two_blocks())


@pytest.mark.parametrize("samples", [True, 2.5, "60", 0, 10**6])
def test_strike_line_sample_counts_are_typed_and_bounded(samples):
    problem = problems.sawyer_pool_shot(1.0)
    with pytest.raises(InvalidInputError, match="samples"):
        strike_line(problem, samples)
    with pytest.raises(InvalidInputError, match="samples"):
        TimeOptimalStrike(samples=samples)


def test_strike_line_names_a_bad_contact_configuration_and_problem():
    problem = problems.sawyer_pool_shot(1.0)
    with pytest.raises(InvalidInputError, match="q_contact"):
        strike_line(problem, 10, q_contact=np.zeros(3))
    with pytest.raises(InvalidInputError, match="PoolStrike"):
        strike_line(problems.ece486_paddle_strike(), 10)
