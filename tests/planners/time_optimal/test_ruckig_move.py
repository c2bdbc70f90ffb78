"""Tests of planners.time_optimal.ruckig_move: moves between states and the fastest stop, their
position checks when planned, polynomials built on first use, and breaches reported."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import get_robot
from ruckig_support import QUANTITIES

from optraj import problems
from optraj.errors import InfeasibleError, InvalidInputError, SolverError
from optraj.planners.checker import check
from optraj.planners.time_optimal import ruckig_limits
from optraj.planners.time_optimal.ruckig_move import state_to_state, stop
from optraj.planners.time_optimal.ruckig_planner import Ruckig


def test_a_plan_whose_polynomials_break_a_limit_raises_on_first_use(monkeypatch):
    limits = get_robot("sawyer").limits
    breach = InfeasibleError("a breach", limit="velocity", joint="right_j0")
    monkeypatch.setattr(ruckig_limits, "limit_violations", lambda *args: [breach])
    traj = state_to_state(np.zeros(7), None, None, np.full(7, 0.5), None, None, limits)
    assert traj.duration > 0.0 and "segments=deferred" in repr(traj)  # not built yet
    with pytest.raises(SolverError, match="a breach"):
        traj.sample(0.0)


def test_position_overshoot_raises_or_is_reported():
    robot = get_robot("sawyer")
    limits = robot.limits
    q1 = robot.home.copy()
    q1[0] = limits.upper[0] - 0.01
    qd1 = np.zeros(7)
    # Arriving 1 cm below the bound already moving back down: the joint must turn above it.
    qd1[0] = -0.9 * limits.velocity[0]
    with pytest.raises(InfeasibleError, match=r"right_j0.*upper position limit") as info:
        state_to_state(robot.home, None, None, q1, qd1, None, limits)
    assert info.value.limit == "position" and info.value.required > limits.upper[0]
    # The problem form raises the same; asked not to, the planner reports the breach.
    problem = problems.PointToPoint(robot, robot.home, q1, qd_goal=qd1)
    with pytest.raises(InfeasibleError):
        Ruckig().plan(problem)
    traj = state_to_state(robot.home, None, None, q1, qd1, None, limits, check_limits=False)
    assert traj.metadata["status"] == "limits exceeded"
    assert not check(traj, problem, quantities=QUANTITIES, rate=200.0)["position"].ok


def test_stop_brings_a_moving_state_to_rest_within_the_limits():
    robot = get_robot("sawyer")
    limits = robot.limits
    rng = np.random.default_rng(9)
    for _ in range(20):
        qd0 = 0.8 * limits.velocity * rng.uniform(-1, 1, 7)
        qdd0 = 0.3 * limits.acceleration * rng.uniform(-1, 1, 7)
        traj = stop(robot.home, qd0, qdd0, limits)
        end = traj.sample(traj.duration)
        np.testing.assert_allclose(end.qd, 0.0, atol=1e-9)
        np.testing.assert_allclose(end.qdd, 0.0, atol=1e-9)
        np.testing.assert_allclose(traj.metadata["stop_position"], end.q)
        assert traj.phases[0].name == "stop"
        report = check(traj, robot, quantities=QUANTITIES, rate=200.0)
        assert report.ok, report.violations
        np.testing.assert_allclose(traj.sample(0.0).qd, qd0, atol=1e-12)


def test_stop_time_matches_the_closed_form():
    limits = get_robot("sawyer").limits
    qd0 = np.zeros(7)
    qd0[0] = 1.5  # >= a^2 / j = 0.35: a trapezoid in acceleration, T = v / a + a / j
    qd0[1] = 0.1  # < 5^2 / 100 = 0.25: a triangle in acceleration, T = 2 sqrt(v / j)
    traj = stop(np.zeros(7), qd0, None, limits, synchronization="none")
    own = traj.metadata["independent_min_durations"]
    assert own[0] == pytest.approx(1.5 / 7.0 + 7.0 / 140.0, rel=1e-12)
    assert own[1] == pytest.approx(2.0 * math.sqrt(0.1 / 100.0), rel=1e-12)
    assert traj.duration == pytest.approx(own[0], rel=1e-12)
    with pytest.raises(InvalidInputError, match="at rest"):
        stop(np.zeros(7), np.zeros(7), None, limits)


def test_stop_that_runs_past_a_position_limit_raises_when_planned():
    limits = get_robot("sawyer").limits
    q0, qd0 = np.zeros(7), np.zeros(7)
    q0[0], qd0[0] = limits.upper[0] - 0.01, 0.9 * limits.velocity[0]
    with pytest.raises(InfeasibleError, match=r"right_j0.*upper position limit") as info:
        stop(q0, qd0, None, limits)
    assert info.value.limit == "position" and info.value.required > limits.upper[0]


def test_stop_that_must_exceed_a_limit_raises():
    limits = get_robot("sawyer").limits
    qd0, qdd0 = np.zeros(7), np.zeros(7)
    qd0[2], qdd0[2] = 1.9, 7.0  # 1.9 + 49 / 320 > 1.957: the velocity limit breaks first
    with pytest.raises(InfeasibleError, match="right_j2") as info:
        stop(np.zeros(7), qd0, qdd0, limits)
    assert info.value.limit == "velocity"
    traj = stop(np.zeros(7), qd0, qdd0, limits, check_limits=False)
    assert traj.metadata["limit_violations"] and traj.sample(traj.duration).qd == pytest.approx(0)
