"""Tests of planners.ocp.rounds."""

from __future__ import annotations

import pytest

from optraj import problems
from optraj.errors import (
    SolverError,
)
from optraj.planners import check
from optraj.planners.ocp.optimal_control import (
    OptimalControl,
)


@pytest.mark.slow
def test_a_strike_that_leaves_its_schedule_is_solved_again_on_a_finer_grid(monkeypatch):
    problem = problems.sawyer_pool_shot()
    plain = OptimalControl(contact_retries=0).plan(problem)
    real = OptimalControl._strike_misses
    calls = []

    def first_misses(self, traj, spec):
        calls.append(traj)
        return [("speed error", 0.2, 0.05, "%")] if len(calls) == 1 else real(self, traj, spec)

    monkeypatch.setattr(OptimalControl, "_strike_misses", first_misses)
    traj = OptimalControl(contact_retries=0).plan(problem)
    assert traj.metadata["rounds"] == 2 and len(calls) == 2
    assert traj.metadata["intervals"]["strike"] == 2 * plain.metadata["intervals"]["strike"]
    assert check(traj, problem).ok


def test_a_strike_grid_that_cannot_be_refined_stops_and_names_the_miss(monkeypatch):
    # Every solve misses the speed between nodes, and the first strike grid is already the
    # finest allowed: one solve, then an error saying what missed, by how much.
    miss = [("speed error", 0.2, 0.05, "%")]
    monkeypatch.setattr(OptimalControl, "_strike_misses", lambda *args: miss)
    monkeypatch.setattr("optraj.planners.ocp.rounds.MAX_STRIKE_INTERVALS", 1)
    monkeypatch.setattr("optraj.planners.ocp.building.MAX_STRIKE_INTERVALS", 1)
    planner = OptimalControl(contact_retries=0)
    with pytest.raises(SolverError, match=r"after 1 rounds: speed error 0\.2 %") as info:
        planner.plan(problems.sawyer_pool_shot())
    assert info.value.status == "strike line not met between nodes"
