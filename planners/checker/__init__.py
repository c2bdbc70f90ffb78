"""The independent trajectory checker: every limit and every task constraint, densely sampled.

:func:`check` judges any :class:`~planners.trajectory.Trajectory` against a robot's joint limits
and, for a problem, against the task constraints it lists (``problem.constraints()``). It trusts
nothing a planner says: it reads only the trajectory's breakpoints, polynomial coefficients and
phases (the planner name is copied into the summary, nothing else of the metadata is used).

How the worst values are found:

* Joint quantities (position, velocity, acceleration, jerk) are bounded exactly on every
  polynomial segment, whatever the sampling rate: the worst value is taken over each segment's
  ends and the real roots of the next derivative, for every segment whose Bernstein enclosure
  could beat the best end or break the limit, vectorised over segments and joints
  (:mod:`.polynomials`, :mod:`.joint_limits`).
* Torques are computed by inverse dynamics (Pinocchio's RNEA, through :class:`robots.Robot`) at
  every sample: ``rate`` plus every breakpoint and the instant just before each.
* Jumps are measured exactly, from the polynomial on each side of every breakpoint, and between
  a prescribed start or end velocity (and acceleration, when prescribed) and the trajectory's
  (:mod:`.jumps`). A jump in a quantity makes every higher derivative unbounded: such findings
  fail with value ``inf``.
* Every comparison (a limit, a jump, a boundary state) allows the same round-off,
  :func:`round_off`: a relative ``RELATIVE_SLACK`` of the value's scale plus what the value
  changes over the round-off of the time at which it is computed (:mod:`.allowance`).
* Task constraints (tool on a line, strike schedule, contact) are measured from the tool frame
  pose and Jacobian, computed in one batched call over every instant needed (:mod:`.kinematics`;
  one module per constraint kind: :mod:`.boundary_state`, :mod:`.via_point`,
  :mod:`.tool_path`, :mod:`.strike_line`, :mod:`.tool_contact`).
* Clearance, for a problem with a ``scene`` or ``check(..., scene=...)``: the signed distance
  of every pair of shapes that may not touch (Pinocchio and coal), at every sample, with a
  bound between samples from the joints' speeds; doubtful intervals are halved
  (:mod:`.clearance`).

Example::

    report = check(trajectory, problem)
    print(report)  # a table of every finding
    assert report.ok, report.violations
"""

from optraj.planners.checker.allowance import (
    ABSOLUTE_SLACK,
    RELATIVE_SLACK,
    TIME_ROUND_OFF,
    round_off,
    state_allowance,
)
from optraj.planners.checker.checking import check
from optraj.planners.checker.joint_limits import QUANTITIES
from optraj.planners.checker.report import Checkable, Finding, Report, TrajectoryInfo
from optraj.planners.checker.strike_line import STRIKE_WINDOW_TOLERANCE
from optraj.planners.checker.verdict import failing_findings, finding_note, verdict
from optraj.planners.trajectory import MAX_RATE

__all__ = [
    "ABSOLUTE_SLACK",
    "MAX_RATE",
    "QUANTITIES",
    "RELATIVE_SLACK",
    "STRIKE_WINDOW_TOLERANCE",
    "TIME_ROUND_OFF",
    "Checkable",
    "Finding",
    "Report",
    "TrajectoryInfo",
    "check",
    "failing_findings",
    "finding_note",
    "round_off",
    "state_allowance",
    "verdict",
]
