"""Tests of planners.profiles.via_lspb: multi-segment LSPB through via points."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InfeasibleError
from optraj.planners.profiles.via_lspb import LSPB_HINT, lspb_fit, lspb_layout, plan_lspb
from optraj.planners.profiles.via_points import ViaPoints

QUANTITIES = ("position", "velocity", "acceleration")


@pytest.mark.slow
def test_lspb_random_problems_respect_limits_and_cut_corners_by_the_blend_bound(via):
    rng = np.random.default_rng(2024)
    robots_ = [get_robot("sawyer"), get_robot("paddle4")]
    for trial in range(200):
        robot = robots_[trial % 2]
        blend_time = rng.uniform(0.05, 0.4) if trial % 4 == 3 else None
        problem = via.random_waypoints(rng, robot)
        traj = ViaPoints("lspb", blend_time=blend_time).plan(problem)
        points, limits = problem.waypoints, problem.limits
        assert traj.degree == 2
        via.at_rest_on_the_ends(traj, points)
        (q_l, q_r), (qd_l, qd_r), (qdd_l, _) = via.sides(traj, 2)
        np.testing.assert_allclose(q_l, q_r, rtol=0, atol=1e-12)
        np.testing.assert_allclose(qd_l, qd_r, rtol=0, atol=1e-9 * np.max(limits.velocity))
        # Piecewise quadratic: the breakpoints' two sides hold every extremum.
        assert np.all(np.abs(qd_l) <= limits.velocity * (1 + 1e-9))
        assert np.all(np.abs(qdd_l) <= limits.acceleration * (1 + 1e-9))
        via.within_limits(traj, limits, 20_000.0 if trial % 20 == 0 else 500.0 / traj.duration)
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


def test_lspb_given_segment_durations_are_honoured(via):
    rng = np.random.default_rng(7)
    robot = get_robot("sawyer")
    for _ in range(20):
        problem = via.random_waypoints(rng, robot)
        fast = ViaPoints("lspb").plan(problem)
        durations = fast.metadata["segment_durations"] * rng.uniform(1.0, 2.0)
        given = problems.Waypoints(
            robot, problem.waypoints, segment_durations=durations, limits=problem.limits
        )
        traj = ViaPoints("lspb").plan(given)
        assert traj.metadata["durations_from"] == "problem"
        np.testing.assert_allclose([p.duration for p in traj.phases], durations, rtol=1e-12)
        assert traj.duration == pytest.approx(np.sum(durations), rel=1e-12)
        via.at_rest_on_the_ends(traj, problem.waypoints)
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


def test_lspb_two_waypoints_is_one_synchronised_move(via):
    robot = get_robot("paddle4")
    problem = problems.Waypoints(robot, [[0.2, 0.0, 0.1, 0.0], [0.8, 1.0, 0.9, -0.5]])
    traj = ViaPoints("lspb").plan(problem)
    assert [p.name for p in traj.phases] == ["segment 1"]
    via.at_rest_on_the_ends(traj, problem.waypoints)
    assert planners.check(traj, problem, quantities=QUANTITIES).ok
    blends = traj.metadata["blend_times"]
    assert blends[0] == blends[1] > 0.0


def test_fixed_blend_time_too_long_for_a_segment():
    robot = get_robot("paddle4")
    points = [[0.1, 0, 0.1, 0], [0.5, 1, 0.5, 0.5], [0.9, -1, 0.2, 0]]
    problem = problems.Waypoints(robot, points, segment_durations=[2.0, 2.0])
    with pytest.raises(InfeasibleError, match=r"segment 1 lasts 2 s, but its blends need 2.25 s"):
        ViaPoints("lspb", blend_time=1.5).plan(problem)
    # From the limits, the segments are stretched to hold the blends instead.
    traj = ViaPoints("lspb", blend_time=1.5).plan(problems.Waypoints(robot, points))
    assert np.all(traj.metadata["segment_durations"] >= 2.25 - 1e-12)


# -------------------------------------------------------------- layout and fit


def _paddle_points():
    robot = get_robot("paddle4")
    points = np.array(
        [[0.1, 0, 0.1, 0], [0.5, 1, 0.5, 0.5], [0.9, -1, 0.2, 0], [0.3, 0.5, 0.6, 0.2]]
    )
    return robot.limits, points


def test_layout_blends_cut_each_corner_by_the_velocity_change():
    limits, points = _paddle_points()
    layout = lspb_layout(points, np.array([2.0, 2.0, 2.0]), limits, None, None)
    assert layout.issues == []
    np.testing.assert_array_equal(layout.times, [0.0, 2.0, 4.0, 6.0])
    # Inner lines pass their via points; the cut is (v_out - v_in) tb / 8.
    np.testing.assert_allclose(layout.velocities[1], (points[2] - points[1]) / 2.0, rtol=1e-15)
    change = np.diff(layout.velocities, axis=0)
    np.testing.assert_allclose(layout.deviation, change * layout.blends[1:-1, None] / 8.0)
    # Automatic inner blends: the binding joint at its acceleration limit.
    for c in (1, 2):
        assert np.max(np.abs(layout.accelerations[c]) / limits.acceleration) == pytest.approx(1.0)


def test_layout_lists_what_too_short_durations_break():
    limits, points = _paddle_points()
    layout = lspb_layout(points, np.array([0.5, 0.5, 0.5]), limits, None, None)
    assert layout.issues
    assert all(issue.ratio > 1.0 and issue.growth > 1.0 for issue in layout.issues)
    assert {issue.limit for issue in layout.issues} <= {"velocity", "acceleration"}
    cut = lspb_layout(points, np.array([2.0, 2.0, 2.0]), limits, None, 1e-6)
    assert [issue.limit for issue in cut.issues] == ["via_tolerance", "via_tolerance"]


def test_fit_is_a_layout_without_issues_that_plan_lspb_draws():
    limits, points = _paddle_points()
    layout = lspb_fit(points, limits, None, 0.01)
    assert layout.issues == []
    assert np.max(np.abs(layout.deviation)) <= 0.01 * (1 + 1e-9)
    traj = plan_lspb(points, None, limits, None, 0.01)
    np.testing.assert_array_equal(traj.metadata["segment_durations"], layout.durations)
    np.testing.assert_array_equal(traj.breakpoints[[0, -1]], [0.0, layout.times[-1]])
    with pytest.raises(InfeasibleError) as info:
        plan_lspb(points, None, limits, None, 0.0)
    assert str(info.value).endswith(LSPB_HINT)
