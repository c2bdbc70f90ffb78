"""Tests of planners.ros_reading: the states of a JointTrajectory dict, every bad field named."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.planners.ros_reading import message_states


def _message() -> dict:
    """Two joints, three points at 0, 0.5 and 1.25 s."""
    return {
        "header": {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""},
        "joint_names": ["a", "b"],
        "points": [
            {"positions": [0.0, 1.0], "velocities": [0.0, 0.0], "accelerations": [1.0, 0.0],
             "effort": [], "time_from_start": {"sec": 0, "nanosec": 0}},
            {"positions": [0.2, 1.0], "velocities": [0.5, 0.0], "accelerations": [0.0, 0.0],
             "effort": [3.0, 4.0], "time_from_start": {"sec": 0, "nanosec": 500_000_000}},
            {"positions": [0.5, 1], "velocities": [0.0, 0.0], "accelerations": [-1.0, 0.0],
             "effort": [], "time_from_start": {"sec": 1, "nanosec": 250_000_000}},
        ],
    }  # fmt: skip


def test_states_of_a_message():
    states = message_states(_message(), "message")
    np.testing.assert_allclose(states.times, [0.0, 0.5, 1.25], rtol=0.0, atol=1e-15)
    np.testing.assert_array_equal(states.q, [[0.0, 1.0], [0.2, 1.0], [0.5, 1.0]])
    np.testing.assert_array_equal(states.qd[:, 0], [0.0, 0.5, 0.0])
    np.testing.assert_array_equal(states.qdd[:, 0], [1.0, 0.0, -1.0])
    assert states.joint_names == ("a", "b")
    bare = _message()
    for point in bare["points"]:
        del point["accelerations"]  # ROS leaves them out, or empty
    bare["points"][1]["accelerations"] = []
    assert message_states(bare, "message").qdd is None


def _edited(path: str, value):
    message = copy.deepcopy(_message())
    keys = [int(key) if key.isdigit() else key for key in path.split(".")]
    target = message
    for key in keys[:-1]:
        target = target[key]
    if value is KeyError:
        del target[keys[-1]]
    else:
        target[keys[-1]] = value
    return message


@pytest.mark.parametrize(
    ("path", "value", "match"),
    [
        ("joint_names", KeyError, "joint_names must be a list of str, got NoneType None"),
        ("joint_names", ["a", 2], "joint_names must be a list of str"),
        ("points", [], "points must be a list of at least 2 points"),
        ("points.1", "p", r"points\[1\] must be a mapping, got str 'p'"),
        ("points.1.positions", [0.0], r"points\[1\].positions must be 2 finite numbers"),
        ("points.1.positions", [0.0, float("nan")], r"points\[1\].positions must be 2 finite"),
        ("points.1.positions", [0.0, True], r"points\[1\].positions must be 2 finite"),
        ("points.2.velocities", KeyError, r"points\[2\].velocities must hold 2 values, got none"),
        ("points.1.accelerations", [], r"points\[1\].accelerations are empty while other"),
        ("points.1.time_from_start", {"sec": 0}, r"points\[1\].time_from_start must be \{sec"),
        ("points.1.time_from_start", {"sec": 0, "nanosec": 2_000_000_000},
         r"points\[1\].time_from_start must be"),
        ("points.1.time_from_start", {"sec": 0.5, "nanosec": 0},
         r"points\[1\].time_from_start must be"),
        ("points.0.time_from_start", {"sec": 0, "nanosec": 1},
         r"points\[0\].time_from_start must be 0 s .* got 1e-09 s"),
        ("points.2.time_from_start", {"sec": 0, "nanosec": 500_000_000},
         r"points\[2\].time_from_start 0.5 s does not come after the point before \(0.5 s\)"),
    ],
)  # fmt: skip
def test_a_bad_field_is_a_typed_error_naming_it(path, value, match):
    with pytest.raises(InvalidInputError, match=f"^'m.yaml': {match}"):
        message_states(_edited(path, value), "'m.yaml'")


def test_a_message_that_is_no_mapping_is_refused():
    with pytest.raises(InvalidInputError, match=r"^message: a JointTrajectory must be a mapping"):
        message_states([1, 2], "message")
