"""Tests of planners.ocp.task_rows.tool_contact."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from optraj import problems
from optraj.errors import InvalidInputError
from optraj.planners.ocp.optimal_control import OptimalControl
from optraj.planners.ocp.task_rows import ToolContactRows
from optraj.problems.constraints import ToolContact


def test_a_contact_without_a_velocity_has_no_rows():
    with pytest.raises(InvalidInputError, match="'ball' has no velocity"):
        ToolContactRows.of(ToolContact(np.zeros(3), label="ball"), phase=0)


def test_the_contact_node_is_where_its_phase_ends_or_starts():
    contact = ToolContact(np.zeros(3), velocity=np.array([1.0, 0.0, 0.0]), offset=0.01)
    first_node = np.array([0, 20, 30])
    assert ToolContactRows.of(contact, phase=0).node(first_node) == 20
    start = ToolContact(np.zeros(3), velocity=np.zeros(3), at="start")
    assert ToolContactRows.of(start, phase=1).node(first_node) == 20
    values = ToolContactRows.of(contact, phase=0).values()
    assert values["contact_velocity"].tolist() == [1.0, 0.0, 0.0]
    assert values["offset"].tolist() == [0.01]


def test_a_paddle_strike_nlp_has_the_contact_s_velocity_rows_and_parameters():
    problem = dataclasses.replace(problems.ece486_paddle_strike(), speed=0.3)
    (contact,) = [c for c in problem.constraints() if isinstance(c, ToolContact)]
    built = OptimalControl().build(problem)
    rows = [b - a for name, a, b in built.compiled.groups if name == "contact velocity"]
    assert rows == [3]
    np.testing.assert_array_equal(built.parameter("contact_velocity"), contact.velocity)
    assert built.parameter("offset").tolist() == [contact.offset]
