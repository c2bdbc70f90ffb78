"""Tests of planners.arrays.multi_segment: mstraj timing, lines, blends, errors, the Toolbox."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import get_robot
from hypothesis import given, settings
from hypothesis import strategies as st

from optraj import planners
from optraj.errors import InvalidInputError
from optraj.planners.arrays.multi_segment import mstraj

VIA = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, 2.0]])


def _sides(traj):
    """(left, right) values of q, qd and qdd at every inner breakpoint, from the polynomials."""
    c = traj.coefficients
    lengths = np.diff(traj.breakpoints)[:-1]
    out = []
    for _ in range(3):
        powers = lengths[:, None] ** np.arange(c.shape[1])[None, :]
        out.append((np.einsum("kd,kdn->kn", powers, c[:-1]), c[1:, 0]))
        c = c[:, 1:] * np.arange(1, c.shape[1])[None, :, None]
    return out


def test_segment_times_follow_the_toolbox_rules_worked_by_hand():
    # tacc = 0.2 s; segment 1: dq = (1, 2) at 1 per s -> 2 s + half a blend 0.1 s = 2.1 s
    # (axis 1 slowest); segment 2: dq = (2, 0) -> 2 s + a blend 0.2 s = 2.2 s (axis 0).
    tg = mstraj(VIA, 0.1, 0.2, qdmax=[1.0, 1.0])
    np.testing.assert_allclose(tg.arrive, [2.1, 4.3], rtol=1e-12)
    assert [info.slowest for info in tg.info] == [1, 0]
    np.testing.assert_allclose([info.segtime for info in tg.info], [2.1, 2.2], rtol=1e-12)
    np.testing.assert_allclose([info.clock for info in tg.info], [0.0, 2.0], atol=1e-12)
    assert len(tg) == 44 and tg.istime is True
    np.testing.assert_allclose(np.diff(tg.t), 0.1, rtol=1e-9)
    np.testing.assert_array_equal(tg.via, VIA[1:])
    assert not tg.via.flags.writeable and not tg.arrive.flags.writeable
    np.testing.assert_array_equal(tg.q[0], VIA[0])
    np.testing.assert_allclose(tg.q[-1], VIA[-1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(tg.qd[[0, -1]], 0.0, rtol=0, atol=1e-12)


def test_lines_pass_the_via_points_and_blends_cut_the_corner_by_three_32nds():
    tg = mstraj(VIA, 0.1, 0.2, qdmax=[1.0, 1.0])
    v_in, v_out = np.array([1.0, 2.0]) / 2.1, np.array([2.0, 0.0]) / 2.2
    traj = tg.trajectory
    np.testing.assert_allclose(traj.sample(1.0).qd, v_in, rtol=1e-12)
    np.testing.assert_allclose(traj.sample(1.0).q, v_in * 1.0, rtol=1e-12)
    np.testing.assert_allclose(traj.sample(3.0).q, VIA[1] + v_out * (3.0 - 2.1), rtol=1e-12)
    # A quintic blend of tacc with zero end accelerations, centred on the via time.
    np.testing.assert_allclose(
        traj.sample(2.1).q - VIA[1], 3.0 / 32.0 * 0.2 * (v_out - v_in), rtol=1e-9, atol=1e-15
    )
    assert [p.name for p in traj.phases] == ["segment 1", "segment 2"]


def test_given_segment_times_end_velocities_and_start():
    tg = mstraj(VIA, 0.05, 0.4, tsegment=[2.0, 3.0], qd0=[0.1, 0.0], qdf=[0.0, -0.2])
    np.testing.assert_allclose(tg.arrive, [2.0, 5.0])
    assert [info.slowest for info in tg.info] == [None, None]
    np.testing.assert_allclose(tg.qd[0], [0.1, 0.0], atol=1e-12)
    np.testing.assert_allclose(tg.qd[-1], [0.0, -0.2], atol=1e-12)
    with_start = mstraj(VIA[1:], 0.05, 0.4, tsegment=[2.0, 3.0], q0=VIA[0])
    np.testing.assert_allclose(with_start.q, mstraj(VIA, 0.05, 0.4, tsegment=[2.0, 3.0]).q)
    np.testing.assert_array_equal(with_start.via, VIA[1:])


def test_without_blends_the_lines_meet_at_the_via_points_with_jumps():
    tg = mstraj(VIA, 0.1, 0.0, tsegment=[1.0, 2.0])
    traj = tg.trajectory
    np.testing.assert_allclose(traj.sample(1.0).q, VIA[1], atol=1e-12)
    np.testing.assert_array_equal(traj.breakpoints, [0.0, 1.0, 3.0])
    np.testing.assert_allclose(traj.sample([0.0, 1.0]).qd, np.diff(VIA, axis=0) / [[1.0], [2.0]])


def test_per_segment_blend_times_and_the_last_sample_at_the_end():
    tg = mstraj(VIA, 0.3, [0.6, 1.2], tsegment=[2.0, 2.5])
    np.testing.assert_allclose(tg.t[-2:], [4.2, 4.5])  # 4.5 s is not a whole number of steps
    np.testing.assert_allclose(tg.q[-1], VIA[-1], atol=1e-12)
    np.testing.assert_allclose([info.clock for info in tg.info], [0.0, 2.0 - 0.6])


def test_random_via_points_give_c2_motion_through_the_lines():
    rng = np.random.default_rng(36)
    for _ in range(40):
        k, n = int(rng.integers(2, 7)), int(rng.integers(1, 5))
        via = rng.uniform(-2.0, 2.0, (k, n))
        dt = float(rng.choice([0.01, 0.02, 0.05]))
        tg = mstraj(via, dt, rng.uniform(0.0, 0.5), qdmax=rng.uniform(0.5, 3.0, n))
        traj = tg.trajectory
        np.testing.assert_allclose(traj.sample(traj.duration).q, via[-1], atol=1e-12)
        np.testing.assert_allclose(tg.arrive[-1], traj.duration, rtol=1e-12)
        assert np.all(np.diff(tg.arrive) > 0.0)
        # q, qd and qdd continuous across every breakpoint: the blends meet the lines.
        for left, right in _sides(traj):
            np.testing.assert_allclose(left, right, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(traj.sample(tg.t).q, tg.q, rtol=0, atol=0)


def test_checker_finds_bounded_acceleration_and_jerk():
    robot = get_robot("sawyer")
    via = robot.limits.sample(np.random.default_rng(4), 4)
    tg = mstraj(via, 0.01, 0.5, qdmax=0.5 * robot.limits.velocity)
    report = planners.check(tg.trajectory, robot)
    assert report["position"].ok
    assert np.isfinite(report["acceleration"].value) and np.isfinite(report["jerk"].value)
    line = np.max(np.abs(np.diff(via, axis=0)) / np.array([i.segtime for i in tg.info])[:, None])
    assert report["velocity"].value <= 3.0 * line  # the blends from rest overshoot the line


@pytest.mark.parametrize(
    ("kwargs", "name", "words"),
    [
        ({"qdmax": 1.0, "tsegment": [1.0, 1.0]}, "qdmax", "not both"),
        ({}, "tsegment", "give qdmax"),
        ({"tsegment": [1.0]}, "tsegment", r"shape \(2,\)"),
        ({"tsegment": [1.0, 0.1]}, "tsegment", r"tsegment\[1\] = 0.1 s is too short.*0.2 s"),
        ({"tsegment": [1.0, -1.0], "tacc": 0.0}, "tsegment", "must be >= 1e-06 s"),
        ({"qdmax": [1.0, 0.0]}, "qdmax", "qdmax must be > 0"),
        ({"qdmax": 1.0, "tacc": -0.1}, "tacc", "tacc must be >= 0 s"),
        ({"qdmax": 1.0, "dt": 0.0}, "dt", "dt must be >= 1e-06 s"),
        ({"qdmax": 1.0, "q0": [0.0]}, "q0", r"q0 must have shape \(2,\)"),
        ({"qdmax": 1.0, "qdf": [0.0, 0.0, 0.0]}, "qdf", r"qdf must have shape \(2,\)"),
        ({"qdmax": 1.0, "viapoints": VIA[:1]}, "viapoints", "two rows"),
        ({"qdmax": 1.0, "viapoints": [[0.0, np.nan], [1.0, 1.0]]}, "viapoints", "finite"),
        ({"qdmax": 0.5, "dt": 1e-6}, "dt", "make dt larger"),
        ({"qdmax": 1e-6}, "qdmax", "more than 86400 s: raise qdmax"),
        ({"tsegment": [1e5, 1.0]}, "tsegment", "more than 86400 s"),
    ],
)
def test_bad_input_is_refused_naming_the_argument(kwargs, name, words):
    args = {"viapoints": VIA, "dt": 0.1, "tacc": 0.2, **kwargs}
    with pytest.raises(InvalidInputError, match=words) as caught:
        mstraj(**args)
    assert caught.value.name == name


@pytest.mark.slow
def test_samples_agree_with_the_robotics_toolbox(rtb):
    # The Toolbox's first row is the state at dt: its rows are ours from the second on.
    rng = np.random.default_rng(12)
    for _ in range(10):
        via = rng.uniform(-2.0, 2.0, (int(rng.integers(2, 6)), 3))
        dt = 0.05
        tacc = float(rng.choice([0.0, 0.1, 0.2, 0.4, 0.5]))  # whole steps, with no round-off
        qdmax = rng.uniform(0.5, 2.0, 3)
        qd0, qdf = rng.uniform(-0.5, 0.5, (2, 3))
        ours = mstraj(via, dt, tacc, qdmax=qdmax, qd0=qd0, qdf=qdf)
        theirs = rtb.mstraj(via, dt, tacc, qdmax=qdmax, qd0=qd0, qdf=qdf)
        np.testing.assert_allclose(ours.q[1:], theirs.q, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(ours.arrive, theirs.arrive, rtol=1e-9)
        assert [i.slowest for i in ours.info] == [i.slowest for i in theirs.info[:-1]]


@settings(max_examples=150, deadline=None, derandomize=True)
@given(
    scale=st.floats(allow_nan=True, allow_infinity=True),
    dt=st.floats(-1.0, 10.0),
    tacc=st.floats(-1.0, 10.0),
    speed=st.floats(allow_nan=True, allow_infinity=True),
    by_time=st.booleans(),
)
def test_any_numbers_give_finite_samples_or_a_typed_error(scale, dt, tacc, speed, by_time):
    timing = {"tsegment": [abs(speed)] * 2} if by_time else {"qdmax": speed}
    try:
        tg = mstraj(VIA * scale, dt, tacc, **timing)
    except InvalidInputError:
        return
    assert all(np.all(np.isfinite(v)) for v in (tg.q, tg.qd, tg.qdd))
    np.testing.assert_allclose(tg.q[-1], VIA[-1] * scale, rtol=1e-9, atol=1e-9)
