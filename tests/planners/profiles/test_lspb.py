"""Tests of planners.profiles.lspb: synchronised moves, their trajectories, limits, errors."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.profiles.lspb import LSPB, lspb_fixed_cruise, lspb_min_time, lspb_trajectory
from optraj.problems.point_to_point import is_still

QUANTITIES = ("position", "velocity", "acceleration")


def _limits(robot, velocity, acceleration):
    return dataclasses.replace(robot.limits, velocity=velocity, acceleration=acceleration)


def _sides(traj):
    """Values of q, qd, qdd just left and right of every inner breakpoint, exactly."""
    knots = traj.breakpoints
    coeffs = traj.coefficients
    lengths = np.diff(knots)[:-1]
    left, right = [], []
    for order in range(3):
        c = coeffs
        for _ in range(order):
            c = c[:, 1:] * np.arange(1, c.shape[1])[None, :, None]
        powers = lengths[:, None] ** np.arange(c.shape[1])[None, :]
        left.append(np.einsum("kd,kdn->kn", powers, c[:-1]))
        right.append(c[1:, 0])
    return left, right


# ----------------------------------------------------------------------------- moves


def test_seed_cruise_time_gives_half_the_displacement_per_second():
    # ECE486 task: T = 3 s, tc = 1 s, so tb = 1 s and v = 2 delta / (3 + 1) exactly.
    delta = np.array([0.45, -0.3911, 0.9985, 0.3911, 0.0])
    timing = lspb_fixed_cruise(delta, 3.0, 1.0)
    np.testing.assert_array_equal(timing.velocity, 2.0 * delta / 4.0)
    np.testing.assert_array_equal(timing.blend_time, 1.0)
    robot = get_robot("paddle4")
    start = np.array([0.45, 0.0, 0.0, 0.0])
    goal = np.array([0.9, 0.3911, 0.9985, -0.3911])
    traj = LSPB(cruise_time=1.0).move(start, goal, robot.limits, 3.0)
    np.testing.assert_array_equal(traj.metadata["cruise_velocities"], (goal - start) / 2.0)
    np.testing.assert_array_equal(traj.metadata["blend_times"], 1.0)
    np.testing.assert_array_equal(traj.breakpoints, [0.0, 1.0, 2.0, 3.0])
    np.testing.assert_allclose(traj.sample(3.0).q, goal, atol=1e-12)
    np.testing.assert_allclose(traj.sample(1.5).qd, (goal - start) / 2.0, atol=1e-12)


def test_synchronised_move_takes_the_slowest_joints_minimum_time():
    robot = get_robot("sawyer")
    limits = robot.limits
    start = robot.home
    goal = np.clip(
        start + np.array([1.0, -0.5, 0.2, 0.0, 2.0, 1e-9, -0.7]), limits.lower, limits.upper
    )
    delta = goal - start
    own = lspb_min_time(delta, limits.velocity, limits.acceleration)
    traj = LSPB().move(start, goal, limits)
    assert traj.duration == pytest.approx(np.max(own.duration), rel=1e-12)
    assert traj.metadata["planner"] == "lspb"
    # Every moving joint blends at its own acceleration limit and moves until the end, except
    # joint 5: its 1e-9 rad would need a blend under 1e-9 T, so it moves on a triangle over T.
    moving = delta != 0.0
    normal = moving & (np.abs(delta) > 1e-6)
    accelerations = np.abs(traj.metadata["accelerations"])
    np.testing.assert_allclose(accelerations[normal], limits.acceleration[normal], rtol=1e-12)
    assert traj.metadata["blend_times"][5] == 0.5 * traj.duration
    assert accelerations[5] == pytest.approx(4e-9 / traj.duration**2, rel=1e-6)
    for t in (1e-6, 0.5 * traj.duration, traj.duration - 1e-6):
        qd = traj.sample(t).qd
        assert np.all(np.sign(qd[moving]) == np.sign(delta[moving]))
        assert np.all(qd[~moving] == 0.0)
    # The slowest joint follows its own minimum-time profile.
    slow = int(np.argmax(own.duration))
    assert traj.metadata["blend_times"][slow] == pytest.approx(own.blend_time[slow], rel=1e-9)
    # Breakpoints: each joint's blend ends and decelerations start, merged.
    blends = traj.metadata["blend_times"][normal]
    for tb in blends:
        assert np.min(np.abs(traj.breakpoints - tb)) < 1e-12
        assert np.min(np.abs(traj.breakpoints - (traj.duration - tb))) < 1e-12


def test_plan_point_to_point_names_the_phase():
    robot = get_robot("paddle4")
    problem = problems.PointToPoint(robot, [0.2, 0.0, 0.1, 0.0], [0.8, 1.0, 0.9, -0.5], duration=2)
    traj = LSPB().plan(problem)
    assert traj.duration == 2.0
    assert [p.name for p in traj.phases] == ["move"]
    assert traj.joint_names == robot.joint_names
    assert traj.degree == 2
    report = planners.check(traj, problem, quantities=QUANTITIES)
    assert report.ok, report


def test_trajectory_holds_joints_that_finish_early():
    # lspb_trajectory also draws unsynchronised timings: fast joints hold their goals.
    delta = np.array([2.0, 0.1, 0.0])
    timing = lspb_min_time(delta, [1.0, 1.0, 1.0], [2.0, 2.0, 2.0])
    traj = lspb_trajectory(np.zeros(3), delta, timing)
    assert traj.duration == pytest.approx(2.5)
    end_fast = timing.duration[1]
    np.testing.assert_allclose(traj.sample(end_fast + 0.1).q[1], 0.1, atol=1e-15)
    np.testing.assert_allclose(traj.sample(traj.duration).q, delta, atol=1e-12)


def test_round_off_displacements_keep_breakpoints_apart_so_moves_chain():
    # IK round-off leaves displacements like 1e-26 rad; their blends would last ~1e-13 s and
    # their breakpoints would collapse once shifted by Trajectory.then.
    robot = get_robot("sawyer")
    limits = robot.limits
    rng = np.random.default_rng(3)
    pieces = []
    current = robot.home.copy()
    current[2] = 0.0
    for k in range(40):
        target = limits.sample(rng, 1)[0]
        target[2] = 1e-26 if k % 2 else -1e-26  # a round-off move
        pieces.append(LSPB().move(current, target, limits))
        # Every joint moves 2e-12 (just above STILL_TOLERANCE, the smallest move planned
        # without a duration): the shortest cruise-time move lasts just over 0.5 s.
        pieces.append(LSPB(cruise_time=0.5).move(target, target + 2e-12, limits))
        current = target + 2e-12
    joined = pieces[0].then(*pieces[1:])
    assert np.all(np.diff(joined.breakpoints) > 1e-12 * pieces[0].duration)
    for piece in pieces:
        assert np.min(np.diff(piece.breakpoints)) >= 1e-12 * piece.duration
        np.testing.assert_array_equal(piece.sample(0.0).qd, 0.0)


# ------------------------------------------------------------------ limits, at random

CASES = ("min_time", "duration", "blend_time", "cruise_time")


def _random_move(rng, robot):
    n = robot.dof
    limits = _limits(robot, rng.uniform(0.2, 6.0, n), rng.uniform(0.5, 50.0, n))
    start, goal = limits.sample(rng, 2)
    kind = rng.integers(0, 4, n)  # 0: zero, 1: tiny, 2-3: anywhere in range
    tiny = rng.choice([1e-15, 1e-12, 1e-9, 1e-6], n) * rng.choice([-1.0, 1.0], n)
    inside = (start + tiny >= limits.lower) & (start + tiny <= limits.upper)
    goal = np.where(kind == 0, start, np.where((kind == 1) & inside, start + tiny, goal))
    if is_still(start, goal):  # the fastest move would last 0 s: refused
        goal[0] = limits.sample(rng, 1)[0, 0]
    return limits, start, goal


def _plan_case(case, rng, start, goal, limits):
    if case == "min_time":
        return LSPB().move(start, goal, limits)
    if case == "duration":
        shortest = np.max(lspb_min_time(goal - start, limits.velocity, limits.acceleration)[0])
        # a duration is at least MIN_DURATION (1 us); a longer one than the shortest is fine
        return LSPB().move(start, goal, limits, max(shortest * rng.uniform(1.0, 3.0), 1e-6))
    if case == "blend_time":
        return LSPB(blend_time=rng.uniform(0.05, 0.6)).move(start, goal, limits)
    return LSPB(cruise_time=rng.choice([0.0, rng.uniform(0.0, 2.0)])).move(start, goal, limits)


@pytest.mark.parametrize("case", CASES)
@pytest.mark.slow
def test_random_moves_respect_limits_and_are_c1(case):
    rng = np.random.default_rng(CASES.index(case) + 100)
    robots_ = [get_robot("sawyer"), get_robot("paddle4")]
    for trial in range(1000):
        robot = robots_[trial % 2]
        limits, start, goal = _random_move(rng, robot)
        traj = _plan_case(case, rng, start, goal, limits)
        vmax, amax = limits.velocity, limits.acceleration
        # Boundary states: exact start, end to 1e-12, at rest.
        first, last = traj.sample(0.0), traj.sample(traj.duration)
        np.testing.assert_array_equal(first.q, start)
        np.testing.assert_array_equal(first.qd, 0.0)
        np.testing.assert_allclose(last.q, goal, rtol=0, atol=1e-12)
        np.testing.assert_allclose(last.qd, 0.0, rtol=0, atol=1e-12)
        # Continuity at every breakpoint, computed exactly from both polynomials.
        (q_l, qd_l, qdd_l), (q_r, qd_r, _) = _sides(traj)
        np.testing.assert_allclose(q_l, q_r, rtol=0, atol=1e-12)
        np.testing.assert_allclose(qd_l, qd_r, rtol=0, atol=1e-9 * np.max(vmax))
        # Limits: on a grid (20 kHz for every 20th move, 500 points otherwise) plus both
        # sides of every breakpoint, which for piecewise quadratics hold every extremum.
        dense = trial % 20 == 0 and traj.duration < 10.0
        # at most 1 MHz, the highest rate Trajectory.times takes (tiny moves last < 1 us)
        rate = 20_000.0 if dense else min(500.0 / traj.duration, 1e6)
        sample = traj.sample(traj.times(rate))
        for values in (sample.qd, qd_l):
            assert np.all(np.abs(values) <= vmax * (1 + 1e-9))
        for values in (sample.qdd, qdd_l):
            assert np.all(np.abs(values) <= amax * (1 + 1e-9))
        assert np.all(limits.contains(sample.q, tolerance=1e-12))
        if case == "min_time":
            own = lspb_min_time(goal - start, vmax, amax)  # a move lasts at least 1 us
            assert traj.duration == pytest.approx(max(np.max(own.duration), 1e-6), rel=1e-12)
        # The independent checker on every move (it refines peaks exactly between samples).
        problem = problems.PointToPoint(robot, start, goal, limits=limits, tolerance=1e-12)
        report = planners.check(traj, problem, rate=200.0, quantities=QUANTITIES)
        assert report.ok, report


# ---------------------------------------------------------------------------- errors


def test_too_short_duration_names_joint_required_and_limit():
    robot = get_robot("paddle4")
    start, goal = [0.2, 0.0, 0.1, 0.0], [0.8, 1.0, 0.9, -0.5]
    with pytest.raises(InfeasibleError, match=r"LSPB in 0.5 s needs joint 'J\d'") as info:
        LSPB().move(start, goal, robot.limits, 0.5)
    error = info.value
    assert error.limit == "acceleration"
    assert error.joint in str(error) and error.joint in robot.joint_names
    j = robot.joint_names.index(error.joint)
    assert error.allowed == robot.limits.acceleration[j]
    assert error.required == pytest.approx(4 * abs(goal[j] - start[j]) / 0.25)
    assert f"limit {error.allowed:g}" in str(error)


def test_duration_too_short_for_the_velocity_limit():
    robot = get_robot("paddle4")
    limits = _limits(robot, [0.1, 3.0, 1.5, 6.0], [100.0, 100.0, 100.0, 100.0])
    # J1 must move 0.6 m: at least 6 s at 0.1 m/s, though 0.16 s would do for its acceleration.
    with pytest.raises(InfeasibleError, match=r"needs joint 'J1' at [\d.]+ m/s, limit 0.1 m/s"):
        LSPB().move([0.2, 0, 0, 0], [0.8, 0, 0, 0], limits, 5.0)


def test_fixed_settings_beyond_limits_raise_unless_told_not_to_check():
    robot = get_robot("paddle4")
    start, goal = [0.2, 0.0, 0.1, 0.0], [0.8, 1.0, 0.9, -0.5]
    with pytest.raises(InfeasibleError, match=r"cruise_time 1 s in 1.2 s needs joint 'J\d'"):
        LSPB(cruise_time=1.0).move(start, goal, robot.limits, 1.2)
    with pytest.raises(InfeasibleError, match=r"blend_time 0.01 s in 1 s needs joint 'J\d'"):
        LSPB(blend_time=0.01).move(start, goal, robot.limits, 1.0)
    traj = LSPB(cruise_time=1.0, check_limits=False).move(start, goal, robot.limits, 1.2)
    assert traj.metadata["limits_checked"] is False
    assert traj.metadata["limit_violations"]
    assert all("needs joint" in text for text in traj.metadata["limit_violations"])
    report = planners.check(traj, robot, quantities=QUANTITIES)
    assert not report.ok  # the checker sees what the metadata says
    # Without a duration the fixed setting gets the shortest duration within the limits.
    traj = LSPB(cruise_time=1.0).move(start, goal, robot.limits)
    assert traj.metadata["limit_violations"] == []
    assert planners.check(traj, robot, quantities=QUANTITIES).ok


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"blend_time": 0.5, "cruise_time": 1.0}, "not both"),
        ({"blend_time": 0.0}, "blend_time must be >= 1e-06 s, got 0 s"),
        ({"blend_time": math.nan}, "blend_time must be finite"),
        ({"cruise_time": -1.0}, "cruise_time must be >= 0 s, got -1 s"),
        ({"check_limits": False}, "applies only with a fixed"),
    ],
)
def test_bad_options(kwargs, match):
    with pytest.raises(InvalidInputError, match=match):
        LSPB(**kwargs)


def test_settings_that_do_not_fit_the_duration():
    limits = get_robot("paddle4").limits
    start, goal = [0.2, 0.0, 0.1, 0.0], [0.3, 0.1, 0.2, 0.1]
    with pytest.raises(InvalidInputError, match="at most half the duration 1 s"):
        LSPB(blend_time=0.6).move(start, goal, limits, 1.0)
    with pytest.raises(InvalidInputError, match="below the duration 1 s"):
        LSPB(cruise_time=1.0).move(start, goal, limits, 1.0)


def test_no_motion():
    limits = get_robot("paddle4").limits
    q = [0.2, 0.0, 0.1, 0.0]
    with pytest.raises(InvalidInputError, match="give a duration to hold still"):
        LSPB().move(q, q, limits)
    traj = LSPB().move(q, q, limits, 1.5)
    assert traj.duration == 1.5
    sample = traj.sample(traj.times(100))
    np.testing.assert_array_equal(sample.q, np.broadcast_to(q, sample.q.shape))
    np.testing.assert_array_equal(sample.qd, 0.0)


def test_bad_inputs_are_typed_errors():
    limits = get_robot("paddle4").limits
    with pytest.raises(InvalidInputError, match="q_goal must be finite"):
        LSPB().move([0.2, 0, 0, 0], [0.3, np.nan, 0, 0], limits)
    with pytest.raises(InvalidInputError, match=r"q_start must have shape \(4,\)"):
        LSPB().move([0.2, 0, 0], [0.3, 0, 0, 0], limits)
    with pytest.raises(InvalidInputError, match="duration must be >= 1e-06 s, got -1 s"):
        LSPB().move([0.2, 0, 0, 0], [0.3, 0, 0, 0], limits, -1.0)
    with pytest.raises(InvalidInputError, match=r"plans a problems\.PointToPoint"):
        LSPB().plan("not a problem")  # type: ignore[arg-type]


# issue 32, defect 6: numbers are numbers (np.array(..., dtype=float) took "1" and True)
def test_text_and_bools_are_not_numbers():
    limits = get_robot("paddle4").limits
    with pytest.raises(InvalidInputError, match="duration must be a numeric"):
        LSPB().move([0.1, 0, 0, 0], [0.2, 0, 0, 0], limits, "2")
    with pytest.raises(InvalidInputError, match="blend_time must be a numeric"):
        LSPB(blend_time="0.1")
    with pytest.raises(InvalidInputError, match="duration must be <= 86400 s"):
        LSPB().move([0.1, 0, 0, 0], [0.2, 0, 0, 0], limits, 1e200)
    with pytest.raises(InvalidInputError, match="cruise_time must be <= 86400 s"):
        LSPB(cruise_time=1e200)
    with pytest.raises(InvalidInputError, match="check_limits must be True or False"):
        LSPB(blend_time=0.1, check_limits=0)


def test_prescribed_accelerations_are_refused_even_zero():
    # An LSPB starts at full acceleration: a prescribed zero is not met (the checker fails it).
    robot = get_robot("paddle4")
    problem = problems.PointToPoint(robot, np.zeros(4), [0.0, 0.0, 0.0, 1.0], qdd_goal=np.zeros(4))
    with pytest.raises(InvalidInputError, match="cannot meet prescribed accelerations") as info:
        LSPB().plan(problem)
    assert info.value.name == "qdd_goal"
