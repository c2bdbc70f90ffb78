"""Tests of planners.export_csv: fixed-rate rows, round trips within the sampling error, bad
files."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
from conftest import get_robot

from optraj import planners, problems
from optraj.errors import InvalidInputError
from optraj.planners.trajectory import Trajectory

# The round-trip bound: between two rows h = 1 / rate [s] apart, ``from_csv`` is the quintic
# Hermite interpolant of (q, qd, qdd) at both rows. For a C2 trajectory whose jerk is at most J,
# the Taylor remainder R after the acceleration term at the first row is at most J h^3 / 6
# (R' <= J h^2 / 2, R'' <= J h); the interpolant reproduces the quadratic part and carries R's
# values at the second row through its basis functions (at most 1, 0.1976 h and 0.01728 h^2).
# So |q error| <= (1/6 + 1/6 + 0.1976/2 + 0.01728) J h^3 < 0.45 J h^3, and likewise
# |qd error| <= (1/2 + 1.875/6 + 1/2 + 0.0678) J h^2 < 1.4 J h^2.
Q_BOUND = 0.45
QD_BOUND = 1.4


def _read(path):
    with path.open(newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], np.array(rows[1:], dtype=float)


def _quintic(seed: int, knots, n: int = 2) -> Trajectory:
    """A C2 piecewise quintic through random states at ``knots`` [s]."""
    rng = np.random.default_rng(seed)
    shape = (len(knots), n)
    return Trajectory.from_hermite(
        knots, rng.normal(size=shape), rng.normal(size=shape), rng.normal(size=shape),
        joint_names=[f"j{k}" for k in range(n)],
    )  # fmt: skip


@pytest.mark.parametrize(
    ("duration", "rate", "rows"),
    [
        (1.5, 10.0, 16),  # T r = 15: the end is on the grid
        (1.55, 10.0, 17),  # T r = 15.5: 0 .. 1.5 s and the end
        (0.1 * 3, 10.0, 4),  # T r = 3.0000000000000004 in floats: still 4 rows
        (0.7, 10.0, 8),  # T r = 7.000000000000001
        (1.0, 3.0, 4),  # k / 3 for k = 0 .. 3
        (2.0, 0.4, 2),  # one interval of 2.5 s does not fit: 0 and the end
        (1e-3, 1000.0, 2),
    ],
)
def test_rows_are_at_k_over_rate_plus_the_end_once(tmp_path, duration, rate, rows):
    traj = _quintic(1, [0.0, 0.37 * duration, duration])  # a breakpoint off the grid
    path = tmp_path / "t.csv"
    traj.to_csv(path, rate=rate)
    header, table = _read(path)
    t = table[:, 0]
    assert len(t) == rows  # floor(T r) + 1, and one more when T r is not a whole number
    whole = math.floor(duration * rate + 1e-9)
    assert rows == whole + 1 + (not math.isclose(duration * rate, whole, abs_tol=1e-9))
    # Rows k / r (the last of them the end itself when it is on the grid), then the end.
    np.testing.assert_allclose(t[: whole + 1], np.arange(whole + 1) / rate, rtol=0.0, atol=1e-12)
    assert t[-1] == duration and np.all(np.diff(t) > 0.0)
    # Each row is the trajectory's own state at its time, written exactly.
    sample = traj.sample(t)
    np.testing.assert_array_equal(table[:, 1:], np.hstack([sample.q, sample.qd, sample.qdd]))
    assert header == ["t", "q_j0", "q_j1", "qd_j0", "qd_j1", "qdd_j0", "qdd_j1"]


def test_a_jump_is_not_written_twice(tmp_path):
    # The seed strike jumps in velocity where the line starts: the former export wrote that
    # breakpoint and a copy 1.66 ns before it.
    plan = planners.PullBackStrike().plan(problems.sawyer_pool_shot(speed=1.0))
    path = tmp_path / "seed.csv"
    plan.to_csv(path, rate=100.0)
    _, table = _read(path)
    steps = np.diff(table[:, 0])
    np.testing.assert_allclose(steps[:-1], 0.01, rtol=1e-9)
    assert steps[-1] <= 0.01 + 1e-12
    assert len(table) == math.floor(plan.duration * 100.0) + 2


def test_quintic_segments_on_the_grid_read_back_exactly(tmp_path):
    traj = _quintic(2, [0.0, 0.2, 0.5, 0.6], n=3)
    path = tmp_path / "t.csv"
    traj.to_csv(path, rate=10.0)
    back = Trajectory.from_csv(path)
    assert back.joint_names == traj.joint_names and back.degree == 5
    grid = np.linspace(0.0, traj.duration, 1201)
    for ours, theirs in zip(traj.sample(grid)[1:4], back.sample(grid)[1:4], strict=True):
        np.testing.assert_allclose(theirs, ours, atol=1e-9, rtol=0.0)


@pytest.mark.parametrize("rate", [7.0, 40.0, 130.0])
def test_a_c2_trajectory_reads_back_within_the_jerk_bound(tmp_path, rate):
    traj = _quintic(3, np.cumsum([0.0, 0.23, 0.41, 0.17, 0.52]), n=3)  # breakpoints off the grid
    path = tmp_path / "t.csv"
    traj.to_csv(path, rate=rate)
    back = Trajectory.from_csv(path)
    grid = np.linspace(0.0, traj.duration, 20_001)
    ours, theirs = traj.sample(grid), back.sample(grid)
    jerk = np.abs(ours.jerk).max() * 1.01  # dense samples of a quadratic jerk: 1 % margin
    h = 1.0 / rate
    q_error = np.abs(theirs.q - ours.q).max()
    assert q_error <= Q_BOUND * jerk * h**3
    assert np.abs(theirs.qd - ours.qd).max() <= QD_BOUND * jerk * h**2
    assert q_error > 1e-4 * Q_BOUND * jerk * h**3  # the bound is not vacuous here


def test_a_ruckig_plan_reads_back_within_its_jerk_limit(tmp_path):
    robot = get_robot("paddle4")
    middle = 0.5 * (robot.limits.lower + robot.limits.upper)
    move = problems.PointToPoint(robot, middle, middle + 0.2 * (robot.limits.upper - middle))
    plan = planners.Ruckig().plan(move)
    path = tmp_path / "ruckig.csv"
    plan.to_csv(path, rate=100.0)
    back = Trajectory.from_csv(path)
    grid = np.linspace(0.0, plan.duration, 10_001)
    error = np.abs(back.sample(grid).q - plan.sample(grid).q)
    # Per joint: Ruckig keeps each joint's jerk within its limit [rad/s^3 or m/s^3].
    assert np.all(error.max(axis=0) <= Q_BOUND * robot.limits.jerk * 0.01**3)
    assert back.joint_names == robot.joint_names


def test_files_without_accelerations_are_cubic_and_jerk_columns_are_ignored(tmp_path):
    path = tmp_path / "old.csv"
    path.write_text("t,q_a,qd_a,qdd_a,jerk_a\n0,0,0,0,6\n1,1,3,6,6\n")
    back = Trajectory.from_csv(path)
    np.testing.assert_allclose(back.sample([0.5]).q[:, 0], 0.125, atol=1e-12)  # t^3
    path.write_text("t,q_a,qd_a\n0,0,0\n1,1,3\n")
    cubic = Trajectory.from_csv(path)
    assert cubic.degree == 3 and cubic.joint_names == ("a",)
    np.testing.assert_allclose(cubic.sample([0.5]).q[:, 0], 0.125, atol=1e-12)


HEADER = "t,q_a,q_b,qd_a,qd_b\n"


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("", r"is empty; expected the header t, q_<joint>"),
        ("\n\n", r"is empty"),
        ("time,q_a,qd_a\n0,0,0\n1,1,1\n", r"row 1, column 1 \(time\): expected the header 't'"),
        ("t,x\n0,0\n1,1\n", r"row 1, column 2 \(x\): expected the header 'q_<joint>'"),
        ("t,q_a,q_b,qd_a\n", r"row 1, column 5 \(missing\): expected the header 'qd_b', got None"),
        ("t,q_a,q_b,qd_b,qd_a\n", r"row 1, column 4 \(qd_b\): expected the header 'qd_a'"),
        ("t,q_a,qd_a,extra\n", r"row 1, column 4 \(extra\): expected the header 'qdd_a'"),
        (HEADER + "0,0,0,0,0\n", r"has 1 rows of samples; a trajectory needs at least 2"),
        (HEADER + "0,0,0,0,0\n1,2,3\n", r"row 3 has 3 values, the header 5"),
        (HEADER + "0,0,0,0,0\n\n1,1,1,1,1\n", r"row 3 has 0 values"),
        (HEADER + "0,0,0,0,0\n1,abc,0,0,0\n", r"row 3, column 2 \(q_a\): 'abc' is not a finite"),
        (HEADER + "0,0,0,0,0\n1,0,0,0,nan\n", r"row 3, column 5 \(qd_b\): 'nan' is not a finite"),
        (HEADER + "0.5,0,0,0,0\n1,0,0,0,0\n", r"row 2, column 1 \(t\): the first time must be 0"),
        (HEADER + "0,0,0,0,0\n1,0,0,0,0\n1,0,0,0,0\n",
         r"row 4, column 1 \(t\): time 1 s does not come after 1 s"),
    ],
)  # fmt: skip
def test_a_bad_file_is_a_typed_error_naming_file_row_and_column(tmp_path, text, match):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(InvalidInputError, match=rf"^'{path}' {match}"):
        Trajectory.from_csv(path)


def test_missing_files_and_bad_paths_are_typed_errors(tmp_path):
    with pytest.raises(InvalidInputError, match="no trajectory file at"):
        Trajectory.from_csv(tmp_path / "missing.csv")
    with pytest.raises(InvalidInputError, match="path must be a str or a Path, got int 3"):
        Trajectory.from_csv(3)
    traj = Trajectory.constant([0.0], 1.0)
    with pytest.raises(InvalidInputError, match=r"cannot write .*: Is a directory"):
        traj.to_csv(tmp_path, rate=10.0)
    with pytest.raises(InvalidInputError, match="path must be a str or a Path"):
        traj.to_csv(3)
    with pytest.raises(InvalidInputError, match="rate must be > 0 Hz"):
        traj.to_csv(tmp_path / "t.csv", rate=0.0)
    assert not (tmp_path / "t.csv").exists()
