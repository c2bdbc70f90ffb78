r"""A strike line as NLP rows: the cue tip on its schedule, the cue axis on the line.

:class:`StrikeLineRows` turns the :class:`problems.constraints.StrikeLine` of a pool strike
into rows at every node of its window phase: the tool origin (the cue tip) at
:math:`p_{entry} + v\,t\,d`, :math:`t` the time since the window opened; the tool z axis with
no component along the two unit vectors :math:`e_1, e_2` across :math:`d` and
:math:`d \cdot z \ge 0` (the roll stays free); the tip velocity :math:`v d` at the window's
first and last nodes only (the positions on the schedule fix the speed in between:
equalities at every node would over-determine a 7-DOF arm whose last joint only rolls the
cue). The line's numbers are the NLP parameters ``entry``, ``direction``, ``e1``, ``e2`` and
``speed``. Between the nodes the plan checks the line after each solve
(:meth:`StrikeLineRows.misses`) and refines the window's grid where it leaves it.

Example::

    rows = StrikeLineRows.of(line, ("approach", "strike", "stop"))
    rows.phase  # 1: the rows are at the nodes of the strike phase
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.ocp.task_rows.base import TaskContext, TaskRows
from optraj.problems.common import normal_pair
from optraj.problems.constraints import StrikeLine

if TYPE_CHECKING:
    from optraj.planners.ocp.rows import Rows
    from optraj.planners.trajectory import Trajectory
    from optraj.robots import Robot

FloatArray = NDArray[np.float64]

#: Relative mismatch allowed between a line's ``run_up`` and ``speed * contact_delay`` (the
#: round-off of a division and a product).
RUN_UP_ROUND_OFF = 1e-12

#: Fractions of each interval at which :meth:`StrikeLineRows.misses` measures the line.
BETWEEN_NODES = (0.25, 0.5, 0.75)


@dataclass(frozen=True)
class StrikeLineRows(TaskRows):
    """The rows of a strike line at the nodes of its window phase.

    Attributes:
        phase: Index of the window phase (the NLP's shape: rows compare by it alone).
        line: The strike line, as the checker reads it.
    """

    phase: int
    line: StrikeLine = field(compare=False, repr=False)

    parameters = (("entry", 3), ("direction", 3), ("e1", 3), ("e2", 3), ("speed", 1))

    @classmethod
    def of(cls, line: StrikeLine, phases: Sequence[str]) -> StrikeLineRows:
        """The rows of ``line`` in the phase of that name among ``phases``.

        Raises:
            InvalidInputError: No phase has the line's name; the line does not hold the cue
                axis along it (these rows always do); or its ``run_up`` is not the distance
                ``speed * contact_delay`` that the checker's schedule puts before contact.
        """
        if line.phase not in phases:
            raise InvalidInputError(
                f"the strike line is in phase {line.phase!r}; the phases are {list(phases)}",
                name="phase",
            )
        if line.align_axis is not True:
            raise InvalidInputError(
                "the optimal-control strike rows hold the cue axis along the line; "
                f"got a StrikeLine with align_axis={line.align_axis!r}",
                name="align_axis",
            )
        if line.run_up is not None:
            timed = float(line.speed) * float(line.contact_delay)
            if abs(float(line.run_up) - timed) > RUN_UP_ROUND_OFF * max(1.0, timed):
                raise InvalidInputError(
                    f"StrikeLine.run_up = {line.run_up!r} m, but speed x contact_delay = "
                    f"{timed!r} m: the schedule would not pass the contact point at "
                    "contact_delay",
                    name="run_up",
                )
        return cls(list(phases).index(line.phase), line)

    def values(self) -> dict[str, FloatArray]:
        """``entry``, ``direction``, the unit vectors ``e1``, ``e2`` across it and ``speed``."""
        direction = np.asarray(self.line.direction)
        e1, e2 = normal_pair(direction)
        return {
            "entry": self.line.entry_point,
            "direction": direction,
            "e1": e1,
            "e2": e2,
            "speed": np.array([float(self.line.speed)]),
        }

    def nodes(self, first_node: NDArray[np.int_]) -> range:
        """The window's nodes, given each phase's first node (and the last node)."""
        return range(int(first_node[self.phase]), int(first_node[self.phase + 1]) + 1)

    def add(self, rows: Rows, nlp: TaskContext) -> None:
        """Cue tip on the schedule and cue axis on the line at every node; speed at the ends."""
        symbolic, params, h = nlp.symbolic, nlp.parameters, nlp.durations
        tool = (
            symbolic.frame_position(nlp.tool_frame),
            symbolic.frame_rotation(nlp.tool_frame),
            symbolic.frame_jacobian(nlp.tool_frame),
        )
        entry, d = params["entry"], params["direction"]
        nodes = self.nodes(nlp.layout.first_node)
        first, last = nodes[0], nodes[-1]
        for j, node in enumerate(nodes):
            q, qd, _ = nlp.state(node)
            target = entry + params["speed"] * ca.sum1(ca.vertcat(0, *h[first : first + j])) * d
            strike_node_rows(rows, tool, params, q, qd, target, node in (first, last), node)

    def misses(self, traj: Trajectory, robot: Robot) -> list[tuple[str, float, float, str]]:
        """Where the cue tip leaves its schedule between the window's nodes.

        Measured at :data:`BETWEEN_NODES` of each interval of the window.

        Returns:
            ``(what, worst, allowed, unit)`` for each of the distance to the schedule [mm],
            the cue axis's angle to the direction [deg] and the relative speed error [%]
            that passes half its tolerance; empty when the strike stays on schedule.
        """
        line = self.line
        phase = traj.phase(line.phase)
        knots = traj.breakpoints
        inside = knots[(knots >= phase.t_start - 1e-12) & (knots <= phase.t_end + 1e-12)]
        fractions = np.array(BETWEEN_NODES)
        times = (inside[:-1, None] + fractions[None, :] * np.diff(inside)[:, None]).reshape(-1)
        s = traj.sample(times)
        poses = robot.tool_pose(s.q)
        direction = np.asarray(line.direction)
        speed = float(line.speed)
        schedule = self.line.entry_point + speed * (times - phase.t_start)[:, None] * direction
        gap = np.max(np.linalg.norm(poses[:, :3, 3] - schedule, axis=1))
        axis = np.clip(poses[:, :3, 2] @ direction, -1.0, 1.0)
        angle = np.max(np.arccos(axis))
        jac = robot.jacobian(s.q)
        velocity = np.einsum("kij,kj->ki", jac[:, :3, :], s.qd)
        speed_error = np.max(np.linalg.norm(velocity - speed * direction, axis=1)) / speed
        measured = (
            ("distance to the schedule", 1e3 * gap, 1e3 * line.position_tolerance, "mm"),
            ("cue axis angle", np.degrees(angle), np.degrees(line.angle_tolerance), "deg"),
            ("speed error", 100 * speed_error, 100 * line.speed_tolerance, "%"),
        )
        return [
            (name, float(value), 0.5 * float(tolerance), unit)
            for name, value, tolerance, unit in measured
            if not value <= 0.5 * tolerance
        ]


def strike_node_rows(
    rows: Rows,
    tool: tuple[ca.Function, ca.Function, ca.Function],
    params: Mapping[str, ca.SX],
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
