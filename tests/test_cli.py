"""Tests of the optraj command."""

from __future__ import annotations

import io
import subprocess
import sys

import numpy as np
import pytest
from conftest import get_robot

from optraj.cli import main


def test_demo_prints_every_robot_with_its_tool_pose():
    out = io.StringIO()
    assert main(["demo"], out=out) == 0
    text = out.getvalue()
    for name in ("paddle4", "sawyer", "youbot"):
        robot = get_robot(name)
        assert f"\n{name}: " in text
        for joint in robot.joint_names:
            assert f"  {joint} " in text
        position = np.array2string(
            robot.tool_position(robot.home) + 0.0,
            precision=4,
            floatmode="fixed",
            suppress_small=True,
        )
        assert f"tool frame {robot.tool_frame!r} at home: position {position} m" in text
    # paddle4's home tool pose is the seed's T_sh.
    assert "position [0.2500 0.0000 0.2500] m" in text


def test_robots_lists_names():
    out = io.StringIO()
    assert main(["robots"], out=out) == 0
    assert out.getvalue().splitlines()[0].startswith("paddle4")


def test_strict_demo_fails_with_one_line_when_optional_package_is_missing(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "example_robot_data", None)
    assert main(["demo", "--strict"], out=io.StringIO()) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("optraj: error: robots.load('panda') needs the package")


def test_demo_skips_missing_optional_robots(monkeypatch):
    monkeypatch.setitem(sys.modules, "example_robot_data", None)
    out = io.StringIO()
    assert main(["demo"], out=out) == 0
    assert "skipped panda" in out.getvalue()


def test_unknown_command_exits_with_usage_error():
    with pytest.raises(SystemExit) as info:
        main(["fly"])
    assert info.value.code == 2


def test_console_script_module_runs():
    done = subprocess.run(
        [sys.executable, "-m", "optraj.cli", "robots"], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert "sawyer" in done.stdout


def test_demo_reproduces_the_seed_table_and_the_checker_verdicts():
    out = io.StringIO()
    assert main(["demo"], out=out) == 0
    text = out.getvalue()
    # Rows printed in the ECE486 seed for the ball (1.1, 0.8, 0.7).
    assert "     0.2   0.4626    0.0110   0.0280   -0.0110" in text
    assert "     1.8   0.8874    0.3802   0.9705   -0.3802" in text
    assert "pick and place (quintic)" in text and "pick and place (lspb)" in text
    seed_line = next(line for line in text.splitlines() if "seed (pull back + line)" in line)
    assert "FAIL" in seed_line and "acceleration unbounded (jump)" in seed_line
