"""The data of an optimal control problem: phase grids, warm starts, specs and the built NLP.

:class:`FixedState` is :mod:`planners.ocp.task_rows.boundary_state`'s, re-exported here.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.planners.ocp.task_rows import FixedState, StrikeLineRows, TaskRows
from optraj.planners.ocp.transcription import (
    CompiledNLP,
    Structure,
)
from optraj.planners.strike.contact import (
    ContactChoice,
)
from optraj.planners.trajectory import Trajectory
from optraj.robots import JointLimits, Robot
from optraj.validation import (
    as_vector,
)

__all__ = [
    "FixedState",
    "OptimalControlProblem",
    "PhaseGrid",
    "Spec",
    "WarmStart",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class PhaseGrid:
    """The time grid of one phase.

    Attributes:
        name: Phase name (as in the trajectory's phases).
        intervals: Equal intervals of the phase.
        duration: Fixed duration [s], or None when the solver chooses it.
        guess: Initial duration [s].
        upper: Largest duration allowed [s] (``intervals * max_interval`` for a free phase).
    """

    name: str
    intervals: int
    duration: float | None
    guess: float
    upper: float


@dataclass(frozen=True, eq=False)
class WarmStart:
    """A solution's primal and dual values, to warm start a solve of the same structure.

    ``time_scale`` [s] is the objective's divisor in that solve: a solve started from these
    multipliers keeps it, so that they still fit its objective.
    """

    structure: Structure
    w: FloatArray
    lam_x: FloatArray
    lam_g: FloatArray
    time_scale: float | None = None


@dataclass(eq=False)
class OptimalControlProblem:
    """A built optimal control problem, ready to solve and open for inspection.

    Attributes:
        problem: The problem it was built from.
        compiled: The CasADi NLP (``compiled.w``, ``.f``, ``.g``, ``.p``, ``.groups``) and
            its solver.
        grids: The phases' time grids.
        x0: Initial guess of the decision vector.
        lbx: Lower bounds of the decision vector (fixed states have equal bounds).
        ubx: Upper bounds.
        p: Parameter values, named by ``compiled.parameters``.
        lam_x0: Initial bound multipliers (a warm start), or None.
        lam_g0: Initial constraint multipliers, or None.
        contact: The chosen contact configuration of a strike, or None.
        guess: The trajectory the initial guess was sampled from.
    """

    problem: Any
    compiled: CompiledNLP
    grids: tuple[PhaseGrid, ...]
    x0: FloatArray
    lbx: FloatArray
    ubx: FloatArray
    p: FloatArray
    lam_x0: FloatArray | None
    lam_g0: FloatArray | None
    contact: ContactChoice | None
    guess: Trajectory

    @property
    def variables(self) -> int:
        """Number of decision variables."""
        return int(self.x0.size)

    def parameter(self, name: str) -> FloatArray:
        """The value of the NLP parameter ``name`` (e.g. ``"time_scale"``, ``"speed"``).

        Raises:
            UnknownNameError: A parameter this NLP does not have.
        """
        return self.compiled.parameters.value(self.p, name)

    @property
    def constraints(self) -> int:
        """Number of constraint rows."""
        return int(self.compiled.lbg.size)

    def violations(self, w: FloatArray) -> dict[str, float]:
        """Largest bound excess of each constraint group (and ``"bounds"``) at ``w``.

        Raises:
            InvalidInputError: ``w`` is not a finite vector of :attr:`variables` entries.
        """
        return self._violations(as_vector(w, "w", self.variables))

    def _violations(self, w: FloatArray) -> dict[str, float]:
        """:meth:`violations` of a solver's point, which may hold NaN (then so do they)."""
        g = np.asarray(self.compiled.constraint_values(w, self.p)).reshape(-1)
        excess = np.maximum(self.compiled.lbg - g, g - self.compiled.ubg)
        result = {"bounds": float(np.max(np.maximum(self.lbx - w, w - self.ubx), initial=0.0))}
        names, order, starts = self.compiled.group_order
        if names:
            peaks = np.maximum(np.maximum.reduceat(excess[order], starts), 0.0)
            result.update(zip(names, peaks.tolist(), strict=True))
        return result


# ------------------------------------------------------------------------------ the spec


@dataclass
class Spec:
    """A problem turned into phases, fixed states, task rows and a first guess."""

    robot: Robot
    limits: JointLimits
    names: tuple[str, ...]
    durations: tuple[float | None, ...]
    guess: Trajectory
    fixed: list[FixedState]
    tasks: tuple[TaskRows, ...] = ()
    contact: ContactChoice | None = None
    intervals: tuple[int, ...] | None = None  # grid forced by a warm start
    contact_time: float = 0.0  # wall time of the contact choice [s]
    #: Joint whose jerk switches in ``guess`` place the first nodes of a free one-phase
    #: move (:func:`planners.ocp.guesses.switch_times`), or None for evenly spaced nodes.
    switch_joint: int | None = None

    @property
    def strike(self) -> StrikeLineRows | None:
        """The strike line's rows, or None for a problem without a strike line."""
        return next((task for task in self.tasks if isinstance(task, StrikeLineRows)), None)
