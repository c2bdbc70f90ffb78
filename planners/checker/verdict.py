"""A checker report in a few words, for tables: the verdict and the failing findings.

:meth:`Report.summary <planners.checker.report.Report.summary>` lists every finding; a table
that compares plans needs one cell per plan instead.

Example::

    report = check(trajectory, problem)
    verdict(report)            # 'FAIL'
    failing_findings(report)   # 'acceleration (unbounded: a jump), jerk (unbounded: a jump)'
"""

from __future__ import annotations

import math

from optraj.errors import InvalidInputError
from optraj.planners.checker.report import Finding, Report

__all__ = ["failing_findings", "finding_note", "verdict"]


def verdict(report: Report) -> str:
    """``"pass"`` when every finding of ``report`` passes, else ``"FAIL"``.

    Raises:
        InvalidInputError: ``report`` is not a checker Report.
    """
    return "pass" if _report(report).ok else "FAIL"


def finding_note(finding: Finding) -> str:
    """A finding's name and its value as a share of its limit, e.g. ``"velocity (104%)"``.

    A value made unbounded by a jump (ratio ``inf``) reads ``"unbounded: a jump"``.

    Raises:
        InvalidInputError: ``finding`` is not a checker Finding.
    """
    if not isinstance(finding, Finding):
        raise InvalidInputError(
            f"finding must be a planners.checker Finding, got {type(finding).__name__}",
            name="finding",
        )
    share = "unbounded: a jump" if math.isinf(finding.ratio) else f"{finding.ratio:.0%}"
    return f"{finding.name} ({share})"


def failing_findings(report: Report, *, none: str = "-") -> str:
    """The failing findings of ``report``, comma-separated, each as :func:`finding_note` says.

    Args:
        report: A checker report.
        none: What to return when every finding passes.

    Raises:
        InvalidInputError: ``report`` is not a checker Report, or ``none`` not a string.
    """
    if not isinstance(none, str):
        raise InvalidInputError(f"none must be a string, got {type(none).__name__}", name="none")
    return ", ".join(finding_note(f) for f in _report(report).violations) or none


def _report(report: Report) -> Report:
    if not isinstance(report, Report):
        raise InvalidInputError(
            f"report must be a planners.checker Report (from planners.check), got "
            f"{type(report).__name__}",
            name="report",
        )
    return report
