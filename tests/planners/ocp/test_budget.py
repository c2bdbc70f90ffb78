"""Tests of planners.ocp.budget."""

from __future__ import annotations

import numpy as np
from conftest import get_robot

from optraj.planners.ocp.transcription import (
    Structure,
    compile_nlp,
    deadline,
    parameter_vector,
    structure_limits,
    time_left,
)
from optraj.robots import SymbolicModel


def _compiled(intervals=(4, 3), **fields):
    robot = get_robot("youbot")
    structure = Structure(
        robot=robot.name,
        limits=structure_limits(robot.limits),
        tool_frame=robot.tool_frame,
        intervals=intervals,
        free=(True, False),
        **fields,
    )
    return robot, compile_nlp(structure, SymbolicModel(robot))


def _exact_motion(compiled, rng):
    """A decision vector whose nodes follow the exact triple integrator (numpy, not CasADi)."""
    layout = compiled.layout
    mid, half, vel, acc, jerk = compiled.scale
    n = layout.n
    w = np.zeros(layout.size)
    h = rng.uniform(0.02, 0.08, layout.K)
    w[: layout.K] = h
    q, v, a = mid + 0.2 * half * rng.uniform(-1, 1, n), 0.1 * vel * rng.uniform(-1, 1, n), 0 * vel
    for k in range(layout.K + 1):
        w[layout.x_index(k, 0)] = (q - mid) / half
        w[layout.x_index(k, 1)] = v / vel
        w[layout.x_index(k, 2)] = a / acc
        if k == layout.K:
            break
        u = jerk * rng.uniform(-0.5, 0.5, n)
        w[layout.u_index(k)] = u / jerk
        q, v, a = (
            q + h[k] * v + h[k] ** 2 / 2 * a + h[k] ** 3 / 6 * u,
            v + h[k] * a + h[k] ** 2 / 2 * u,
            a + h[k] * u,
        )
    return w


def test_a_solve_past_its_deadline_is_stopped_by_the_iteration_callback():
    _, compiled = _compiled(options=(("ipopt.max_iter", 3), ("ipopt.print_level", 0)))
    rng = np.random.default_rng(3)
    w = _exact_motion(compiled, rng)
    args = {"x0": w, "p": parameter_vector(), "lbg": compiled.lbg, "ubg": compiled.ubg}
    assert time_left() == np.inf
    with deadline(-1.0):  # already past
        assert time_left() < 0.0
        compiled.solver(**args)
    stats = compiled.solver.stats()
    assert stats["return_status"] == "User_Requested_Stop" and stats["iter_count"] == 0
    with deadline(3600.0), deadline(7200.0):  # the nearer deadline holds
        assert 3500.0 < time_left() <= 3600.0
        compiled.solver(**args)
    assert compiled.solver.stats()["return_status"] != "User_Requested_Stop"
    assert time_left() == np.inf
