"""Tests of planners.trajectory.Trajectory: phases by name, deferred building, pickling, errors."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.trajectory import Phase, Trajectory


def _random_states(seed: int, m: int = 6, n: int = 3):
    rng = np.random.default_rng(seed)
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 0.5, m - 1))])
    return t, rng.normal(size=(m, n)), rng.normal(size=(m, n)), rng.normal(size=(m, n))


def test_phases_are_found_by_name():
    traj = Trajectory.constant([0.0], 1.0, phases=[Phase("a", 0.0, 0.4), Phase("b", 0.4, 1.0)])
    assert traj.phase("b").duration == pytest.approx(0.6)
    with pytest.raises(UnknownNameError, match="known: a, b"):
        traj.phase("c")


def test_deferred_trajectory_is_built_once_on_first_use():
    t, q, qd, _ = _random_states(4)
    eager = Trajectory.from_hermite(t, q, qd)
    calls = []

    def build():
        calls.append(1)
        return eager.breakpoints, eager.coefficients

    lazy = Trajectory.deferred(
        eager.duration,
        eager.dof,
        build,
        joint_names=["a", "b", "c"],
        phases=[Phase("move", 0.0, eager.duration)],
        metadata={"planner": "test"},
    )
    assert (lazy.duration, lazy.dof, lazy.joint_names) == (eager.duration, 3, ("a", "b", "c"))
    assert lazy.phase("move").t_end == eager.duration and lazy.metadata["planner"] == "test"
    assert not calls
    times = np.linspace(0.0, eager.duration, 101)
    for _ in range(2):
        for got, want in zip(lazy.sample(times), eager.sample(times), strict=True):
            np.testing.assert_array_equal(got, want)
    assert len(calls) == 1
    np.testing.assert_array_equal(lazy.breakpoints, eager.breakpoints)


def test_deferred_trajectory_pickles_as_built():
    t, q, qd, _ = _random_states(5)
    eager = Trajectory.from_hermite(t, q, qd)
    lazy = Trajectory.deferred(
        eager.duration, eager.dof, lambda: (eager.breakpoints, eager.coefficients)
    )
    clone = pickle.loads(pickle.dumps(lazy))  # the lambda itself would not pickle
    np.testing.assert_array_equal(clone.coefficients, eager.coefficients)
    assert clone.duration == eager.duration


@pytest.mark.parametrize(
    ("duration", "dof", "match"),
    [(0.0, 3, "duration"), (float("nan"), 3, "duration"), (1.0, 0, "dof")],
)
def test_deferred_trajectory_rejects_bad_descriptions(duration, dof, match):
    with pytest.raises(InvalidInputError, match=match):
        Trajectory.deferred(duration, dof, lambda: ([0.0, 1.0], np.zeros((1, 1, 3))))


def test_a_trajectory_pickled_in_the_former_layout_still_loads():
    t, q, qd, _ = _random_states(6)
    eager = Trajectory.from_hermite(t, q, qd, joint_names=["a", "b", "c"])
    former = {
        "_knots": eager.breakpoints,
        "_coeffs": list(eager._coeffs),  # the position polynomial and three derivatives
        "joint_names": eager.joint_names,
        "phases": (),
        "metadata": {},
    }
    restored = Trajectory.__new__(Trajectory)
    restored.__setstate__(former)
    assert (restored.duration, restored.dof) == (eager.duration, 3)
    np.testing.assert_array_equal(restored.sample(t).qd, eager.sample(t).qd)


# ------------------------------------------------------------- typed errors at every entry


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: Trajectory.constant([0.0], "2"), "duration must be a numeric"),
        (lambda: Trajectory.constant([0.0], 1e300), r"duration must be <= 86400 s"),
        (lambda: Trajectory.deferred(True, 1, lambda: None), "duration must be a numeric"),
        (lambda: Trajectory.deferred(1e300, 1, lambda: None), "duration must be <= 86400 s"),
        (lambda: Trajectory.deferred(1.0, 1, None), "build must be a function"),
        (lambda: Trajectory.constant([0.0], 1.0).then(5), "joins planners.Trajectory"),
        (lambda: Trajectory.sequence([("a", [5])]), r"\(name, \[Trajectory, ...\]\) pairs"),
        (lambda: Trajectory.sequence(5), "pairs"),
    ],
)
def test_malformed_arguments_are_typed_errors(build, match):
    with pytest.raises(InvalidInputError, match=match):
        build()
