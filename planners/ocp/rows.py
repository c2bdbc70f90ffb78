"""Constraint rows of the transcription: bounds of each group, torque expansions, task rows."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.planners.ocp.structure import (
    Layout,
    Structure,
)
from optraj.robots import JointLimits, SymbolicModel

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
    """Parameters of the linear torque rows, after :data:`PARAMETERS` (0 for RNEA rows)."""
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


def strike_rows(
    rows: Rows,
    structure: Structure,
    layout: Layout,
    symbolic: SymbolicModel,
    params: dict[str, ca.SX],
    h: list[ca.SX],
    state: Any,
) -> None:
    """Cue tip on the schedule, cue axis on the line at every node; speed at entry and exit."""
    ph = structure.strike_phase
    tool = (
        symbolic.frame_position(structure.tool_frame),
        symbolic.frame_rotation(structure.tool_frame),
        symbolic.frame_jacobian(structure.tool_frame),
    )
    entry, d = params["entry"], params["direction"]
    first, last = int(layout.first_node[ph]), int(layout.first_node[ph + 1])
    for j, node in enumerate(range(first, last + 1)):
        q, qd, _ = state(node)
        target = entry + params["speed"] * ca.sum1(ca.vertcat(0, *h[first : first + j])) * d
        strike_node_rows(rows, tool, params, q, qd, target, node in (first, last), node)


def strike_node_rows(
    rows: Rows,
    tool: tuple[ca.Function, ca.Function, ca.Function],
    params: dict[str, ca.SX],
    q: ca.SX,
    qd: ca.SX,
    target: ca.SX,
    at_end: bool,
    node: int = -1,
) -> None:
    """The strike line's rows at one node, shared by the NLP and the window check.

    The cue tip at ``target`` [m], the cue axis along the direction (its two components across
    it zero, and pointing forward), and at the window's ends (``at_end``) the tip velocity
    ``speed * direction`` [m/s].

    Args:
        rows: The rows to add to.
        tool: The tool frame's position, rotation and Jacobian as functions of q.
        params: ``direction``, ``e1``, ``e2`` (the unit vectors across it) and ``speed``.
        q: Joint positions [rad or m].
        qd: Joint velocities [rad/s or m/s].
        target: The tip's place on the schedule [m].
        at_end: Whether the node is the window's first or last.
        node: The node's index, to label the rows with (-1: none).
    """
    position, rotation, jacobian = tool
    d, e1, e2 = params["direction"], params["e1"], params["e2"]
    rows.add("strike position", position(q) - target, 0.0, 0.0, at=node)
    z = rotation(q)[:, 2]
    rows.add("strike axis", ca.vertcat(ca.dot(e1, z), ca.dot(e2, z)), 0.0, 0.0, at=node)
    rows.add("strike axis sign", ca.dot(d, z), 0.0, np.inf, at=node)
    if at_end:
        speed = jacobian(q)[:3, :] @ qd - params["speed"] * d
        rows.add("strike speed", speed, 0.0, 0.0, at=node)


def contact_rows(
    rows: Rows,
    structure: Structure,
    symbolic: SymbolicModel,
    params: dict[str, ca.SX],
    state: Any,
) -> None:
    """Velocity of the contact point (``offset`` along tool z) at the contact node."""
    rotation = symbolic.frame_rotation(structure.tool_frame)
    jacobian = symbolic.frame_jacobian(structure.tool_frame)
    q, qd, _ = state(structure.contact_node)
    jac = jacobian(q)
    lever = params["offset"] * rotation(q)[:, 2]
    twist = jac @ qd
    velocity = twist[:3] + ca.cross(twist[3:], lever)
    rows.add("contact velocity", velocity - params["contact_velocity"], 0.0, 0.0)
