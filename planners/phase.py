"""Named time windows of a trajectory: :class:`Phase` (``approach``, ``strike``, ``stop``, ...).

Planners mark the parts of a plan with phases; the checker and the controllers find them by
name through :meth:`~optraj.planners.trajectory.Trajectory.phase`. :func:`shifted` and
:func:`back_to_back` lay phases out when trajectories are joined one after another.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from optraj.errors import InvalidInputError
from optraj.validation import as_number

__all__ = ["Phase", "back_to_back", "shifted"]


@dataclass(frozen=True)
class Phase:
    """A named time window of a trajectory, e.g. ``approach``, ``strike``, ``stop``.

    Attributes:
        name: Phase name.
        t_start: Start time [s].
        t_end: End time [s], >= t_start.
    """

    name: str
    t_start: float
    t_end: float

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise InvalidInputError(
                f"a phase name must be a str, got {type(self.name).__name__} {self.name!r}",
                name="phases",
            )
        for field in ("t_start", "t_end"):
            value = getattr(self, field)
            if isinstance(value, float) and math.isfinite(value):  # a NumPy float64 too
                value = float(value)
            else:
                value = as_number(value, f"phase {self.name!r} {field}", "s")
            object.__setattr__(self, field, value)
        if self.t_end < self.t_start:
            raise InvalidInputError(
                f"phase {self.name!r} ends at {self.t_end:.6g} s before it starts at "
                f"{self.t_start:.6g} s",
                name="phases",
            )

    @property
    def duration(self) -> float:
        """Length of the phase [s]."""
        return self.t_end - self.t_start


def shifted(phases: Iterable[Phase], offset: float) -> list[Phase]:
    """The phases moved ``offset`` [s] later in time (earlier when negative)."""
    return [Phase(p.name, p.t_start + offset, p.t_end + offset) for p in phases]


def back_to_back(lengths: Sequence[tuple[str, float]]) -> list[Phase]:
    """Phases that follow one another from 0 s, one per ``(name, length [s])`` in order."""
    windows: list[Phase] = []
    clock = 0.0
    for name, length in lengths:
        start = clock
        clock += length
        windows.append(Phase(name, start, clock))
    return windows
