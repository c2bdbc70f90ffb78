"""Between refinement rounds: tightened limits, shrunk position bounds, kept multipliers."""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import NDArray

from optraj.planners.checker import RELATIVE_SLACK
from optraj.planners.ocp.options import (
    MAX_SHRINK,
    SHRINK_EXTRA,
    STRIKE_ACCELERATION_ROOM,
    STRIKE_VELOCITY_ROOM,
    TORQUE_POINTS,
)
from optraj.planners.ocp.problem import (
    FixedState,
    Spec,
    WarmStart,
)
from optraj.planners.ocp.transcription import (
    CompiledNLP,
)
from optraj.planners.trajectory import Trajectory
from optraj.robots import JointLimits
from optraj.validation import (
    as_number,
)

FloatArray = NDArray[np.float64]


def fixed_room(
    spec: Spec, first: NDArray[np.int_], nodes: tuple[int, ...], margin: float | FloatArray
) -> float | FloatArray:
    """Torque row margins that a fully fixed state's own torques fit within.

    The margin keeps room below the effort limits for the linear rows' expansion error and
    for peaks between nodes; at a node whose state the problem fixes the torques are what
    they are, and a margin past them would make the NLP infeasible at that node alone (a
    start at rest holding 99 % of a limit against gravity, with a margin of 3 %).

    Args:
        spec: The problem's spec (its fixed states).
        first: First node of each phase, and the last node, shape (phases + 1,).
        nodes: The nodes with torque rows.
        margin: One margin for every row, or one per row node and joint, shape
            (len(nodes), n) [-].

    Returns:
        ``margin``, or per row node and joint with each fixed node's margin at most
        ``1 - |tau| / effort`` there (at least 0).
    """
    index = {node: i for i, node in enumerate(nodes)}
    room: FloatArray | None = None
    for fixed in spec.fixed:
        state = fixed.exact()
        node = fixed.node(first)
        if state is None or node not in index:
            continue
        tau = spec.robot.inverse_dynamics(*state)
        left = np.maximum(1.0 - np.abs(tau) / spec.limits.effort, 0.0)
        if room is None:
            room = np.array(np.broadcast_to(margin, (len(nodes), spec.limits.n)), dtype=float)
        room[index[node]] = np.minimum(room[index[node]], left)
    return margin if room is None else room


def fixed_ratios(spec: Spec) -> FloatArray:
    """Each joint's largest ``|tau| / effort`` over the problem's fully fixed states [-], (n,)."""
    ratios = np.zeros(spec.limits.n)
    for fixed in spec.fixed:
        state = fixed.exact()
        if state is None:
            continue
        tau = spec.robot.inverse_dynamics(*state)
        ratios = np.maximum(ratios, np.abs(tau) / spec.limits.effort)
    return ratios


def fixed_name(fixed: FixedState, last: int) -> str:
    """A fixed state in words: ``"the start state (at rest)"``, ``"the goal state"`` ..."""
    if fixed.at == "start" and fixed.phase == 0:
        name = "the start state"
    elif fixed.at == "end" and fixed.phase == last:
        name = "the goal state"
    else:  # pragma: no cover - the problems fix no other full state
        name = f"the state at the {fixed.at} of phase {fixed.phase}"
    moving = np.any(np.asarray(fixed.qd) != 0.0) or np.any(np.asarray(fixed.qdd) != 0.0)
    return name if moving else f"{name} (at rest)"


def strike_caps(ratio: float, keep: float = 1.0) -> tuple[float, float]:
    """Bounds of the strike nodes' joint velocities and accelerations, fractions of the limits.

    Args:
        ratio: The largest fraction of a joint velocity limit the strike line needs at the
            requested speed (:attr:`planners.strike.contact.ContactChoice.ratio`), >= 0 [-].
        keep: The bound without a cap, 1 minus the planner's margin, in (0, 1] [-].

    Returns:
        ``(velocity, acceleration)``: :data:`STRIKE_VELOCITY_ROOM` times ``ratio`` and
        :data:`STRIKE_ACCELERATION_ROOM` times its square, each at most ``keep`` [-].
        The caps bind only in slow strikes.

    Raises:
        InvalidInputError: A ratio that is not a finite number >= 0, or ``keep`` outside
            (0, 1].
    """
    value = as_number(ratio, "ratio", minimum=0.0)
    room = as_number(keep, "keep", minimum=0.0, maximum=1.0, open_minimum=True)
    return (
        min(room, STRIKE_VELOCITY_ROOM * value),
        min(room, STRIKE_ACCELERATION_ROOM * value * value),
    )


