"""Tests of planners.strike.window_nlp: the run-out rows and the NLP's layout."""

from __future__ import annotations

import numpy as np
from conftest import get_robot

from optraj import problems
from optraj.planners.ocp.transcription import jerk_step
from optraj.planners.strike.contact import choose_contact
from optraj.planners.strike.window_nlp import (
    build_window_nlp,
    first_point,
    parameters,
    run_out,
    split_point,
)


def test_run_out_is_the_velocity_where_the_acceleration_reaches_zero():
    # Against the exact steps at the jerk limit: forward from the state with the jerk against
    # its acceleration, and backward in time from it.
    rng = np.random.default_rng(5)
    velocity, acceleration = rng.uniform(-2.0, 2.0, 6), rng.uniform(-8.0, 8.0, 6)
    jerk = rng.uniform(100.0, 500.0, 6)
    stop = np.abs(acceleration) / jerk  # [s] until the acceleration is zero
    for sign in (1.0, -1.0):
        _, v, a = jerk_step(
            sign * stop, 0.0, velocity, acceleration, -sign * np.sign(acceleration) * jerk
        )
        np.testing.assert_allclose(a, 0.0, atol=1e-12)
        np.testing.assert_allclose(run_out(velocity, acceleration, jerk, sign), v, rtol=1e-12)


def test_no_jerk_within_the_limit_stops_the_acceleration_with_less_run_out():
    # Seeded random jerk profiles within the limit, held over 0.1 ms steps, take a joint's
    # acceleration (> 0) to zero forward and backward in time: the velocity then is past
    # run_out's, on the far side from the state's, so the speed over that stretch (the state
    # included) peaks at least at |run_out|.
    rng = np.random.default_rng(8)
    jerk, dt = 300.0, 1e-4
    for _ in range(20):
        v0, a0 = rng.uniform(-2.0, 2.0), rng.uniform(0.5, 8.0)
        for sign in (1.0, -1.0):
            v, a = v0, a0
            while True:
                u = -sign * rng.uniform(-0.2, 1.0) * jerk  # |u| <= jerk, mostly braking a
                step = dt
                if a + sign * u * dt <= 0.0:  # the acceleration reaches zero in this step
                    step = a / abs(u)
                _, v, a = jerk_step(sign * step, 0.0, v, a, u)
                if step < dt:
                    break
            bound = run_out(v0, a0, jerk, sign)
            assert sign * (v - bound) >= -1e-9
            assert max(abs(v), abs(v0)) >= abs(bound) - 1e-9


def test_the_first_point_is_the_strike_line_within_the_nlp_bounds():
    robot = get_robot("sawyer")
    problem = problems.sawyer_pool_shot(1.0)
    n, k = robot.dof, 8
    nlp = build_window_nlp(robot, problem.limits, k, 10, effort_rows=False)
    assert nlp.lbx.shape == nlp.ubx.shape == ((k + 1) * 3 * n + k * n + 1,)
    assert nlp.lbg.shape == nlp.ubg.shape == (nlp.solver.size1_out("g"),)
    q = choose_contact(problem).q
    x0 = first_point(nlp, problem, q, k)
    assert np.all(nlp.lbx <= x0) and np.all(x0 <= nlp.ubx)
    states, jerks = split_point(x0, k, n)
    assert states.shape == (k + 1, 3 * n) and jerks.shape == (k, n)
    # The node positions are the strike line's, scaled by the position ranges: the first at
    # the line's entry point.
    q_nodes = nlp.mid + nlp.half * states[:, :n]
    np.testing.assert_allclose(robot.tool_position(q_nodes[0]), problem.entry_point, atol=1e-6)
    p = parameters(problem, k)
    np.testing.assert_allclose(p[:3], problem.entry_point, rtol=0, atol=0)
    np.testing.assert_allclose(p[3:6], problem.direction, rtol=0, atol=1e-15)
    assert p[12] == problem.speed and p[13] == problem.window / k
