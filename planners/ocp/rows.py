"""Constraint rows of the transcription, collected by group; the torque rows' coefficients.

The task rows (strike line, tool contact) are in :mod:`planners.ocp.task_rows`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.planners.ocp.structure import Structure
from optraj.robots import JointLimits

if TYPE_CHECKING:
    from optraj.planners.ocp.transcription import CompiledNLP

FloatArray = NDArray[np.float64]


class Rows:
    """Constraint rows collected group by group, each labelled with its joint and place."""

    def __init__(self) -> None:
        self.rows: list[ca.SX] = []
        self.lower: list[FloatArray] = []
        self.upper: list[FloatArray] = []
        self.groups: list[tuple[str, int, int]] = []
        self.joint: list[NDArray[np.intp]] = []
        self.part: list[NDArray[np.intp]] = []
        self.at: list[NDArray[np.intp]] = []
        self.count = 0

    def add(
        self,
        name: str,
        expr: ca.SX,
        lower: float | FloatArray,
        upper: float | FloatArray,
        *,
        joints: int = 0,
        parts: Sequence[int] = (),
        at: int = -1,
    ) -> None:
        """Rows ``lower <= expr <= upper`` (bounds broadcast), in group ``name``.

        Args:
            name: The group.
            expr: The row expressions (any shape; taken column by column).
            lower: Lower bounds, broadcast to the rows.
            upper: Upper bounds, broadcast to the rows.
            joints: With n > 0, the rows come in blocks of one row per joint (row i is
                joint ``i % n``'s); 0 for rows of no one joint.
            parts: The state part of each block (0 position, 1 velocity, 2 acceleration),
                one entry per block; none given: -1.
            at: The interval or node the rows belong to, -1 for none.
        """
        size = int(expr.numel())
        if size == 0:
            return
        self.rows.append(ca.vec(expr))
        self.lower.append(np.broadcast_to(np.asarray(lower, float).reshape(-1), (size,)))
        self.upper.append(np.broadcast_to(np.asarray(upper, float).reshape(-1), (size,)))
        index = np.arange(size, dtype=np.intp)
        self.joint.append(index % joints if joints else np.full(size, -1, np.intp))
        blocks = index // joints if joints else index
        part = np.asarray(parts, dtype=np.intp)
        self.part.append(part[blocks] if part.size else np.full(size, -1, np.intp))
        self.at.append(np.full(size, at, np.intp))
        if self.groups and self.groups[-1][0] == name and self.groups[-1][2] == self.count:
            self.groups[-1] = (name, self.groups[-1][1], self.count + size)
        else:
            self.groups.append((name, self.count, self.count + size))
        self.count += size


def structure_limits(limits: JointLimits) -> tuple[tuple[float, ...], ...]:
    """Limit rows of a :class:`Structure`: lower, upper, velocity, acceleration, jerk, effort."""
    return tuple(
        tuple(float(v) for v in values)
        for values in (
            limits.lower,
            limits.upper,
            limits.velocity,
            limits.acceleration,
            limits.jerk,
            limits.effort,
        )
    )


def torque_parameter_count(structure: Structure) -> int:
    """Size of the linear torque rows' parameter ``torque`` (0 for RNEA rows)."""
    if structure.torque_rows != "linear":
        return 0
    n = len(structure.limits[0])
    return len(structure.torque_nodes) * (n + 3 * n * n)


def torque_linearization(
    compiled: CompiledNLP, w: FloatArray, margin: float | FloatArray
) -> FloatArray:
    """Coefficients of linear torque rows, expanded about the node states of ``w``.

    The row of a torque node is ``c + B z`` with ``z = (zq, zv, za)`` its scaled state,
    bounded by [-1, 1]: at the expansion point it equals the RNEA torque over
    ``(1 - margin)`` times the effort limit, and its gradient is the RNEA's.

    Args:
        compiled: An NLP with linear torque rows.
        w: Decision vector whose node states are the expansion points.
        margin: Fraction of the torque limits kept free [-]: one for every row, or one per
            torque node and joint, shape (nodes, n).

    Returns:
        Parameter values, shape (:func:`torque_parameter_count`,): per torque node ``c``
        then ``B`` (n x 3n) in column order.
    """
    structure, layout = compiled.structure, compiled.layout
    nodes = structure.torque_nodes
    if compiled.torque_expansion is None or not nodes:
        return np.zeros(0)
    n = layout.n
    _, states, _ = layout.split(np.asarray(w, dtype=float))
    z = states[list(nodes)].T  # (3n, m)
    t, jac = (np.asarray(v) for v in compiled.torque_expansion(z))
    # The mapped Jacobians sit side by side, (n, 3n m): node i's in columns 3n i .. 3n (i + 1).
    jac = jac.reshape(n, 3 * n, len(nodes), order="F").transpose(2, 0, 1)  # (m, n, 3n)
    scale = np.broadcast_to(1.0 / (1.0 - np.asarray(margin, dtype=float)), (len(nodes), n))
    c = scale * (t.T - np.einsum("mij,jm->mi", jac, z))
    b = scale[:, :, None] * jac
    blocks = [np.concatenate([c[i], b[i].reshape(-1, order="F")]) for i in range(len(nodes))]
    return np.concatenate(blocks)
