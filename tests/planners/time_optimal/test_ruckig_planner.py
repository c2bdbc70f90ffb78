"""Tests of planners.time_optimal.ruckig_planner: the Ruckig planner's random moves judged by
the checker, its synchronisation and duration options, its end-state check and its metadata."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from conftest import HAVE_ERD, get_robot
from ruckig_support import QUANTITIES, inner, random_limits, scaled_limits

from optraj import problems
from optraj.errors import InfeasibleError, InvalidInputError, OptrajError, SolverError
from optraj.planners.checker import check
from optraj.planners.time_optimal.ruckig_planner import Ruckig
from optraj.planners.trajectory import Trajectory


def _moving(robot, q0, q1, shares, limits, **options):
    """A PointToPoint between q0 and q1 whose boundary velocities and accelerations are the
    rows of ``shares`` (shape (4, n)) times the limits: qd_start, qd_goal, qdd_start, qdd_goal.
    """
    return problems.PointToPoint(
        robot,
        q0,
        q1,
        qd_start=shares[0] * limits.velocity,
        qd_goal=shares[1] * limits.velocity,
        qdd_start=shares[2] * limits.acceleration,
        qdd_goal=shares[3] * limits.acceleration,
        limits=limits,
        **options,
    )


def _slow_limits(robot, rng, low, high):
    """Limits scaled per joint and quantity, log-uniformly: velocity, acceleration, jerk."""
    return scaled_limits(robot, np.exp(rng.uniform(np.log(low), np.log(high), (robot.dof, 3))).T)


@pytest.mark.slow
def test_random_rest_to_rest_moves_pass_the_checker():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(20240611)
    planner = Ruckig()
    failures = []
    for k in range(1000):
        limits = random_limits(robot, rng)
        q0, q1 = limits.sample(rng, 2)
        traj = planner.move(q0, q1, limits)
        problem = problems.PointToPoint(robot, q0, q1, limits=limits)
        report = check(traj, problem, quantities=QUANTITIES, rate=200.0)
        if not report.ok:
            failures.append((k, report.violations))
        # Time synchronisation: the move takes the slowest joint's own minimum time.
        durations = traj.metadata["independent_min_durations"]
        assert traj.duration == pytest.approx(durations.max(), rel=1e-12, abs=1e-12)
    assert not failures, failures[:3]


@pytest.mark.slow
def test_random_state_to_state_moves_pass_the_checker_or_raise_typed_errors():
    robot = get_robot("sawyer")
    rng = np.random.default_rng(7)
    planner = Ruckig()
    raised: list[OptrajError] = []
    failures = []
    for k in range(300):
        limits = random_limits(robot, rng)
        q0, q1 = inner(limits, rng), inner(limits, rng)
        half = 0.5 * rng.uniform(-1.0, 1.0, size=(4, robot.dof))
        problem = _moving(robot, q0, q1, half, limits)
        try:
            traj = planner.plan(problem)
        except InfeasibleError as exc:
            raised.append(exc)
            continue
        report = check(traj, problem, quantities=QUANTITIES, rate=200.0)
        assert {"start state", "end state"} <= set(report.names)
        if not report.ok:
            failures.append((k, report.violations))
    assert not failures, failures[:3]
    # Few moves are out of reach: those that must overshoot a position limit.
    assert len(raised) <= 10, [str(exc) for exc in raised]
    assert all(exc.limit == "position" and exc.joint in robot.joint_names for exc in raised)


@pytest.mark.skipif(not HAVE_ERD, reason="needs optraj[examples]")
def test_long_rest_to_rest_moves_with_small_limits_are_usable_and_pass_the_checker():
    # Panda moves of minutes with limits scaled to 0.1-10 %: late in such a move a breakpoint
    # is known only to about 1e-13 s, over which a steep acceleration ramp moves by more than
    # a relative 1e-9 of its limit; every plan must still build, sample and pass the checker.
    robot = get_robot("panda")
    rng = np.random.default_rng(1)
    planner = Ruckig()
    failures = []
    longest = 0.0
    for k in range(300):
        limits = _slow_limits(robot, rng, [1e-3] * 3, [1e-1] * 3)
        q0, q1 = limits.sample(rng, 2)
        traj = planner.move(q0, q1, limits)
        longest = max(longest, traj.duration)
        try:
            traj.sample(0.0)
        except SolverError as exc:
            failures.append((k, str(exc)))
            continue
        problem = problems.PointToPoint(robot, q0, q1, limits=limits)
        report = check(traj, problem, quantities=QUANTITIES, rate=1.0)
        if not report.ok:
            failures.append((k, report.violations))
    assert not failures, failures[:3]
    assert longest > 1000.0


def test_moving_state_plans_with_steep_jerk_pass_the_checker():
    # Small velocity and acceleration limits with large jerk limits: long moves whose
    # acceleration ramps last microseconds, where the round-off of a breakpoint must not be
    # judged a jump in acceleration (an infinite jerk).
    names = ["sawyer", "youbot", *(["panda"] if HAVE_ERD else [])]
    rng = np.random.default_rng(3)
    planner = Ruckig()
    failures = []
    for k in range(450):
        robot = get_robot(names[k % len(names)])
        limits = _slow_limits(robot, rng, [0.01, 0.01, 1.0], [0.1, 0.1, 100.0])
        middle, half = 0.5 * (limits.lower + limits.upper), 0.5 * (limits.upper - limits.lower)
        q0, q1 = (middle + 0.8 * half * rng.uniform(-1.0, 1.0, robot.dof) for _ in range(2))
        speed = 0.5 * rng.uniform(-1.0, 1.0, size=(2, robot.dof))
        problem = problems.PointToPoint(
            robot,
            q0,
            q1,
            qd_start=speed[0] * limits.velocity,
            qd_goal=speed[1] * limits.velocity,
            qdd_start=0.5 * speed[0] * limits.acceleration,
            qdd_goal=0.5 * speed[1] * limits.acceleration,
            limits=limits,
        )
        try:
            traj = planner.plan(problem)
        except InfeasibleError:
            continue
        report = check(traj, problem, quantities=QUANTITIES, rate=1.0)
        if not report.ok:
            failures.append((k, robot.name, report.violations))
    assert not failures, failures[:3]


def test_a_tolerance_tighter_than_ruckigs_precision_raises_when_planned():
    # With tolerance 0 a plan either meets its end state as the checker judges it (within
    # round-off) or plan raises.
    names = ("sawyer", "youbot")
    rng = np.random.default_rng(1)
    planned, missed = 0, []
    failures = []
    for k in range(400):
        robot = get_robot(names[k % 2])
        limits = _slow_limits(robot, rng, [0.01] * 3, [3.0] * 3)
        middle, half = 0.5 * (limits.lower + limits.upper), 0.5 * (limits.upper - limits.lower)
        q0, q1 = (middle + 0.8 * half * rng.uniform(-1.0, 1.0, robot.dof) for _ in range(2))
        state = rng.uniform(-1.0, 1.0, size=(4, robot.dof)) * rng.uniform(0.0, 1.0)
        problem = _moving(robot, q0, q1, state, limits, tolerance=0.0)
        try:
            traj = Ruckig().plan(problem)
        except InfeasibleError:
            continue
        except SolverError as exc:
            missed.append(exc)
            continue
        planned += 1
        report = check(traj, problem, quantities=QUANTITIES, rate=1.0)
        if not report.ok:
            failures.append((k, report.violations))
    assert not failures, failures[:3]
    assert planned >= 100
    assert missed and all("target state missed" in str(exc) for exc in missed)
    assert all("tolerance 0" in str(exc) for exc in missed)


def test_phase_synchronisation_moves_on_a_straight_line():
    robot = get_robot("sawyer")
    limits = robot.limits
    rng = np.random.default_rng(3)
    q0, q1 = limits.sample(rng, 2)
    times = np.linspace(0.0, 1.0, 101)

    def progress(traj):
        q = traj.sample(times * traj.duration).q
        return (q - q0) / (q1 - q0)  # per joint, in [0, 1]

    phase = Ruckig("phase").move(q0, q1, limits)
    timed = Ruckig("time").move(q0, q1, limits)
    assert phase.metadata["synchronization"] == "phase"
    assert phase.duration == pytest.approx(timed.duration, rel=1e-12)
    s = progress(phase)
    assert np.max(np.ptp(s, axis=1)) < 1e-9  # every joint at the same fraction of its way
    assert np.max(np.ptp(progress(timed), axis=1)) > 1e-3  # time sync alone is not a line
    assert check(phase, robot, quantities=QUANTITIES, rate=200.0).ok


def test_without_synchronisation_each_joint_arrives_at_its_own_fastest():
    limits = get_robot("sawyer").limits
    rng = np.random.default_rng(4)
    q0, q1 = limits.sample(rng, 2)
    traj = Ruckig("none").move(q0, q1, limits)
    own = traj.metadata["independent_min_durations"]
    assert traj.duration == pytest.approx(own.max(), rel=1e-12)
    for j, t in enumerate(own):
        after = traj.sample(np.linspace(t, traj.duration, 5))
        np.testing.assert_allclose(after.q[:, j], q1[j], atol=1e-9)
        np.testing.assert_allclose(after.qd[:, j], 0.0, atol=1e-9)
        before = traj.sample(0.99 * t)
        assert abs(before.q[j] - q1[j]) > 1e-9


def test_minimum_duration_stretches_the_move():
    robot = get_robot("sawyer")
    limits = robot.limits
    q0, q1 = robot.home, robot.home + 0.2
    fastest = Ruckig().move(q0, q1, limits).duration
    assert Ruckig().move(q0, q1, limits, 2.0 * fastest).duration == pytest.approx(2 * fastest)
    assert Ruckig().move(q0, q1, limits, 0.5 * fastest).duration == pytest.approx(fastest)
    assert Ruckig(minimum_duration=3.0).move(q0, q1, limits).duration == pytest.approx(3.0)
    problem = problems.PointToPoint(robot, q0, q1, duration=4.0)
    traj = Ruckig(minimum_duration=3.0).plan(problem)
    assert traj.duration == pytest.approx(4.0)
    assert traj.metadata["minimum_duration"] == 4.0
    assert check(traj, problem, quantities=QUANTITIES, rate=200.0).ok
    with pytest.raises(InvalidInputError, match="minimum_duration"):
        Ruckig(minimum_duration=0.0)


def test_plan_records_metadata_and_exports_without_the_native_object():
    robot = get_robot("sawyer")
    problem = problems.PointToPoint(
        robot, robot.home, robot.home + 0.3, qd_goal=0.2 * robot.limits.velocity
    )
    traj = Ruckig().plan(problem)
    meta = traj.metadata
    assert meta["planner"] == "ruckig" and meta["status"] == "ok"
    assert meta["synchronization"] == "time" and meta["limit_violations"] == []
    assert 0.0 < meta["solve_time"] < 1.0
    assert meta["independent_min_durations"].shape == (7,)
    assert [p.name for p in traj.phases] == ["move"] and traj.joint_names == robot.joint_names
    np.testing.assert_allclose(traj.sample(traj.duration).qd, 0.2 * robot.limits.velocity)
    again = Trajectory.from_json(traj.to_json())
    assert "native" not in again.metadata
    np.testing.assert_array_equal(again.coefficients, traj.coefficients)


def test_plans_pickle_without_ruckigs_own_object():
    robot = get_robot("sawyer")
    move = problems.PointToPoint(robot, q_start=robot.home, q_goal=robot.home + 0.3)
    traj = Ruckig().plan(move)
    with pytest.raises(TypeError):
        pickle.dumps(traj.metadata["native"])  # ruckig's Trajectory does not pickle
    clone = pickle.loads(pickle.dumps(traj))
    t = np.linspace(0.0, traj.duration, 50)
    np.testing.assert_array_equal(clone.sample(t).q, traj.sample(t).q)
    assert "native" not in clone.metadata and "native" in traj.metadata
    assert clone.metadata["planner"] == traj.metadata["planner"]
