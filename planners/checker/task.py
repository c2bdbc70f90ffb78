"""What every task-constraint evaluator shares: validated fields, task findings, deferrals.

Each evaluator (``boundary_state_check``, ``via_point_check``, ``tool_path_check``,
``strike_line_check``, ``tool_contact_check``) validates its constraint's fields with
:func:`constraint_vector`, :func:`constraint_tolerance` and :func:`constraint_direction`,
asks the tool kinematics for the instants it needs, and returns an :data:`Evaluation`: a
callable that makes its findings once every pose has been computed in one batch.
:func:`missing_findings` is the evaluation of a constraint whose phase or instant does not
exist in the trajectory.

Example::

    tolerance = constraint_tolerance(line.position_tolerance, "StrikeLine.position_tolerance", "m")
    finding = task_finding("strike position", 2e-4, tolerance, 0.5, "m", "tool 0.0002 m off")
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.planners.checker.report import Finding, build_finding
from optraj.validation import as_number, as_vector

__all__ = [
    "Evaluation",
    "constraint_direction",
    "constraint_tolerance",
    "constraint_vector",
    "missing_findings",
    "task_finding",
]

FloatArray = NDArray[np.float64]

#: A constraint's deferred evaluation: called after the tool kinematics are computed, it
#: returns the constraint's findings.
Evaluation = Callable[[], list[Finding]]


def constraint_vector(value: ArrayLike, name: str, size: int) -> FloatArray:
    """A constraint's array as a finite float vector of ``size``, or InvalidInputError."""
    try:
        shape: tuple[int, ...] | None = np.shape(value)
    except ValueError:  # ragged nesting
        shape = None
    if shape != (size,):
        raise InvalidInputError(
            f"constraint {name} must be a finite vector of length {size}, got shape {shape}",
            name=name,
        )
    return as_vector(value, f"constraint {name}", size)


def constraint_tolerance(value: object, name: str, unit: str = "") -> float:
    """A constraint's tolerance or time as a finite number >= 0 [unit], or InvalidInputError."""
    return as_number(value, name, unit, minimum=0.0)


def constraint_direction(value: ArrayLike, name: str) -> FloatArray:
    """A constraint's direction as a unit vector, shape (3,), or InvalidInputError if zero."""
    vector = constraint_vector(value, name, 3)
    norm = float(np.linalg.norm(vector))
    if norm < 1e-12:
        raise InvalidInputError(f"constraint {name} must be a non-zero direction", name=name)
    return vector / norm


def task_finding(
    name: str,
    value: float,
    limit: float,
    time: float | None,
    unit: str,
    detail: str,
    *,
    joint: str | None = None,
    slack: float | None = None,
) -> Finding:
    """A finding of kind ``"task"``: :func:`~planners.checker.report.build_finding` for it.

    Args:
        name: Finding name.
        value: Worst deviation [unit].
        limit: The constraint's tolerance [unit].
        time: When [s], or None.
        unit: Unit text.
        detail: One readable sentence on the worst case.
        joint: Which joint, or None.
        slack: The pass slack [unit]; the round-off of ``limit`` when None.
    """
    return build_finding(
        name, "task", value, limit, time=time, joint=joint, unit=unit, detail=detail, slack=slack
    )


def missing_findings(expected: list[tuple[str, float, str]], why: str) -> Evaluation:
    """Findings that fail with value ``inf`` because what they measure does not exist.

    Args:
        expected: (name, tolerance, unit) of each finding the constraint would make.
        why: The detail of every finding.
    """

    def evaluate() -> list[Finding]:
        return [
            task_finding(name, math.inf, limit, None, unit, why) for name, limit, unit in expected
        ]

    return evaluate
