"""The shape of a transcribed NLP: its structure key and its decision-vector layout."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from optraj.planners.ocp.task_rows.base import TaskRows

FloatArray = NDArray[np.float64]


#: Ways of writing the torque rows (module docstring).
TORQUE_ROWS = ("rnea", "linear")


def jerk_step(h: Any, q: Any, v: Any, a: Any, u: Any) -> tuple[Any, Any, Any]:
    """Position, velocity and acceleration after ``h`` [s] at constant jerk ``u``.

    The exact triple-integrator step of the transcription, for NumPy arrays and CasADi
    expressions alike: the NLP's dynamics rows, the solution's integration and the guess fit
    all take it from here.
    """
    return (
        q + h * v + h**2 / 2 * a + h**3 / 6 * u,
        v + h * a + h**2 / 2 * u,
        a + h * u,
    )


@dataclass(frozen=True)
class Structure:
    """Everything that shapes the NLP; equal structures share one compiled solver.

    Attributes:
        robot: The robot's :attr:`~robots.Robot.fingerprint` (with ``limits`` it identifies
            the constants in the NLP).
        limits: Limit rows (lower, upper, velocity, acceleration, jerk, effort) as tuples.
        tool_frame: Frame whose pose the task rows constrain.
        intervals: Intervals per phase.
        free: Per phase, whether its duration is a decision (else fixed by bounds).
        tasks: The task rows (:mod:`planners.ocp.task_rows`), in the order they are added;
            they compare by their phase, not by their constraint's numbers.
        position_rows: Whether positions are bounded between nodes (Bernstein rows) or at
            the nodes only.
        torque_nodes: Nodes with torque rows.
        torque_rows: ``"rnea"`` (the symbolic inverse dynamics) or ``"linear"`` (its
            expansion, its coefficients the NLP parameter ``torque``).
        weights: Objective weights as ``(term, weight)`` pairs (time, jerk, effort, posture).
        margin: Fraction of the velocity, acceleration and jerk limits kept free [-].
        torque_margin: Fraction of the torque limits kept free at torque nodes [-] (RNEA
            rows; linear rows take it in their coefficients).
        solver: CasADi NLP plugin name.
        options: Solver options as sorted ``(key, value)`` pairs.
    """

    robot: str
    limits: tuple[tuple[float, ...], ...]
    tool_frame: str
    intervals: tuple[int, ...]
    free: tuple[bool, ...]
    free_grid: bool = True
    tasks: tuple[TaskRows, ...] = ()
    position_rows: bool = True
    torque_nodes: tuple[int, ...] = ()
    torque_rows: str = "rnea"
    weights: tuple[tuple[str, float], ...] = (("time", 1.0),)
    margin: float = 0.0
    torque_margin: float = 0.0
    solver: str = "ipopt"
    options: tuple[tuple[str, Any], ...] = ()


class Layout:
    """Where each quantity sits in the decision vector ``w``.

    ``w = [h_0 .. h_{K-1}, x_0 .. x_K, u_0 .. u_{K-1}]``: interval lengths [s], scaled node
    states ``(zq, zv, za)`` (3n each) and scaled jerks (n each).

    Args:
        n: Joint count.
        intervals: Intervals per phase.
    """

    def __init__(self, n: int, intervals: Sequence[int]) -> None:
        self.n = n
        self.intervals = tuple(int(i) for i in intervals)
        self.phases = len(self.intervals)
        self.K = sum(self.intervals)
        self.nodes = self.K + 1
        self.x_start = self.K
        self.u_start = self.x_start + 3 * n * self.nodes
        self.size = self.u_start + n * self.K
        #: Phase of each interval, shape (K,).
        self.phase_of = np.repeat(np.arange(self.phases), self.intervals)
        #: First node of each phase, shape (P + 1,) (the last entry is K).
        self.first_node = np.concatenate([[0], np.cumsum(self.intervals)]).astype(int)

    def x_index(self, node: int, block: int) -> slice:
        """Indices of block 0 (zq), 1 (zv) or 2 (za) of a node's state."""
        start = self.x_start + 3 * self.n * node + block * self.n
        return slice(start, start + self.n)

    def u_index(self, interval: int) -> slice:
        """Indices of an interval's scaled jerk."""
        start = self.u_start + self.n * interval
        return slice(start, start + self.n)

    def split(self, w: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(h, X, U)``: interval lengths (K,), scaled states (K + 1, 3n), jerks (K, n)."""
        durations = w[: self.K]
        states = w[self.x_start : self.u_start].reshape(self.nodes, 3 * self.n)
        jerks = w[self.u_start :].reshape(self.K, self.n)
        return durations, states, jerks
