"""Tests of the pieces of ``optraj demo`` (the whole demo runs in tests/top/test_cli.py)."""

from __future__ import annotations

import io
import sys

from conftest import get_robot

from optraj import planners, problems
from optraj.demo import Progress, write_plots


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_shows_only_on_a_terminal():
    piped = io.StringIO()
    progress = Progress(3, piped)
    progress("planning")
    progress("tracking")
    progress.done()
    assert piped.getvalue() == ""  # not even a carriage return
    terminal = _Terminal()
    progress = Progress(3, terminal)
    progress("planning the pool shot: optimal control (min time), a label longer than 28")
    progress("tracking")
    text = terminal.getvalue()
    assert "a label longer than 28" in text  # not cut
    assert "tracking" in text and "<" in text  # elapsed<remaining
    progress.done()


def test_plots_are_skipped_with_one_line_without_matplotlib(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    robot = get_robot("sawyer")
    traj = planners.Ruckig().plan(problems.PointToPoint(robot, robot.home, robot.home + 0.1))
    out = io.StringIO()
    assert write_plots(tmp_path, robot, {"ruckig": traj}, [], out) == []
    lines = out.getvalue().strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("plots skipped: matplotlib is not installed")
    assert list(tmp_path.iterdir()) == []
