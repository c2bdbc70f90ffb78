"""Strikes built from the time-optimal profiles: approach, constant-speed line, stop.

For a :class:`problems.PoolStrike`: the strike line (the cue tip at the commanded speed along
the direction, through the contact point, cue axis on the line) is turned into joints by IK
sample by sample; its first state (position, velocity, acceleration) is the entry state. The
approach reaches that state from rest, with Ruckig (state to state, interpolating in joints)
or with TOPPRA (a joint path ending along the entry velocity, entered at its path speed);
after the line, Ruckig stops the arm as fast as its limits allow. The line starts from the
problem's own contact configuration (``problem.q_contact``, the IK solution nearest the
start), or with ``contact="choose"`` from :func:`planners.strike.contact.choose_contact`'s (the IK
branch with room for the strike speed that the arm reaches soonest, as
:class:`planners.OptimalControl` uses), so that profiles can be compared on one branch.

For a :class:`problems.PaddleStrike`: the approach reaches the contact configuration with the
joint velocity that moves the paddle's ball point at the commanded speed along its normal, at
the commanded contact time (holding still first when the fastest approach is quicker); then
the stop.
"""

from __future__ import annotations

import time
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InfeasibleError, InvalidInputError, UnreachableError
from optraj.planners.base import stamp
from optraj.planners.profiles.cartesian import (
    follow_tool_path,
    limit_report,
    paddle_contact_velocity,
)
from optraj.planners.profiles.time_scaling import rate_limit_error, worst_rate_limit
from optraj.planners.strike.contact import choose_contact
from optraj.planners.time_optimal.ruckig_planner import state_to_state, stop
from optraj.planners.time_optimal.toppra_planner import Toppra
from optraj.planners.trajectory import Trajectory, TrajectorySample
from optraj.problems import PaddleStrike, PoolStrike
from optraj.robots import JointLimits, Robot, solve_ik
from optraj.validation import as_choice, as_count, as_number, as_vector

__all__ = [
    "CONTACTS",
    "MAX_LINE_SAMPLES",
    "TimeOptimalStrike",
    "check_contact",
    "check_line",
    "contact_configuration",
    "strike_line",
]

FloatArray = NDArray[np.float64]

#: Samples per line segment when the line is checked against the limits.
_LINE_SAMPLES = 16
#: Relative slack on the rate limits (round-off).
_RATE_SLACK = 1e-9
#: The rate limits each approach keeps (TOPPRA's joint path is acceleration-limited only).
_LIMITED: dict[str, tuple[str, ...]] = {
    "ruckig": ("velocity", "acceleration", "jerk"),
    "toppra": ("velocity", "acceleration"),
}
#: A pool approach keeps the tool frame's origin (the front of the cue tip) this far off the
#: ball's surface [m] (a cue tip's diameter and some room); at most half the run-up.
BALL_CLEARANCE = 0.02
#: An approach that would pass closer first goes to rest at the line's entry pose moved this
#: far back along the shot [m]; a second joint-space move from there reaches the entry.
RETREAT = 0.10
#: The approach is checked for the clearance at least this often [s].
_CLEARANCE_STEP = 1e-3

#: Most IK samples of a strike line: one IK step each (about a millisecond), so 10,000 is
#: some seconds; no line needs more than a few hundred (the planners use 10 to 60).
MAX_LINE_SAMPLES = 10_000

#: Where a pool strike's contact configuration comes from (:func:`contact_configuration`).
CONTACTS: tuple[str, ...] = ("problem", "choose")


def check_contact(contact: str) -> str:
    """``contact`` if it is one of :data:`CONTACTS`.

    Raises:
        UnknownNameError: Another name (lists the known ones).
    """
    as_choice(contact, "contact", CONTACTS)
    return contact


def contact_configuration(
    problem: PoolStrike, contact: str = "problem"
) -> tuple[FloatArray, dict[str, object]]:
    """The contact configuration a pool strike's line starts from, and metadata about it.

    Args:
        problem: The pool strike.
        contact: ``"problem"``: ``problem.q_contact`` (the IK solution nearest the start);
            ``"choose"``: :func:`planners.strike.contact.choose_contact`'s choice.

    Returns:
        The configuration [rad], shape (n,), and the metadata entries
        ``contact_configuration`` and, for ``"choose"``, ``contact_speed_ratio`` (the
        largest joint velocity over its limit that the strike needs there [-]).

    Raises:
        UnknownNameError: An unknown ``contact``.
        InfeasibleError: ``"choose"``: no configuration can make the strike (names the
            binding joint and the fastest reachable speed).
    """
    if check_contact(contact) == "problem":
        q = np.asarray(problem.q_contact, dtype=float)
        return q, {"contact_configuration": q.copy()}
    choice = choose_contact(problem)
    q = np.asarray(choice.q, dtype=float)
    return q, {"contact_configuration": q.copy(), "contact_speed_ratio": choice.ratio}


