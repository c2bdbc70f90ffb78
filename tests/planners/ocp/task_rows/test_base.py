"""Tests of planners.ocp.task_rows.base."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot

from optraj.planners.ocp.rows import structure_limits
from optraj.planners.ocp.task_rows import TaskRows
from optraj.planners.ocp.transcription import Structure, compile_nlp
from optraj.robots import SymbolicModel


class _FirstSpeed(TaskRows):
    """Rows of a test: the first node's joint velocities equal the parameter ``qd0``."""

    parameters = (("qd0", 2),)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _FirstSpeed)

    def __hash__(self) -> int:
        return 0

    def values(self):
        return {"qd0": np.array([0.5, -0.5])}

    def add(self, rows, nlp):
        _, qd, _ = nlp.state(0)
        rows.add("first speed", qd[:2] - nlp.parameters["qd0"], 0.0, 0.0)


def test_a_task_row_kind_adds_its_named_rows_and_parameters():
    robot = get_robot("paddle4")
    structure = Structure(
        robot=robot.name,
        limits=structure_limits(robot.limits),
        tool_frame=robot.tool_frame,
        intervals=(3,),
        free=(True,),
        tasks=(_FirstSpeed(),),
    )
    compiled = compile_nlp(structure, SymbolicModel(robot))
    assert compiled.parameters.names == ("time_scale", "qd0", "torque")
    name, first, end = compiled.groups[-1]
    assert (name, end - first) == ("first speed", 2)
    p = compiled.parameters.vector(**_FirstSpeed().values())
    w = np.zeros(compiled.layout.size)
    g = np.asarray(compiled.constraint_values(w, p)).reshape(-1)
    np.testing.assert_allclose(g[first:end], [-0.5, 0.5])


def test_the_base_is_abstract():
    with pytest.raises(TypeError):
        TaskRows()
