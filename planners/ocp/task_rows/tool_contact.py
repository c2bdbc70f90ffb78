"""A tool contact as NLP rows: the velocity of the contact point at the contact node.

:class:`ToolContactRows` turns the :class:`problems.constraints.ToolContact` of a paddle
strike into rows at the node where its phase starts or ends: the velocity of the point
``offset`` along the tool z axis equals the contact's velocity. The contact's position and
axis need no rows: the formulation pins the contact configuration the contact choice found
(variable bounds), which puts the point and the axis there. The contact's numbers are the
NLP parameters ``contact_velocity`` and ``offset``.

Example::

    rows = ToolContactRows.of(contact, phase=0)  # at the end of the approach
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.ocp.task_rows.base import TaskContext, TaskRows
from optraj.problems.constraints import ToolContact

if TYPE_CHECKING:
    from optraj.planners.ocp.rows import Rows

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ToolContactRows(TaskRows):
    """The velocity rows of a tool contact at the start or end of a phase.

    Attributes:
        phase: Index of the phase (with ``at``, the NLP's shape: rows compare by them alone).
        at: ``"start"`` or ``"end"`` of the phase.
        contact: The tool contact, as the checker reads it; its velocity is required.
    """

    phase: int
    at: Literal["start", "end"]
    contact: ToolContact = field(compare=False, repr=False)

    parameters = (("contact_velocity", 3), ("offset", 1))

    @classmethod
    def of(cls, contact: ToolContact, phase: int) -> ToolContactRows:
        """The rows of ``contact`` at its end (``contact.at``) of the phase of index ``phase``.

        Raises:
            InvalidInputError: The contact requires no velocity.
        """
        if contact.velocity is None:
            raise InvalidInputError(
                f"tool contact {contact.label!r} has no velocity to write rows for",
                name="velocity",
            )
        return cls(phase, contact.at, contact)

    def values(self) -> dict[str, FloatArray]:
        """``contact_velocity`` [m/s] and ``offset`` [m]."""
        return {
            "contact_velocity": np.asarray(self.contact.velocity, dtype=float),
            "offset": np.array([float(self.contact.offset)]),
        }

    def node(self, first_node: NDArray[np.int_]) -> int:
        """The contact node, given each phase's first node (and the last node)."""
        return int(first_node[self.phase] if self.at == "start" else first_node[self.phase + 1])

    def add(self, rows: Rows, nlp: TaskContext) -> None:
        """Velocity of the contact point (``offset`` along tool z) at the contact node."""
        params = nlp.parameters
        rotation = nlp.symbolic.frame_rotation(nlp.tool_frame)
        jacobian = nlp.symbolic.frame_jacobian(nlp.tool_frame)
        q, qd, _ = nlp.state(self.node(nlp.layout.first_node))
        jac = jacobian(q)
        lever = params["offset"] * rotation(q)[:, 2]
        twist = jac @ qd
        velocity = twist[:3] + ca.cross(twist[3:], lever)
        rows.add("contact velocity", velocity - params["contact_velocity"], 0.0, 0.0)
