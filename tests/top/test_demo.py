"""Tests of the pieces of ``optraj demo`` (the whole demo runs in tests/top/test_cli.py)."""

from __future__ import annotations

import io
import sys

from conftest import get_robot

from optraj import planners, problems
from optraj.demo import Progress, short_reason, write_plots
from optraj.errors import InvalidInputError


def test_short_reason_keeps_the_class_and_the_first_clause():
    exc = InvalidInputError(
        "the strike line needs joint 'j1' at 2.2 rad/s (velocity), limit 1.3 rad/s; more"
    )
    assert short_reason(exc) == (
        "InvalidInputError: the strike line needs joint 'j1' at 2.2 rad/s, limit 1.3 rad/s"
    )
    long = short_reason(InvalidInputError("x" * 300), width=40)
    assert len(long) == 40 and long.endswith("...")


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_shows_only_on_a_terminal():
    quiet = io.StringIO()
    progress = Progress(quiet)
    progress("planning")
    progress.done()
    assert quiet.getvalue() == ""
    terminal = _Terminal()
    progress = Progress(terminal)
    progress("planning")
    assert "planning ..." in terminal.getvalue()
    progress.done()
    assert terminal.getvalue().endswith("\r\033[K")


def test_plots_are_skipped_with_one_line_without_matplotlib(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    robot = get_robot("sawyer")
    traj = planners.Ruckig().plan(problems.PointToPoint(robot, robot.home, robot.home + 0.1))
    out = io.StringIO()
    assert write_plots(tmp_path, robot, {"ruckig": traj}, [], out) == []
    lines = out.getvalue().strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("plots skipped: matplotlib is not installed")
    assert list(tmp_path.iterdir()) == []