class TimeOptimalStrike:
    """Plan a pool or paddle strike with a Ruckig or TOPPRA approach and a Ruckig stop.

    Args:
        approach: ``"ruckig"`` or ``"toppra"``.
        samples: IK samples along the strike line.
        contact: Pool strikes: ``"problem"`` (the problem's contact configuration) or
            ``"choose"`` (:func:`contact_configuration`). A paddle strike's contact
            configuration is always the problem's (closed-form IK).
    """

    def __init__(
        self,
        approach: Literal["ruckig", "toppra"] = "ruckig",
        samples: int = 60,
        contact: Literal["problem", "choose"] = "problem",
    ) -> None:
        as_choice(approach, "approach", ("ruckig", "toppra"))
        self.approach = approach
        self.samples = as_count(samples, "samples", 4, MAX_LINE_SAMPLES)
        self.contact = check_contact(contact)

    @property
    def name(self) -> str:
        """Name recorded in trajectory metadata."""
        return f"{self.approach} strike"

    def plan(self, problem: PoolStrike | PaddleStrike) -> Trajectory:
        """Approach, strike, stop; phases ``approach``, ``strike`` (pool) and ``stop``.

        Raises:
            InfeasibleError: The strike line breaks a joint limit (pool; Ruckig's limits
                are position, velocity, acceleration and jerk, TOPPRA's all but jerk), the
                entry state cannot be reached, the contact time is too
                short for the fastest approach, (``contact="choose"``) no contact
                configuration can make the strike, or (pool, ``limit="clearance"``) the
                approach passes closer to the ball than :data:`BALL_CLEARANCE` even through
                the rest pose :data:`RETREAT` behind the entry (or that pose is out of reach).
            UnreachableError: A pose on the strike line cannot be reached.
        """
        started = time.perf_counter()
        if isinstance(problem, PoolStrike):
            traj, extra = self._pool(problem)
        elif isinstance(problem, PaddleStrike):
            traj, extra = self._paddle(problem)
        else:
            raise InvalidInputError(
                f"TimeOptimalStrike plans a PoolStrike or a PaddleStrike, got "
                f"{type(problem).__name__}",
                name="problem",
            )
        return stamp(traj, self.name, started, **extra)

    # ------------------------------------------------------------------------------ pool

    def _pool(self, problem: PoolStrike) -> tuple[Trajectory, dict[str, object]]:
        limits = problem.limits
        q_contact, extra = contact_configuration(problem, self.contact)
        line = strike_line(problem, self.samples, q_contact=q_contact)
        check_line(line, problem.robot, limits, _LIMITED[self.approach], float(problem.speed))
        entry = line.sample(0.0)
        exit_state = line.sample(line.duration)
        approach = [self._pool_approach(problem.q_start, entry, problem.robot, limits)]
        clearance = min(BALL_CLEARANCE, 0.5 * float(problem.run_up))
        if _ball_gap(problem, approach) < clearance:
            # The joint-space move sweeps the tool through the ball: come in from behind.
            q_via = _retreat(problem, entry.q)
            approach = [
                self._rest_to_rest(problem.q_start, q_via, problem.robot, limits),
                self._pool_approach(q_via, entry, problem.robot, limits),
            ]
            gap = _ball_gap(problem, approach)
            if gap < clearance:
                raise InfeasibleError(
                    f"the approach passes {gap * 1e3:.1f} mm from the ball's surface, less "
                    f"than the {clearance * 1e3:.1f} mm clearance, even through a rest pose "
                    f"{RETREAT:g} m behind the strike line",
                    limit="clearance",
                )
        brake = stop(exit_state.q, exit_state.qd, exit_state.qdd, limits)
        traj = Trajectory.sequence(
            [("approach", approach), ("strike", [line]), ("stop", [brake])],
            joint_names=limits.names,
        )
        report = {
            "approach_line_gap": _approach_gap(problem, approach[-1]),
            "approach_retreat": len(approach) == 2,
        }
        return traj, {**report, **extra}

    def _pool_approach(
        self, q_from: FloatArray, entry: TrajectorySample, robot: Robot, limits: JointLimits
    ) -> Trajectory:
        """From rest at ``q_from`` to the line's entry state (Ruckig or TOPPRA)."""
        zeros = np.zeros(limits.n)
        if self.approach == "ruckig":
            return state_to_state(q_from, zeros, zeros, entry.q, entry.qd, entry.qdd, limits)
        return self._toppra_approach(q_from, entry.q, entry.qd, robot, limits)

    def _rest_to_rest(
        self, q_from: FloatArray, q_to: FloatArray, robot: Robot, limits: JointLimits
    ) -> Trajectory:
        zeros = np.zeros(limits.n)
        if self.approach == "ruckig":
            return state_to_state(q_from, zeros, zeros, q_to, zeros, zeros, limits)
        return Toppra().time_parametrize(np.array([q_from, q_to]), limits, robot=robot)

    def _toppra_approach(
        self,
        q_start: FloatArray,
        q_entry: FloatArray,
        qd_entry: FloatArray,
        robot: Robot,
        limits: JointLimits,
    ) -> Trajectory:
        """TOPPRA along a joint path that leaves q_start and arrives along qd_entry."""
        chord = float(np.linalg.norm(q_entry - q_start))
        speed = float(np.linalg.norm(qd_entry))
        if chord < 1e-9 or speed < 1e-12:
            raise InfeasibleError(
                "the TOPPRA approach needs the entry configuration away from the start and a "
                "moving entry state",
                limit="path",
            )
        # Geometric path s in [0, 1]: cubic Hermite, unit-chord tangents at both ends.
        tangent_end = qd_entry / speed * chord
        path = Trajectory.from_hermite(
            [0.0, 1.0], [q_start, q_entry], [q_entry - q_start, tangent_end]
        )
        return Toppra().time_parametrize(
            path, limits, robot=robot, sd_start=0.0, sd_end=speed / chord
        )

    # ---------------------------------------------------------------------------- paddle

    def _paddle(self, problem: PaddleStrike) -> tuple[Trajectory, dict[str, object]]:
        limits = problem.limits
        zeros = np.zeros(limits.n)
        q_contact = np.asarray(problem.q_contact)
        qd_contact = paddle_contact_velocity(problem)
        if self.approach == "ruckig":
            approach = state_to_state(
                problem.q_start, zeros, zeros, q_contact, qd_contact, zeros, limits
            )
        elif float(problem.speed) > 0.0:
            approach = self._toppra_approach(
                problem.q_start, q_contact, qd_contact, problem.robot, limits
            )
        else:
            approach = Toppra().time_parametrize(
                np.array([problem.q_start, q_contact]), limits, robot=problem.robot
            )
        wait = float(problem.contact_time) - approach.duration
        if wait < -1e-9:
            raise InfeasibleError(
                f"the fastest {self.approach} approach takes {approach.duration:.4g} s, longer "
                f"than the contact time {float(problem.contact_time):.4g} s",
                limit="contact time",
                required=approach.duration,
                allowed=float(problem.contact_time),
            )
        phases: list[tuple[str, list[Trajectory]]] = []
        if wait > 1e-9:
            phases.append(("wait", [Trajectory.constant(problem.q_start, wait)]))
        phases.append(("approach", [approach]))
        if float(problem.speed) > 0.0:
            phases.append(("stop", [stop(q_contact, qd_contact, zeros, limits)]))
        traj = Trajectory.sequence(phases, joint_names=limits.names)
        return traj, {"wait": max(wait, 0.0)}


