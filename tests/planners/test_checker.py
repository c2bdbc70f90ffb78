"""Tests of planners.checker, the independent trajectory checker, both ways.

Every trajectory here is made by hand (polynomials, Hermite interpolation of IK solutions), so
the expected worst values are known analytically or by brute-force sampling, independently of
the checker.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from itertools import pairwise

import numpy as np
import pinocchio as pin
import pytest
from conftest import get_robot

from optraj import problems
from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.checker import QUANTITIES, Finding, Report, check
from optraj.planners.trajectory import Phase, Trajectory
from optraj.problems import (
    BoundaryState,
    CartesianLine,
    PaddleStrike,
    PointToPoint,
    StrikeLine,
    ToolContact,
    Waypoints,
)
from optraj.robots import JointLimits, Robot, solve_ik

SQRT3 = math.sqrt(3.0)
#: Start and move of the paddle4 quintic [m, rad, m, rad]; joint J3 is index 2.
Q0 = np.array([0.45, 0.0, 0.3, 0.0])
DELTA = np.array([0.2, 0.5, 0.3, -0.4])
T = 2.0


# ----------------------------------------------------------------------------- helpers


def quintic(q0: np.ndarray, q1: np.ndarray, duration: float, **kwargs) -> Trajectory:
    """Rest-to-rest quintic q0 -> q1: peak |qd| 1.875 d/T at T/2, |qdd| 10/sqrt(3) d/T^2."""
    d = np.asarray(q1, dtype=float) - q0
    c = np.zeros((1, 6, len(q0)))
    c[0, 0] = q0
    c[0, 3] = 10 * d / duration**3
    c[0, 4] = -15 * d / duration**4
    c[0, 5] = 6 * d / duration**5
    return Trajectory([0.0, duration], c, **kwargs)


def peaks(delta: np.ndarray, duration: float) -> dict[str, np.ndarray]:
    """Analytic peak magnitudes of the quintic, per joint."""
    d = np.abs(delta)
    return {
        "velocity": 1.875 * d / duration,
        "acceleration": 10 / SQRT3 * d / duration**2,
        "jerk": 60 * d / duration**3,
    }


def limits_of(robot: Robot, **fields: np.ndarray) -> JointLimits:
    base = robot.limits
    names = ("lower", "upper", "velocity", "acceleration", "jerk", "effort")
    values = {name: getattr(base, name) for name in names}
    values.update(fields)
    return JointLimits(base.names, base.kinds, **values)


def no_nan(report: Report) -> None:
    for f in report.findings:
        for value in (f.value, f.limit, f.margin, f.ratio):
            assert not math.isnan(value), f
        assert f.time is None or math.isfinite(f.time)


def two_segments(first: np.ndarray, second: np.ndarray) -> Trajectory:
    """Segments [0, 1] and [1, 2] s with coefficient rows (d + 1, n) given per segment."""
    return Trajectory([0.0, 1.0, 2.0], np.stack([first, second]))


@dataclass
class Task:
    """A duck-typed problem: anything with robot, limits and constraints() is checkable."""

    robot: Robot
    items: tuple

    @property
    def limits(self) -> JointLimits:
        return self.robot.limits

    def constraints(self) -> tuple:
        return self.items


@pytest.fixture(scope="module")
def paddle() -> Robot:
    return get_robot("paddle4")


@pytest.fixture(scope="module")
def sawyer() -> Robot:
    return get_robot("sawyer")


# -------------------------------------------------------------------- a good trajectory


def test_known_good_quintic_passes_with_the_analytic_peaks(paddle):
    peak = peaks(DELTA, T)
    factors = np.array([1.5, 1.3, 1.01, 1.2])  # joint J3 comes nearest its limits
    limits = limits_of(
        paddle,
        velocity=factors * peak["velocity"],
        acceleration=factors * peak["acceleration"],
        jerk=factors * peak["jerk"],
    )
    problem = PointToPoint(paddle, Q0, Q0 + DELTA, limits=limits)
    report = check(quintic(Q0, Q0 + DELTA, T), problem)
    assert report.ok, report.summary()
    assert report.violations == ()
    assert report.names == (*QUANTITIES, "start state", "end state")

    velocity = report["velocity"]
    assert velocity.joint == "J3"
    assert velocity.value == pytest.approx(1.875 * 0.3 / T, rel=1e-9)
    assert velocity.time == pytest.approx(T / 2, abs=1e-9)
    assert velocity.ratio == pytest.approx(1 / 1.01, rel=1e-9)
    assert velocity.margin == pytest.approx(velocity.limit - velocity.value, rel=1e-12)

    acceleration = report["acceleration"]
    assert acceleration.value == pytest.approx(10 / SQRT3 * 0.3 / T**2, rel=1e-9)
    expected = T * (0.5 + np.array([-1.0, 1.0]) * SQRT3 / 6)  # either side of the middle
    assert np.min(np.abs(acceleration.time - expected)) < 1e-9

    jerk = report["jerk"]
    assert jerk.value == pytest.approx(60 * 0.3 / T**3, rel=1e-9)
    assert min(jerk.time, T - jerk.time) < 1e-9  # the jerk peaks at both ends

    # J3 starts 0.3 m above its lower limit 0: the smallest position margin.
    position = report["position"]
    assert (position.joint, position.value, position.limit) == ("J3", 0.3, 0.0)
    assert position.margin == pytest.approx(0.3)
    assert position.time == 0.0

    # Torque against an independent, denser sampling of inverse dynamics.
    times = np.linspace(0.0, T, 8001)
    sample = quintic(Q0, Q0 + DELTA, T).sample(times)
    torque = np.abs(paddle.inverse_dynamics(sample.q, sample.qd, sample.qdd)) / paddle.limits.effort
    assert report["torque"].ratio == pytest.approx(torque.max(), rel=1e-3)
    assert report["torque"].joint == paddle.joint_names[int(np.argmax(torque.max(axis=0)))]


def test_peaks_between_samples_are_found_exactly(paddle):
    duration = 2.2  # at 3 Hz the samples miss T/2
    delta = np.array([0.1, 0.5, 0.3, -0.4])  # J3 nearest its limit: 0.3 m at 1.5 m/s
    trajectory = quintic(Q0, Q0 + delta, duration)
    assert not np.any(np.isclose(trajectory.times(3.0), duration / 2))
    velocity = check(trajectory, paddle, rate=3.0)["velocity"]
    assert velocity.value == pytest.approx(1.875 * 0.3 / duration, rel=1e-12)
    assert velocity.joint == "J3"
    assert velocity.time == pytest.approx(duration / 2, abs=1e-9)


def test_position_overshoot_between_samples_is_caught(paddle):
    upper = paddle.limits.upper[1]
    # J2 rises to 1e-6 rad above its limit at 0.4995 s, midway between two 1 kHz samples.
    c = np.zeros((1, 3, 4))
    c[0, 0] = Q0
    c[0, :, 1] = [upper + 1e-6 - 10 * 0.4995**2, 2 * 10 * 0.4995, -10.0]
    trajectory = Trajectory([0.0, 1.0], c)
    sampled = trajectory.sample(trajectory.times(1000.0)).q[:, 1]
    assert sampled.max() < upper  # no sample is outside
    position = check(trajectory, paddle)["position"]
    assert not position.ok
    assert position.joint == "J2"
    assert position.limit == upper
    assert position.margin == pytest.approx(-1e-6, rel=1e-6)
    assert position.time == pytest.approx(0.4995, abs=1e-9)


def via_move(sawyer: Robot, h: float, peak_ratio: float) -> Trajectory:
    """Two rest-to-rest quintics of h seconds each: joint right_j1 out and back, peaking at
    ``peak_ratio`` of its velocity limit mid-segment, at rest (zero velocity and acceleration)
    at every breakpoint; joint right_j6 creeps on at 0.001 of its limit. Samples at the
    breakpoints see right_j1 still, so only exact bounds of every segment find its peak."""
    q0 = 0.5 * (sawyer.limits.lower + sawyer.limits.upper)
    rise = peak_ratio * sawyer.limits.velocity[1] * h / 1.875
    c = np.zeros((2, 6, sawyer.dof))
    c[:, 0] = q0
    for k, (start, move) in enumerate(((0.0, rise), (rise, -rise))):
        c[k, 0, 1] += start
        c[k, 3:, 1] = move * np.array([10.0, -15.0, 6.0]) / h ** np.arange(3, 6)
        c[k, 1, 6] = 1e-3 * sawyer.limits.velocity[6]
        c[k, 0, 6] += k * h * c[k, 1, 6]
    return Trajectory([0.0, h, 2.0 * h], c, joint_names=sawyer.joint_names)


@pytest.mark.parametrize(("h", "rate"), [(1.6e-3, 250.0), (0.4e-3, 1000.0), (1.6e-3, 1.0)])
def test_every_segment_is_bounded_exactly_whatever_the_rate(sawyer, h, rate):
    # A 3.2 ms (and a 0.8 ms) two-segment via-point move whose joint right_j1 peaks at 1.077
    # of its velocity limit passed at 250 Hz (1 kHz), reporting right_j6 at 0.001.
    trajectory = via_move(sawyer, h, 1.077)
    report = check(trajectory, sawyer, rate=rate, quantities=["velocity", "acceleration"])
    velocity = report["velocity"]
    assert not velocity.ok
    assert velocity.joint == "right_j1"
    assert velocity.ratio == pytest.approx(1.077, rel=1e-9)
    assert min(abs(velocity.time - h / 2), abs(velocity.time - 1.5 * h)) < 1e-12
    rise = 1.077 * sawyer.limits.velocity[1] * h / 1.875
    acceleration = report["acceleration"]
    assert acceleration.joint == "right_j1"
    assert acceleration.value == pytest.approx(10.0 / SQRT3 * rise / h**2, rel=1e-9)


def test_many_segments_match_brute_force_sampling_at_a_coarse_rate(sawyer):
    # 400 random quintic pieces checked at 1 Hz (three samples and the breakpoints): every
    # polynomial quantity is still its exact worst, as dense sampling finds it.
    rng = np.random.default_rng(32)
    knots = np.concatenate([[0.0], np.cumsum(rng.uniform(0.002, 0.008, 400))])
    limits = sawyer.limits
    middle, half = 0.5 * (limits.lower + limits.upper), 0.5 * (limits.upper - limits.lower)
    shape = (len(knots), sawyer.dof)
    trajectory = Trajectory.from_hermite(
        knots,
        middle + 0.9 * half * rng.uniform(-1.0, 1.0, shape),
        rng.uniform(-300.0, 300.0, shape),
        rng.uniform(-1e5, 1e5, shape),
    )
    report = check(trajectory, sawyer, rate=1.0, quantities=QUANTITIES[:4])
    times = np.unique(np.concatenate([np.linspace(0.0, trajectory.duration, 400_001), knots]))
    sample = trajectory.sample(times)
    # The exact worst is at least the sampled one, and above it by no more than the samples'
    # spacing (5 us) can hide.
    score = np.maximum(limits.lower - sample.q, sample.q - limits.upper)
    assert score.max() - 1e-12 <= -report["position"].margin <= score.max() + 1e-5
    assert report["position"].joint == sawyer.joint_names[int(np.argmax(score.max(axis=0)))]
    for name, values, bound in (
        ("velocity", sample.qd, limits.velocity),
        ("acceleration", sample.qdd, limits.acceleration),
        ("jerk", sample.jerk, limits.jerk),
    ):
        ratio = np.abs(values) / bound
        finding = report[name]
        assert ratio.max() * (1 - 1e-12) <= finding.ratio <= ratio.max() * (1 + 1e-4), name
        assert finding.joint == sawyer.joint_names[int(np.argmax(ratio.max(axis=0)))], name


def test_smooth_breakpoints_are_not_jumps(paddle):
    # The quintic cut into 200 quintic Hermite pieces is the same C-infinity motion.
    whole = quintic(Q0, Q0 + DELTA, T)
    knots = np.linspace(0.0, T, 201)
    s = whole.sample(knots)
    pieces = Trajectory.from_hermite(knots, s.q, s.qd, s.qdd)
    report = check(pieces, paddle)
    assert report.ok, report.summary()
    for name in ("velocity", "acceleration", "jerk"):
        # (the Hermite coefficients carry round-off of about 1e-8 in the jerk; the ratio, as
        # joints J1 and J3 tie in velocity by design)
        assert report[name].ratio == pytest.approx(check(whole, paddle)[name].ratio, rel=1e-6)


# ------------------------------------------------------------------ limit violations


@pytest.mark.parametrize(
    ("quantity", "times"),
    [
        ("velocity", (T / 2,)),
        ("acceleration", (T * (0.5 - SQRT3 / 6), T * (0.5 + SQRT3 / 6))),
        ("jerk", (0.0, T)),
    ],
)
def test_joint_limit_violations_are_located(paddle, quantity, times):
    peak = peaks(DELTA, T)[quantity]
    bound = 2.0 * peak
    bound[1] = 0.9 * peak[1]  # only J2 breaks its limit, by 10 %
    problem = PointToPoint(paddle, Q0, Q0 + DELTA, limits=limits_of(paddle, **{quantity: bound}))
    report = check(quintic(Q0, Q0 + DELTA, T), problem)
    assert [f.name for f in report.violations] == [quantity]
    finding = report[quantity]
    assert finding.joint == "J2"
    assert finding.value == pytest.approx(peak[1], rel=1e-9)
    assert finding.limit == pytest.approx(0.9 * peak[1])
    assert finding.margin == pytest.approx(-0.1 * peak[1], rel=1e-6)
    assert finding.ratio == pytest.approx(1 / 0.9, rel=1e-9)
    assert min(abs(finding.time - t) for t in times) < 1e-9
    assert (
        finding.unit
        == {"velocity": "rad/s", "acceleration": "rad/s^2", "jerk": "rad/s^3"}[quantity]
    )
    assert not report.ok and not report.passed(quantity) and report.passed("position")


def test_torque_limit_violation_is_located(paddle):
    # Standing still at home, J1 (lifting along z) holds the arm's weight.
    weight = float(paddle.gravity_torque(paddle.home)[0])
    effort = paddle.limits.effort.copy()
    effort[0] = 0.5 * weight
    problem = PointToPoint(
        paddle, paddle.home, paddle.home, limits=limits_of(paddle, effort=effort)
    )
    report = check(Trajectory.constant(paddle.home, 1.0), problem)
    assert [f.name for f in report.violations] == ["torque"]
    torque = report["torque"]
    assert torque.joint == "J1"
    assert torque.unit == "N"
    assert torque.value == pytest.approx(weight, rel=1e-9)
    assert torque.ratio == pytest.approx(2.0, rel=1e-9)


def test_position_outside_the_range(paddle):
    q1 = Q0.copy()
    q1[1] = paddle.limits.upper[1] + 0.05
    position = check(quintic(Q0, q1, T), paddle)["position"]
    assert not position.ok
    assert position.joint == "J2"
    assert position.value == pytest.approx(q1[1])
    assert position.limit == paddle.limits.upper[1]
    assert position.margin == pytest.approx(-0.05)
    assert position.time == pytest.approx(T)
    assert "beyond its upper limit" in position.detail


# ------------------------------------------------------------------------------- jumps


def test_velocity_jump_at_a_breakpoint_makes_acceleration_unbounded(paddle):
    rest = np.stack([Q0, np.zeros(4)])
    moving = np.stack([Q0, [0.0, 0.0, 0.2, 0.0]])  # J3 starts at 0.2 m/s at t = 1 s
    report = check(two_segments(rest, moving), paddle)
    no_nan(report)
    assert [f.name for f in report.violations] == ["acceleration", "jerk", "torque"]
    acceleration = report["acceleration"]
    assert (acceleration.value, acceleration.margin, acceleration.ratio) == (
        math.inf,
        -math.inf,
        math.inf,
    )
    assert (acceleration.time, acceleration.joint) == (1.0, "J3")
    assert "velocity jumps by 0.2 m/s at t = 1 s (joint 'J3')" in acceleration.detail
    assert "unbounded acceleration" in acceleration.detail
    assert "unbounded torque" in report["torque"].detail
    assert report["velocity"].ok and report["velocity"].value == pytest.approx(0.2)
    text = report.summary()
    assert "inf" in text and "FAIL" in text and text == str(report)


def test_position_jump_makes_velocity_unbounded(paddle):
    shifted = Q0 + np.array([0.0, 0.0, 0.01, 0.0])
    report = check(two_segments(Q0[None], shifted[None]), paddle)
    no_nan(report)
    velocity = report["velocity"]
    assert velocity.value == math.inf and not velocity.ok
    assert "position jumps by 0.01 m at t = 1 s (joint 'J3')" in velocity.detail
    assert {"velocity", "acceleration", "jerk", "torque"} == {f.name for f in report.violations}


def test_acceleration_jump_makes_only_jerk_unbounded(paddle):
    accelerating = np.stack([Q0, np.zeros(4), [0.0, 0.0, 0.2, 0.0]])  # 0.4 m/s^2
    cruising = np.stack([Q0 + np.array([0, 0, 0.2, 0]), [0.0, 0.0, 0.4, 0.0], np.zeros(4)])
    report = check(two_segments(accelerating, cruising), paddle)
    assert [f.name for f in report.violations] == ["jerk"]
    assert "acceleration jumps by -0.4 m/s^2 at t = 1 s" in report["jerk"].detail
    assert report["acceleration"].value == pytest.approx(0.4)


def test_start_state_mismatch_is_a_jump_and_a_failed_start(paddle):
    qd0 = np.array([0.0, 0.0, 0.2, 0.0])  # the trajectory starts moving, the robot is at rest
    trajectory = Trajectory.from_hermite(
        [0.0, T], [Q0, Q0 + DELTA], [qd0, np.zeros(4)], [np.zeros(4), np.zeros(4)]
    )
    report = check(trajectory, PointToPoint(paddle, Q0, Q0 + DELTA))
    no_nan(report)
    start = report["start state"]
    assert not start.ok
    assert (start.joint, start.unit, start.time) == ("J3", "m/s", 0.0)
    assert start.value == pytest.approx(0.2)
    assert "qd of joint 'J3'" in start.detail
    acceleration = report["acceleration"]
    assert acceleration.value == math.inf and acceleration.time == 0.0
    assert "from the prescribed start state" in acceleration.detail
    assert report["end state"].ok
    # Against the robot alone there is no start state, hence no jump.
    assert check(trajectory, paddle)["acceleration"].ok


def test_end_state_position_gap_fails_the_end_state_only(paddle):
    goal = Q0 + DELTA
    short = goal - np.array([0.0, 0.0, 1e-3, 0.0])
    report = check(quintic(Q0, short, T), PointToPoint(paddle, Q0, goal))
    end = report["end state"]
    assert not end.ok and end.value == pytest.approx(1e-3) and end.time == T
    assert "q of joint 'J3'" in end.detail
    assert [f.name for f in report.violations] == ["end state"]


def test_end_velocity_mismatch_is_a_jump(paddle):
    qd1 = np.array([0.0, 0.3, 0.0, 0.0])  # still turning at the end, the goal is rest
    trajectory = Trajectory.from_hermite([0.0, T], [Q0, Q0 + DELTA], [np.zeros(4), qd1])
    report = check(trajectory, PointToPoint(paddle, Q0, Q0 + DELTA))
    assert report["end state"].value == pytest.approx(0.3)
    acceleration = report["acceleration"]
    assert acceleration.value == math.inf and acceleration.time == T
    assert "velocity jumps by -0.3 rad/s at t = 2 s (joint 'J2') from the prescribed end state" in (
        acceleration.detail
    )


@dataclass
class Limited:
    """A duck-typed problem with limits of its own and no constraints."""

    robot: Robot
    limits: JointLimits

    def constraints(self) -> tuple:
        return ()


def late_ramp(jerk: float, tau: float, step: float = 0.0) -> Trajectory:
    """J1 at rest until 574.297 s, then jerk +jerk and -jerk for tau each, then cruising.

    Each phase starts from the exact end state of the one before, as Ruckig reports it, so
    the two sides of a breakpoint differ only by the round-off of its time (about 1e-13 s
    there); ``step`` adds a real acceleration jump [m/s^2] to the second phase.
    """
    t1 = 574.2970347063706
    knots = np.array([0.0, t1, t1 + tau, t1 + 2.0 * tau, t1 + 3.0])
    c = np.zeros((4, 4, 4))
    c[:, 0, :] = Q0
    c[1, 3, 0] = jerk / 6.0
    c[2, :3, 0] = [Q0[0] + jerk * tau**3 / 6.0, jerk * tau**2 / 2.0, (jerk * tau + step) / 2.0]
    c[2, 3, 0] = -jerk / 6.0
    powers = tau ** np.arange(4)
    c[3, 0, 0] = c[2, :, 0] @ powers
    c[3, 1, 0] = (c[2, 1:, 0] * np.arange(1, 4)) @ powers[:3]
    return Trajectory(knots, c)


def test_round_off_at_a_late_breakpoint_is_not_a_jump(paddle):
    # At t = 574 s a breakpoint is known to 1e-13 s, over which a 1e6 m/s^3 jerk changes the
    # acceleration by 4.5e-8 m/s^2: that is no jump (it was one, failing jerk with inf).
    limits = limits_of(
        paddle, acceleration=np.array([0.4, 6.0, 8.0, 30.0]), jerk=np.array([2e6, 120, 160, 600])
    )
    problem = Limited(paddle, limits)
    report = check(late_ramp(1e6, 2e-7), problem, rate=1.0)
    assert report.ok, report.summary()
    assert report["acceleration"].value == pytest.approx(0.2, rel=1e-6)
    # A real jump of 1e-3 m/s^2 is still one.
    jumped = check(late_ramp(1e6, 2e-7, step=1e-3), problem, rate=1.0)
    assert jumped["jerk"].value == math.inf
    assert "acceleration jumps by -0.001 m/s^2 at t = 574.297 s" in jumped["jerk"].detail


@pytest.mark.parametrize("miss", [0.5, 1.0, 1.0 + 1e-7, 1.001, 1.1, 2.0])
def test_end_state_finding_and_boundary_jump_follow_one_rule(paddle, miss):
    # The end acceleration misses its prescription by ``miss`` tolerances: the end state
    # passes exactly when there is no jump (the jump rule once failed jerk with inf at an
    # end state that passed, 1 + 1e-7 tolerances off). Round-off, 1e-9 of the 8 m/s^2
    # limit, is allowed on top of the tolerance.
    tolerance = 1e-6
    trajectory = quintic(Q0, Q0 + DELTA, T)
    qdd1 = np.array([0.0, 0.0, miss * tolerance, 0.0])
    problem = PointToPoint(paddle, Q0, Q0 + DELTA, qdd_goal=qdd1, tolerance=tolerance)
    report = check(trajectory, problem, quantities=["jerk"])
    assert report["end state"].ok == report["jerk"].ok == (miss < 1.05)
    assert report["end state"].value == pytest.approx(miss * tolerance)
    if miss > 1.05:
        assert "from the prescribed end state" in report["jerk"].detail


# -------------------------------------------------------------------------- via points


def test_via_point_passed_between_samples_and_missed(paddle):
    a, c = Q0, Q0 + DELTA
    b = a + 0.3 * DELTA  # on the straight joint path, reached between two samples
    problem = Waypoints(paddle, [a, b, c], via_tolerance=1e-7)
    report = check(quintic(a, c, T), problem)
    via = report["via point 1"]
    assert via.ok, report.summary()
    assert via.value < 1e-9
    s = (via.time / T) ** 3 * (10 - 15 * via.time / T + 6 * (via.time / T) ** 2)
    assert s == pytest.approx(0.3, abs=1e-9)

    missed = b + np.array([0.0, 0.0, 0.01, 0.0])
    trajectory = quintic(a, missed, 1.0).then(quintic(missed, c, 1.0))
    report = check(trajectory, Waypoints(paddle, [a, b, c], via_tolerance=1e-3))
    via = report["via point 1"]
    times = np.linspace(0.0, 2.0, 200_001)
    brute = np.max(np.abs(trajectory.sample(times).q - b), axis=1).min()
    assert not via.ok
    assert brute - 1e-6 <= via.value <= brute + 1e-12
    assert via.value > 5e-3
    assert report.passed("start state", "end state", "velocity")


def test_a_via_point_passed_away_from_the_closest_sample_is_found(paddle):
    # J2 rests at every breakpoint (0, 0.4, 0.35, 0.6, 0.55 rad), the only samples at 0.25 Hz,
    # and passes its via point 0.2 rad mid-way through the first segment, fast. The closest
    # sample (0.35 rad, 0.15 away) was refined with a slope bound taken from the samples,
    # where J2 is still, so the pass went unseen and the via point failed.
    def at(j2: float) -> np.ndarray:
        q = Q0.copy()
        q[1] = j2
        return q

    path = [0.0, 0.4, 0.35, 0.6, 0.55]
    pieces = [quintic(at(a), at(b), 1.0) for a, b in pairwise(path)]
    trajectory = pieces[0].then(pieces[1]).then(pieces[2]).then(pieces[3])
    problem = Waypoints(paddle, [at(0.0), at(0.2), at(0.55)], via_tolerance=1e-6)
    found = check(trajectory, problem, rate=0.25)["via point 1"]
    assert found.ok and found.value < 1e-9
    assert found.time == pytest.approx(0.5, abs=1e-9)  # the quintic's middle


# -------------------------------------------------------------------------- tool paths


def bump(trajectory: Trajectory, joint: int, height: float) -> Trajectory:
    """Add height * 16 s^2 (1 - s)^2 to one joint (zero value and slope at both ends)."""
    duration = trajectory.duration
    c = trajectory.coefficients.copy()
    c[0, 2:5, joint] += height * np.array([16, -32, 16]) / duration ** np.arange(2, 5)
    return Trajectory(trajectory.breakpoints, c)


def test_tool_path_on_and_off_the_line(paddle):
    q1 = Q0 + np.array([0.3, 0.0, 0.0, 0.0])  # J1 lifts the paddle straight up
    problem = CartesianLine(paddle, paddle.tool_pose(Q0), paddle.tool_pose(q1), q_start=Q0)
    straight = quintic(Q0, q1, T)
    report = check(straight, problem)
    assert report.ok, report.summary()
    assert report["tool path position"].value < 1e-12
    assert report["tool path orientation"].value < 1e-12

    sideways = check(bump(straight, 2, 1e-3), problem)  # J3 pushes the paddle along x
    off = sideways["tool path position"]
    assert [f.name for f in sideways.violations] == ["tool path position"]
    assert off.value == pytest.approx(1e-3, rel=1e-9)
    assert off.time == pytest.approx(T / 2, abs=1e-9)
    assert "off the line" in off.detail

    twisted = check(bump(straight, 3, 0.01), problem)  # J4 turns the paddle about z
    turn = twisted["tool path orientation"]
    assert not turn.ok
    assert turn.value == pytest.approx(0.01, rel=1e-9)
    assert turn.time == pytest.approx(T / 2, abs=1e-9)


def pose_path(robot: Robot, T0: np.ndarray, T1: np.ndarray, duration: float, lag: bool):
    """Joint motion along the line T0 -> T1, by IK and Hermite cubics.

    The tool moves along the line with a quintic time scaling s(t) (not at constant speed, so
    the fraction of the way differs from the fraction of the time); its orientation follows
    SLERP at s, or at s^2 with ``lag``.
    """
    times = np.linspace(0.0, duration, 41)
    turn = pin.log3(T0[:3, :3].T @ T1[:3, :3])
    qs, qds = [], []
    q = None
    for t in times:
        x = t / duration
        s = x**3 * (10 - 15 * x + 6 * x**2)
        ds = 30 * x**2 * (1 - x) ** 2 / duration
        r, dr = (s * s, 2 * s * ds) if lag else (s, ds)
        pose = np.eye(4)
        pose[:3, :3] = T0[:3, :3] @ pin.exp3(r * turn)
        pose[:3, 3] = T0[:3, 3] + s * (T1[:3, 3] - T0[:3, 3])
        q = solve_ik(robot, pose, q_near=robot.home if q is None else q).q
        twist = np.concatenate([(T1[:3, 3] - T0[:3, 3]) * ds, T0[:3, :3] @ turn * dr])
        qs.append(q)
        qds.append(np.linalg.lstsq(robot.jacobian(q), twist, rcond=None)[0])
    return Trajectory.from_hermite(times, qs, qds)


def test_tool_path_orientation_follows_slerp_by_position(sawyer):
    T0 = sawyer.tool_pose(sawyer.home)
    T1 = T0.copy()
    T1[:3, 3] += [0.1, 0.05, 0.0]
    T1[:3, :3] = pin.exp3(np.array([0.0, 0.0, np.radians(20.0)])) @ T0[:3, :3]
    problem = CartesianLine(sawyer, T0, T1, q_start=sawyer.home)
    report = check(pose_path(sawyer, T0, T1, 1.0, lag=False), problem)
    assert report.passed("tool path position", "tool path orientation"), report.summary()

    lagging = check(pose_path(sawyer, T0, T1, 1.0, lag=True), problem)
    turn = lagging["tool path orientation"]
    assert lagging["tool path position"].ok
    assert not turn.ok
    # The orientation lags the SLERP by (s - s^2) x 20 deg, most (5 deg) at s = 1/2.
    assert turn.value == pytest.approx(np.radians(5.0), rel=1e-2)
    assert turn.time == pytest.approx(0.5, abs=0.02)


# ------------------------------------------------------------------------------ strikes


@pytest.fixture(scope="module")
def pool_shot() -> problems.PoolStrike:
    return problems.sawyer_pool_shot()


def strike_motion(problem: problems.PoolStrike, factor: float = 1.0, step: float = 0.005):
    """The cue tip on the strike line at factor x the commanded speed, by IK and Hermite."""
    robot = problem.robot
    line = next(c for c in problem.constraints() if isinstance(c, StrikeLine))
    rotation = robot.tool_pose(problem.q_contact)[:3, :3]  # z along the shot, roll fixed
    times = np.arange(0.0, line.window + step / 2, step)
    qs, qds = [], []
    q = problem.q_contact
    for t in times:
        pose = np.eye(4)
        pose[:3, :3] = rotation
        pose[:3, 3] = line.point + factor * line.speed * (t - line.contact_delay) * line.direction
        q = solve_ik(robot, pose, q_near=q).q
        twist = np.concatenate([factor * line.speed * line.direction, np.zeros(3)])
        qs.append(q)
        qds.append(np.linalg.lstsq(robot.jacobian(q), twist, rcond=None)[0])
    return Trajectory.from_hermite(times, qs, qds, phases=[Phase("strike", 0.0, times[-1])])


STRIKE = ("strike window", "strike position", "strike speed", "strike axis", "contact")


def test_pool_strike_on_schedule_and_one_percent_fast(pool_shot):
    report = check(strike_motion(pool_shot), pool_shot)
    assert report.passed(*STRIKE), report.summary()
    assert report["contact"].time == pytest.approx(pool_shot.contact_delay)
    # This piece is only the strike: it does not start at rest at q_start.
    assert not report["start state"].ok

    fast = check(strike_motion(pool_shot, 1.01), pool_shot)
    speed = fast["strike speed"]
    assert not speed.ok and speed.unit == "-"
    assert speed.value == pytest.approx(0.01, rel=1e-2)
    schedule = fast["strike position"]
    assert not schedule.ok
    # 1 % of the 0.1 m run-up: 1 mm behind the schedule when the window opens.
    assert schedule.value == pytest.approx(1e-3, rel=1e-2)
    assert schedule.time == pytest.approx(0.0, abs=1e-9)
    assert fast.passed("contact", "strike axis", "strike window")


def test_strike_without_its_phase_fails_every_strike_finding(pool_shot):
    moving = strike_motion(pool_shot)
    bare = Trajectory(moving.breakpoints, moving.coefficients)
    report = check(bare, pool_shot)
    no_nan(report)
    for name in STRIKE:
        assert report[name].value == math.inf and not report[name].ok
        assert report[name].detail == "phase 'strike' missing"


def paddle_push(paddle: Robot, speed: float, contact: float, window: float) -> Task:
    """A strike along the paddle normal (+x at home): exactly what joint J3 does."""
    line = StrikeLine(
        phase="strike",
        point=paddle.tool_position(Q0),
        direction=np.array([1.0, 0.0, 0.0]),
        speed=speed,
        contact_delay=contact,
        window=window,
    )
    return Task(paddle, (line,))


def test_paddle_strike_line_is_exact_and_its_errors_are_measured(paddle):
    # J3 runs at 0.5 m/s through Q0 at t = 0.1 s; the strike window is [0, 0.3] s.
    c = np.zeros((1, 2, 4))
    c[0, 0] = Q0 - np.array([0.0, 0.0, 0.05, 0.0])
    c[0, 1, 2] = 0.5
    trajectory = Trajectory([0.0, 0.3], c, phases=[Phase("strike", 0.0, 0.3)])
    report = check(trajectory, paddle_push(paddle, 0.5, 0.1, 0.3))
    assert report.ok, report.summary()
    assert all(report[name].value < 1e-12 for name in STRIKE)

    late = check(trajectory, paddle_push(paddle, 0.5, 0.102, 0.3))  # contact 2 ms later
    assert late["contact"].value == pytest.approx(1e-3, rel=1e-9)
    assert late["contact"].time == pytest.approx(0.102)
    assert late["strike position"].value == pytest.approx(1e-3, rel=1e-9)
    assert late.passed("strike speed", "strike axis", "strike window")

    slow = check(trajectory, paddle_push(paddle, 0.5 / 1.01, 0.1, 0.3))
    assert slow["strike speed"].value == pytest.approx(0.01, rel=1e-9)
    drifting = c.copy()
    drifting[0, 1, 0] = 0.005  # J1 lifts the paddle at 1 % of the strike speed
    lifted = Trajectory([0.0, 0.3], drifting, phases=[Phase("strike", 0.0, 0.3)])
    across = check(lifted, paddle_push(paddle, 0.5, 0.1, 0.3))["strike speed"]
    assert across.value == pytest.approx(0.01, rel=1e-9)
    assert "across the line" in across.detail
    assert check(trajectory, paddle_push(paddle, 0.5, 0.1, 0.2))["strike window"].value == (
        pytest.approx(0.1)
    )


# ------------------------------------------------------------------------------ contacts


def test_paddle_contact_hit_and_missed_by_one_millimetre(paddle):
    problem = PaddleStrike(paddle, ball=(1.0, 0.3, 0.4), contact_angle=0.3)
    hit = check(quintic(problem.q_start, problem.q_contact, problem.contact_time), problem)
    assert hit.ok, hit.summary()
    contact = ("ball contact", "ball contact axis", "ball contact velocity")
    assert hit.names[-4:] == (*contact, "end state")
    assert hit["ball contact"].value < 1e-9
    assert hit["ball contact"].time == problem.contact_time

    high = problem.q_contact + np.array([1e-3, 0.0, 0.0, 0.0])  # J1 one millimetre up
    missed = check(quintic(problem.q_start, high, problem.contact_time), problem)
    assert {f.name for f in missed.violations} == {"ball contact", "end state"}
    assert missed["ball contact"].value == pytest.approx(1e-3, rel=1e-9)
    assert missed["ball contact axis"].ok


def test_contact_speed_and_missing_phase(paddle):
    problem = PaddleStrike(paddle, ball=(1.0, 0.3, 0.4), speed=0.5)
    report = check(quintic(problem.q_start, problem.q_contact, problem.contact_time), problem)
    velocity = report["ball contact velocity"]
    assert not velocity.ok  # arrives at rest instead of 0.5 m/s along the normal
    assert velocity.value == pytest.approx(0.5, rel=1e-9)
    assert velocity.unit == "m/s"

    grasp = ToolContact(position=np.zeros(3), phase="grasp_0", at="start", label="grasp 0")
    task = Task(paddle, (grasp,))
    report = check(quintic(Q0, Q0 + DELTA, T), task)
    assert report["grasp 0"].value == math.inf
    assert report["grasp 0"].detail == "phase 'grasp_0' missing"
    point = paddle.tool_position(Q0 + DELTA)
    task = Task(paddle, (ToolContact(position=point, phase="move", at="end", label="drop"),))
    moving = quintic(Q0, Q0 + DELTA, T, phases=[Phase("move", 0.0, T)])
    assert check(moving, task)["drop"].value < 1e-12


# --------------------------------------------------------------------- randomised check


def test_random_polynomials_match_brute_force_sampling(paddle):
    rng = np.random.default_rng(20240611)
    for _ in range(6):
        segments = int(rng.integers(1, 5))
        knots = np.concatenate([[0.0], np.cumsum(rng.uniform(0.2, 0.8, segments))])
        shape = (segments + 1, 4)
        trajectory = Trajectory.from_hermite(
            knots,
            rng.uniform(-1.0, 1.0, shape),
            rng.uniform(-2.0, 2.0, shape),
            rng.uniform(-10.0, 10.0, shape),
        )
        report = check(trajectory, paddle, quantities=["velocity", "acceleration"])
        assert report.names == ("velocity", "acceleration")
        times = np.linspace(0.0, trajectory.duration, int(trajectory.duration * 1e5) + 1)
        sample = trajectory.sample(times)
        for name, values, bound in (
            ("velocity", sample.qd, paddle.limits.velocity),
            ("acceleration", sample.qdd, paddle.limits.acceleration),
        ):
            ratio = np.abs(values) / bound
            i, j = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
            finding = report[name]
            assert finding.value == pytest.approx(abs(values[i, j]), rel=1e-3)
            assert finding.joint == paddle.joint_names[j]
            assert ratio.max() - 1e-12 <= finding.ratio <= ratio.max() * (1 + 1e-3)


# ----------------------------------------------------------------------- API and errors


def test_bad_input_raises_typed_errors(paddle, sawyer):
    trajectory = quintic(Q0, Q0 + DELTA, T)
    with pytest.raises(InvalidInputError, match=r"planners\.Trajectory"):
        check("not a trajectory", paddle)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match=r"robots\.Robot or a problem"):
        check(trajectory, object())
    with pytest.raises(InvalidInputError, match="4 joints"):
        check(trajectory, sawyer)
    with pytest.raises(UnknownNameError, match="velocity") as info:
        check(trajectory, paddle, quantities=["speed"])
    assert info.value.known == QUANTITIES
    with pytest.raises(InvalidInputError, match="rate"):
        check(trajectory, paddle, rate=0.0)
    bad = Task(paddle, (BoundaryState("start", np.zeros(3), np.zeros(4)),))
    with pytest.raises(InvalidInputError, match="length 4"):
        check(trajectory, bad)
    with pytest.raises(InvalidInputError, match="cannot check"):
        check(trajectory, Task(paddle, ("not a constraint",)))


@pytest.mark.parametrize(
    ("rate", "match"),
    [
        (True, "rate"),
        ("1000", "rate"),
        (-1.0, "rate must be > 0 Hz"),
        (1e9, r"rate must be <= 1e\+06 Hz"),
        (math.nan, "finite"),
    ],
)
def test_a_bad_rate_raises_a_typed_error(paddle, rate, match):
    # rate=True sampled at 1 Hz; rate=1e9 allocated gigabytes.
    with pytest.raises(InvalidInputError, match=match):
        check(quintic(Q0, Q0 + DELTA, T), paddle, rate=rate)


def test_a_rate_beyond_the_sample_budget_names_a_rate_that_fits(paddle):
    day = quintic(Q0, Q0 + DELTA, 86_400.0)
    with pytest.raises(InvalidInputError, match=r"rate 1000 Hz .* rate <= \d") as info:
        check(day, paddle)
    assert info.value.name == "rate"
    assert check(day, paddle, rate=10.0).trajectory.samples == 864_001


def test_malformed_constraint_fields_raise_typed_errors(paddle):
    trajectory = quintic(Q0, Q0 + DELTA, T, phases=[Phase("strike", 1.5, 2.0)])
    line = StrikeLine("strike", np.zeros(3), np.array([1.0, 0.0, 0.0]), 1.0, 0.2, 0.5)
    for field, value, match in (
        ("speed", "fast", "StrikeLine.speed"),
        ("speed", 0.0, "StrikeLine.speed must be > 0 m/s"),
        ("contact_delay", None, "StrikeLine.contact_delay"),
        ("position_tolerance", -1.0, "StrikeLine.position_tolerance must be >= 0 m"),
        ("align_axis", 1, "StrikeLine.align_axis must be True or False"),
    ):
        bad = dataclasses.replace(line, **{field: value})
        with pytest.raises(InvalidInputError, match=match):
            check(trajectory, Task(paddle, (bad,)))
    state = BoundaryState("end", None, np.zeros(4), None, tolerance="1e-6")
    with pytest.raises(InvalidInputError, match=r"BoundaryState\.tolerance"):
        check(trajectory, Task(paddle, (state,)))
    with pytest.raises(InvalidInputError, match="quantities"):
        check(trajectory, paddle, quantities=5)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="must be a number"):
        Finding("x", "task", "1", 1.0, 0.0, 0.0, None, None, "m", "", True)  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="ok must be True or False"):
        Finding("x", "task", 1.0, 1.0, 0.0, 0.0, None, None, "m", "", "no")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError, match="iterable of constraints"):
        check(trajectory, Task(paddle, 5))  # type: ignore[arg-type]


def test_report_api(paddle):
    q1 = Q0.copy()
    q1[1] = paddle.limits.upper[1] + 0.05
    trajectory = quintic(Q0, q1, T, metadata={"planner": "by hand", "status": "ok"})
    report = check(trajectory, paddle, quantities="position")
    assert report.names == ("position",)
    assert report.trajectory.planner == "by hand"
    assert report.trajectory.duration == T
    assert report.trajectory.robot == "paddle4"
    assert not report.ok and report.violations == (report["position"],)
    with pytest.raises(UnknownNameError, match="position"):
        report["velocity"]
    with pytest.raises(UnknownNameError):
        report.passed("nothing")
    assert not report.passed()
    text = report.summary()
    assert "'by hand'" in text and "FAIL: 1 of 1" in text and "J2" in text
    with pytest.raises(dataclasses.FrozenInstanceError):
        report.findings[0].value = 0.0  # type: ignore[misc]
    with pytest.raises(InvalidInputError, match="NaN"):
        Finding("x", "task", math.nan, 1.0, 0.0, 0.0, None, None, "m", "", True)
    good = check(quintic(Q0, Q0 + DELTA, T), paddle)
    assert good.ok and good.passed() and "PASS: all 5 findings pass" in str(good)


def test_metadata_claims_are_ignored(paddle):
    fast = quintic(Q0, Q0 + DELTA, 0.2, metadata={"status": "ok", "feasible": True})
    assert not check(fast, paddle)["velocity"].ok  # 1.875 x 0.5 / 0.2 = 4.7 rad/s > 3


def test_three_second_sawyer_check_is_fast(sawyer, pool_shot):
    trajectory = quintic(
        np.asarray(sawyer.home),
        pool_shot.q_contact,
        3.0,
        phases=[Phase("strike", 3.0 - pool_shot.window, 3.0)],
    )
    elapsed = []
    for _ in range(3):
        started = time.perf_counter()
        report = check(trajectory, pool_shot)
        elapsed.append(time.perf_counter() - started)
    assert report.trajectory.samples >= 3001
    assert min(elapsed) < 0.5, elapsed


def test_a_tool_speed_cap_is_verified_over_the_trajectory_and_a_tool_path():
    # The checker could not verify the cap that Toppra(tool_speed=...) and CartesianLine(speed=)
    # promise.
    from optraj.planners import CartesianStraightLine, Toppra

    robot = get_robot("sawyer")
    move = problems.PointToPoint(robot, q_start=robot.home, q_goal=robot.home + 0.4)
    capped = check(Toppra(tool_speed=0.3).plan(move), move, tool_speed=0.3)["tool speed"]
    assert capped.ok and 0.29 < capped.value <= 0.3 + 1e-6 and capped.unit == "m/s"
    free = check(Toppra().plan(move), move, tool_speed=0.3)["tool speed"]
    assert not free.ok and free.value > 1.0
    start = robot.tool_pose(robot.home)
    goal = start.copy()
    goal[:3, 3] += [0.1, 0.0, 0.0]
    line = problems.CartesianLine(robot, start, goal, speed=0.05)
    report = check(CartesianStraightLine().plan(line), line)
    assert report["tool speed"].ok and report["tool speed"].value <= 0.05 + 1e-6
    fast = problems.CartesianLine(robot, start, goal, speed=0.01)
    assert not check(CartesianStraightLine().plan(line), fast)["tool speed"].ok
    with pytest.raises(InvalidInputError, match="tool_speed must be > 0 m/s"):
        check(Toppra().plan(move), move, tool_speed=-1.0)
