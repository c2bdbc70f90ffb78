"""Tests of planners.profiles.time_scaling: cubic and quintic scalings, judged by the checker."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.checker import check
from optraj.planners.profiles.time_scaling import (
    Cubic,
    Quintic,
    polynomial_peaks,
    worst_rate_limit,
)

# ECE486 task, ball (1.1, 0.8, 0.7), T = 2 s, 5 Hz: the printed rows at t = 0.2, 0.4, 1.0, 1.8 s.
ECE486_ROWS = {
    0.2: [0.4626, 0.0110, 0.0280, -0.0110],
    0.4: [0.4968, 0.0407, 0.1038, -0.0407],
    1.0: [0.6750, 0.1956, 0.4992, -0.1956],
    1.8: [0.8874, 0.3802, 0.9705, -0.3802],
}
ECE486_GOALS = {
    (1.1, 0.8, 0.7): [0.9000, 0.3911, 0.9985, -0.3911],
    (1.1, -0.8, 0.7): [0.9000, -0.3911, 0.9985, 0.3911],
    (1.1, -0.8, -0.1): [0.1000, -0.3911, 0.9985, 0.3911],
    (1.1, 0.8, -0.1): [0.1000, 0.3911, 0.9985, -0.3911],
}
HOME = np.array([0.45, 0.0, 0.0, 0.0])


def test_seed_table_first_corner_rows():
    traj = Cubic().plan(problems.ece486_paddle_strike((1.1, 0.8, 0.7)))
    times = np.arange(0.0, 2.0 + 1e-9, 0.2)  # t = 0 .. T at f = 5 Hz: 11 rows
    rows = traj.sample(times).q
    assert rows.shape == (11, 4)
    np.testing.assert_allclose(rows[0], HOME, atol=1e-12)
    np.testing.assert_allclose(rows[-1], ECE486_GOALS[(1.1, 0.8, 0.7)], atol=1e-4)
    for t, expected in ECE486_ROWS.items():
        np.testing.assert_allclose(traj.sample(t).q, expected, atol=1e-4)


@pytest.mark.parametrize("ball", list(ECE486_GOALS)[1:])
def test_seed_table_other_corners(ball):
    # The ECE486 scaling values s(t) read off its first-corner table (joint 2 / its goal).
    traj = Cubic().plan(problems.ece486_paddle_strike(ball))
    goal = np.array(ECE486_GOALS[ball])
    for t, row in ECE486_ROWS.items():
        s = row[1] / 0.3911
        np.testing.assert_allclose(traj.sample(t).q, HOME + s * (goal - HOME), atol=2e-4)
    np.testing.assert_allclose(traj.sample(2.0).q, goal, atol=1e-4)


def _limits(robot, rng):
    return dataclasses.replace(
        robot.limits,
        velocity=rng.uniform(0.2, 3.0, robot.dof),
        acceleration=rng.uniform(0.5, 10.0, robot.dof),
        jerk=rng.uniform(5.0, 200.0, robot.dof),
    )


def test_shortest_durations_match_the_closed_form():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(8)
    for _ in range(50):
        limits = _limits(robot, rng)
        q0, q1 = robot.random_configurations(2, rng)
        delta = np.abs(q1 - q0)
        cubic = np.max(
            np.maximum(1.5 * delta / limits.velocity, np.sqrt(6 * delta / limits.acceleration))
        )
        quintic = np.max(
            np.maximum.reduce(
                [
                    1.875 * delta / limits.velocity,
                    np.sqrt(10 / np.sqrt(3) * delta / limits.acceleration),
                    np.cbrt(60 * delta / limits.jerk),
                ]
            )
        )
        assert Cubic().move(q0, q1, limits).duration == pytest.approx(cubic, rel=1e-6)
        assert Quintic().move(q0, q1, limits).duration == pytest.approx(quintic, rel=1e-6)


@pytest.mark.parametrize(("profile", "quantities"), [
    (Cubic(), ("position", "velocity", "acceleration")),
    (Quintic(), ("position", "velocity", "acceleration", "jerk")),
])  # fmt: skip
@pytest.mark.slow
def test_1000_random_moves_pass_the_checker(profile, quantities):
    robot = get_robot("paddle4")
    rng = np.random.default_rng(1000)
    for _ in range(1000):
        limits = _limits(robot, rng)
        q0, q1 = robot.random_configurations(2, rng)
        problem = problems.PointToPoint(robot, q0, q1, limits=limits)
        report = check(profile.plan(problem), problem, quantities=quantities, rate=500.0)
        assert report.ok, report.summary()


@pytest.mark.slow
def test_moving_boundaries_are_met_and_checked():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(3)
    for _ in range(100):
        q0, q1 = robot.random_configurations(2, rng)
        v0, v1 = rng.uniform(-0.3, 0.3, (2, robot.dof)) * robot.limits.velocity
        a0, a1 = rng.uniform(-0.3, 0.3, (2, robot.dof)) * robot.limits.acceleration
        problem = problems.PointToPoint(robot, q0, q1, v0, v1, a0, a1)
        try:
            traj = Quintic().plan(problem)
        except InfeasibleError:
            continue  # e.g. an overshoot past a position limit; the error names it
        report = check(traj, problem, quantities=("position", "velocity", "acceleration", "jerk"))
        assert report.ok, report.summary()


def test_fixed_duration_too_short_names_joint_and_limit():
    robot = get_robot("paddle4")
    problem = problems.PointToPoint(robot, robot.home, [0.9, 0.39, 0.99, -0.39], duration=0.2)
    with pytest.raises(InfeasibleError, match=r"cubic in 0.2 s needs joint 'J\d'") as info:
        Cubic().plan(problem)
    assert info.value.required > info.value.allowed


def test_cubic_cannot_meet_accelerations_and_rejects_other_problems():
    robot = get_robot("paddle4")
    problem = problems.PointToPoint(robot, robot.home, robot.home, qdd_start=[0.1, 0, 0, 0])
    with pytest.raises(InvalidInputError, match="use Quintic"):
        Cubic().plan(problem)
    with pytest.raises(InvalidInputError, match="PointToPoint or a PaddleStrike"):
        Cubic().plan(problems.youbot_two_blocks())
    with pytest.raises(InvalidInputError, match="duration must be >= 1e-06 s, got -1 s"):
        Quintic(duration=-1.0)


def test_paddle_strike_at_speed_meets_the_ball_and_stops():
    robot = get_robot("paddle4")
    problem = problems.PaddleStrike(robot, ball=(1.0, 0.3, 0.4), speed=0.5, contact_time=1.5)
    traj = Quintic().plan(problem)
    report = check(traj, problem, quantities=("position", "velocity", "acceleration", "jerk"))
    assert report.ok, report.summary()
    assert [p.name for p in traj.phases] == ["approach", "stop"]


def test_ece486_paddle_strike_passes_the_checker():
    problem = problems.ece486_paddle_strike()
    report = check(
        Cubic().plan(problem), problem, quantities=("position", "velocity", "acceleration")
    )
    assert report.ok, report.summary()


# issue 32, defect 6: a duration is a number of seconds in [1e-6, 86400] everywhere
@pytest.mark.parametrize("profile", [Cubic, Quintic])
@pytest.mark.parametrize(
    ("duration", "match"),
    [
        ("2", "duration must be a numeric"),
        (True, "duration must be a numeric"),
        (1e200, "duration must be <= 86400 s, got 1e[+]200 s"),
        (1e-200, "duration must be >= 1e-06 s, got 1e-200 s"),
    ],
)
def test_durations_are_numbers_in_range_in_the_planner_and_in_move(profile, duration, match):
    limits = get_robot("paddle4").limits
    with pytest.raises(InvalidInputError, match=match):
        profile(duration=duration)
    with pytest.raises(InvalidInputError, match=match):
        profile().move([0.1, 0, 0, 0], [0.2, 0, 0, 0], limits, duration)


def test_a_cubic_refuses_even_zero_prescribed_accelerations():
    # A rest-to-rest cubic starts at 6 delta / T^2: it planned a move given qdd = 0 that the
    # checker then failed at both ends (a fuzz finding of issue 32).
    robot = get_robot("paddle4")
    for label in ("qdd_start", "qdd_goal"):
        problem = problems.PointToPoint(
            robot, np.zeros(4), [0.0, 0.0, 0.0, 1.0], **{label: np.zeros(4)}
        )
        with pytest.raises(InvalidInputError, match="cannot meet prescribed accelerations") as info:
            Cubic().plan(problem)
        assert info.value.name == label
        traj = Quintic().plan(problem)
        assert check(traj, problem).ok


def _exact_check(profile, coeffs, duration, limits):
    """The check with every peak exact, for comparison with the screened one."""
    peaks = polynomial_peaks(coeffs, duration)
    for excess, values, bound in (
        (limits.lower - peaks["position_min"], peaks["position_min"], limits.lower),
        (peaks["position_max"] - limits.upper, peaks["position_max"], limits.upper),
    ):
        j = int(np.argmax(excess))
        if excess[j] > 1e-9:
            return "position", j, float(values[j]), float(bound[j])
    return worst_rate_limit(peaks, limits, profile.limited)


@pytest.mark.parametrize("profile", [Cubic(), Quintic()])
def test_screened_check_answers_as_the_exact_one(profile):
    robot = get_robot("panda")
    rng = np.random.default_rng(35)
    answers = set()
    for _ in range(300):
        limits = _limits(robot, rng)
        q0, q1 = robot.random_configurations(2, rng)
        v0, v1 = rng.uniform(-0.5, 0.5, (2, robot.dof)) * limits.velocity
        duration = float(rng.uniform(0.3, 4.0))
        boundary = {"v0": v0, "v1": v1, "a0": np.zeros(7), "a1": np.zeros(7)}
        coeffs = profile._coefficients(q0, q1, duration, boundary)
        screened = profile._check(coeffs, duration, limits)
        exact = _exact_check(profile, coeffs, duration, limits)
        assert (screened is None) == (exact is None)
        if exact is not None:
            assert screened[:2] == exact[:2]
            assert screened[2:] == pytest.approx(exact[2:], rel=1e-12)
        assert profile._fits(coeffs, duration, limits) == (exact is None)
        answers.add(None if exact is None else exact[0])
    assert None in answers and len(answers) > 2  # fits, and more than one limit broken


@pytest.mark.parametrize("profile", [Cubic, Quintic])
@pytest.mark.parametrize("duration", [None, 2.0])
def test_plans_with_moving_ends_pass_the_checker_or_name_the_limit(profile, duration):
    robot = get_robot("panda")
    limits = robot.limits
    rng = np.random.default_rng(35)
    span = limits.upper - limits.lower
    planned = 0
    for _ in range(12):
        q0, q1 = limits.lower + span * rng.uniform(0.1, 0.9, (2, robot.dof))
        v0, v1 = 0.2 * limits.velocity * rng.uniform(-1, 1, (2, robot.dof))
        problem = problems.PointToPoint(robot, q0, q1, v0, v1)
        try:
            traj = profile(duration=duration).plan(problem)
        except InfeasibleError as error:
            assert duration is not None and error.required > error.allowed
            continue
        planned += 1
        report = check(traj, problem, quantities=("position", *profile.limited))
        assert report.ok, report.summary()
        if duration is not None:
            assert traj.duration == duration
    assert planned >= 4


@pytest.mark.parametrize(("profile", "name"), [(Cubic(), "cubic"), (Quintic(), "quintic")])
def test_a_start_speeding_into_a_limit_fits_no_duration(profile, name):
    robot = get_robot("panda")
    limits = robot.limits
    q0 = (limits.lower + limits.upper) / 2
    q1 = q0.copy()
    q1[0] += 0.1
    q0[1] = limits.upper[1] - 1e-3
    v0 = np.zeros(robot.dof)
    v0[1] = 0.9 * limits.velocity[1]  # 1 mm from the limit: every duration overshoots it
    problem = problems.PointToPoint(robot, q0, q1, qd_start=v0)
    with pytest.raises(InfeasibleError, match=f"no {name} of any duration keeps joint") as info:
        profile.plan(problem)
    assert info.value.limit == "position" and info.value.joint == limits.names[1]
    assert info.value.required > info.value.allowed == limits.upper[1]


@pytest.mark.parametrize(("profile", "name"), [(Cubic(), "cubic"), (Quintic(), "quintic")])
def test_a_move_too_long_for_any_duration_names_the_velocity_limit(profile, name):
    robot = get_robot("panda")
    limits = dataclasses.replace(robot.limits, velocity=np.full(robot.dof, 1e-5))
    q0 = (limits.lower + limits.upper) / 2
    # at 1e-5 rad/s, 0.3 rad take 3e4 s: beyond the longest duration tried
    problem = problems.PointToPoint(
        robot, q0, q0 + 0.3, qd_start=np.full(robot.dof, 1e-6), limits=limits
    )
    with pytest.raises(InfeasibleError, match=f"no {name} of any duration keeps joint") as info:
        profile.plan(problem)
    assert info.value.limit == "velocity" and info.value.required > info.value.allowed == 1e-5