def tightened(
    margins: FloatArray,
    ratio: FloatArray,
    fixed: FloatArray | float = 0.0,
    per_interval: int = TORQUE_POINTS,
) -> FloatArray:
    """Torque row margins after a round whose dense torques broke their limits.

    Args:
        margins: Margins of the rows at every node, shape (K + 1, n) [-].
        ratio: Signed torque over effort limit at ``per_interval`` points per interval and
            the last node (as :func:`dense_times`), shape (per_interval K + 1, n) [-].
        fixed: Per joint, the share of its limit a fixed state of the problem needs
            (:func:`fixed_ratios`), shape (n,) [-]: a peak up to it is no excess.
        per_interval: Points per interval in ``ratio``.

    Returns:
        The margins of both end nodes of an interval whose peak passes ``1 - margin / 2``
        (and ``fixed``) raised by that excess plus 0.005, at most 0.5.
    """
    size = np.abs(ratio)
    intervals = margins.shape[0] - 1
    inner = size[:-1].reshape(intervals, per_interval, -1).max(axis=1)
    peaks = np.maximum(inner, size[per_interval::per_interval])  # (K, n), ends included
    excess = peaks - np.maximum(1.0 - 0.5 * np.minimum(margins[:-1], margins[1:]), fixed)
    bump = np.where(excess > 0.0, excess + 0.005, 0.0)
    raised = margins.copy()
    raised[:-1] = np.maximum(raised[:-1], margins[:-1] + bump)
    raised[1:] = np.maximum(raised[1:], margins[1:] + bump)
    return np.minimum(raised, 0.5)


def constraint_duals(saved: WarmStart, compiled: CompiledNLP) -> FloatArray | None:
    """A solution's constraint multipliers for ``compiled``, or None when they do not apply.

    They apply to the same structure, and to one that differs only in its torque rows
    (those come last, n per node): a torque node's multipliers carry over where it had
    rows before, new rows start at zero.
    """
    old, new = saved.structure, compiled.structure
    if old == new:
        return saved.lam_g
    same_rows = dataclasses.replace(
        old,
        torque_nodes=new.torque_nodes,
        torque_rows=new.torque_rows,
        torque_margin=new.torque_margin,
    )
    if same_rows != new:
        return None
    n = compiled.layout.n
    base = saved.lam_g.size - n * len(old.torque_nodes)
    lam_g = np.zeros(compiled.lbg.size)
    if base < 0 or base + n * len(new.torque_nodes) != lam_g.size:
        return None
    lam_g[:base] = saved.lam_g[:base]
    before = {node: i for i, node in enumerate(old.torque_nodes)}
    for i, node in enumerate(new.torque_nodes):
        if node in before:
            j = before[node]
            lam_g[base + n * i : base + n * (i + 1)] = saved.lam_g[
                base + n * j : base + n * (j + 1)
            ]
    return lam_g


def shrunk(shrink: FloatArray | None, excess: FloatArray, limits: JointLimits) -> FloatArray:
    """Node bounds moved in after pieces passed a position limit between their nodes.

    Args:
        shrink: Moves so far, shape (K + 1, 2, n) [rad or m] (lower bound raised, upper
            lowered), or None.
        excess: :func:`position_excess` of the last solution, shape (K, 2, n).
        limits: The joint limits.

    Returns:
        Both end nodes of a piece that passed a limit keep twice that excess (plus
        :data:`SHRINK_EXTRA`) more room on that side (once is seldom enough: the piece
        moves with its nodes), at most :data:`MAX_SHRINK` of the joint's range.
    """
    moved = np.zeros((excess.shape[0] + 1, *excess.shape[1:])) if shrink is None else shrink
    bump = np.where(excess > 0.0, 2.0 * excess + SHRINK_EXTRA, 0.0)
    raised = moved.copy()
    raised[:-1] = np.maximum(raised[:-1], moved[:-1] + bump)
    raised[1:] = np.maximum(raised[1:], moved[1:] + bump)
    return np.minimum(raised, MAX_SHRINK * (limits.upper - limits.lower))


def position_excess(traj: Trajectory, limits: JointLimits) -> FloatArray:
    """How far each cubic piece passes the position limits between its ends [rad or m].

    Exact: each piece's extremes are at its ends or where its velocity vanishes inside it.
    A limit may be passed by the checker's slack (:data:`planners.checker.RELATIVE_SLACK`).

    Returns:
        Shape (K, 2, n): per piece, how far it goes below the lower limit (column 0) and
        above the upper one (column 1); 0 where it stays within.
    """
    c = traj.coefficients  # (K, 4, n): q0, qd0, qdd0 / 2, jerk / 6
    h = np.diff(traj.breakpoints)[:, None]
    a, b, lin = 3.0 * c[:, 3], 2.0 * c[:, 2], c[:, 1]  # velocity a t^2 + b t + lin
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.maximum(b * b - 4.0 * a * lin, 0.0))
        quadratic = np.abs(a) > 1e-300
        times = np.stack(
            [
                np.where(quadratic, (-b + root) / (2.0 * a), -lin / b),
                np.where(quadratic, (-b - root) / (2.0 * a), -lin / b),
            ]
        )
    inside = np.isfinite(times) & (times > 0.0) & (times < h) & (b * b >= 4.0 * a * lin)
    t = np.where(inside, times, 0.0)
    q = c[:, 0] + t * (c[:, 1] + t * (c[:, 2] + t * c[:, 3]))
    slack = RELATIVE_SLACK * np.maximum(np.abs(limits.lower), np.abs(limits.upper))
    below = np.where(inside, limits.lower - q, 0.0).max(axis=0)  # (K, n)
    above = np.where(inside, q - limits.upper, 0.0).max(axis=0)
    excess = np.stack([below, above], axis=1)
    return np.where(excess > slack, excess, 0.0)
