"""Tests of planners.description: joint names, phases and metadata of a trajectory, checked."""

from __future__ import annotations

import pickle

import pytest

from optraj.errors import InvalidInputError
from optraj.planners.description import picklable, short_repr
from optraj.planners.trajectory import Phase, Trajectory


def test_phases_outside_the_trajectory_are_refused():
    with pytest.raises(InvalidInputError, match="outside the trajectory"):
        Trajectory.constant([0.0], 1.0, phases=[Phase("late", 0.5, 1.5)])
    # Round-off beyond either end is accepted.
    Trajectory.constant([0.0], 1.0, phases=[Phase("all", -1e-12, 1.0 + 1e-12)])


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: Trajectory([0.0, 1.0], [[[0.0]]], metadata=["ab"]), "metadata must be a mapping"),
        (lambda: Trajectory([0.0, 1.0], [[[0.0]]], phases=5), "phases must be a sequence"),
        (lambda: Trajectory([0.0, 1.0], [[[0.0]]], phases=[5]), "planners.Phase"),
        (lambda: Trajectory([0.0, 1.0], [[[0.0]]], joint_names=5), "joint_names must be"),
        (lambda: Trajectory([0.0, 1.0], [[[0.0]]], joint_names=["a", "b"]), "got 2 names"),
    ],
)
def test_malformed_descriptions_are_typed_errors(build, match):
    with pytest.raises(InvalidInputError, match=match):
        build()


def test_joint_names_may_come_from_a_generator():
    # The names were checked in one pass over the argument and taken in a second: a
    # generator came out empty ("got 0 names").
    traj = Trajectory.constant([0.0, 1.0], 1.0, joint_names=(name for name in ("a", "b")))
    assert traj.joint_names == ("a", "b")


def test_default_joint_names_and_metadata():
    traj = Trajectory.constant([0.0, 1.0, 2.0], 1.0)
    assert traj.joint_names == ("q0", "q1", "q2")
    assert traj.metadata == {}


def test_metadata_that_does_not_pickle_is_left_out_of_a_pickle_only():
    metadata = {"planner": "x", "native": lambda: 0}
    assert picklable(metadata) == {"planner": "x"}
    traj = Trajectory.constant([0.0], 1.0, metadata=metadata)
    clone = pickle.loads(pickle.dumps(traj))
    assert clone.metadata == {"planner": "x"}
    assert set(traj.metadata) == {"planner", "native"}


def test_short_repr_names_the_type_and_shortens_the_value():
    assert short_repr(5) == "int 5"
    assert short_repr(list(range(100))).startswith("list [0, 1, 2")
    assert len(short_repr(list(range(100)))) < 60
