"""Tests of planners.trajectory.Trajectory: sampling, construction, joining, export."""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.trajectory import Phase, Trajectory


def _random_states(seed: int, m: int = 6, n: int = 3):
    rng = np.random.default_rng(seed)
    t = np.concatenate([[0.0], np.cumsum(rng.uniform(0.1, 0.5, m - 1))])
    return t, rng.normal(size=(m, n)), rng.normal(size=(m, n)), rng.normal(size=(m, n))


def test_polynomial_evaluation_and_derivatives_on_a_known_cubic():
    # q(t) = 1 + 2t - 3t^2 + 4t^3 on [0, 2]: derivatives by hand.
    traj = Trajectory([0.0, 2.0], [[[1.0], [2.0], [-3.0], [4.0]]])
    t = np.array([0.0, 0.5, 1.7, 2.0])
    sample = traj.sample(t)
    np.testing.assert_allclose(sample.q[:, 0], 1 + 2 * t - 3 * t**2 + 4 * t**3, rtol=1e-14)
    np.testing.assert_allclose(sample.qd[:, 0], 2 - 6 * t + 12 * t**2, rtol=1e-14)
    np.testing.assert_allclose(sample.qdd[:, 0], -6 + 24 * t, rtol=1e-14)
    np.testing.assert_allclose(sample.jerk[:, 0], 24.0, rtol=1e-14)
    assert traj.sample(0.5).q.shape == (1,)


@pytest.mark.parametrize("with_acceleration", [False, True])
def test_hermite_meets_every_state_and_derivatives_agree_with_finite_differences(with_acceleration):
    t, q, qd, qdd = _random_states(1)
    traj = Trajectory.from_hermite(t, q, qd, qdd if with_acceleration else None)
    sample = traj.sample(t)
    np.testing.assert_allclose(sample.q, q, atol=1e-12)
    np.testing.assert_allclose(sample.qd, qd, atol=1e-11)
    if with_acceleration:
        np.testing.assert_allclose(sample.qdd, qdd, atol=1e-9)
    inner = np.linspace(0.01, traj.duration - 0.01, 97)
    h = 1e-6
    plus, minus = traj.sample(inner + h), traj.sample(inner - h)
    # Away from breakpoints the polynomial derivatives are exact; central differences agree.
    mask = np.min(np.abs(inner[:, None] - t[None, :]), axis=1) > 2 * h
    np.testing.assert_allclose(
        ((plus.q - minus.q) / (2 * h))[mask], traj.sample(inner).qd[mask], atol=1e-6
    )
    np.testing.assert_allclose(
        ((plus.qdd - minus.qdd) / (2 * h))[mask], traj.sample(inner).jerk[mask], atol=1e-4
    )


def test_breakpoints_are_right_continuous_and_jumps_are_kept():
    # Two constant segments: 0 then 1; at t = 1 the second one applies.
    traj = Trajectory([0.0, 1.0, 2.0], [[[0.0]], [[1.0]]])
    np.testing.assert_array_equal(traj.sample([0.999, 1.0, 2.0]).q[:, 0], [0.0, 1.0, 1.0])


@pytest.mark.parametrize(
    ("breakpoints", "coefficients", "match"),
    [
        ([0.0, 1.0], np.zeros((2, 1, 1)), "one row per segment"),
        ([0.5, 1.0], np.zeros((1, 1, 1)), "start at 0"),
        ([0.0, 1.0, 1.0], np.zeros((2, 1, 1)), "strictly increase"),
        ([0.0, 1.0], [[[np.nan]]], "finite"),
        ([0.0, 1.0], np.zeros((1, 2)), "shape"),
    ],
)
def test_bad_construction_is_rejected(breakpoints, coefficients, match):
    with pytest.raises(InvalidInputError, match=match):
        Trajectory(breakpoints, coefficients)


def test_sampling_outside_the_duration_is_an_error():
    traj = Trajectory.constant([0.0, 1.0], 2.0)
    with pytest.raises(InvalidInputError, match=r"time 2.5 s is outside the trajectory \[0, 2\] s"):
        traj.sample([0.0, 2.5])
    with pytest.raises(InvalidInputError, match="finite"):
        traj.sample(np.nan)
    traj.sample(2.0 + 1e-12)  # round-off at the end is accepted


def test_phases_are_checked_and_found():
    traj = Trajectory.constant([0.0], 1.0, phases=[Phase("a", 0.0, 0.4), Phase("b", 0.4, 1.0)])
    assert traj.phase("b").duration == pytest.approx(0.6)
    with pytest.raises(UnknownNameError, match="known: a, b"):
        traj.phase("c")
    with pytest.raises(InvalidInputError, match="outside the trajectory"):
        Trajectory.constant([0.0], 1.0, phases=[Phase("late", 0.5, 1.5)])
    with pytest.raises(InvalidInputError, match="ends at"):
        Phase("backwards", 1.0, 0.5)


def test_then_shifts_time_and_phases_and_raises_degree():
    first = Trajectory([0.0, 1.0], [[[0.0], [1.0]]], phases=[Phase("ramp", 0.0, 1.0)])
    second = Trajectory.constant([1.0], 0.5, phases=[Phase("hold", 0.0, 0.5)])
    joined = first.then(second)
    assert joined.duration == pytest.approx(1.5)
    assert [p.name for p in joined.phases] == ["ramp", "hold"]
    assert joined.phase("hold").t_start == pytest.approx(1.0)
    np.testing.assert_allclose(joined.sample([0.5, 1.2]).q[:, 0], [0.5, 1.0])
    with pytest.raises(InvalidInputError, match="1 and 2 joints"):
        first.then(Trajectory.constant([0.0, 0.0], 1.0))


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