def strike_line(
    problem: PoolStrike, samples: int = 60, q_contact: FloatArray | None = None
) -> Trajectory:
    """The strike window of a pool strike in joints: cue tip on schedule, cue axis on the line.

    The tool keeps the orientation it has at ``q_contact`` (the problem's when None) and its
    origin moves from the entry point at ``speed`` along the direction; joints follow by
    :func:`planners.profiles.cartesian.follow_tool_path` from the IK solution at the entry.

    Args:
        problem: The strike.
        samples: IK samples along the line, in [1, :data:`MAX_LINE_SAMPLES`].
        q_contact: Configuration at contact [rad], shape (n,); the problem's when None.

    Returns:
        The window, ``problem.window`` long, starting at t = 0.

    Raises:
        UnreachableError: A pose on the line cannot be reached.
        InvalidInputError: Not a pool strike, a bad sample count or contact configuration.
    """
    if not isinstance(problem, PoolStrike):
        raise InvalidInputError(
            f"strike_line takes a PoolStrike, got {type(problem).__name__}", name="problem"
        )
    samples = as_count(samples, "samples", 1, MAX_LINE_SAMPLES)
    robot = problem.robot
    contact = as_vector(
        problem.q_contact if q_contact is None else q_contact, "q_contact", robot.dof
    )
    direction = np.asarray(problem.direction)
    speed = float(problem.speed)
    rotation = robot.tool_pose(contact)[:3, :3]  # cue axis along the direction
    entry_pose = np.eye(4)
    entry_pose[:3, :3] = rotation
    entry_pose[:3, 3] = problem.entry_point
    q_entry = solve_ik(robot, entry_pose, q_near=contact).q
    times = np.linspace(0.0, problem.window, samples + 1)
    poses = np.repeat(entry_pose[None], times.size, axis=0)
    poses[:, :3, 3] = problem.entry_point + speed * times[:, None] * direction
    twists = np.tile(np.concatenate([speed * direction, np.zeros(3)]), (times.size, 1))
    return follow_tool_path(robot, times, poses, twists, np.zeros_like(twists), q_entry)


