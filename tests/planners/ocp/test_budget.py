"""Tests of planners.ocp.budget."""

from __future__ import annotations

import numpy as np
from ocp_support import exact_motion, youbot_nlp

from optraj.planners.ocp.transcription import (
    deadline,
    time_left,
)


def test_a_solve_past_its_deadline_is_stopped_by_the_iteration_callback():
    _, compiled = youbot_nlp(options=(("ipopt.max_iter", 3), ("ipopt.print_level", 0)))
    rng = np.random.default_rng(3)
    w = exact_motion(compiled, rng)
    args = {"x0": w, "p": compiled.parameters.vector(), "lbg": compiled.lbg, "ubg": compiled.ubg}
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
