"""Tests of planners.checker.task: constraint fields, task findings and missing findings."""

from __future__ import annotations

import math

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.planners.checker.task import (
    constraint_direction,
    constraint_tolerance,
    constraint_vector,
    missing_findings,
    task_finding,
)


def test_constraint_fields_are_validated_with_typed_errors():
    np.testing.assert_array_equal(constraint_vector([1, 2, 3], "Field.q", 3), [1.0, 2.0, 3.0])
    with pytest.raises(InvalidInputError, match=r"Field\.q must be a finite vector of length 4"):
        constraint_vector([1.0, 2.0, 3.0], "Field.q", 4)
    with pytest.raises(InvalidInputError, match="got shape None"):
        constraint_vector([[1.0], [2.0, 3.0]], "Field.q", 3)  # ragged
    with pytest.raises(InvalidInputError, match="finite"):
        constraint_vector([1.0, math.nan, 3.0], "Field.q", 3)
    assert constraint_tolerance(1e-3, "Field.tolerance", "m") == 1e-3
    with pytest.raises(InvalidInputError, match=r"Field\.tolerance must be >= 0 m"):
        constraint_tolerance(-1.0, "Field.tolerance", "m")
    np.testing.assert_allclose(constraint_direction([0.0, 3.0, 4.0], "Field.axis"), [0, 0.6, 0.8])
    with pytest.raises(InvalidInputError, match=r"Field\.axis must be a non-zero direction"):
        constraint_direction([0.0, 0.0, 1e-13], "Field.axis")


def test_task_findings_and_missing_findings():
    inside = task_finding("strike speed", 0.001, 0.002, 0.5, "-", "fine")
    assert (inside.kind, inside.ok, inside.joint, inside.time) == ("task", True, None, 0.5)
    assert inside.margin == pytest.approx(0.001)
    # The slack is the round-off of the tolerance unless given.
    assert task_finding("x", 0.002 + 1e-15, 0.002, None, "m", "").ok
    assert not task_finding("x", 0.003, 0.002, None, "m", "", slack=1e-4).ok
    assert task_finding("x", 0.003, 0.002, None, "m", "", slack=2e-3, joint="J1").ok
    found = missing_findings([("a", 1e-3, "m"), ("b", 0.1, "rad")], "phase 'p' missing")()
    assert [f.name for f in found] == ["a", "b"]
    assert [f.unit for f in found] == ["m", "rad"]
    assert all(f.value == math.inf and not f.ok and f.detail == "phase 'p' missing" for f in found)
