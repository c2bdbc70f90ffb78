"""The face every task row kind shows the transcription: its parameters and its rows.

A task row kind (:class:`planners.ocp.task_rows.strike_line.StrikeLineRows`,
:class:`planners.ocp.task_rows.tool_contact.ToolContactRows`) is built from one constraint
object of ``problem.constraints()`` (:mod:`problems.constraints`, the objects the checker
measures) and the phase it applies to. It names the NLP parameters its rows read
(:attr:`TaskRows.parameters`), gives their values for its constraint (:meth:`TaskRows.values`)
and adds its rows to the NLP (:meth:`TaskRows.add`). Only its phase belongs to the NLP's
shape: the constraint's numbers are parameter values, so problems that differ only in them
share one compiled NLP (a row kind compares and hashes by its phase alone).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    import casadi as ca

    from optraj.planners.ocp.rows import Rows
    from optraj.planners.ocp.structure import Layout
    from optraj.robots import SymbolicModel

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class TaskContext:
    """What task rows are written in: the NLP's symbols and the robot's tool frame.

    Attributes:
        symbolic: Symbolic kinematics of the robot.
        tool_frame: Frame whose pose the rows constrain.
        layout: Where each quantity sits in the decision vector.
        durations: The interval lengths ``h_k`` [s], one symbol each.
        parameters: The NLP parameters by name (:class:`planners.ocp.parameters.ParameterLayout`).
        state: ``node -> (q, qd, qdd)``, a node's state in physical units.
    """

    symbolic: SymbolicModel
    tool_frame: str
    layout: Layout
    durations: list[ca.SX]
    parameters: Mapping[str, ca.SX]
    state: Callable[[int], tuple[ca.SX, ca.SX, ca.SX]]


class TaskRows(ABC):
    """A kind of task rows: named parameters, their values and the rows that read them."""

    #: The parameters the rows read, ``(name, size)`` in order.
    parameters: ClassVar[tuple[tuple[str, int], ...]] = ()

    @abstractmethod
    def values(self) -> dict[str, FloatArray]:
        """The parameter values of this constraint, by name."""

    @abstractmethod
    def add(self, rows: Rows, nlp: TaskContext) -> None:
        """Add the rows, in their fixed order, to ``rows``."""
