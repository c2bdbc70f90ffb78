"""Tests of planners.ocp.problem."""

from __future__ import annotations

import numpy as np
from ocp_support import sawyer_shots

from optraj.planners import check
from optraj.planners.ocp.optimal_control import (
    OptimalControl,
)


def test_build_and_solve_apart():
    problem = next(sawyer_shots(1, speed=1.0))
    planner = OptimalControl("time")
    built = planner.build(problem)
    names = {name for name, _, _ in built.compiled.groups}
    assert {"dynamics", "strike position", "strike axis", "strike speed"} <= names
    assert built.variables == built.compiled.w.numel() and built.constraints > 0
    assert np.all(built.lbx <= built.x0) and np.all(built.x0 <= built.ubx)
    assert built.contact is not None and built.contact.ratio <= 1.0
    # The guess breaks some rows: each group reports the largest excess of its own rows.
    g = np.asarray(built.compiled.constraint_values(built.x0, built.p)).reshape(-1)
    excess = np.maximum(built.compiled.lbg - g, g - built.compiled.ubg)
    found = built.violations(built.x0)
    assert set(found) == names | {"bounds"} and found["bounds"] == 0.0
    for name in names:
        rows = [excess[a:b] for group, a, b in built.compiled.groups if group == name]
        assert found[name] == max(0.0, float(np.concatenate(rows).max()))
    assert found["dynamics"] > 1e-3
    traj = planner.solve(built)
    assert check(traj, problem).ok
    for key in ("solver_status", "iterations", "nlp_time", "constraint_violation", "objective"):
        assert key in traj.metadata
