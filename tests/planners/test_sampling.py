"""Tests of planners.sampling: evaluation at breakpoints and between, holding past the end,
time grids, rates."""

from __future__ import annotations

import numpy as np
import pytest

from optraj.errors import InvalidInputError
from optraj.planners.sampling import TIME_TOLERANCE, uniform_times
from optraj.planners.trajectory import Trajectory


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


def test_breakpoints_are_right_continuous_and_jumps_are_kept():
    # Two constant segments: 0 then 1; at t = 1 the second one applies.
    traj = Trajectory([0.0, 1.0, 2.0], [[[0.0]], [[1.0]]])
    np.testing.assert_array_equal(traj.sample([0.999, 1.0, 2.0]).q[:, 0], [0.0, 1.0, 1.0])


def test_sampling_outside_the_duration_is_an_error():
    traj = Trajectory.constant([0.0, 1.0], 2.0)
    with pytest.raises(
        InvalidInputError,
        match=r"^time 2.5 s is outside the trajectory \[0, 2\] s; sample\(t, hold=True\) holds",
    ):
        traj.sample([0.0, 2.5])
    with pytest.raises(
        InvalidInputError, match=r"^time -0.5 s is outside the trajectory \[0, 2\] s$"
    ):
        traj.sample(-0.5, hold=True)  # before the start there is nothing to hold
    with pytest.raises(InvalidInputError, match="finite"):
        traj.sample(np.nan)
    traj.sample(2.0 + 1e-12)  # round-off at the end is accepted


def test_holding_past_the_end_keeps_the_final_position_at_rest():
    # q(t) = t^2 on [0, 1]: it ends moving, at 2 rad/s.
    traj = Trajectory([0.0, 1.0], [[[0.0], [0.0], [1.0]]])
    sample = traj.sample([0.5, 1.0, 1.5, 30.0], hold=True)
    np.testing.assert_array_equal(sample.t, [0.5, 1.0, 1.5, 30.0])
    np.testing.assert_array_equal(sample.q[:, 0], [0.25, 1.0, 1.0, 1.0])
    np.testing.assert_array_equal(sample.qd[:, 0], [1.0, 2.0, 0.0, 0.0])  # its own value at T
    np.testing.assert_array_equal(sample.qdd[:, 0], [2.0, 2.0, 0.0, 0.0])
    np.testing.assert_array_equal(sample.jerk[:, 0], 0.0)
    one = traj.sample(3.0, hold=True)
    assert one.t == 3.0 and one.q.tolist() == [1.0] and one.qd.tolist() == [0.0]
    # Round-off past the end is the end, with or without hold.
    end = traj.sample(1.0 + 0.5 * TIME_TOLERANCE, hold=True)
    assert end.t == 1.0 and end.qd.tolist() == [2.0]
    with pytest.raises(InvalidInputError, match="hold must be"):
        traj.sample(2.0, hold="yes")


@pytest.mark.parametrize(
    ("duration", "rate", "expected"),
    [
        (1.0, 4.0, [0.0, 0.25, 0.5, 0.75, 1.0]),
        (1.1, 4.0, [0.0, 0.25, 0.5, 0.75, 1.0, 1.1]),
        (0.1 * 3, 10.0, [0.0, 0.1, 0.2, 0.1 * 3]),  # 3 * 0.1 is 0.30000000000000004
        (0.3 + 2 * TIME_TOLERANCE, 10.0, [0.0, 0.1, 0.2, 0.3, 0.3 + 2 * TIME_TOLERANCE]),
        (0.05, 4.0, [0.0, 0.05]),
        (1e-12, 1.0, [0.0, 1e-12]),
    ],
)
def test_uniform_times_are_k_over_rate_and_the_end_once(duration, rate, expected):
    times = uniform_times(duration, rate)
    np.testing.assert_array_equal(times, expected)


def test_to_arrays_includes_both_sides_of_breakpoints():
    traj = Trajectory([0.0, 1.0, 2.0], [[[0.0]], [[1.0]]])
    arrays = traj.to_arrays(rate=4.0)
    assert set(arrays) == {"t", "q", "qd", "qdd", "jerk"}
    assert 1.0 in arrays["t"] and np.any((arrays["t"] < 1.0) & (arrays["t"] > 0.999))


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
