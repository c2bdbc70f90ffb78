"""Checks of what describes a trajectory besides its polynomials: joint names, phases, metadata.

:class:`~optraj.planners.trajectory.Trajectory` runs these on its keyword arguments, so that
each bad value is refused with a typed error naming it. :func:`short_repr` is the short form
of a bad value that the trajectory modules put in their error messages.
"""

from __future__ import annotations

import pickle
import reprlib
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from optraj.errors import InvalidInputError
from optraj.planners.phase import Phase
from optraj.planners.sampling import TIME_TOLERANCE

__all__ = [
    "as_joint_names",
    "as_metadata",
    "as_phases",
    "check_phases_within",
    "picklable",
    "short_repr",
]


def short_repr(value: object) -> str:
    """A value's type and a short repr, for error messages: ``"int 5"``, ``"list [1, 2, ...]"``."""
    return f"{type(value).__name__} {reprlib.repr(value)}"


def _is_collection(value: object) -> bool:
    """Whether ``value`` holds items (a list, tuple, generator ...), not a str or a mapping."""
    return isinstance(value, Iterable) and not isinstance(value, (str, bytes, Mapping))


def as_joint_names(joint_names: Sequence[str] | None, n: int) -> tuple[str, ...]:
    """The names of n joints as a tuple; ``q0 .. q{n-1}`` when ``joint_names`` is None.

    Raises:
        InvalidInputError: Not a collection of n str.
    """
    names: tuple[Any, ...] | None = None
    if joint_names is None:
        names = tuple(f"q{j}" for j in range(n))
    elif _is_collection(joint_names):
        names = tuple(joint_names)  # once: a generator is spent by one pass
    if names is None or not all(isinstance(name, str) for name in names):
        raise InvalidInputError(
            f"joint_names must be a sequence of {n} str, got {short_repr(joint_names)}",
            name="joint_names",
        )
    if len(names) != n:
        raise InvalidInputError(
            f"joint_names must name the {n} joints, got {len(names)} names", name="joint_names"
        )
    return names


def as_phases(phases: Iterable[Phase]) -> tuple[Phase, ...]:
    """The phases as a tuple.

    Raises:
        InvalidInputError: Not a collection of :class:`~optraj.planners.phase.Phase`.
    """
    windows = tuple(phases) if _is_collection(phases) else None
    if windows is None or not all(isinstance(phase, Phase) for phase in windows):
        raise InvalidInputError(
            f"phases must be a sequence of planners.Phase, got {short_repr(phases)}",
            name="phases",
        )
    return windows


def check_phases_within(phases: Iterable[Phase], duration: float) -> None:
    """Refuse a phase outside [0, duration] [s], beyond round-off (``TIME_TOLERANCE``).

    Raises:
        InvalidInputError: Names the first phase that lies outside.
    """
    for phase in phases:
        if phase.t_start < -TIME_TOLERANCE or phase.t_end > duration + TIME_TOLERANCE:
            raise InvalidInputError(
                f"phase {phase.name!r} [{phase.t_start:.6g}, {phase.t_end:.6g}] s lies "
                f"outside the trajectory [0, {duration:.6g}] s",
                name="phases",
            )


def as_metadata(metadata: Mapping[str, Any] | None) -> dict[str, Any]:
    """A copy of ``metadata`` as a dict (empty for None).

    Raises:
        InvalidInputError: Neither a mapping nor None.
    """
    if metadata is not None and not isinstance(metadata, Mapping):
        raise InvalidInputError(
            f"metadata must be a mapping (dict) or None, got {short_repr(metadata)}",
            name="metadata",
        )
    return dict(metadata or {})


def picklable(metadata: Mapping[str, Any]) -> dict[str, Any]:
    """The items of ``metadata`` whose values pickle (a solver's own object may not).

    A trajectory pickles with these only, so that it can be sent to worker processes.
    """
    kept = {}
    for key, value in metadata.items():
        try:
            pickle.dumps(value)
        except Exception:
            continue
        kept[key] = value
    return kept
