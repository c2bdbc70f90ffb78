"""Tests of planners.profiles.via_points: multi-segment LSPB and quintics through via points."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InfeasibleError, InvalidInputError, UnknownNameError
from optraj.planners.profiles.via_points import PROFILES, ViaPoints

QUANTITIES = ("position", "velocity", "acceleration")


def _limits(robot, velocity, acceleration):
    return dataclasses.replace(robot.limits, velocity=velocity, acceleration=acceleration)


def _random_problem(rng, robot, **kwargs):
    """Random limits and 2..8 waypoints, some repeated, some joints not moving at all."""
    n = robot.dof
    limits = _limits(robot, rng.uniform(0.3, 5.0, n), rng.uniform(1.0, 40.0, n))
    k = int(rng.integers(2, 9))
    points = limits.sample(rng, k)
    if rng.random() < 0.2:
        points[rng.integers(1, k)] = points[rng.integers(0, k)]
    if rng.random() < 0.3:
        j = rng.integers(0, n)
        points[:, j] = points[0, j]
    if not np.any(points != points[0]):
        points[-1] = limits.sample(rng, 1)[0]
    return problems.Waypoints(robot, points, limits=limits, **kwargs)


def _sides(traj, order_max):
    """Derivatives 0..order_max just left and right of every inner breakpoint, exactly."""
    knots = traj.breakpoints
    lengths = np.diff(knots)[:-1]
    out = []
    c = traj.coefficients
    for _ in range(order_max + 1):
        powers = lengths[:, None] ** np.arange(c.shape[1])[None, :]
        out.append((np.einsum("kd,kdn->kn", powers, c[:-1]), c[1:, 0]))
        c = c[:, 1:] * np.arange(1, c.shape[1])[None, :, None]
    return out


def _at_rest_on_the_ends(traj, points):
    first, last = traj.sample(0.0), traj.sample(traj.duration)
    np.testing.assert_array_equal(first.q, points[0])
    np.testing.assert_allclose(last.q, points[-1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(first.qd, 0.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(last.qd, 0.0, rtol=0, atol=1e-12)


def _within_limits(traj, limits, rate):
    sample = traj.sample(traj.times(rate))
    assert np.all(np.abs(sample.qd) <= limits.velocity * (1 + 1e-9))
    assert np.all(np.abs(sample.qdd) <= limits.acceleration * (1 + 1e-9))
    assert np.all(limits.contains(sample.q, tolerance=1e-12))


# --------------------------------------------------------------------------- LSPB


def test_lspb_random_problems_respect_limits_and_cut_corners_by_the_blend_bound():
    rng = np.random.default_rng(2024)
    robots_ = [get_robot("sawyer"), get_robot("paddle4")]
    for trial in range(200):
        robot = robots_[trial % 2]
        blend_time = rng.uniform(0.05, 0.4) if trial % 4 == 3 else None
        problem = _random_problem(rng, robot)
        traj = ViaPoints("lspb", blend_time=blend_time).plan(problem)
        points, limits = problem.waypoints, problem.limits
        assert traj.degree == 2
        _at_rest_on_the_ends(traj, points)
        (q_l, q_r), (qd_l, qd_r), (qdd_l, _) = _sides(traj, 2)
        np.testing.assert_allclose(q_l, q_r, rtol=0, atol=1e-12)
        np.testing.assert_allclose(qd_l, qd_r, rtol=0, atol=1e-9 * np.max(limits.velocity))
        # Piecewise quadratic: the breakpoints' two sides hold every extremum.
        assert np.all(np.abs(qd_l) <= limits.velocity * (1 + 1e-9))
        assert np.all(np.abs(qdd_l) <= limits.acceleration * (1 + 1e-9))
        _within_limits(traj, limits, 20_000.0 if trial % 20 == 0 else 500.0 / traj.duration)
        report = planners.check(traj, problem, rate=200.0, quantities=QUANTITIES)
        assert report.ok, report
        loose = problems.Waypoints(robot, points, via_tolerance=1e3, limits=limits)
        measured = planners.check(traj, loose, rate=200.0, quantities=())
        # Phases: one per segment, between the via times.
        times = traj.metadata["via_times"]
        assert [p.name for p in traj.phases] == [f"segment {i + 1}" for i in range(len(points) - 1)]
        np.testing.assert_allclose([p.t_start for p in traj.phases], times[:-1], atol=1e-12)
        assert traj.duration == pytest.approx(times[-1], rel=1e-12)
        if blend_time is not None:
            np.testing.assert_array_equal(traj.metadata["blend_times"], blend_time)
        # At an inner via time the blend passes the via point at (v_out - v_in) tb / 8, with
        # v_in and v_out measured on the trajectory just outside the blend.
        blends = traj.metadata["blend_times"]
        for c in range(1, len(points) - 1):
            tb = blends[c]
            v_in = traj.sample(times[c] - 0.5 * tb - 1e-9).qd
            v_out = traj.sample(times[c] + 0.5 * tb + 1e-9).qd
            cut = traj.sample(times[c]).q - points[c]
            bound = (v_out - v_in) * tb / 8.0
            np.testing.assert_allclose(cut, bound, rtol=0, atol=1e-6 * (1 + tb))
            np.testing.assert_allclose(traj.metadata["via_deviation"][c - 1], cut, atol=1e-12)
            # The checker's closest approach (exact, largest joint distance) is no farther.
            closest = measured[f"via point {c}"].value
            assert closest <= np.max(np.abs(bound)) * (1 + 1e-9) + 1e-12


def test_lspb_given_segment_durations_are_honoured():
    rng = np.random.default_rng(7)
    robot = get_robot("sawyer")
    for _ in range(20):
        problem = _random_problem(rng, robot)
        fast = ViaPoints("lspb").plan(problem)
        durations = fast.metadata["segment_durations"] * rng.uniform(1.0, 2.0)
        given = problems.Waypoints(
            robot, problem.waypoints, segment_durations=durations, limits=problem.limits
        )
        traj = ViaPoints("lspb").plan(given)
        assert traj.metadata["durations_from"] == "problem"
        np.testing.assert_allclose([p.duration for p in traj.phases], durations, rtol=1e-12)
        assert traj.duration == pytest.approx(np.sum(durations), rel=1e-12)
        _at_rest_on_the_ends(traj, problem.waypoints)
        assert planners.check(traj, given, rate=200.0, quantities=QUANTITIES).ok


def test_lspb_via_tolerance_is_met_by_slowing_down():
    robot = get_robot("paddle4")
    points = [[0.1, 0, 0.1, 0], [0.5, 1, 0.5, 0.5], [0.9, -1, 0.2, 0], [0.3, 0.5, 0.6, 0.2]]
    loose = ViaPoints("lspb").plan(problems.Waypoints(robot, points))
    assert loose.metadata["max_via_deviation"] > 0.01
    problem = problems.Waypoints(robot, points, via_tolerance=0.01)
    traj = ViaPoints("lspb").plan(problem)
    assert traj.metadata["max_via_deviation"] <= 0.01 * (1 + 1e-9)
    assert traj.duration > loose.duration
    report = planners.check(traj, problem, quantities=QUANTITIES)
    assert report.ok, report
    assert {"via point 1", "via point 2"} <= set(report.names)
    # Given durations cannot slow down: the cut is reported against the tolerance.
    fixed = problems.Waypoints(robot, points, segment_durations=[2, 2, 2], via_tolerance=0.01)
    with pytest.raises(InfeasibleError, match=r"via point 2 .*passes joint 'J2' .*0.01 rad"):
        ViaPoints("lspb").plan(fixed)
    # A zero tolerance cannot be met by cutting corners at all.
    exact = problems.Waypoints(robot, points, via_tolerance=0.0)
    with pytest.raises(InfeasibleError, match="profile 'quintic' passes every via point"):
        ViaPoints("lspb").plan(exact)
    assert planners.check(ViaPoints("quintic").plan(exact), exact, quantities=QUANTITIES).ok


def test_lspb_two_waypoints_is_one_synchronised_move():
    robot = get_robot("paddle4")
    problem = problems.Waypoints(robot, [[0.2, 0.0, 0.1, 0.0], [0.8, 1.0, 0.9, -0.5]])
    traj = ViaPoints("lspb").plan(problem)
    assert [p.name for p in traj.phases] == ["segment 1"]
    _at_rest_on_the_ends(traj, problem.waypoints)
    assert planners.check(traj, problem, quantities=QUANTITIES).ok
    blends = traj.metadata["blend_times"]
    assert blends[0] == blends[1] > 0.0


# ------------------------------------------------------------------------- quintic


def test_quintic_passes_every_via_point_and_is_c2():
    rng = np.random.default_rng(99)
    robots_ = [get_robot("sawyer"), get_robot("paddle4")]
    for trial in range(60):
        problem = _random_problem(rng, robots_[trial % 2])
        traj = ViaPoints("quintic").plan(problem)
        points, limits = problem.waypoints, problem.limits
        assert traj.degree == 5
        _at_rest_on_the_ends(traj, points)
        times = traj.metadata["via_times"]
        np.testing.assert_allclose(traj.sample(times).q, points, rtol=0, atol=1e-9)
        # C2: position, velocity and acceleration agree on both sides of every breakpoint.
        for order, (left, right) in enumerate(_sides(traj, 2)):
            scale = (1.0, np.max(limits.velocity), np.max(limits.acceleration))[order]
            np.testing.assert_allclose(left, right, rtol=0, atol=1e-9 * scale)
        np.testing.assert_allclose(traj.sample(traj.duration).qdd, 0.0, atol=1e-9)
        # Monotone segments: each joint stays between the waypoints it moves between.
        for i, phase in enumerate(traj.phases):
            q = traj.sample(np.linspace(phase.t_start, phase.t_end, 200)).q
            low = np.minimum(points[i], points[i + 1])
            high = np.maximum(points[i], points[i + 1])
            assert np.all((q >= low - 1e-12) & (q <= high + 1e-12))
        _within_limits(traj, limits, 20_000.0 if trial % 20 == 0 else 500.0 / traj.duration)
        report = planners.check(traj, problem, rate=200.0, quantities=QUANTITIES)
        assert report.ok, report


def test_quintic_uses_craigs_via_velocities():
    robot = get_robot("paddle4")
    points = np.array(
        [[0.1, 0.0, 0.1, 0.0], [0.3, 1.0, 0.2, 0.5], [0.5, -1.0, 0.6, 0.5], [0.6, -0.5, 0.7, 0.2]]
    )
    problem = problems.Waypoints(robot, points, segment_durations=[2.0, 2.0, 2.0])
    traj = ViaPoints("quintic").plan(problem)
    slopes = np.diff(points, axis=0) / 2.0
    qd = traj.sample(traj.metadata["via_times"]).qd
    np.testing.assert_allclose(qd[0], 0.0, atol=1e-12)
    np.testing.assert_allclose(qd[-1], 0.0, atol=1e-12)
    # J1 keeps its direction: mean of the slopes; J2 turns back at both inner points: 0;
    # J4 stops at point 1 (slope 0 after it): 0.
    np.testing.assert_allclose(qd[1:3, 0], 0.5 * (slopes[:-1, 0] + slopes[1:, 0]), atol=1e-12)
    np.testing.assert_allclose(qd[1:3, 1], 0.0, atol=1e-12)
    assert qd[1, 3] == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(traj.sample(traj.metadata["via_times"]).qdd, 0.0, atol=1e-9)
    np.testing.assert_allclose([p.duration for p in traj.phases], 2.0, rtol=1e-12)
    # Slopes 0.05 then 0.35 m/s: the mean 0.2 is capped at 15/7 x 0.05 to stay monotone.
    points[:, 2] = [0.1, 0.2, 0.9, 0.95]
    problem = problems.Waypoints(robot, points, segment_durations=[2.0, 2.0, 2.0])
    traj = ViaPoints("quintic").plan(problem)
    assert traj.sample(2.0).qd[2] == pytest.approx(15.0 / 7.0 * 0.05, rel=1e-12)
    assert planners.check(traj, problem, quantities=QUANTITIES).ok


def test_quintic_given_durations_are_honoured_and_checked():
    robot = get_robot("paddle4")
    points = [[0.1, 0, 0.1, 0], [0.5, 1, 0.5, 0.5], [0.9, -1, 0.2, 0], [0.3, 0.5, 0.6, 0.2]]
    problem = problems.Waypoints(robot, points, segment_durations=[2.0, 2.5, 2.0])
    traj = ViaPoints("quintic").plan(problem)
    np.testing.assert_allclose([p.duration for p in traj.phases], [2.0, 2.5, 2.0], rtol=1e-12)
    assert traj.metadata["durations_from"] == "problem"
    assert planners.check(traj, problem, quantities=QUANTITIES).ok


# -------------------------------------------------------------------------- errors


@pytest.mark.parametrize("profile", PROFILES)
def test_too_short_segment_durations_name_joint_segment_and_limit(profile):
    robot = get_robot("paddle4")
    points = [[0.1, 0, 0.1, 0], [0.5, 1, 0.5, 0.5], [0.9, -1, 0.2, 0], [0.3, 0.5, 0.6, 0.2]]
    problem = problems.Waypoints(robot, points, segment_durations=[0.5, 0.5, 0.5])
    with pytest.raises(InfeasibleError, match=r"(segment|via point) \d.*joint 'J\d'") as info:
        ViaPoints(profile).plan(problem)
    error = info.value
    assert error.joint in robot.joint_names
    assert error.required > error.allowed
    assert f"{error.allowed:.6g}" in str(error) and f"{error.required:.6g}" in str(error)


def test_fixed_blend_time_too_long_for_a_segment():
    robot = get_robot("paddle4")
    points = [[0.1, 0, 0.1, 0], [0.5, 1, 0.5, 0.5], [0.9, -1, 0.2, 0]]
    problem = problems.Waypoints(robot, points, segment_durations=[2.0, 2.0])
    with pytest.raises(InfeasibleError, match=r"segment 1 lasts 2 s, but its blends need 2.25 s"):
        ViaPoints("lspb", blend_time=1.5).plan(problem)
    # From the limits, the segments are stretched to hold the blends instead.
    traj = ViaPoints("lspb", blend_time=1.5).plan(problems.Waypoints(robot, points))
    assert np.all(traj.metadata["segment_durations"] >= 2.25 - 1e-12)


def test_unknown_profile_lists_the_valid_ones():
    with pytest.raises(UnknownNameError, match="known: lspb, quintic") as info:
        ViaPoints("cubic")
    assert info.value.known == PROFILES


def test_bad_arguments_and_problems():
    robot = get_robot("paddle4")
    with pytest.raises(InvalidInputError, match=r"plans a problems\.Waypoints, got PointToPoint"):
        ViaPoints().plan(problems.PointToPoint(robot, [0.1, 0, 0, 0], [0.2, 0, 0, 0]))
    with pytest.raises(InvalidInputError, match="blend_time applies to profile 'lspb' only"):
        ViaPoints("quintic", blend_time=0.2)
    with pytest.raises(InvalidInputError, match="blend_time must be >= 1e-06 s, got 0 s"):
        ViaPoints("lspb", blend_time=0.0)
    same = [[0.1, 0, 0, 0]] * 3
    for profile in PROFILES:
        with pytest.raises(InvalidInputError, match="give segment_durations to hold still"):
            ViaPoints(profile).plan(problems.Waypoints(robot, same))
        held = ViaPoints(profile).plan(problems.Waypoints(robot, same, segment_durations=[1, 2]))
        assert held.duration == pytest.approx(3.0)
        sample = held.sample(held.times(100))
        np.testing.assert_allclose(sample.q, np.broadcast_to(same[0], sample.q.shape), atol=1e-15)


def test_blend_time_is_a_duration():
    # issue 32, defect 6: float("0.2") took text for a number
    with pytest.raises(InvalidInputError, match="blend_time must be a numeric"):
        ViaPoints("lspb", blend_time="0.2")
    with pytest.raises(InvalidInputError, match="blend_time must be <= 86400 s"):
        ViaPoints("lspb", blend_time=1e200)


def test_waypoints_within_the_still_tolerance_are_refused_without_durations():
    # issue 32, defect 8: one rule with PointToPoint (exact equality was refused, 1e-13 not)
    robot = get_robot("paddle4")
    same = [[0.1, 0, 0, 0], [0.1 + 1e-13, 0, 0, 0], [0.1, 0, 0, 0]]
    for profile in PROFILES:
        with pytest.raises(InvalidInputError, match="every waypoint equals the first"):
            ViaPoints(profile).plan(problems.Waypoints(robot, same))
