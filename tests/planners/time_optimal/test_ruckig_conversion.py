"""Tests of planners.time_optimal.ruckig_conversion: Ruckig's result as an exact piecewise
cubic, brake pre-profiles included."""

from __future__ import annotations

import numpy as np
import pytest
import ruckig
from conftest import get_robot
from ruckig_support import QUANTITIES, inner

from optraj import problems
from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.checker import check
from optraj.planners.time_optimal.ruckig_conversion import native_to_trajectory
from optraj.planners.time_optimal.ruckig_move import state_to_state
from optraj.planners.time_optimal.ruckig_validation import SYNCHRONIZATIONS


def _max_deviation_from_native(traj, native, times):
    ours = traj.sample(times)
    theirs = np.array([np.concatenate(native.at_time(float(t))) for t in times])
    return float(np.max(np.abs(np.hstack([ours.q, ours.qd, ours.qdd]) - theirs)))


@pytest.mark.parametrize("synchronization", sorted(SYNCHRONIZATIONS))
def test_conversion_matches_ruckig_at_time(synchronization):
    robot = get_robot("sawyer")
    limits = robot.limits
    rng = np.random.default_rng(5)
    q0, q1 = inner(limits, rng, 0.5), inner(limits, rng, 0.5)
    qd0 = 0.3 * limits.velocity * rng.uniform(-1, 1, 7)
    qdd0 = 0.3 * limits.acceleration * rng.uniform(-1, 1, 7)
    moving = synchronization != "none"  # "none" needs a target at rest
    qd1 = 0.3 * limits.velocity * rng.uniform(-1, 1, 7) * moving
    qdd1 = 0.3 * limits.acceleration * rng.uniform(-1, 1, 7) * moving
    traj = state_to_state(q0, qd0, qdd0, q1, qd1, qdd1, limits, synchronization=synchronization)
    native = traj.metadata["native"]
    assert isinstance(native, ruckig.Trajectory)
    assert traj.duration == native.duration
    assert traj.degree == 3 and np.all(np.diff(traj.breakpoints) >= 1e-12)
    times = np.concatenate([rng.uniform(0.0, traj.duration, 1990), traj.breakpoints[:10]])
    assert _max_deviation_from_native(traj, native, times) < 1e-9
    # Every joint's jerk is at its limit or zero (bang-zero-bang) for the fastest joint.
    fastest = int(np.argmax(traj.metadata["independent_min_durations"]))
    jerk = np.abs(traj.sample(times).jerk[:, fastest])
    limit = limits.jerk[fastest]
    assert np.all(np.isclose(jerk, limit, rtol=1e-9) | (jerk < 1e-9 * limit))
    problem = problems.PointToPoint(robot, q0, q1, qd0, qd1, qdd0, qdd1, limits=limits)
    assert check(traj, problem, quantities=QUANTITIES, rate=200.0).ok


def test_conversion_of_a_brake_profile_matches_and_reports_the_breach():
    # A start above the velocity limit: Ruckig brakes first (its brake pre-profile).
    limits = get_robot("sawyer").limits
    q0 = np.zeros(7)
    qd0 = 0.5 * limits.velocity
    qd0[0] = 1.3 * limits.velocity[0]
    with pytest.raises(InfeasibleError, match="right_j0") as info:
        state_to_state(q0, qd0, None, q0 + 0.5, None, None, limits)
    assert info.value.limit == "velocity" and info.value.required == pytest.approx(qd0[0])
    traj = state_to_state(q0, qd0, None, q0 + 0.5, None, None, limits, check_limits=False)
    native = traj.metadata["native"]
    assert native.profiles[0][0].brake.duration > 0.0
    times = np.random.default_rng(1).uniform(0.0, traj.duration, 2000)
    assert _max_deviation_from_native(traj, native, times) < 1e-9
    assert traj.metadata["status"] == "limits exceeded"
    assert any("right_j0" in text for text in traj.metadata["limit_violations"])
    report = check(traj, get_robot("sawyer"), quantities=QUANTITIES, rate=200.0)
    assert not report["velocity"].ok and report["velocity"].joint == "right_j0"


def test_native_to_trajectory_on_a_direct_ruckig_result():
    inp = ruckig.InputParameter(2)
    inp.current_position, inp.current_velocity = [0.0, 1.0], [0.0, -0.2]
    inp.current_acceleration = [0.0, 0.0]
    inp.target_position, inp.target_velocity = [1.0, -0.5], [0.0, 0.3]
    inp.target_acceleration = [0.0, 0.0]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [1.0, 1.0], [2.0, 2.0], [10.0, 5.0]
    native = ruckig.Trajectory(2)
    assert ruckig.Ruckig(2).calculate(inp, native) == ruckig.Result.Working
    traj = native_to_trajectory(native, joint_names=["a", "b"])
    assert traj.joint_names == ("a", "b")
    times = np.linspace(0.0, native.duration, 2000)
    assert _max_deviation_from_native(traj, native, times) < 1e-9
    np.testing.assert_allclose(traj.sample(traj.duration).qd, [0.0, 0.3], atol=1e-12)
    with pytest.raises(InvalidInputError, match="duration"):
        native_to_trajectory(ruckig.Trajectory(2))