def check_line(
    line: Trajectory,
    robot: Robot,
    limits: JointLimits,
    quantities: tuple[str, ...],
    speed: float,
) -> None:
    """Raise if the strike line leaves the position limits or breaks a rate limit.

    A guard, so that no approach is planned onto a line the arm cannot follow (a joint that
    the inverse kinematics pins on a position limit part-way along kinks the line):
    positions are judged exactly (:func:`planners.profiles.cartesian.limit_report`), rates at 16
    instants per segment; :func:`planners.check` judges the whole trajectory.

    Args:
        line: The strike window in joints.
        robot: The robot.
        limits: The joint limits.
        quantities: Limited derivatives among ``velocity``, ``acceleration``, ``jerk``.
        speed: The strike speed [m/s], for the message.

    Raises:
        InfeasibleError: E.g. "the strike line at 1 m/s needs joint 'right_j2' at 2.165 rad/s
            (velocity), limit 1.957 rad/s (at its contact configuration)".
    """
    subject = f"the strike line at {as_number(speed, 'speed', 'm/s'):.4g} m/s"
    limit_report(line, robot, limits, (), subject, " (at its contact configuration)")
    knots = line.breakpoints
    fractions = np.linspace(0.0, 1.0, _LINE_SAMPLES, endpoint=False)
    times = np.concatenate(
        [(knots[:-1, None] + np.diff(knots)[:, None] * fractions).ravel(), knots[-1:]]
    )
    states = line.sample(times)
    peaks = {
        "velocity": np.max(np.abs(states.qd), axis=0),
        "acceleration": np.max(np.abs(states.qdd), axis=0),
        "jerk": np.max(np.abs(states.jerk), axis=0),
    }
    worst = worst_rate_limit(peaks, limits, quantities, _RATE_SLACK)
    if worst is not None:
        raise rate_limit_error(worst, limits, subject, " (at its contact configuration)")


def _ball_gap(problem: PoolStrike, pieces: list[Trajectory]) -> float:
    """Closest the tool frame's origin comes to the ball's surface over the pieces [m].

    Only that point is checked; the rest of the cue and the arm need a collision scene.
    """
    robot = problem.robot
    ball = np.asarray(problem.ball)
    gap = np.inf
    for piece in pieces:
        count = max(2, int(np.ceil(piece.duration / _CLEARANCE_STEP)) + 1)
        times = np.linspace(0.0, piece.duration, count)
        points = robot.tool_position(piece.sample(times).q)
        gap = min(gap, float(np.min(np.linalg.norm(points - ball, axis=1))))
    return gap - float(problem.ball_radius)


def _retreat(problem: PoolStrike, q_entry: FloatArray) -> FloatArray:
    """A configuration with the tool at the entry pose moved :data:`RETREAT` back."""
    robot = problem.robot
    pose = robot.tool_pose(q_entry).copy()
    pose[:3, 3] -= RETREAT * np.asarray(problem.direction)
    try:
        return solve_ik(robot, pose, q_near=q_entry, restarts=20).q
    except UnreachableError as exc:
        x, y, z = pose[:3, 3]
        raise InfeasibleError(
            f"the approach passes through the ball and the rest pose {RETREAT:g} m behind the "
            f"strike line's entry, at ({x:.3f}, {y:.3f}, {z:.3f}) m, is out of reach",
            limit="clearance",
        ) from exc


def _approach_gap(problem: PoolStrike, approach: Trajectory) -> float:
    """Largest distance of the cue tip from the strike line in the approach's last 20 % [m].

    A joint-space approach meets the line only at the entry; this says how far off it comes
    (of the piece that reaches the entry, when the approach goes through a rest pose).
    """
    robot = problem.robot
    times = np.linspace(0.8 * approach.duration, approach.duration, 50)
    points = robot.tool_position(approach.sample(times).q)
    direction = np.asarray(problem.direction)
    rel = points - np.asarray(problem.entry_point)
    lateral = rel - (rel @ direction)[:, None] * direction
    return float(np.max(np.linalg.norm(lateral, axis=1)))
