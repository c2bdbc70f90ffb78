"""Tests of ``optraj robots``."""

from __future__ import annotations

import io

import numpy as np
import pytest
from conftest import get_robot

from optraj.cli import main
from optraj.cli_robots import robot_table


def test_without_a_name_it_lists_the_robots():
    out = io.StringIO()
    assert main(["robots"], out=out) == 0
    lines = out.getvalue().splitlines()
    assert [line.split()[0] for line in lines[:3]] == ["paddle4", "sawyer", "youbot"]
    assert lines[-1] == "joints and limits of one: optraj robots NAME"


@pytest.mark.parametrize("name", ["paddle4", "sawyer", "youbot"])
def test_a_robot_table_gives_every_joint_and_the_tool_pose(name):
    robot = get_robot(name)
    out = io.StringIO()
    robot_table(name, out)
    text = out.getvalue()
    assert text.startswith(f"{name}: ")
    for joint, upper in zip(robot.joint_names, robot.limits.upper, strict=True):
        row = next(line for line in text.splitlines() if line.startswith(f"  {joint} "))
        assert f"{upper:.4f}" in row
    position = np.array2string(
        robot.tool_position(robot.home) + 0.0, precision=4, floatmode="fixed", suppress_small=True
    )
    assert f"tool frame {robot.tool_frame!r} at home: position {position} m" in text


def test_poses_that_rename_home_say_so():
    out = io.StringIO()
    assert main(["robots", "SAWYER", "paddle4"], out=out) == 0
    text = out.getvalue()
    assert "  poses: home, neutral (= home)\n" in text
    # paddle4's home tool pose is the ECE486 paddle task's T_sh.
    assert "position [0.2500 0.0000 0.2500] m" in text
