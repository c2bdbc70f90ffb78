"""Tests of planners.checker.boundary_state: the start state and end state findings."""

from __future__ import annotations

import numpy as np
import pytest
from checker_support import DELTA, Q0, T, Task, quintic

from optraj.errors import InvalidInputError
from optraj.planners.checker import check
from optraj.planners.trajectory import Phase
from optraj.problems import BoundaryState, PointToPoint


def test_end_state_position_gap_fails_the_end_state_only(paddle):
    goal = Q0 + DELTA
    short = goal - np.array([0.0, 0.0, 1e-3, 0.0])
    report = check(quintic(Q0, short, T), PointToPoint(paddle, Q0, goal))
    end = report["end state"]
    assert not end.ok and end.value == pytest.approx(1e-3) and end.time == T
    assert "q of joint 'J3'" in end.detail
    assert [f.name for f in report.violations] == ["end state"]


def test_a_malformed_boundary_state_raises_a_typed_error(paddle):
    trajectory = quintic(Q0, Q0 + DELTA, T, phases=[Phase("strike", 1.5, 2.0)])
    state = BoundaryState("end", None, np.zeros(4), None, tolerance="1e-6")
    with pytest.raises(InvalidInputError, match=r"BoundaryState\.tolerance"):
        check(trajectory, Task(paddle, (state,)))
