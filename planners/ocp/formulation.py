"""Problems turned into specs: phases, fixed node states, task rows and a first guess."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any, Literal, TypeVar

import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    InfeasibleError,
    InvalidInputError,
    OptrajError,
    SolverError,
)
from optraj.planners.ocp.clearance import Clearance
from optraj.planners.ocp.guesses import (
    move_guess,
    quintic_guess,
    window_guess,
    zero_vector,
)
from optraj.planners.ocp.problem import (
    FixedState,
    Spec,
    WarmStart,
)
from optraj.planners.ocp.refinement import fixed_name
from optraj.planners.ocp.task_rows import (
    ClearanceRows,
    StrikeLineRows,
    TaskRows,
    ToolContactRows,
)
from optraj.planners.strike.contact import (
    BRANCH_SPREAD,
    ContactChoice,
    choose_contact,
    contact_near,
)
from optraj.planners.time_optimal.lower_bound import check_state_torques, joint_min_durations
from optraj.planners.time_optimal.ruckig_planner import stop
from optraj.planners.trajectory import Phase, Trajectory
from optraj.problems import PaddleStrike, PointToPoint, PoolStrike, Waypoints
from optraj.problems.constraints import BoundaryState, StrikeLine, ToolContact
from optraj.robots import JointLimits

if TYPE_CHECKING:
    from optraj.planners.ocp.optimal_control import OptimalControl

FloatArray = NDArray[np.float64]
C = TypeVar("C")


def check_duration(
    what: str,
    name: str,
    duration: float,
    needed: FloatArray,
    limits: JointLimits,
    bound: Literal["velocity", "jerk"],
) -> None:
    """Raise when a fixed duration [s] is below a joint's lower bound ``needed`` [s], (n,).

    ``bound`` says which limits the bound counts: ``"velocity"`` (distance over the velocity
    limit) or ``"jerk"`` (the velocity, acceleration and jerk limits together).
    """
    joint = int(np.argmax(needed))
    if needed[joint] > duration * (1.0 + 1e-9):
        limits_text = (
            "velocity limit" if bound == "velocity" else "velocity, acceleration and jerk limits"
        )
        raise InfeasibleError(
            f"{what} needs at least {needed[joint]:.4g} s: joint {limits.names[joint]!r} "
            f"cannot move faster within its {limits_text}; {name} is {duration:.4g} s",
            limit="duration",
            joint=limits.names[joint],
            required=float(needed[joint]),
            allowed=duration,
        )


def point_to_point_spec(problem: PointToPoint) -> Spec:
    """The one-phase spec of a point-to-point move, with its quintic first guess."""
    limits = problem.limits
    n = limits.n
    a0 = zero_vector(n) if problem.qdd_start is None else problem.qdd_start
    a1 = zero_vector(n) if problem.qdd_goal is None else problem.qdd_goal
    guess = move_guess(
        problem.q_start,
        problem.qd_start,
        a0,
        problem.q_goal,
        problem.qd_goal,
        a1,
        limits,
        problem.duration,
    )
    if problem.duration is not None and guess.duration > problem.duration * (1 + 1e-9):
        raise InfeasibleError(
            f"the move needs at least {guess.duration:.4g} s within the velocity, acceleration "
            f"and jerk limits; duration is {problem.duration:.4g} s",
            limit="duration",
            required=guess.duration,
            allowed=problem.duration,
        )
    alone = guess.metadata.get("independent_min_durations")  # a Ruckig move's, else none
    switch_joint = None
    if problem.duration is None and alone is not None and np.size(alone) == n:
        switch_joint = int(np.argmax(alone))
    guess = Trajectory(
        guess.breakpoints, guess.coefficients, phases=[Phase("move", 0.0, guess.duration)]
    )
    return Spec(
        robot=problem.robot,
        limits=limits,
        names=("move",),
        durations=(problem.duration,),
        guess=guess,
        fixed=_boundary_states(problem, phases=1),
        switch_joint=switch_joint,
    )


def keep_switch_grid(spec: Spec, warm_start: Trajectory | None) -> None:
    """Drop ``spec``'s switch grid (:attr:`Spec.switch_joint`) when a warm start sets the grid.

    A previous solution planned on a switch grid keeps it (its grid and multipliers carry
    over); any other warm start is sampled on an even grid, which the neighbour grid term
    and IPOPT's own first barrier suit.
    """
    if warm_start is None:
        return
    saved = warm_start.metadata.get("warm_start")
    if not isinstance(saved, WarmStart) or "anchor" not in dict(saved.structure.weights):
        spec.switch_joint = None


def waypoints_spec(problem: Waypoints) -> Spec:
    """The spec of a waypoint path: one phase per segment, rest at both ends."""
    limits = problem.limits
    n = limits.n
    points = np.asarray(problem.waypoints)
    fixed_durations = problem.segment_durations
    tol = 0.0 if problem.via_tolerance is None else float(problem.via_tolerance)
    pieces = []
    names = []
    for k in range(len(points) - 1):
        duration = None if fixed_durations is None else float(fixed_durations[k])
        if duration is not None:  # inner waypoints: passed at any speed, within tol of them
            slack = tol * ((k > 0) + (k + 1 < len(points) - 1))
            spans = np.maximum(np.abs(points[k + 1] - points[k]) - slack, 0.0) / limits.velocity
            check_duration(
                f"segment {k + 1}", f"segment_durations[{k}]", duration, spans, limits, "velocity"
            )
        pieces.append(
            (
                f"segment {k + 1}",
                [
                    move_guess(
                        points[k],
                        zero_vector(n),
                        zero_vector(n),
                        points[k + 1],
                        zero_vector(n),
                        zero_vector(n),
                        limits,
                        duration,
                    )
                ],
            )
        )
        names.append(f"segment {k + 1}")
    guess = Trajectory.sequence(pieces, joint_names=limits.names)
    start, end = _boundary_states(problem, phases=len(names))
    inner = [FixedState(k, "end", points[k + 1], None, None, tol) for k in range(len(points) - 2)]
    fixed = [start, *inner, end]
    durations: tuple[float | None, ...] = (
        (None,) * len(names)
        if fixed_durations is None
        else tuple(float(d) for d in fixed_durations)
    )
    return Spec(problem.robot, limits, tuple(names), durations, guess, fixed)


def _constraints_of(problem: Any, kind: type[C]) -> list[C]:
    """The constraints of ``problem`` (``problem.constraints()``) of one kind, in order."""
    return [item for item in problem.constraints() if isinstance(item, kind)]


def _boundary_states(problem: Any, phases: int) -> list[FixedState]:
    """The problem's start and goal states, pinned at the ends of its ``phases`` phases.

    From its :class:`problems.constraints.BoundaryState` objects (:meth:`FixedState.of`).
    """
    return [FixedState.of(state, phases) for state in _constraints_of(problem, BoundaryState)]


def checked_warm_start(problem: Any, warm_start: Any) -> Trajectory | None:
    """``warm_start`` checked against the problem: None, or a Trajectory of its joints."""
    if warm_start is None:
        return None
    if not isinstance(warm_start, Trajectory):
        raise InvalidInputError(
            f"warm_start must be a planners.Trajectory or None, got {type(warm_start).__name__}",
            name="warm_start",
        )
    limits = getattr(problem, "limits", None)
    if isinstance(limits, JointLimits) and warm_start.dof != limits.n:
        raise InvalidInputError(
            f"warm_start moves {warm_start.dof} joints; the problem's robot has {limits.n}",
            name="warm_start",
        )
    return warm_start


def previous_contact(problem: PoolStrike, warm_start: Trajectory | None) -> FloatArray | None:
    """The contact configuration a previous pool solution recorded [rad], shape (n,).

    None when there is none, or it does not lie within this problem's position limits.
    """
    if warm_start is None:
        return None
    previous = warm_start.metadata.get("contact_configuration")
    if previous is None:
        return None
    try:  # an array, or a list once read back from JSON
        q = np.asarray(previous, dtype=float)
    except (TypeError, ValueError):
        return None
    if (
        q.shape != (problem.limits.n,)
        or not np.all(np.isfinite(q))
        or not problem.limits.contains(q)
    ):
        return None
    return q


def contact_from(
    problem: PoolStrike, warm_start: Trajectory | None, margin: float
) -> ContactChoice | None:
    """The contact branch of a previous pool solution, if it still fits this problem.

    ``margin`` is the fraction of the velocity limits kept in reserve [-].
    """
    q = previous_contact(problem, warm_start)
    return None if q is None else contact_near(problem, q, margin=margin)


def lends_to(problem: PoolStrike, warm_start: Trajectory | None, choice: ContactChoice) -> bool:
    """Whether a warm start may seed the plan through ``choice``.

    Not when it is a pool solution through another IK branch (its contact configuration more
    than :data:`planners.strike.contact.BRANCH_SPREAD` from the choice's on some joint): IPOPT would
    have to drag the whole strike across from there, at the warm start's small barrier
    parameter, which takes far more iterations than a solve from the cold guess. A warm
    start that recorded no contact seeds any choice.
    """
    if warm_start is None:
        return False
    previous = warm_start.metadata.get("contact_configuration")
    if previous is None:
        return True
    q = previous_contact(problem, warm_start)
    return q is not None and float(np.abs(q - choice.q).max()) <= BRANCH_SPREAD


def pool_spec(
    problem: PoolStrike,
    choice: ContactChoice,
    warm_start: Trajectory | None = None,
    clearance: Clearance | None = None,
) -> Spec:
    """The pool strike's phases; the guess is a previous solution's, when one is given.

    With ``clearance``, the spec also keeps the arm and cue above the cloth and the cue tip
    behind the ball on the approach (:class:`planners.ocp.task_rows.ClearanceRows`).

    A previous pool solution (a re-plan's warm start, with its primal and dual values) also
    gives the phase durations the grid starts from, which saves the IK of the strike line
    and the Ruckig moves of a fresh guess.
    """
    limits = problem.limits
    n = limits.n
    phases = ("approach", "strike", "stop")
    if (
        warm_start is not None
        and isinstance(warm_start.metadata.get("warm_start"), WarmStart)
        and tuple(p.name for p in warm_start.phases) == phases
    ):
        guess = warm_start
    else:
        line = window_guess(problem, choice)
        entry = line.sample(0.0)
        leave = line.sample(line.duration)
        approach = move_guess(
            problem.q_start, zero_vector(n), zero_vector(n), entry.q, entry.qd, entry.qdd, limits
        )
        try:
            brake = stop(leave.q, leave.qd, leave.qdd, limits, check_limits=False)
        except OptrajError:
            brake = quintic_guess(leave.q, leave.q + 0.1 * leave.qd, 0.2)  # pragma: no cover
        guess = Trajectory.sequence(
            [("approach", [approach]), ("strike", [line]), ("stop", [brake])],
            joint_names=limits.names,
        )
    (strike,) = _constraints_of(problem, StrikeLine)
    tasks: tuple[TaskRows, ...] = (StrikeLineRows.of(strike, phases),)
    if clearance is not None:
        tasks = (*tasks, ClearanceRows.of(problem, clearance, phases))
    return Spec(
        robot=problem.robot,
        limits=limits,
        names=phases,
        durations=(None, problem.window, None),
        guess=guess,
        fixed=_boundary_states(problem, phases=len(phases)),
        tasks=tasks,
        contact=choice,
    )


def paddle_spec(problem: PaddleStrike, choice: ContactChoice) -> Spec:
    """The spec of a paddle strike at ``choice``: approach over the contact time, then stop."""
    limits = problem.limits
    n = limits.n
    q_contact = np.asarray(problem.q_contact)
    contact_time = float(problem.contact_time)
    # No joint is faster than its distance over its velocity limit; arriving at rest, none is
    # faster than alone (planners.lower_bound), within Ruckig's range.
    needed = np.abs(q_contact - np.asarray(problem.q_start)) / limits.velocity
    bound: Literal["velocity", "jerk"] = "velocity"
    if float(problem.speed) == 0.0:
        try:
            needed = joint_min_durations(q_start=problem.q_start, q_goal=q_contact, limits=limits)
            bound = "jerk"
        except SolverError:
            pass
    check_duration("the paddle", "contact_time", contact_time, needed, limits, bound)
    if float(problem.speed) == 0.0:
        approach = quintic_guess(np.asarray(problem.q_start), q_contact, contact_time)
        guess = Trajectory.sequence([("approach", [approach])], joint_names=limits.names)
        return Spec(
            robot=problem.robot,
            limits=limits,
            names=("approach",),
            durations=(contact_time,),
            guess=guess,
            fixed=_boundary_states(problem, phases=1),
        )
    qd_contact = choice.qd
    start, end = _boundary_states(problem, phases=2)
    (contact,) = _constraints_of(problem, ToolContact)
    approach = quintic_guess(np.asarray(problem.q_start), q_contact, contact_time, qd_contact)
    try:
        brake = stop(q_contact, qd_contact, zero_vector(n), limits, check_limits=False)
    except OptrajError:  # pragma: no cover - a guess only
        brake = quintic_guess(q_contact, q_contact, 0.5)
    guess = Trajectory.sequence(
        [("approach", [approach]), ("stop", [brake])], joint_names=limits.names
    )
    return Spec(
        robot=problem.robot,
        limits=limits,
        names=("approach", "stop"),
        durations=(contact_time, None),
        guess=guess,
        fixed=[start, FixedState(0, "end", q_contact, None, None), end],
        tasks=(ToolContactRows.of(contact, phase=0),),  # at the end of the approach
        contact=choice,
    )


def problem_spec(planner: OptimalControl, problem: Any) -> Spec:
    """The problem's phases, fixed states and guess; its fixed states' torques checked.

    Raises:
        InfeasibleError: A state the problem fixes (start, goal) needs more torque than
            the effort limits
            (:func:`planners.time_optimal.lower_bound.check_state_torques`), unless
            ``torque=False``; a strike no contact configuration can make.
    """
    if isinstance(problem, PointToPoint):
        problem.require_motion(planner.name)
        return planner._held(point_to_point_spec(problem))
    if isinstance(problem, Waypoints):
        problem.require_motion(planner.name)
        return planner._held(waypoints_spec(problem))
    if isinstance(problem, (PoolStrike, PaddleStrike)):
        planner._strike_start_held(problem)
        started = time.perf_counter()
        # The margin the NLP keeps from the velocity limits: a contact past it is refused
        # here, with its binding joint, instead of by an infeasible solve.
        choice = choose_contact(
            problem, candidates=planner.contact_candidates, margin=planner.margin
        )
        searched = time.perf_counter() - started
        spec = (
            pool_spec(problem, choice, clearance=planner.clearance)
            if isinstance(problem, PoolStrike)
            else paddle_spec(problem, choice)
        )
        spec.contact_time = searched
        return spec
    raise InvalidInputError(
        f"OptimalControl plans a PointToPoint, Waypoints, PoolStrike or PaddleStrike, got "
        f"{type(problem).__name__}",
        name="problem",
    )


def held_spec(planner: OptimalControl, spec: Spec) -> Spec:
    """``spec``, once the torques of its fully fixed states are within the effort limits.

    Raises:
        InfeasibleError: One needs more (unless ``torque=False``, which plans without
            torque limits).
    """
    if planner.torque is not False:
        last = len(spec.names) - 1
        states = []
        for fixed in spec.fixed:
            exact = fixed.exact()
            if exact is not None:
                states.append((fixed_name(fixed, last), *exact))
        check_state_torques(spec.robot, spec.limits, states)
    return spec


def check_strike_start_held(planner: OptimalControl, problem: PoolStrike | PaddleStrike) -> None:
    """Check a strike's start at rest before its contact choice (:meth:`_held`)."""
    if planner.torque is not False:
        zeros = zero_vector(problem.limits.n)
        start = ("the start state (at rest)", problem.q_start, zeros, zeros)
        check_state_torques(problem.robot, problem.limits, [start])
