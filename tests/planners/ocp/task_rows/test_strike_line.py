"""Tests of planners.ocp.task_rows.strike_line."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from optraj import problems
from optraj.errors import InvalidInputError
from optraj.planners.ocp.optimal_control import OptimalControl
from optraj.planners.ocp.task_rows import StrikeLineRows
from optraj.planners.ocp.transcription import Structure
from optraj.problems.constraints import StrikeLine

PHASES = ("approach", "strike", "stop")


def _rows(shot: problems.PoolStrike) -> StrikeLineRows:
    (line,) = [c for c in shot.constraints() if isinstance(c, StrikeLine)]
    return StrikeLineRows.of(line, PHASES)


def test_the_strike_phase_is_found_by_the_line_s_phase_name():
    rows = _rows(problems.sawyer_pool_shot(1.0))
    assert rows.phase == 1
    assert list(rows.nodes(np.array([0, 10, 15, 25]))) == list(range(10, 16))
    with pytest.raises(InvalidInputError, match="'strike'"):
        StrikeLineRows.of(rows.line, ("approach", "stop"))


@pytest.mark.parametrize(
    ("change", "name"),
    [({"align_axis": False}, "align_axis=False"), ({"run_up": 0.2}, "run_up = 0.2 m")],
)
def test_a_line_the_rows_cannot_hold_is_refused(change, name):
    line = _rows(problems.sawyer_pool_shot(1.0)).line
    assert line.run_up is not None  # a pool strike gives its run-up
    with pytest.raises(InvalidInputError, match=name):
        StrikeLineRows.of(dataclasses.replace(line, **change), PHASES)
    timed = dataclasses.replace(line, run_up=None)  # the run-up from speed and delay
    assert StrikeLineRows.of(timed, PHASES).phase == 1


def test_rows_of_lines_in_the_same_phase_share_one_nlp_shape():
    one = _rows(problems.sawyer_pool_shot(1.0))
    slow = problems.sawyer_pool_shot(0.5, heading_deg=10.0)
    other = _rows(slow)
    assert one == other and hash(one) == hash(other)
    fields = {"robot": "r", "limits": (), "tool_frame": "tool", "intervals": (3,), "free": (True,)}
    assert Structure(**fields, tasks=(one,)) == Structure(**fields, tasks=(other,))
    assert dataclasses.replace(one, phase=0) != one
    values = other.values()
    np.testing.assert_array_equal(values["entry"], slow.entry_point)
    assert values["speed"].tolist() == [0.5]
    for name in ("e1", "e2"):  # unit vectors across the direction
        assert abs(float(values[name] @ values["direction"])) < 1e-12
        assert float(np.linalg.norm(values[name])) == pytest.approx(1.0, abs=1e-12)


def test_strike_misses_are_measured_in_the_units_they_name():
    problem = problems.sawyer_pool_shot()
    traj = OptimalControl(contact_retries=0).plan(problem)
    assert _rows(problem).misses(traj, problem.robot) == []
    tight = dataclasses.replace(
        problem, position_tolerance=1e-15, speed_tolerance=1e-15, angle_tolerance=1e-15
    )
    misses = {
        name: (value, allowed, unit)
        for name, value, allowed, unit in _rows(tight).misses(traj, problem.robot)
    }
    assert set(misses) == {"distance to the schedule", "cue axis angle", "speed error"}
    assert misses["distance to the schedule"][1:] == (pytest.approx(0.5e-12), "mm")
    assert misses["cue axis angle"][1:] == (pytest.approx(0.5 * np.degrees(1e-15)), "deg")
    assert misses["speed error"][1:] == (pytest.approx(0.5e-13), "%")
    # Within half of what the default problem allows, in those units: 0.01 mm, 0.01 deg, 0.1 %.
    assert 0 < misses["distance to the schedule"][0] <= 0.5e-2
    assert 0 < misses["cue axis angle"][0] <= 0.5e-2
    assert 0 < misses["speed error"][0] <= 0.5e-1
