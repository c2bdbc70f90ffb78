"""The command line: any argv, any input file, exits 0, 1 or 2; an error is one stderr line.

``optraj.cli.main`` runs in-process (argparse's own errors arrive as ``SystemExit``). The
argv cases combine real and malformed tokens for ``robots``, ``plan`` and ``check`` (the
optimal-control planners are left to the planner properties: one IPOPT solve per case
would dominate the run); the file cases write a trajectory file that is broken in one way
(a bad value for one key, a missing key, bad problem metadata, truncated, not UTF-8, deeply
nested, a huge number, a directory, a missing file) and check it.
"""

from __future__ import annotations

import atexit
import contextlib
import io
import json
import math
import shutil
import tempfile
from functools import cache
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, note, settings
from hypothesis import strategies as st

from fuzz.budget import examples, recorded
from optraj import cli

_DIR = Path(tempfile.mkdtemp(prefix="optraj-fuzz-cli-"))
atexit.register(shutil.rmtree, _DIR, ignore_errors=True)
_NUMBERS = ("0", "1", "-1", "0.5", "2", "nan", "inf", "-inf", "1e308", "1e-300", "1e9", "abc", "")


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    """``(status, stdout, stderr)`` of ``optraj <argv>``, run in this process."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        try:
            status: Any = cli.main(argv, out=out)
        except SystemExit as exc:  # argparse's usage errors and --help
            status = exc.code
    return status, out.getvalue(), err.getvalue()


def assert_one_line_errors(argv: list[str]) -> str:
    """Run ``argv``; the status is 0, 1 or 2 and an error is exactly one line on stderr."""
    status, _, err = run_cli(argv)
    note(f"status {status}, stderr {err!r}")
    assert status in (0, 1, 2), f"exit status {status!r}"
    if status == 2:
        lines = err.splitlines()
        assert len(lines) == 1 and lines[0].strip(), f"stderr is not one line: {err!r}"
        assert "Traceback" not in err
    return f"exit {status}"


_numbers = st.sampled_from(_NUMBERS)
_robots = st.sampled_from(("paddle4", "sawyer", "youbot", "panda", "ur5", "SAWYER", "r2d2", ""))
_problems = st.sampled_from((*cli.PROBLEMS, "pool", "", "point_to_point"))
_planners = st.sampled_from(("pull-back", "cubic", "quintic", "lspb", "toppra", "ruckig", "x", ""))


@st.composite
def plan_argv(draw: st.DrawFn) -> list[str]:
    """``plan`` with a real or junk robot, problem and planner and random options; half of
    them a robot, problem and planner that fit (no optimal control)."""
    if draw(st.booleans()):
        problem = draw(st.sampled_from(tuple(cli.PROBLEMS)))
        robot = cli.PROBLEMS[problem] or draw(st.sampled_from(("paddle4", "youbot", "sawyer")))
        names = [n for n in cli.PLANNERS[problem] if not n.startswith("optimal-control")]
        planner = draw(st.sampled_from(names))
    else:
        robot, problem, planner = draw(_robots), draw(_problems), draw(_planners)
    argv = ["plan", robot, "--problem", problem, "--planner", planner]
    for option, count in draw(
        st.lists(
            st.sampled_from(
                (
                    ("--speed", 1),
                    ("--ball", 3),
                    ("--ball", 2),
                    ("--heading", 1),
                    ("--q-start", 4),
                    ("--q-goal", 4),
                    ("--q-goal", 7),
                    ("--q-goal", 0),
                    ("--duration", 1),
                    ("--limit-scale", 1),
                )
            ),
            max_size=4,
        )
    ):
        argv += [option, *(draw(_numbers | st.just("home")) for _ in range(count))]
    return [*argv, "--out", str(_DIR / "plan.json")]


_argv = st.one_of(
    plan_argv(),
    plan_argv(),
    plan_argv(),
    st.just(["robots"]),
    st.lists(st.sampled_from(("robots", "check", "plan", "--help", "-x", "--rate", "junk"))).map(
        list
    ),
    st.tuples(_numbers).map(lambda rate: ["check", str(_DIR / "none.json"), "--rate", *rate]),
)


@settings(max_examples=examples("cli argv"))
@given(argv=_argv)
@recorded
def test_any_argv_exits_0_1_or_2_with_one_error_line(argv):
    return assert_one_line_errors(argv)


@cache
def _valid() -> dict[str, Any]:
    """A valid trajectory file's content: a paddle4 point-to-point cubic, planned by the CLI."""
    path = _DIR / "valid.json"
    status, _, err = run_cli(
        ["plan", "paddle4", "--problem", "point-to-point", "--planner", "cubic",
         "--q-goal", "0.5", "0.1", "0.1", "0.1", "--out", str(path)]
    )  # fmt: skip
    assert status == 0, err
    return json.loads(path.read_text())


