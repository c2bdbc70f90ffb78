"""Tests of planners.ocp.failures."""

from __future__ import annotations

import dataclasses

from ocp_support import tight_choice

from optraj import problems
from optraj.errors import (
    SolverError,
)
from optraj.planners.ocp.failures import near_the_limit


def test_the_tight_ratio_hint_comes_only_with_infeasibility_and_no_room():
    problem = problems.sawyer_pool_shot(1.0)
    failure = SolverError("ipopt", "Infeasible_Problem_Detected", iterations=7, detail="x")
    tight = tight_choice(1.03)
    tighter = dataclasses.replace(tight, ratio=0.95, max_speed=1.05, binding_joint="right_j3")
    hinted = near_the_limit(failure, problem, [tight, tighter])
    assert (hinted.solver, hinted.status, hinted.iterations) == ("ipopt", failure.status, 7)
    assert hinted.detail.startswith("x; at 1 m/s the 2 contact configurations tried need at ")
    assert "least 95.0 % of a velocity limit (right_j3 binds; the best" in hinted.detail
    assert "up to 1.05 m/s" in hinted.detail  # the best choice's, not the first's
    assert "x; at 1 m/s the contact configuration tried needs at least 97.0 %" in (
        near_the_limit(failure, problem, [tight]).detail
    )
    # Room to spare at one contact (the threshold itself counts as room), no contact, or
    # another failure than infeasibility: the error as it was.
    at_threshold = dataclasses.replace(tight, ratio=0.9)
    assert near_the_limit(failure, problem, [tight, at_threshold]) is failure
    assert near_the_limit(failure, problem, []) is failure
    missed = SolverError("ipopt", "strike line not met between nodes", detail="faster")
    assert near_the_limit(missed, problem, [tight]) is missed
