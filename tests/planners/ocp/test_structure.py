"""Tests of planners.ocp.structure."""

from __future__ import annotations

import numpy as np
import pytest
from ocp_support import youbot_nlp

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.ocp.transcription import (
    PARAMETERS,
    Layout,
    parameter_vector,
)


def test_layout_splits_what_it_indexes():
    layout = Layout(3, (2, 4))
    w = np.arange(layout.size, dtype=float)
    h, states, jerks = layout.split(w)
    assert h.shape == (6,) and states.shape == (7, 9) and jerks.shape == (6, 3)
    np.testing.assert_array_equal(states[5, 3:6], w[layout.x_index(5, 1)])
    np.testing.assert_array_equal(jerks[4], w[layout.u_index(4)])
    np.testing.assert_array_equal(layout.first_node, [0, 2, 6])


def test_parameter_vector_names_what_is_wrong():
    assert parameter_vector().size == sum(size for _, size in PARAMETERS)
    with pytest.raises(InvalidInputError, match="speed"):
        parameter_vector(speed=[1.0, 2.0])
    with pytest.raises(UnknownNameError, match="unknown NLP parameter 'velocity'"):
        parameter_vector(velocity=1.0)
    for bad in (True, "1.0", np.nan):  # no bool, string or NaN posing as a speed
        with pytest.raises(InvalidInputError, match="speed"):
            parameter_vector(speed=bad)


def test_unknown_torque_rows_are_named():
    with pytest.raises(UnknownNameError, match="rnea"):
        youbot_nlp(torque_nodes=(1,), torque_rows="quadratic")
