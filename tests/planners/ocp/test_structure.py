"""Tests of planners.ocp.structure."""

from __future__ import annotations

import numpy as np
import pytest
from ocp_support import youbot_nlp

from optraj.errors import UnknownNameError
from optraj.planners.ocp.transcription import Layout


def test_layout_splits_what_it_indexes():
    layout = Layout(3, (2, 4))
    w = np.arange(layout.size, dtype=float)
    h, states, jerks = layout.split(w)
    assert h.shape == (6,) and states.shape == (7, 9) and jerks.shape == (6, 3)
    np.testing.assert_array_equal(states[5, 3:6], w[layout.x_index(5, 1)])
    np.testing.assert_array_equal(jerks[4], w[layout.u_index(4)])
    np.testing.assert_array_equal(layout.first_node, [0, 2, 6])


def test_unknown_torque_rows_are_named():
    with pytest.raises(UnknownNameError, match="rnea"):
        youbot_nlp(torque_nodes=(1,), torque_rows="quadratic")