def test_csv_and_ros_exports(tmp_path):
    traj = Trajectory([0.0, 1.5], [[[0.0, 1.0], [1.0, 0.0]]], joint_names=("a", "b"))
    path = tmp_path / "traj.csv"
    traj.to_csv(path, rate=10.0)
    lines = path.read_text().splitlines()
    assert lines[0] == "t,q_a,q_b,qd_a,qd_b,qdd_a,qdd_b,jerk_a,jerk_b"
    assert len(lines) == 1 + 16  # 0 .. 1.5 s at 10 Hz
    assert [float(v) for v in lines[-1].split(",")[:3]] == [1.5, 1.5, 1.0]
    ros = traj.to_ros(rate=2.0)
    assert ros["joint_names"] == ["a", "b"]
    assert [p["time_from_start"] for p in ros["points"]][-1] == {"sec": 1, "nanosec": 500_000_000}
    assert ros["points"][1]["positions"] == [0.5, 1.0]
    assert ros["points"][1]["velocities"] == [1.0, 0.0]
    json.dumps(ros)  # plain data


def test_to_arrays_includes_both_sides_of_breakpoints():
    traj = Trajectory([0.0, 1.0, 2.0], [[[0.0]], [[1.0]]])
    arrays = traj.to_arrays(rate=4.0)
    assert set(arrays) == {"t", "q", "qd", "qdd", "jerk"}
    assert 1.0 in arrays["t"] and np.any((arrays["t"] < 1.0) & (arrays["t"] > 0.999))


def test_sequence_names_one_phase_per_group_of_pieces():
    ramp = Trajectory([0.0, 1.0], [[[0.0], [1.0]]])
    hold = Trajectory.constant([1.0], 0.5)
    traj = Trajectory.sequence([("idle", []), ("ramp", [ramp]), ("rest", [hold, hold])])
    assert [(p.name, p.t_start, p.t_end) for p in traj.phases] == [
        ("idle", 0.0, 0.0),
        ("ramp", 0.0, 1.0),
        ("rest", 1.0, 2.0),
    ]
    np.testing.assert_allclose(traj.sample([0.5, 1.7]).q[:, 0], [0.5, 1.0])
    with pytest.raises(InvalidInputError, match="at least one piece"):
        Trajectory.sequence([("idle", [])])


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


def test_deferred_build_that_does_not_fit_is_rejected_on_first_use():
    lazy = Trajectory.deferred(2.0, 3, lambda: ([0.0, 1.0], np.zeros((1, 1, 3))))
    with pytest.raises(InvalidInputError, match=r"deferred trajectory of 2\.0 s"):
        lazy.sample(0.5)


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
        (lambda: Trajectory([0.0, 1.0], [[[0.0]]], metadata=["ab"]), "metadata must be a mapping"),
        (lambda: Trajectory([0.0, 1.0], [[[0.0]]], phases=5), "phases must be a sequence"),
        (lambda: Trajectory([0.0, 1.0], [[[0.0]]], phases=[5]), "planners.Phase"),
        (lambda: Trajectory([0.0, 1.0], [[[0.0]]], joint_names=5), "joint_names must be"),
        (lambda: Trajectory([0.0, 1e300], [[[0.0]]]), r"<= 86400 s, got 1e\+300 s"),
        (lambda: Phase("a", "0", "1"), "t_start must be a numeric"),
        (lambda: Phase("a", False, True), "t_start must be a numeric"),
        (lambda: Phase(3, 0.0, 1.0), "phase name must be a str"),
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


@pytest.mark.parametrize(
    ("rate", "match"),
    [
        ("1000", "rate must be a numeric"),
        (True, "rate must be a numeric"),  # a bool is no rate (it sampled at 1 Hz)
        (1e300, r"rate must be <= 1e\+06 Hz, got 1e\+300 Hz"),
    ],
)
def test_a_rate_is_a_number_in_its_range(rate, match):
    traj = Trajectory.constant([0.0], 1.0)
    with pytest.raises(InvalidInputError, match=match):
        traj.times(rate)
    with pytest.raises(InvalidInputError, match=match):
        traj.to_ros(rate)


def test_a_sampling_grid_holds_at_most_max_count_values():
    traj = Trajectory.constant(np.zeros(7), 2000.0)  # 2e6 + 1 samples of 7 joints at 1 kHz
    with pytest.raises(InvalidInputError, match=r"1\.4e\+07 sampled values, more than MAX_COUNT"):
        traj.times(1000.0)
    with pytest.raises(InvalidInputError, match=r"give rate <= 714\.28\d+ Hz"):
        traj.to_arrays(1000.0)
    assert traj.times(700.0, include_breakpoints=False).size == 1_400_001


def test_writing_to_a_path_that_cannot_be_written_is_a_typed_error(tmp_path):
    traj = Trajectory.constant([0.0], 1.0)
    with pytest.raises(InvalidInputError, match=r"cannot write .*: Is a directory"):
        traj.to_csv(tmp_path, rate=10.0)
    with pytest.raises(InvalidInputError, match=r"cannot write .*: Is a directory"):
        traj.to_json(tmp_path)
    with pytest.raises(InvalidInputError, match=r"cannot write .*no_such_folder"):
        traj.to_json(tmp_path / "no_such_folder" / "t.json")
    with pytest.raises(InvalidInputError, match="path must be a str or a Path"):
        traj.to_csv(3)


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


def test_joint_names_may_come_from_a_generator():
    # The names were checked in one pass over the argument and taken in a second: a
    # generator came out empty ("got 0 names").
    traj = Trajectory.constant([0.0, 1.0], 1.0, joint_names=(name for name in ("a", "b")))
    assert traj.joint_names == ("a", "b")
