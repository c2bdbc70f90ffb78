"""Tests of planners.phase: Phase checks, shifted and back-to-back phases."""

from __future__ import annotations

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.planners.phase import Phase, back_to_back, shifted


def test_a_phase_has_a_duration_and_may_last_zero_seconds():
    assert Phase("strike", 0.5, 0.75).duration == pytest.approx(0.25)
    assert Phase("instant", 1.0, 1.0).duration == 0.0


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: Phase("backwards", 1.0, 0.5), "ends at"),
        (lambda: Phase("a", "0", "1"), "t_start must be a numeric"),
        (lambda: Phase("a", False, True), "t_start must be a numeric"),
        (lambda: Phase(3, 0.0, 1.0), "phase name must be a str"),
    ],
)
def test_malformed_phases_are_typed_errors(build, match):
    with pytest.raises(InvalidInputError, match=match):
        build()


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_a_non_finite_float_time_is_refused(bad):
    with pytest.raises(InvalidInputError, match="t_end must be finite"):
        Phase("a", 0.0, bad)


def test_times_are_kept_as_python_floats():
    phase = Phase("a", np.float64(0.25), 1)
    assert type(phase.t_start) is float and type(phase.t_end) is float
    assert type(Phase("c", np.float64(0.5), np.float32(1.0)).t_end) is float
    assert (phase.t_start, phase.t_end) == (0.25, 1.0)
    assert Phase("b", 0.5, 2.0).t_end == 2.0


def test_shifted_moves_every_phase_by_the_offset():
    phases = [Phase("a", 0.0, 0.5), Phase("b", 0.5, 2.0)]
    assert shifted(phases, 1.5) == [Phase("a", 1.5, 2.0), Phase("b", 2.0, 3.5)]
    assert shifted([], 1.0) == []


def test_back_to_back_phases_follow_one_another_from_zero():
    assert back_to_back([("idle", 0.0), ("ramp", 1.0), ("rest", 0.5)]) == [
        Phase("idle", 0.0, 0.0),
        Phase("ramp", 0.0, 1.0),
        Phase("rest", 1.0, 1.5),
    ]
