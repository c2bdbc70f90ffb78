"""Helpers of the command-line tests (tests/top)."""

from __future__ import annotations

import pytest


def error_line(capsys: pytest.CaptureFixture[str]) -> str:
    """The one line a failed command wrote on stderr (more lines fail the test)."""
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


def refused(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    """Run ``optraj argv``, require exit status 2, and return its one error line."""
    import io

    from optraj.cli import main

    try:
        status = main(argv, out=io.StringIO())
    except SystemExit as exc:  # argparse's own errors
        status = exc.code
    assert status == 2
    return error_line(capsys)
