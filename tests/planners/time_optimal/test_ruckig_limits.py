"""Tests of planners.time_optimal.ruckig_limits: exact peaks of piecewise cubics, the position
checks made when a move is planned, and the check of the polynomials when first built."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from conftest import get_robot
from ruckig_support import inner, random_limits

from optraj.errors import InfeasibleError, SolverError
from optraj.planners.time_optimal import ruckig_limits
from optraj.planners.time_optimal.ruckig_conversion import native_pieces
from optraj.planners.time_optimal.ruckig_limits import (
    checked_pieces,
    limit_violations,
    position_breach,
)
from optraj.planners.time_optimal.ruckig_move import state_to_state, stop
from optraj.planners.time_optimal.ruckig_validation import SYNCHRONIZATIONS


def test_plan_time_position_check_agrees_with_the_exact_check():
    # Moves planned without the checks, then judged both ways: the fast check at planning
    # time (speed bound, then Ruckig's root finder) and the exact peaks of the polynomials.
    robot = get_robot("sawyer")
    rng = np.random.default_rng(11)
    breaches = 0
    disagreements = []
    for k in range(600):
        limits = random_limits(robot, rng)
        q0, q1 = inner(limits, rng, 0.95), inner(limits, rng, 0.95)
        half = 0.8 * rng.uniform(-1.0, 1.0, size=(2, robot.dof))
        qd0, qd1 = half[0] * limits.velocity, half[1] * limits.velocity
        if k % 3 == 0:  # a stop: the end position is free
            traj = stop(q0, qd0, None, limits, check_limits=False)
            goal = None
        else:
            traj = state_to_state(q0, qd0, None, q1, qd1, None, limits, check_limits=False)
            goal = q1
        native = traj.metadata["native"]
        exact = [
            e for e in limit_violations(*native_pieces(native), limits) if e.limit == "position"
        ]
        fast = position_breach(native, limits, q0, goal)
        breaches += bool(exact)
        if (fast is None) != (not exact) or (fast is not None and str(fast) != str(exact[0])):
            disagreements.append((k, str(fast), [str(e) for e in exact]))
    assert not disagreements, disagreements[:3]
    assert breaches >= 60  # the check is exercised on both sides


@pytest.mark.parametrize("name", ["sawyer", "youbot", "paddle4"])
def test_rest_to_rest_moves_stay_between_start_and_target(name):
    # The planner skips the position check for such moves on this property (its polynomials
    # are still checked when built): judged here on the exact peaks, every synchronisation,
    # with and without a minimum duration, joints that hardly move or stay put included.
    robot = get_robot(name)
    rng = np.random.default_rng(29)
    for k in range(400):
        limits = random_limits(robot, rng, 0.1, 3.0)
        q0, q1 = limits.sample(rng, 2)
        if k % 5 == 0:
            q1[: robot.dof // 2] = q0[: robot.dof // 2]
        if k % 7 == 0:
            q1 = np.clip(q0 + 1e-4 * rng.normal(size=robot.dof), limits.lower, limits.upper)
        minimum = None if k % 3 else float(rng.uniform(0.1, 10.0))
        sync = sorted(SYNCHRONIZATIONS)[k % len(SYNCHRONIZATIONS)]
        traj = state_to_state(
            q0, None, None, q1, None, None, limits, synchronization=sync, minimum_duration=minimum
        )
        box = dataclasses.replace(
            limits, lower=np.minimum(q0, q1) - 1e-9, upper=np.maximum(q0, q1) + 1e-9
        )
        errors = limit_violations(traj.breakpoints, traj.coefficients, box)
        assert not [e for e in errors if e.limit == "position"], (k, sync, minimum)


def test_exact_peaks_of_a_known_cubic_name_their_value_and_time():
    # At rest for 0.5 s, then q = tau - tau^3 for tau = t - 0.5 in [0, 1]: highest at
    # tau = 1/sqrt(3), q = 2 / (3 sqrt(3)); velocity 1 - 3 tau^2 is largest in magnitude at
    # tau = 1 (-2); acceleration -6 tau also (-6).
    base = get_robot("paddle4").limits
    limits = dataclasses.replace(
        base,
        lower=[-1.0, *base.lower[1:]],
        upper=[0.3, *base.upper[1:]],
        velocity=[1.5, *base.velocity[1:]],
        acceleration=[5.0, *base.acceleration[1:]],
        jerk=[7.0, *base.jerk[1:]],
    )
    coefficients = np.zeros((2, 4, 4))
    coefficients[1, :, 0] = [0.0, 1.0, 0.0, -1.0]
    coefficients[:, 0, 1:] = 0.5 * (limits.lower[1:] + limits.upper[1:])
    knots = np.array([0.0, 0.5, 1.5])
    errors = {e.limit: e for e in limit_violations(knots, coefficients, limits)}
    assert set(errors) == {"position", "velocity", "acceleration"}  # jerk 6 <= 7
    peak = 2.0 / (3.0 * math.sqrt(3.0))
    assert errors["position"].required == pytest.approx(peak, rel=1e-12)
    assert f"t = {0.5 + 1.0 / math.sqrt(3.0):.4g} s" in str(errors["position"])
    for quantity, value in (("velocity", 2.0), ("acceleration", 6.0)):
        assert errors[quantity].required == pytest.approx(value)
        assert "t = 1.5 s" in str(errors[quantity])


def test_a_joint_starting_at_rest_on_its_limit_is_not_a_breach():
    # Ruckig's root finder reports a crossing of the limit's round-off margin here.
    limits = get_robot("paddle4").limits
    q0 = np.array([0.45, 0.0, 0.0, 0.0])
    q1 = np.array([0.6, 0.16162135518301302, 0.764296113818832, -0.16162135518301302])
    qd1 = np.array([0.0, -0.04315801588214984, 0.49348383724057016, 0.04315801588214984])
    traj = state_to_state(q0, None, None, q1, qd1, None, limits)
    assert traj.sample(traj.times(2000.0)).q[:, 2].min() >= 0.0


def test_polynomials_are_checked_again_when_first_built():
    # A move planned for some limits, then built against tighter ones: the build refuses.
    limits = get_robot("sawyer").limits
    traj = state_to_state(np.zeros(7), None, None, np.full(7, 0.5), None, None, limits)
    native = traj.metadata["native"]
    knots, coefficients = checked_pieces(native, limits)
    np.testing.assert_array_equal(knots, traj.breakpoints)
    np.testing.assert_array_equal(coefficients, traj.coefficients)
    tighter = dataclasses.replace(limits, velocity=0.9 * limits.velocity)
    with pytest.raises(SolverError, match=r"limits exceeded.*velocity"):
        checked_pieces(native, tighter)


def test_a_rest_to_rest_move_from_just_outside_a_short_range_raises_when_planned():
    # Positions are accepted 1e-9 outside a limit; the round-off slack of a 0.1 m range is
    # 1e-10, so the move is out of its limits and must be refused now, not on first use.
    base = get_robot("paddle4").limits
    limits = dataclasses.replace(base, lower=[0.0, *base.lower[1:]], upper=[0.1, *base.upper[1:]])
    q0 = np.array([-0.9e-9, 0.0, 0.1, 0.0])
    with pytest.raises(InfeasibleError, match=r"'J1'.*below its lower position limit") as info:
        state_to_state(q0, None, None, q0 + np.array([0.05, 0.1, 0.1, 0.1]), None, None, limits)
    assert info.value.limit == "position"


def test_the_least_slack_shortcut_lists_what_the_full_rule_lists_on_seeded_random_moves(
    monkeypatch,
):
    # Moves that meet their limits (Ruckig's own), and the same polynomials scaled by a
    # hair or more past them: the shortcut must not hide a breach the full rule finds.
    limits = get_robot("panda").limits
    rng = np.random.default_rng(3511)
    cases = []
    for _ in range(30):
        q0, q1 = limits.sample(rng, 2)
        qd = 0.3 * limits.velocity * rng.uniform(-1, 1, limits.n)
        traj = state_to_state(q0, qd, None, q1, None, None, limits, check_limits=False)
        knots, coefficients = native_pieces(traj.metadata["native"])
        for scale in (1.0, 1.0 + 1e-12, 1.0 + 2e-9, 1.01):
            cases.append((knots, coefficients * scale))
    found = []
    for knots, coefficients in cases:
        found.append([str(e) for e in limit_violations(knots, coefficients, limits)])
    monkeypatch.setattr(ruckig_limits, "_within_least_slack", lambda *args: False)
    full = [[str(e) for e in limit_violations(k, c, limits)] for k, c in cases]
    assert found == full
    assert any(found) and not all(found)  # both kinds of case occurred
