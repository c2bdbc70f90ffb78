"""Tests of planners.strike.window_check: the least fraction of the limits a strike window needs."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from optraj import problems
from optraj.errors import InvalidInputError
from optraj.planners import OptimalControl, Trajectory, check
from optraj.planners.ocp.transcription import jerk_step
from optraj.planners.strike.contact import choose_contact
from optraj.planners.strike.window_check import QUANTITIES, WindowCheck, _velocity_peaks

#: Strike benchmark ball 3 and its heading [deg]: at 1.5 m/s its contact configurations need
#: more than 0.99 of right_j0's velocity limit, and its window more than the limits.
BALL_3 = ((0.7009739175308249, 0.10577670705892629, -0.04954517410420467), 2.1398940829796977)
#: Strike benchmark ball 0 and its heading [deg].
BALL_0 = ((0.7750190933209333, 0.2640248303393514, -0.022431430975480643), -10.991712400376326)


def _window_peaks(traj: Trajectory, problem: problems.PoolStrike) -> tuple[float, float, float]:
    """Largest velocity ratio over the whole motion (the check counts the velocities just
    before and after the window), acceleration and jerk ratios over the strike phase, sampled
    at 1 kHz (the jerk just inside each end, where the cubic pieces of the window hold)."""
    phase = traj.phase("strike")
    times = np.linspace(phase.t_start + 1e-9, phase.t_end - 1e-9, 1001)
    sample = traj.sample(times)
    limits = problem.limits
    return (
        float((np.abs(traj.sample(traj.times()).qd) / limits.velocity).max()),
        float((np.abs(sample.qdd) / limits.acceleration).max()),
        float((np.abs(sample.jerk) / limits.jerk).max()),
    )


def test_the_window_check_asks_no_more_than_a_planned_strike_window():
    # A minimum-jerk plan is a point of the window NLP (to its node tolerances): the check's
    # optimum needs at most the fraction of the limits that plan's window does, measured on
    # the trajectory itself.
    problem = problems.sawyer_pool_shot(1.0)
    traj = OptimalControl("jerk").plan(problem)
    assert check(traj, problem).ok
    window = WindowCheck()(problem, traj.metadata["contact_configuration"])
    assert window.converged
    planned = max(_window_peaks(traj, problem))
    assert 0.1 < window.ratio <= planned + 1e-3
    assert window.ratio == max(window.velocity, window.acceleration, window.jerk, window.effort)
    assert window.max_speed > problem.speed  # within the limits, so faster is possible


def test_a_window_past_the_limits_names_the_quantity_and_a_slower_speed():
    problem = problems.sawyer_pool_shot(1.5, *BALL_3)
    window = WindowCheck()(problem, choose_contact(problem).q)
    assert window.converged and window.exceeds()
    assert window.ratio > 1.02
    assert window.limit in QUANTITIES and window.joint in problem.limits.names
    joint = problem.limits.names.index(window.joint)
    assert window.allowed == pytest.approx(getattr(problem.limits, window.limit)[joint])
    assert window.required > window.allowed
    assert window.unit == problem.limits.unit(window.limit, joint)
    # Run slower by the named factor, the same joint path scales its velocities, accelerations
    # and jerks by the factor's first, second and third powers: the largest lands on 1.
    factor = window.max_speed / problem.speed
    scaled = (window.velocity * factor, window.acceleration * factor**2, window.jerk * factor**3)
    assert 0.0 < factor < 1.0 and max(scaled) == pytest.approx(1.0)
    assert f"{window.max_speed:.4g} m/s" in window.describe()
    # The binding joint's own share of its limit, and the limit scale that would do at speed.
    share = 100.0 * window.required / window.allowed
    assert f"{share:.1f} % of its {window.limit} limit" in window.describe()
    assert f"limits {window.ratio:.4g} times as large" in window.describe()


def test_a_window_that_gravity_overloads_names_effort_and_a_limit_scale():
    # A slow shot with Sawyer's effort limits at 21 %: the arm, held out over the ball for the
    # whole 2 s window, needs more shoulder torque than that, at any slower speed too.
    sawyer = problems.sawyer_pool_shot(0.07)
    limits = sawyer.robot.limits.scaled(0.21, ("effort",))
    problem = problems.PoolStrike(sawyer.robot, sawyer.ball, sawyer.direction, 0.07, limits=limits)
    window = WindowCheck()(problem, choose_contact(problem).q)
    assert window.converged and window.exceeds()
    assert (window.limit, window.joint) == ("effort", "right_j1")
    assert window.effort == pytest.approx(window.ratio) and window.ratio > 1.2
    joint = limits.names.index("right_j1")
    assert window.allowed == pytest.approx(limits.effort[joint])
    assert window.unit == "N m" and window.required > window.allowed
    assert window.max_speed == 0.0
    assert "no slower strike keeps within them" in window.describe()
    assert f"limits {window.ratio:.4g} times as large" in window.describe()


def test_the_window_check_pickles_and_answers_the_same():
    problem = problems.sawyer_pool_shot(1.5, *BALL_3)
    q = choose_contact(problem).q
    check_ = WindowCheck()
    first = check_(problem, q)
    copy = pickle.loads(pickle.dumps(check_))
    again = copy(problem, q)
    assert again.ratio == pytest.approx(first.ratio, rel=1e-9)
    assert (again.limit, again.joint) == (first.limit, first.joint)


def test_the_window_check_refuses_what_it_cannot_check():
    problem = problems.sawyer_pool_shot(1.0)
    with pytest.raises(InvalidInputError, match="q_contact"):
        WindowCheck()(problem, np.zeros(3))
    with pytest.raises(InvalidInputError, match="PoolStrike"):
        WindowCheck()(problems.ece486_paddle_strike(), np.zeros(4))
    with pytest.raises(InvalidInputError, match="intervals"):
        WindowCheck(intervals=1)


def test_ball_0s_window_at_1_5_m_s_needs_more_than_the_limits_with_its_approach_and_stop():
    # Without the run-out rows this window keeps within 0.997 of the limits, though the whole
    # NLP is infeasible up to limits 1.01 times as large; with them a velocity binds.
    problem = problems.sawyer_pool_shot(1.5, *BALL_0)
    window = WindowCheck()(problem, choose_contact(problem).q)
    assert window.converged and window.ratio > 1.01
    assert window.limit == "velocity"


def test_velocity_peaks_count_the_turns_between_nodes_and_the_run_outs():
    # Against the velocity sampled densely along the exact steps, on seeded random states
    # whose accelerations change sign inside intervals, and the velocities the joints reach
    # before the first node and after the last at the jerk limit.
    rng = np.random.default_rng(3)
    n, k, h = 3, 6, 0.02
    scale = (np.array([2.0, 1.5, 1.0]), np.array([10.0, 8.0, 6.0]), np.array([500.0, 400.0, 300.0]))
    jerks = rng.uniform(-1.0, 1.0, (k, n))
    states = np.zeros((k + 1, 3 * n))
    states[0, n:] = rng.uniform(-0.5, 0.5, 2 * n)
    for i in range(k):
        v, a = scale[0] * states[i, n : 2 * n], scale[1] * states[i, 2 * n :]
        _, v1, a1 = jerk_step(h, 0.0, v, a, scale[2] * jerks[i])
        states[i + 1, n:] = np.concatenate([v1 / scale[0], a1 / scale[1]])
    t = np.linspace(0.0, h, 2001)[:, None]
    dense = [
        jerk_step(
            t,
            0.0,
            scale[0] * states[i, n : 2 * n],
            scale[1] * states[i, 2 * n :],
            scale[2] * jerks[i],
        )[1]
        for i in range(k)
    ]
    window = (np.abs(np.concatenate(dense)) / scale[0]).max(axis=0)
    ends = []
    for node, sign in ((0, -1.0), (k, 1.0)):
        v, a = scale[0] * states[node, n : 2 * n], scale[1] * states[node, 2 * n :]
        stop = np.abs(a) / scale[2]
        ends.append(jerk_step(sign * stop, 0.0, v, a, -sign * np.sign(a) * scale[2])[1])
    after = np.abs(ends).max(axis=0) / scale[0]
    peaks = _velocity_peaks(states, jerks, h, scale)
    np.testing.assert_allclose(peaks, np.maximum(window, after), rtol=1e-6)
    nodes = np.abs(states[:, n : 2 * n]).max(axis=0)
    assert np.any(window > np.maximum(nodes, after) + 1e-3)  # a turn decides a peak
    assert np.any(after > np.maximum(nodes, window) + 1e-3)  # and a run-out another
