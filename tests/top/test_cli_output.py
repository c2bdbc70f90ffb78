"""Tests of optraj.cli_output: ``optraj plan --format json|csv|ros-yaml --rate HZ``."""

from __future__ import annotations

import argparse
import io
import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import get_robot

from optraj import planners
from optraj.cli import main
from optraj.cli_output import DEFAULT_RATE, OutputFile, output_file

PLAN = ["plan", "paddle4", "--problem", "point-to-point", "--planner", "quintic", "--q-goal"]
GOAL = ["0.5", "0.3", "0.5", "0.2"]


def _plan(*options: str) -> str:
    out = io.StringIO()
    assert main([*PLAN, *GOAL, *options], out=out) == 0
    return " ".join(out.getvalue().split())


def test_json_stays_the_default(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    summary = _plan()
    assert "Wrote traj.json; check it again with: optraj check traj.json" in summary
    assert [p.name for p in tmp_path.iterdir()] == ["traj.json"]


def test_csv_at_a_rate_holds_the_planned_states(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _plan("--out", "exact.json")
    summary = _plan("--format", "csv", "--rate", "40")
    assert "Wrote traj.csv (t, q_, qd_ and qdd_ of each joint, at 40 Hz)" in summary
    exact = planners.Trajectory.from_json("exact.json")
    rows = np.loadtxt("traj.csv", delimiter=",", skiprows=1)
    # The quintic lasts 0.6250000000006251 s: 6e-13 s past the grid time 0.625 s is round-off
    # (within TIME_TOLERANCE), so that row is the end, not a second row 0.6 ps later.
    whole = math.floor(exact.duration * 40.0)
    assert len(rows) == whole + 1 + (not math.isclose(exact.duration, whole / 40.0, abs_tol=1e-9))
    assert rows[-1, 0] == exact.duration
    sample = exact.sample(rows[:, 0])
    np.testing.assert_array_equal(rows[:, 1:], np.hstack([sample.q, sample.qd, sample.qdd]))
    assert Path("traj.csv").read_text().startswith("t,q_J1,q_J2,q_J3,q_J4,qd_J1")


def test_ros_yaml_carries_the_robots_efforts_at_the_default_rate(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _plan("--out", "exact.json")
    summary = _plan("--format", "ros-yaml", "--out", "move.yaml")
    assert f"Wrote move.yaml (a ROS 2 JointTrajectory with efforts, at {DEFAULT_RATE:g} Hz)" in (
        summary
    )
    robot = get_robot("paddle4")
    exact = planners.Trajectory.from_json("exact.json")
    message = yaml.safe_load(Path("move.yaml").read_text())
    assert message == exact.to_ros(DEFAULT_RATE, robot=robot)
    assert message["joint_names"] == list(robot.joint_names)
    back = planners.Trajectory.from_ros("move.yaml")
    assert back.duration == pytest.approx(exact.duration, abs=1e-9)


@pytest.mark.parametrize(
    ("options", "expected"),
    [
        (["--format", "xml"], "unknown --format 'xml'; known: json, csv, ros-yaml"),
        (["--format", "csv", "--rate", "0"], "--rate must be > 0 Hz, got 0 Hz"),
        (["--format", "ros-yaml", "--rate", "2e6"], "--rate must be <= 1e+06 Hz, got 2e+06 Hz"),
        (["--rate", "100"], "--rate applies to --format csv and ros-yaml; --format json writes"),
        (["--format", "csv", "--rate", "fast"], "argument --rate: invalid float value: 'fast'"),
        (["--format", "csv", "--out", "no/such/dir/t.csv"], "cannot write 'no/such/dir/t.csv'"),
    ],
)
def test_bad_output_options_exit_2_naming_the_option(options, expected, tmp_path, monkeypatch,
                                                     capsys):  # fmt: skip
    monkeypatch.chdir(tmp_path)
    try:
        status = main([*PLAN, *GOAL, *options], out=io.StringIO())
    except SystemExit as exc:  # argparse's own errors
        status = exc.code
    assert status == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("optraj") and expected in err[0]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("fmt", "rate", "out", "expected"),
    [
        ("json", None, None, OutputFile(Path("traj.json"), "json", None)),
        ("csv", None, None, OutputFile(Path("traj.csv"), "csv", DEFAULT_RATE)),
        ("ros-yaml", 250.0, "a/b.yml", OutputFile(Path("a/b.yml"), "ros-yaml", 250.0)),
    ],
)
def test_default_paths_and_rates_follow_the_format(fmt, rate, out, expected):
    args = argparse.Namespace(format=fmt, rate=rate, out=out)
    assert output_file(args) == expected
