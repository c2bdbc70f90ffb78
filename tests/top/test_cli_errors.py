"""Tests of the option names in the ``optraj`` command's error lines."""

from __future__ import annotations

import argparse

from optraj.cli_errors import error_line, option_flags
from optraj.errors import InfeasibleError, InvalidInputError, UnknownNameError, WorkspaceError


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser()
    parser.add_argument("robot")
    parser.add_argument("--speed", type=float)
    parser.add_argument("--ball", nargs=3)
    parser.add_argument("--heading", type=float)
    parser.add_argument("--q-goal", nargs="+")
    parser.add_argument("--duration", type=float)
    parser.add_argument("--limit-scale", type=float)
    parser.add_argument("--out")
    return parser


FLAGS = option_flags(_parser())


def _line(exc: BaseException, **given: object) -> str:
    return error_line(exc, str(exc), FLAGS, given)


def test_flags_by_destination_leave_positionals_and_help_out():
    assert FLAGS == {
        "speed": "--speed",
        "ball": "--ball",
        "heading": "--heading",
        "q_goal": "--q-goal",
        "duration": "--duration",
        "limit_scale": "--limit-scale",
        "out": "--out",
    }


def test_an_argument_name_becomes_its_option():
    exc = InvalidInputError("speed must be > 0 m/s, got -1 m/s", name="speed")
    assert _line(exc, speed=-1.0) == "argument --speed: speed must be > 0 m/s, got -1 m/s"
    named = InvalidInputError("--speed must be finite, got nan", name="--speed")
    assert _line(named) == "--speed must be finite, got nan"  # said already
    other = InvalidInputError("options must be a mapping", name="options")
    assert _line(other) == "options must be a mapping"  # no option to name


def test_an_unknown_name_and_a_repeated_prefix():
    exc = UnknownNameError("robot", "nope", ["sawyer"])
    assert _line(exc) == str(exc)  # the positional ROBOT: its word is in the message
    goal = InvalidInputError("q_goal: joint 'j1' position 9 rad is too high", name="q_goal")
    assert _line(goal) == "argument --q-goal: joint 'j1' position 9 rad is too high"


def test_errors_that_follow_from_options():
    far = WorkspaceError((9.0, 9.0, 9.0), "x", 9.0, 0.3, 1.1)
    assert _line(far, ball=[9, 9, 9]).startswith("argument --ball: point (9, 9, 9) m")
    assert _line(far).startswith("argument --ball/--heading: ")  # neither given
    fast = InfeasibleError("the strike line at 3 m/s needs more", limit="velocity")
    assert _line(fast).startswith("argument --speed: ")
    short = InfeasibleError("a 0.1 s move needs right_j0 at 9 rad/s", limit="velocity")
    assert _line(short, duration=0.1).startswith("argument --duration: ")


def test_a_file_error_names_the_option_that_gave_the_file():
    exc = PermissionError(13, "Permission denied", "/out/table.parquet.jsonl")
    message = "cannot use '/out/table.parquet.jsonl': Permission denied"
    assert error_line(exc, message, FLAGS, {"out": "/out/table.parquet"}).startswith(
        "argument --out: cannot use"
    )
    assert error_line(exc, message, FLAGS, {"out": "/elsewhere"}) == message
