"""Tests of planners.serialization: JSON round trips, bad files and their messages."""

from __future__ import annotations

import json

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.planners.trajectory import Phase, Trajectory


def _random_states(seed: int, m: int = 6, n: int = 3):
    rng = np.random.default_rng(seed)
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 0.5, m - 1))])
    return t, rng.normal(size=(m, n)), rng.normal(size=(m, n)), rng.normal(size=(m, n))


def test_json_round_trip_is_exact_and_drops_non_json_metadata(tmp_path):
    t, q, qd, qdd = _random_states(2)
    traj = Trajectory.from_hermite(
        t, q, qd, qdd, joint_names=("a", "b", "c"), phases=[Phase("p", 0.0, t[2])],
        metadata={"planner": "x", "solve_time": 0.25, "native": object(), "array": np.arange(3)},
    )  # fmt: skip
    path = tmp_path / "traj.json"
    traj.to_json(path)
    back = Trajectory.from_json(path)
    grid = traj.times(500.0)
    np.testing.assert_array_equal(back.sample(grid).q, traj.sample(grid).q)
    assert back.joint_names == ("a", "b", "c")
    assert back.phases == traj.phases
    assert back.metadata == {"planner": "x", "solve_time": 0.25, "array": [0, 1, 2]}
    assert Trajectory.from_json(traj.to_json()).duration == traj.duration


@pytest.mark.parametrize(
    ("source", "match"),
    [
        ('{"format": "other"}', "not an optraj trajectory"),
        ("{nope", "malformed"),
        ("/no/such.json", "no trajectory file"),
    ],
)
def test_bad_json_is_a_typed_error(source, match):
    with pytest.raises(InvalidInputError, match=match):
        Trajectory.from_json(source)


def test_a_file_that_is_no_trajectory_is_named_in_the_error(tmp_path):
    path = tmp_path / "other.json"
    path.write_text('{"format": "other"}')
    with pytest.raises(InvalidInputError, match=rf"^'{path}': not an optraj trajectory"):
        Trajectory.from_json(path)
    path.write_text('{"format": "optraj.trajectory/1", "breakpoints": [0, 1]}')
    with pytest.raises(InvalidInputError, match=rf"^'{path}': .*no coefficients, phases"):
        Trajectory.from_json(str(path))
    # JSON text has no file to name.
    with pytest.raises(InvalidInputError, match=r"^not an optraj trajectory"):
        Trajectory.from_json('{"format": "other"}')


def test_writing_to_a_path_that_cannot_be_written_is_a_typed_error(tmp_path):
    traj = Trajectory.constant([0.0], 1.0)
    with pytest.raises(InvalidInputError, match=r"cannot write .*: Is a directory"):
        traj.to_json(tmp_path)
    with pytest.raises(InvalidInputError, match=r"cannot write .*no_such_folder"):
        traj.to_json(tmp_path / "no_such_folder" / "t.json")
    with pytest.raises(InvalidInputError, match="path must be a str or a Path, got int 3"):
        traj.to_json(3)


def _good_dict() -> dict:
    return Trajectory.constant([0.0], 1.0, phases=[Phase("hold", 0.0, 1.0)]).to_dict()


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"metadata": ["abc"]}, "metadata must be an object"),  # was dict()'s ValueError
        ({"metadata": [1, 2]}, "metadata must be an object"),
        ({"phases": 5}, "phases must be a list"),
        ({"phases": [{"name": "a"}]}, "phases must be a list"),
        ({"phases": [{"name": "a", "t_start": "0", "t_end": 1}]}, "t_start must be a numeric"),
        ({"joint_names": 7}, "joint_names must be"),
        ({"joint_names": [7]}, "joint_names must be"),
        ({"breakpoints": [0, "1"]}, "breakpoints must be a numeric"),
        ({"metadata": {"deep": json.loads("[" * 40 + "]" * 40)}}, "nested at most 32 levels"),
    ],
)
def test_malformed_trajectory_data_is_a_typed_error(change, match):
    data = {**_good_dict(), **change}
    with pytest.raises(InvalidInputError, match=match):
        Trajectory.from_dict(data)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ('{"a": ' + "[" * 100_000 + "]" * 100_000 + "}", "nested too deeply"),  # RecursionError
        ('{"format": "optraj.trajectory/1", "breakpoints": [0, 1' + "0" * 5000 + "]}",
         "4300 digits"),  # json's own ValueError for long integers
    ],
)  # fmt: skip
def test_json_that_json_cannot_read_is_a_typed_error(text, match, tmp_path):
    with pytest.raises(InvalidInputError, match=f"trajectory JSON is malformed: .*{match}"):
        Trajectory.from_json(text)
    path = tmp_path / "bad.json"
    path.write_text(text)
    with pytest.raises(InvalidInputError, match=f"malformed in '{path}': .*{match}"):
        Trajectory.from_json(path)


def test_oversized_json_is_refused_before_it_is_read(tmp_path, monkeypatch):
    from optraj import planners

    text = _good_dict()
    path = tmp_path / "t.json"
    path.write_text(json.dumps(text))
    monkeypatch.setattr(planners.trajectory, "MAX_JSON_BYTES", 100)
    with pytest.raises(InvalidInputError, match=r"bytes, more than the 100 bytes"):
        Trajectory.from_json(path)
    with pytest.raises(InvalidInputError, match="more than the 100 of any"):
        Trajectory.from_json(json.dumps(text))
    with pytest.raises(InvalidInputError, match="JSON text or a file path"):
        Trajectory.from_json(5)
