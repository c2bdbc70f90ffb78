"""Boundary states as variable bounds: the node states a plan starts from and ends in.

A :class:`FixedState` pins a node's positions, velocities and accelerations (those given)
by equal lower and upper bounds of the decision vector (:meth:`FixedState.pin`), not by
rows: a start or goal is then a bound value, and one compiled NLP serves every problem of
the same shape. The start and goal come from the problem's
:class:`problems.constraints.BoundaryState` objects (:meth:`FixedState.of`); the formulation
adds the states its phases meet at (a waypoint, a paddle's contact configuration).

Example::

    start = FixedState.of(problems.constraints.BoundaryState("start", q, qd), phases=3)
    start.node(first_node)  # 0
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.planners.ocp.structure import Layout
from optraj.problems.constraints import BoundaryState

FloatArray = NDArray[np.float64]


@dataclass
class FixedState:
    """A node state pinned by bounds: ``phase`` start or end; None entries stay free.

    Attributes:
        phase: Index of the phase.
        at: ``"start"`` or ``"end"`` of the phase.
        q: Positions [rad or m], shape (n,), or None.
        qd: Velocities [rad/s or m/s], shape (n,), or None.
        qdd: Accelerations [rad/s^2 or m/s^2], shape (n,), or None.
        tolerance: Room the positions keep either side [rad or m].
    """

    phase: int
    at: str
    q: FloatArray | None
    qd: FloatArray | None
    qdd: FloatArray | None
    tolerance: float = 0.0

    @classmethod
    def of(cls, state: BoundaryState, phases: int) -> FixedState:
        """The start or goal of a motion of ``phases`` phases, pinned exactly.

        A state met exactly is met within any tolerance of the problem's; an acceleration the
        problem leaves open is pinned at zero (the motion starts and ends without a jerk
        impulse).
        """
        qdd = np.zeros(len(state.qd)) if state.qdd is None else state.qdd
        phase = 0 if state.at == "start" else phases - 1
        return cls(phase, state.at, state.q, state.qd, qdd)

    def exact(self) -> tuple[FloatArray, FloatArray, FloatArray] | None:
        """``(q, qd, qdd)`` when all three are pinned exactly (no tolerance), else None."""
        if self.q is None or self.qd is None or self.qdd is None or self.tolerance:
            return None
        return self.q, self.qd, self.qdd

    def node(self, first_node: NDArray[np.int_]) -> int:
        """The pinned node, given each phase's first node (and the last node)."""
        return int(first_node[self.phase] if self.at == "start" else first_node[self.phase + 1])

    def pin(
        self,
        lbx: FloatArray,
        ubx: FloatArray,
        layout: Layout,
        scale: tuple[FloatArray, ...],
        first_node: NDArray[np.int_],
    ) -> None:
        """Set the node's bounds to the state (positions within the tolerance), in place.

        Args:
            lbx: Scaled lower bounds of the decision vector.
            ubx: Scaled upper bounds.
            layout: The decision vector's layout.
            scale: The NLP's scales ``(mid, half, velocity, acceleration, ...)``.
            first_node: Each phase's first node, and the last node.
        """
        mid, half, vel, acc = scale[:4]
        node = self.node(first_node)
        for block, value, size, shift in (
            (0, self.q, half, mid),
            (1, self.qd, vel, 0.0),
            (2, self.qdd, acc, 0.0),
        ):
            if value is None:
                continue
            tol = self.tolerance if block == 0 else 0.0
            index = layout.x_index(node, block)
            lbx[index] = (value - tol - shift) / size
            ubx[index] = (value + tol - shift) / size
