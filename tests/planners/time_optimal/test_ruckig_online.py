"""Tests of planners.time_optimal.ruckig_online: one control tick at a time, against the
offline plan, with a changing moving target, and its misuse."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.time_optimal.ruckig_online import OnlineRuckig
from optraj.planners.time_optimal.ruckig_planner import Ruckig


def test_online_ruckig_reaches_the_target_in_the_planned_number_of_ticks():
    robot = get_robot("sawyer")
    limits = robot.limits
    dt = 1e-3
    rng = np.random.default_rng(11)
    q0, q1 = limits.sample(rng, 2)
    offline = Ruckig().move(q0, q1, limits)
    online = OnlineRuckig(limits, dt)
    online.reset(q0)
    states = []
    while not online.finished:
        states.append(online.update(q1))
        assert len(states) < 10 * offline.duration / dt
    q, qd, qdd = (np.array(x) for x in zip(*states, strict=True))
    assert abs(len(states) - offline.duration / dt) <= 1.0
    assert online.duration == pytest.approx(offline.duration, rel=1e-12)
    np.testing.assert_allclose(q[-1], q1, atol=1e-9)
    np.testing.assert_allclose(qd[-1], 0.0, atol=1e-9)
    assert np.all(np.abs(qd) <= limits.velocity * (1 + 1e-9))
    assert np.all(np.abs(qdd) <= limits.acceleration * (1 + 1e-9))
    jerk = np.diff(np.vstack([np.zeros(7), qdd]), axis=0) / dt
    assert np.all(np.abs(jerk) <= limits.jerk * (1 + 1e-6))
    low, high = np.minimum(q0, q1), np.maximum(q0, q1)
    assert np.all((q >= low - 1e-9) & (q <= high + 1e-9))
    # Tick k returns the offline plan's state at (k + 1) dt.
    times = np.minimum(dt * np.arange(1, len(q) + 1), offline.duration)
    np.testing.assert_allclose(q, offline.sample(times).q, atol=1e-9)


def test_online_ruckig_follows_a_changing_moving_target():
    limits = get_robot("sawyer").limits
    online = OnlineRuckig(limits, 0.01)
    online.reset(np.zeros(7), 0.2 * limits.velocity, None)
    goal, speed = np.full(7, 0.5), 0.1 * limits.velocity
    ticks = 0
    while not online.finished:
        target = goal if ticks < 30 else -goal  # the target jumps after 0.3 s
        q, qd, _ = online.update(target, speed)
        ticks += 1
        assert np.all(np.abs(qd) <= limits.velocity * (1 + 1e-9))
        assert ticks < 2000
    # The finishing tick ends past the target by the rest of the tick at the target speed.
    assert np.all(np.abs(q + goal) <= speed * 0.01 + 1e-12)
    np.testing.assert_allclose(q, -goal + speed * (online.time - online.duration), atol=1e-9)
    np.testing.assert_allclose(qd, speed, atol=1e-9)


def test_online_ruckig_rejects_bad_use():
    limits = get_robot("sawyer").limits
    online = OnlineRuckig(limits, 1e-3)
    with pytest.raises(InvalidInputError, match="reset"):
        online.update(np.zeros(7))
    online.reset(np.zeros(7))
    with pytest.raises(InfeasibleError, match="right_j0"):
        online.update(np.zeros(7), [2.5, 0, 0, 0, 0, 0, 0])
    with pytest.raises(InvalidInputError, match="shape"):
        online.update(np.zeros(3))
    with pytest.raises(InvalidInputError, match="dt"):
        OnlineRuckig(limits, 0.0)
    with pytest.raises(InfeasibleError, match="start velocity"):
        online.reset(np.zeros(7), np.full(7, 5.0))
