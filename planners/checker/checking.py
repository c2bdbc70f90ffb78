"""The checker's entry point: :func:`check` a trajectory against a robot or a problem.

It validates its inputs, builds the :class:`~planners.checker.context.CheckContext`,
measures the jumps, prepares one evaluation per task constraint (so that the tool
kinematics of all of them are computed in one batch), and gathers the limit findings, then
the task findings, into a :class:`~planners.checker.report.Report`.

Example::

    report = check(trajectory, problem, rate=1000.0, tool_speed=0.3)
    assert report.ok, report.violations
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import replace
from typing import Any

import numpy as np

from optraj.errors import InvalidInputError
from optraj.planners.checker.boundary_state import boundary_state_check, boundary_wanted
from optraj.planners.checker.clearance import clearance_check
from optraj.planners.checker.context import CheckContext
from optraj.planners.checker.joint_limits import QUANTITIES, limit_findings
from optraj.planners.checker.jumps import Jump, boundary_jumps, breakpoint_jumps
from optraj.planners.checker.kinematics import ToolKinematics
from optraj.planners.checker.polynomials import derivatives_of
from optraj.planners.checker.report import Checkable, Finding, Report, TrajectoryInfo
from optraj.planners.checker.strike_line import strike_line_check
from optraj.planners.checker.task import Evaluation
from optraj.planners.checker.tool_contact import tool_contact_check
from optraj.planners.checker.tool_path import tool_path_check, tool_speed_check
from optraj.planners.checker.via_point import via_point_check
from optraj.planners.trajectory import Trajectory, fitted_to, sampling_rate
from optraj.problems.constraints import BoundaryState, StrikeLine, ToolContact, ToolPath, ViaPoint
from optraj.problems.scene import Scene
from optraj.problems.scene_distances import SceneCollision
from optraj.robots import JointLimits, Robot
from optraj.validation import as_choice, as_positive

__all__ = ["check"]


def _target(target: Any) -> tuple[Robot, JointLimits, tuple[Any, ...]]:
    """Robot, limits and constraints of a robot or of a duck-typed problem."""
    if isinstance(target, Robot):
        return target, target.limits, ()
    robot = getattr(target, "robot", None)
    limits = getattr(target, "limits", None)
    constraints = getattr(target, "constraints", None)
    if not (isinstance(robot, Robot) and isinstance(limits, JointLimits) and callable(constraints)):
        raise InvalidInputError(
            "target must be a robots.Robot or a problem with .robot (a robots.Robot), .limits "
            f"(a robots.JointLimits) and .constraints(), got {type(target).__name__}",
            name="target",
        )
    if limits.n != robot.dof:
        raise InvalidInputError(
            f"the problem's limits cover {limits.n} joints, its robot has {robot.dof}",
            name="target",
        )
    listed = constraints()
    try:
        items = tuple(listed)
    except TypeError as exc:
        raise InvalidInputError(
            "target.constraints() must return an iterable of constraints, got "
            f"{type(listed).__name__}",
            name="target",
        ) from exc
    return robot, limits, items


def _quantities(quantities: Iterable[str] | None) -> tuple[str, ...]:
    if quantities is None:
        return QUANTITIES
    if isinstance(quantities, str):
        wanted: list[object] = [quantities]
    else:
        try:
            wanted = list(quantities)
        except TypeError as exc:
            raise InvalidInputError(
                f"quantities must be a name or names from {QUANTITIES}, got {quantities!r}",
                name="quantities",
            ) from exc
    for name in wanted:
        as_choice(name, "quantity", QUANTITIES)
    return tuple(q for q in QUANTITIES if q in wanted)


def check(
    trajectory: Trajectory,
    target: Robot | Checkable,
    *,
    rate: float = 1000.0,
    quantities: Iterable[str] | None = None,
    tool_speed: float | None = None,
    scene: Scene | None = None,
) -> Report:
    """Check a trajectory against joint limits and, for a problem, its task constraints.

    Args:
        trajectory: The trajectory to judge (only its polynomials and phases are used).
        target: A :class:`robots.Robot` (its limits only), or a problem with ``.robot``,
            ``.limits`` and ``.constraints()`` (limits and every constraint).
        rate: Sampling rate [Hz], in (0, :data:`planners.trajectory.MAX_RATE`], for torques
            and task constraints (breakpoints and the instants just before them are always
            sampled); position, velocity, acceleration and jerk are bounded exactly on every
            segment whatever the rate. Rate times duration times joints must stay within
            :data:`optraj.validation.MAX_COUNT`.
        quantities: The limit findings to make, a subset of :data:`QUANTITIES`; all when None.
            Task findings are always made.
        tool_speed: A cap on the tool frame origin's speed over the whole trajectory [m/s]
            (what ``Toppra(tool_speed=...)`` promises): adds a ``tool speed`` finding,
            sampled at ``rate`` and every breakpoint; None for none. A
            :class:`problems.ToolPath` with ``speed`` adds one over its phase.
        scene: The robot's surroundings (:class:`problems.Scene`): adds a ``clearance``
            finding, the smallest distance between every pair that may not touch, sampled
            at ``rate`` with a bound between samples (:mod:`.clearance`), judged against the
            scene's margin. None: the problem's ``scene`` if it has one, else no clearance.

    Returns:
        The report: limit findings (one per quantity, worst joint and time) then task findings
        (``start state``, ``via point k``, ``tool path position``, ``strike speed``, ...).

    Raises:
        InvalidInputError: Not a Trajectory, an unusable target, a joint count that differs
            from the robot's, a bad rate, a malformed or unknown constraint, or a scene that
            is not a problems.Scene.
        UnknownNameError: An unknown quantity; lists the valid ones.
    """
    if not isinstance(trajectory, Trajectory):
        raise InvalidInputError(
            f"trajectory must be a planners.Trajectory, got {type(trajectory).__name__}",
            name="trajectory",
        )
    robot, limits, constraints = _target(target)
    fitted_to(trajectory, robot)
    wanted = _quantities(quantities)
    rate = sampling_rate(rate, trajectory.duration, trajectory.dof)
    ctx = _context(trajectory, robot, limits, rate)
    jumps = breakpoint_jumps(ctx.derivatives, ctx.knots, limits)
    evaluations: list[Evaluation] = []
    if tool_speed is not None:
        evaluations.append(tool_speed_check(as_positive(tool_speed, "tool_speed", "m/s"), ctx))
    evaluations.extend(_constraint_checks(constraints, ctx, jumps))
    surroundings = getattr(target, "scene", None) if scene is None else scene
    if surroundings is not None:
        evaluations.append(clearance_check(SceneCollision(robot, surroundings), ctx))
    ctx.kinematics.compute()
    findings = limit_findings(wanted, robot, ctx, jumps)
    findings.extend(_task_findings(evaluations))
    planner = trajectory.metadata.get("planner")
    info = TrajectoryInfo(
        duration=trajectory.duration,
        dof=trajectory.dof,
        segments=len(ctx.knots) - 1,
        samples=int(ctx.grid.size),
        rate=rate,
        planner=None if planner is None else str(planner),
        robot=robot.name,
    )
    return Report(tuple(findings), info)


def _context(
    trajectory: Trajectory, robot: Robot, limits: JointLimits, rate: float
) -> CheckContext:
    """The check context of ``trajectory`` sampled at ``rate`` [Hz]."""
    grid = trajectory.times(rate)
    knots = np.asarray(trajectory.breakpoints, dtype=float)
    derivatives = derivatives_of(np.asarray(trajectory.coefficients, dtype=float), 4)
    return CheckContext(
        trajectory=trajectory,
        limits=limits,
        names=limits.names,
        knots=knots,
        derivatives=derivatives,
        grid=grid,
        spacing=float(np.max(np.diff(grid))) if grid.size > 1 else trajectory.duration,
        kinematics=ToolKinematics(robot, derivatives, knots),
    )


def _constraint_checks(
    constraints: tuple[Any, ...], ctx: CheckContext, jumps: list[Jump]
) -> list[Evaluation]:
    """One evaluation per task constraint; the jumps against boundary states join ``jumps``.

    Raises:
        InvalidInputError: A malformed constraint, or one of an unknown type.
    """
    evaluations: list[Evaluation] = []
    for item in constraints:
        if isinstance(item, BoundaryState):
            prescribed = boundary_wanted(item, ctx.limits.n)
            evaluations.append(boundary_state_check(item, prescribed, ctx))
            time = 0.0 if item.at == "start" else ctx.duration
            jumps.extend(
                boundary_jumps(item, prescribed, ctx.state(time), time, ctx.limits, ctx.duration)
            )
        elif isinstance(item, ViaPoint):
            evaluations.append(via_point_check(item, ctx))
        elif isinstance(item, ToolPath):
            evaluations.append(tool_path_check(item, ctx))
        elif isinstance(item, StrikeLine):
            evaluations.append(strike_line_check(item, ctx))
        elif isinstance(item, ToolContact):
            evaluations.append(tool_contact_check(item, ctx))
        else:
            raise InvalidInputError(
                f"cannot check a constraint of type {type(item).__name__}; known: "
                "BoundaryState, ViaPoint, ToolPath, StrikeLine, ToolContact",
                name="constraints",
            )
    return evaluations


def _task_findings(evaluations: list[Evaluation]) -> list[Finding]:
    """The findings of every evaluation, in order, their names made unique.

    A repeated name gets a count, e.g. two contacts: ``"contact"``, ``"contact (2)"``.
    """
    findings: list[Finding] = []
    seen: dict[str, int] = {}
    for evaluate in evaluations:
        for finding in evaluate():
            count = seen.get(finding.name, 0) + 1
            seen[finding.name] = count
            if count > 1:
                finding = replace(finding, name=f"{finding.name} ({count})")
            findings.append(finding)
    return findings
