"""Tests of planners.ocp.guesses."""

from __future__ import annotations

import numpy as np
import pytest

from optraj import problems
from optraj.errors import (
    PathJumpError,
    UnreachableError,
)
from optraj.planners import check
from optraj.planners.ocp.guesses import quintic_guess
from optraj.planners.ocp.optimal_control import (
    OptimalControl,
)


@pytest.mark.parametrize(
    "raised", [PathJumpError(0.1, "right_j3", 0.2, 0.1), None], ids=["jumps", "unreachable"]
)
def test_a_pool_guess_without_its_line_starts_from_the_contact_choice(monkeypatch, raised):
    # When the guess's line cannot be followed (it jumps, or a pose with the contact's roll
    # has no solution), the guess joins the choice's entry, contact and exit by quintics.
    problem = problems.sawyer_pool_shot(1.0)
    failure = raised or UnreachableError(
        "no IK", position_error=0.1, orientation_error=0.0, attempts=1
    )

    def refused(*args, **kwargs):
        raise failure

    monkeypatch.setattr("optraj.planners.ocp.guesses.strike_line", refused)
    traj = OptimalControl("time").plan(problem)
    report = check(traj, problem)
    assert report.ok, report.summary()


def test_a_quintic_guess_joins_rest_to_the_given_end_state():
    q0, q1 = np.zeros(3), np.array([0.3, -0.2, 0.1])
    v1, a1 = np.array([0.1, 0.0, -0.1]), np.array([0.0, 0.5, 0.0])
    traj = quintic_guess(q0, q1, 2.0, v1, a1)
    start, end = traj.sample(np.array([0.0, 2.0])).q
    np.testing.assert_allclose(start, q0, atol=1e-12)
    np.testing.assert_allclose(end, q1, atol=1e-12)
    np.testing.assert_allclose(traj.sample(np.array([2.0])).qd[0], v1, atol=1e-12)
    np.testing.assert_allclose(traj.sample(np.array([2.0])).qdd[0], a1, atol=1e-12)
    np.testing.assert_allclose(traj.sample(np.array([0.0])).qd[0], 0.0, atol=1e-12)
    rest = quintic_guess(q0, q1, 1.0)
    np.testing.assert_allclose(rest.sample(np.array([1.0])).qd[0], 0.0, atol=1e-12)
