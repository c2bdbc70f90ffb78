"""The task constraints of a problem as NLP rows and bounds, one kind per module.

Each kind is built from a constraint object of ``problem.constraints()``
(:mod:`problems.constraints`, the objects the checker measures):

* :class:`StrikeLineRows` (:class:`problems.constraints.StrikeLine`): the cue tip on its
  schedule and the cue axis on the line at every node of the strike window;
* :class:`ToolContactRows` (:class:`problems.constraints.ToolContact`): the velocity of the
  contact point at the contact node;
* :class:`FixedState` (:class:`problems.constraints.BoundaryState`): the start and goal
  states, as variable bounds;
* :class:`ClearanceRows` (a pool strike's cloth and ball, :mod:`planners.ocp.clearance`):
  spheres on the arm and cue above the cloth, the cue tip behind the ball on the approach.

The row kinds share the face of :class:`TaskRows`: named parameters, their values, and
:meth:`TaskRows.add`, which :func:`planners.ocp.transcription.compile_nlp` calls in order.
"""

from optraj.planners.ocp.task_rows.base import TaskContext, TaskRows
from optraj.planners.ocp.task_rows.boundary_state import FixedState
from optraj.planners.ocp.task_rows.clearance import ClearanceRows
from optraj.planners.ocp.task_rows.strike_line import StrikeLineRows, strike_node_rows
from optraj.planners.ocp.task_rows.tool_contact import ToolContactRows

__all__ = [
    "ClearanceRows",
    "FixedState",
    "StrikeLineRows",
    "TaskContext",
    "TaskRows",
    "ToolContactRows",
    "strike_node_rows",
]