_json_values = st.one_of(
    st.none(),
    st.booleans(),
    st.sampled_from((math.nan, math.inf, -math.inf, 1e308, -1e308, 1e-300, -1, 0, 2**63)),
    st.text(max_size=5),
    st.just([]),
    st.just({}),
    st.just([[1.0], [2.0, 3.0]]),
    st.just([[[0.0] * 4]] * 3),
    st.lists(st.floats(), max_size=4),
)
_keys = ("format", "joint_names", "breakpoints", "coefficients", "phases", "metadata")
_metadata_keys = ("robot", "problem", "problem_options", "planner")
_option_keys = ("q_start", "q_goal", "duration", "speed", "ball", "heading", "limit_scale")


@st.composite
def broken_files(draw: st.DrawFn) -> tuple[str, bytes | None]:
    """``(how it is broken, file bytes)``; bytes None for a directory or a missing file."""
    data = json.loads(json.dumps(_valid()))
    how = draw(
        st.sampled_from(
            ("value", "missing", "metadata", "option", "truncated", "not utf-8", "nested",
             "long number", "directory", "missing file", "valid")
        )
    )  # fmt: skip
    if how == "value":
        data[draw(st.sampled_from(_keys))] = draw(_json_values)
    elif how == "missing":
        del data[draw(st.sampled_from(_keys))]
    elif how == "metadata":
        data["metadata"][draw(st.sampled_from(_metadata_keys))] = draw(
            _json_values | st.sampled_from(("sawyer", "pool-shot", "paddle-strike", "youbot"))
        )
    elif how == "option":
        data["metadata"]["problem_options"][draw(st.sampled_from(_option_keys))] = draw(
            _json_values
        )
    elif how in ("directory", "missing file"):
        return how, None
    if how == "nested":
        depth = draw(st.sampled_from((100, 10_000, 100_000)))
        return how, b'{"breakpoints": ' + b"[" * depth + b"]" * depth + b"}"
    if how == "long number":
        return how, b'{"breakpoints": [0, 1' + b"0" * draw(st.sampled_from((400, 100_000))) + b"]}"
    text = json.dumps(data, allow_nan=True).encode()
    if how == "truncated":
        text = text[: draw(st.integers(0, len(text) - 1))]
    elif how == "not utf-8":
        text = b"\xff\xfe" + text
    return how, text


@pytest.mark.slow
@settings(max_examples=examples("cli file"))
@given(file=broken_files(), robot=st.none() | _robots, rate=st.none() | _numbers)
@recorded
def test_checking_a_broken_file_exits_0_1_or_2_with_one_error_line(file, robot, rate):
    how, content = file
    path = _DIR / "broken.json"
    if how == "directory":
        path = _DIR
    elif how == "missing file":
        path = _DIR / "no such file.json"
    else:
        path.write_bytes(content)
    argv = ["check", str(path)]
    if robot is not None:
        argv += ["--robot", robot]
    if rate is not None:
        argv += ["--rate", rate]
    return assert_one_line_errors(argv)
