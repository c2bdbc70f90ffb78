"""Tool paths in Cartesian space turned into joint trajectories.

* :func:`follow_tool_path`: poses, twists and accelerations of the tool at sample times become
  joint states by inverse kinematics, sample by sample from the previous solution (so the
  nearest branch is kept), and joint rates by least squares on the Jacobian (a joint the
  inverse kinematics holds on a position limit keeps still); a quintic
  Hermite spline through the states is the trajectory. A joint that jumps between samples is
  reported as :class:`optraj.errors.PathJumpError` (or a warning).
* :class:`CartesianStraightLine`: a straight line between two poses with SLERP orientation,
  time-scaled by a cubic, quintic or LSPB profile.
* :class:`LinearTrajectory`: the pool-cue line of the Sawyer pool-cue exercise, reproduced exactly:
  constant velocity from the start, holding still after the end.

:func:`point_joint_velocity` and :func:`paddle_contact_velocity` live in
:mod:`optraj.planners.profiles.contact_velocity` and are re-exported here.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import (
    InfeasibleError,
    InvalidInputError,
    PathJumpError,
    PathJumpWarning,
    UnknownNameError,
    UnreachableError,
)
from optraj.planners.base import stamp
from optraj.planners.checker import Report, check
from optraj.planners.profiles.contact_velocity import (
    paddle_contact_velocity,
    point_joint_velocity,
)
from optraj.planners.trajectory import Phase, Trajectory
from optraj.problems import CartesianLine
from optraj.problems.common import MAX_TOOL_SPEED
from optraj.robots import JointLimits, Robot, solve_ik
from optraj.validation import (
    as_array,
    as_choice,
    as_count,
    as_duration,
    as_positive,
    as_vector,
    ndim_of,
)

__all__ = [
    "MAX_IK_SAMPLES",
    "CartesianStraightLine",
    "LinearTrajectory",
    "follow_tool_path",
    "limit_report",
    "paddle_contact_velocity",
    "path_scaling",
    "point_joint_velocity",
]

FloatArray = NDArray[np.float64]

_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
#: LSPB path scaling: blend time as a fraction of the duration (our choice).
_LSPB_BLEND = 0.25
#: A joint this close to a position limit [rad or m] counts as on it (our choice: far above the
#: 1e-9 the inverse kinematics converges to, far below a joint's step between samples).
_AT_LIMIT = 1e-6
#: Most samples a tool path may be followed at: each is one inverse-kinematics solve (about a
#: millisecond), so this many take minutes, where a line needs a few hundred.
MAX_IK_SAMPLES = 100_000
#: How far a joint path may pass a position limit before it is refused [rad or m] (round-off).
_POSITION_SLACK = 1e-9


def path_scaling(name: str, tau: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """A rest-to-rest scaling s of normalised time tau in [0, 1], with ds/dtau, d2s/dtau2.

    ``"cubic"``: s = 3 tau^2 - 2 tau^3; ``"quintic"``: s = 10 tau^3 - 15 tau^4 + 6 tau^5;
    ``"lspb"``: parabolic blends of 0.25 of the time at each end, constant speed between.
    """
    x = np.clip(np.asarray(tau, dtype=float), 0.0, 1.0)
    if name == "cubic":
        return 3 * x**2 - 2 * x**3, 6 * x - 6 * x**2, 6 - 12 * x
    if name == "quintic":
        return (
            10 * x**3 - 15 * x**4 + 6 * x**5,
            30 * x**2 - 60 * x**3 + 30 * x**4,
            60 * x - 180 * x**2 + 120 * x**3,
        )
    if name == "lspb":
        tb = _LSPB_BLEND
        v = 1.0 / (1.0 - tb)
        a = v / tb
        s = np.where(
            x < tb,
            0.5 * a * x**2,
            np.where(x <= 1 - tb, v * (x - 0.5 * tb), 1.0 - 0.5 * a * (1.0 - x) ** 2),
        )
        ds = np.where(x < tb, a * x, np.where(x <= 1 - tb, v, a * (1.0 - x)))
        dds = np.where(x < tb, a, np.where(x <= 1 - tb, 0.0, -a))
        return s, ds, dds
    raise UnknownNameError("path scaling", name, ["cubic", "quintic", "lspb"])


def _joint_rates(
    robot: Robot,
    frame_id: int,
    q: FloatArray,
    jac: FloatArray,
    twist: FloatArray,
    acceleration: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    r"""Least-squares joint velocity and its time derivative that make the frame move as asked.

    qd = J^+ V over the joints that are free to move; a joint that sits on a position limit
    and that least squares would drive past it is held (zero rate), as the inverse kinematics
    holds it at the neighbouring samples: rates that ignore the hold disagree with the
    positions and a spline through both bends between samples. The acceleration is

    .. math:: \ddot q = J^+ (a - \dot J \dot q) + (I - J^+ J) \dot J^T (J J^T)^{-1} V

    over the free joints. The second term (only for more free joints than task rows) is the
    null-space part of d(J^+)/dt V; without it the accelerations would not be the derivative
    of the velocities.

    Returns:
        qd [rad/s or m/s] and qdd [rad/s^2 or m/s^2], shape (n,) each.
    """
    limits = robot.limits
    at_lower = q <= limits.lower + _AT_LIMIT
    at_upper = q >= limits.upper - _AT_LIMIT
    free = np.ones(q.size, dtype=bool)
    qd = np.zeros(q.size)
    for _ in range(q.size):
        qd[:] = 0.0
        qd[free] = np.linalg.lstsq(jac[:, free], twist, rcond=None)[0]
        outward = free & ((at_lower & (qd < 0.0)) | (at_upper & (qd > 0.0)))
        if not outward.any():
            break
        free &= ~outward
    model, data = robot.model, robot.data
    pin.computeJointJacobiansTimeVariation(model, data, q, qd)
    jac_dot = pin.getFrameJacobianTimeVariation(model, data, frame_id, _WORLD_ALIGNED)
    jac_free = jac[:, free]
    pseudo_inverse = np.linalg.pinv(jac_free)
    qdd = np.zeros(q.size)
    qdd[free] = pseudo_inverse @ (acceleration - jac_dot @ qd)
    rows, columns = jac_free.shape
    if columns > rows and np.linalg.matrix_rank(jac_free) == rows:
        null_space = np.eye(columns) - pseudo_inverse @ jac_free
        # (J J^T)^-1 = J^+^T J^+ at full row rank, without a solve that fails near a
        # singularity (where matrix_rank still counts the rows)
        inverse_twist = pseudo_inverse.T @ (pseudo_inverse @ twist)
        qdd[free] += null_space @ jac_dot[:, free].T @ inverse_twist
    return qd, qdd


def limit_report(
    traj: Trajectory,
    robot: Robot,
    limits: JointLimits,
    quantities: Sequence[str],
    subject: str,
    context: str = "",
) -> Report:
    """The checker's report on a joint path against the joint limits alone (no task).

    Positions are always judged (exact peaks, between samples too); a path that leaves the
    position limits by more than :data:`_POSITION_SLACK` is refused.

    Args:
        traj: The joint path.
        robot: The robot.
        limits: The limits to judge against.
        quantities: Other quantities to report, e.g. ``["velocity", "acceleration"]``.
        subject: What the path is, for the message, e.g. ``"the line"``.
        context: Appended to the message, e.g. ``" (at its contact configuration)"``.

    Returns:
        The report, with ``position`` and the findings of ``quantities``.

    Raises:
        InfeasibleError: The path leaves the position limits (``limit="position"``, the
            ``joint``, the position it reaches and the limit) [rad or m].
    """
    report = check(traj, _LimitsOnly(robot, limits), quantities=["position", *quantities])
    position = report["position"]
    if position.margin < -_POSITION_SLACK:
        raise InfeasibleError(
            f"{subject} leaves the position limits: it takes joint {position.joint!r} to "
            f"{position.value:.6g} {position.unit}, {-position.margin:.3g} {position.unit} "
            f"beyond its limit {position.limit:.6g} {position.unit}{context}",
            limit="position",
            joint=position.joint,
            required=position.value,
            allowed=position.limit,
        )
    return report


def follow_tool_path(
    robot: Robot,
    times: ArrayLike,
    poses: ArrayLike,
    twists: ArrayLike,
    accelerations: ArrayLike,
    q_start: ArrayLike,
    *,
    frame: str | None = None,
    jump_threshold: float = 0.1,
    on_jump: Literal["raise", "warn"] = "raise",
) -> Trajectory:
    """Joint trajectory that makes a frame follow sampled poses.

    Args:
        robot: The robot.
        times: Sample times [s], shape (m,), increasing from 0.
        poses: ``T_world_frame`` at each time, shape (m, 4, 4).
        twists: Frame velocity [linear m/s; angular rad/s] in world axes, shape (m, 6).
        accelerations: Frame acceleration [m/s^2; rad/s^2] (classical, world axes), (m, 6).
        q_start: Configuration [rad or m] near the first pose; the IK starts there.
        frame: The frame; the tool frame when None.
        jump_threshold: Largest joint change between neighbouring samples [rad or m].
        on_jump: ``"raise"`` a PathJumpError or ``"warn"`` (PathJumpWarning) and go on.

    Returns:
        A C2 trajectory through the IK solutions (quintic Hermite segments).

    Raises:
        UnreachableError: A pose along the path has no solution within the joint limits.
        PathJumpError: The solution jumps between samples (with ``on_jump="raise"``).
        InvalidInputError: Malformed arrays, fewer than 2 or more than MAX_IK_SAMPLES + 1
            times, times not increasing, or a jump threshold that is not a number > 0.
        UnknownNameError: An unknown ``on_jump`` policy.
    """
    t = as_vector(times, "times")
    m = as_count(t.size, "the number of times", 2, maximum=MAX_IK_SAMPLES + 1)
    if np.any(np.diff(t) <= 0.0):
        raise InvalidInputError("times must be increasing", name="times")
    threshold = as_positive(jump_threshold, "jump_threshold", "rad or m")
    pose_array = as_array(poses, "poses", (m, 4, 4))
    twist_array = as_array(twists, "twists", (m, 6))
    accel_array = as_array(accelerations, "accelerations", (m, 6))
    as_choice(on_jump, "on_jump policy", ("raise", "warn"))
    frame_id = robot.frame_id(frame)
    previous = as_vector(q_start, "q_start", robot.dof)
    q = np.empty((m, robot.dof))
    qd = np.empty_like(q)
    qdd = np.empty_like(q)
    for i in range(m):
        # Start each IK where the previous state is heading (second order): the solution then
        # follows the same least-squares joint rates as qd, also in a redundant arm's null
        # space, and the spline through the samples does not wiggle.
        if i > 0:
            dt = t[i] - t[i - 1]
            predicted = robot.limits.clip(previous + qd[i - 1] * dt + 0.5 * qdd[i - 1] * dt**2)
        else:
            predicted = previous
        try:
            solution = solve_ik(robot, pose_array[i], frame=frame, q_near=predicted, restarts=0)
        except UnreachableError:
            solution = solve_ik(robot, pose_array[i], frame=frame, q_near=previous, restarts=20)
        q[i] = solution.q
        if i > 0:
            step = np.abs(q[i] - q[i - 1])
            j = int(np.argmax(step))
            if step[j] > threshold:
                error = PathJumpError(float(t[i]), robot.joint_names[j], step[j], threshold)
                if on_jump == "raise":
                    raise error
                warnings.warn(str(error), PathJumpWarning, stacklevel=2)
        jac = pin.computeFrameJacobian(robot.model, robot.data, q[i], frame_id, _WORLD_ALIGNED)
        qd[i], qdd[i] = _joint_rates(robot, frame_id, q[i], jac, twist_array[i], accel_array[i])
        previous = q[i]
    return Trajectory.from_hermite(t, q, qd, qdd, joint_names=robot.joint_names)


class CartesianStraightLine:
    """Plan a :class:`problems.CartesianLine`: straight line, SLERP orientation.

    The path parameter s runs from 0 to 1 along a rest-to-rest ``profile`` (cubic, quintic
    or LSPB). The duration is the problem's; else set by its speed cap (the peak of ds/dt
    times the length); else the shortest for which the joint velocity, acceleration (and for
    the quintic, jerk) peaks at the samples fit the limits. A path traced more slowly has
    joint rates scaled by 1/T and accelerations by 1/T^2, so one IK pass serves every T.

    Args:
        profile: ``"cubic"``, ``"quintic"`` or ``"lspb"``.
        samples: IK samples along the line (>= 10).
        jump_threshold: Largest joint change between samples [rad or m].
        on_jump: ``"raise"`` or ``"warn"`` on a jump.
    """

    def __init__(
        self,
        profile: str = "quintic",
        samples: int = 200,
        jump_threshold: float = 0.1,
        on_jump: Literal["raise", "warn"] = "raise",
    ) -> None:
        path_scaling(profile, 0.0)  # validates the name
        self.profile = profile
        self.samples = as_count(samples, "samples", 10, maximum=MAX_IK_SAMPLES)
        self.jump_threshold = as_positive(jump_threshold, "jump_threshold", "rad or m")
        as_choice(on_jump, "on_jump policy", ("raise", "warn"))
        self.on_jump = on_jump

    @property
    def name(self) -> str:
        """Name recorded in trajectory metadata."""
        return f"cartesian line ({self.profile})"

    def plan(self, problem: CartesianLine) -> Trajectory:
        """Plan the line; see the class docstring.

        Raises:
            UnreachableError: A pose on the line cannot be reached.
            PathJumpError: The joint solution jumps (near a singularity).
            InfeasibleError: The joint path leaves the position limits between samples (a
                joint the inverse kinematics pins on a limit part-way kinks it), the given
                duration and speed cap disagree, or a fixed duration breaks a joint limit.
        """
        if not isinstance(problem, CartesianLine):
            raise InvalidInputError(
                f"CartesianStraightLine plans a problems.CartesianLine, got "
                f"{type(problem).__name__}",
                name="problem",
            )
        problem.require_motion(self.name)  # a still line without a duration: 0 s
        started = time.perf_counter()
        robot = problem.robot
        start, goal = np.asarray(problem.T_start), np.asarray(problem.T_goal)
        tau = np.linspace(0.0, 1.0, self.samples + 1)
        s, ds, dds = path_scaling(self.profile, tau)
        delta_p = goal[:3, 3] - start[:3, 3]
        rotvec = pin.log3(start[:3, :3].T @ goal[:3, :3])  # in the start frame
        poses = np.repeat(np.eye(4)[None], tau.size, axis=0)
        poses[:, :3, 3] = start[:3, 3] + s[:, None] * delta_p
        poses[:, :3, :3] = [start[:3, :3] @ pin.exp3(si * rotvec) for si in s]
        omega_dir = start[:3, :3] @ rotvec  # angular velocity per unit ds, world axes
        twists = np.hstack([ds[:, None] * delta_p, ds[:, None] * omega_dir])
        accels = np.hstack([dds[:, None] * delta_p, dds[:, None] * omega_dir])
        unit = follow_tool_path(
            robot,
            tau,
            poses,
            twists,
            accels,
            problem.q_start,
            jump_threshold=self.jump_threshold,
            on_jump=self.on_jump,
        )
        sample = unit.sample(tau)

        def at(duration: float) -> Trajectory:
            return Trajectory.from_hermite(
                tau * duration,
                sample.q,
                sample.qd / duration,
                sample.qdd / duration**2,
                joint_names=robot.joint_names,
                phases=[Phase("line", 0.0, duration)],
            )

        traj = at(self._duration(problem, unit, float(np.max(ds))))
        if problem.speed is not None:
            traj = self._within_speed_cap(problem, traj, at)
        return stamp(traj, self.name, started, samples=self.samples)

    def _within_speed_cap(
        self, problem: CartesianLine, traj: Trajectory, at: Callable[[float], Trajectory]
    ) -> Trajectory:
        """The plan slowed down until the checker finds the tool within the speed cap.

        The joint path through the IK samples carries the tool a hair off the exact profile
        (6.5e-7 m/s over a 1 m/s cap in a fuzz case), and the tool speed scales as 1 / T, so
        the duration grows by the checker's own peak-to-cap ratio (sampled at its default
        rate and every breakpoint; a second pass covers a peak that moved between samples).

        Raises:
            InfeasibleError: A fixed duration whose plan is over the cap, or a plan still
                over it after three slow-downs (every returned plan is checked).
        """
        cap = float(problem.speed)  # type: ignore[arg-type]  # called only with a speed set
        target = _LimitsOnly(problem.robot, problem.limits)
        slowdowns = 0
        while True:
            peak = check(traj, target, quantities=[], tool_speed=cap)["tool speed"].value
            if peak <= cap:
                return traj
            if problem.duration is not None or slowdowns == 3:
                raise InfeasibleError(
                    f"a {self.profile} line of {problem.length:.4g} m in {traj.duration:.4g} s "
                    f"takes the tool to {peak:.6g} m/s, above the speed cap {cap:.6g} m/s",
                    limit="tool speed",
                    required=peak,
                    allowed=cap,
                )
            traj = at(traj.duration * (peak / cap) * (1.0 + 1e-9))
            slowdowns += 1

    def _shortest(self, unit: Trajectory, problem: CartesianLine) -> float:
        """Shortest duration within the joint limits, from the exact peaks of the 1 s path.

        Traced in T seconds the path's joint rates scale as 1/T, accelerations as 1/T^2 and
        jerks as 1/T^3, so each peak-to-limit ratio r of the unit-time trajectory needs
        T >= r^(1/k); the checker finds the peaks exactly, between samples too.
        """
        quantities = ["velocity", "acceleration"] + (["jerk"] if self.profile == "quintic" else [])
        # Positions do not scale with the duration: no duration keeps a path inside that
        # leaves the box.
        report = limit_report(unit, problem.robot, problem.limits, quantities, "the line")
        order = {"velocity": 1.0, "acceleration": 2.0, "jerk": 3.0}
        return max(max(report[name].ratio, 0.0) ** (1.0 / order[name]) for name in quantities)

    def _duration(self, problem: CartesianLine, unit: Trajectory, peak_ds: float) -> float:
        shortest = self._shortest(unit, problem)
        by_speed = problem.length * peak_ds / problem.speed if problem.speed is not None else None
        if problem.duration is not None:
            duration = float(problem.duration)
            if by_speed is not None and duration < by_speed * (1 - 1e-9):
                raise InfeasibleError(
                    f"a {self.profile} line of {problem.length:.4g} m in {duration:.4g} s peaks "
                    f"at {problem.length * peak_ds / duration:.4g} m/s, above the speed cap "
                    f"{problem.speed:.4g} m/s",
                    limit="tool speed",
                    required=problem.length * peak_ds / duration,
                    allowed=problem.speed,
                )
            if duration < shortest * (1 - 1e-6):
                raise InfeasibleError(
                    f"the line in {duration:.4g} s breaks a joint limit; it needs at least "
                    f"{shortest:.4g} s",
                    limit="joint",
                    required=shortest,
                    allowed=duration,
                )
            return duration
        return max(shortest, by_speed or 0.0)


@dataclass(frozen=True)
class _LimitsOnly:
    """A check target with a robot and limits but no task constraints."""

    robot: Robot
    limits: JointLimits

    def constraints(self) -> tuple[()]:
        return ()


@dataclass(frozen=True)
class LinearTrajectory:
    """The pull-back shot's constant-velocity tool line, with its exact semantics.

    For 0 <= t <= T = |end - start| / speed: position = start + speed t d, velocity =
    speed d, acceleration 0 (d the unit direction). After T the position holds at ``end``
    with zero velocity and acceleration. It starts at full speed: joined to a robot at rest
    it needs an unbounded acceleration at t = 0, and again when it stops at T.

    Attributes:
        start: Start point [m], shape (3,).
        end: End point [m], shape (3,).
        speed: [m/s], > 0.
        orientation: Tool rotation held throughout, shape (3, 3).
    """

    start: FloatArray
    end: FloatArray
    speed: float
    orientation: FloatArray

    def __post_init__(self) -> None:
        start = as_vector(self.start, "start", 3)
        end = as_vector(self.end, "end", 3)
        if np.linalg.norm(end - start) <= 0.0:
            raise InvalidInputError("start and end must differ", name="end")
        object.__setattr__(self, "start", start)
        object.__setattr__(self, "end", end)
        speed = as_positive(self.speed, "speed", "m/s", maximum=MAX_TOOL_SPEED)
        object.__setattr__(self, "speed", speed)
        # |end - start| / speed: a line too slow (or too short) for a trajectory's duration
        as_duration(float(np.linalg.norm(end - start)) / speed, "the line's |end - start| / speed")
        rotation = as_array(self.orientation, "orientation", (3, 3))
        if np.max(np.abs(rotation.T @ rotation - np.eye(3))) > 1e-6:
            raise InvalidInputError("orientation must be a rotation matrix", name="orientation")
        object.__setattr__(self, "orientation", rotation)

    @property
    def direction(self) -> FloatArray:
        """Unit direction of travel, shape (3,)."""
        delta = self.end - self.start
        return delta / np.linalg.norm(delta)

    @property
    def duration(self) -> float:
        """T = |end - start| / speed [s]."""
        return float(np.linalg.norm(self.end - self.start) / self.speed)

    def sample(self, t: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position [m], velocity [m/s], acceleration [m/s^2] at times t >= 0, each (m, 3)."""
        times = np.atleast_1d(as_array(t, "t", (None,)) if ndim_of(t) else as_array(t, "t", ()))
        if np.any(times < 0.0):
            raise InvalidInputError("t must be >= 0 s", name="t")
        moving = times <= self.duration
        position = np.where(
            moving[:, None], self.start + self.speed * times[:, None] * self.direction, self.end
        )
        velocity = np.where(moving[:, None], self.speed * self.direction, 0.0)
        return position, velocity, np.zeros_like(position)

    def to_joints(self, robot: Robot, q_start: ArrayLike, samples: int = 100) -> Trajectory:
        """The line as a joint trajectory over [0, T] (IK of the tool pose, orientation held).

        The result starts and ends at full speed, as the pull-back shot's line does.

        Args:
            robot: The robot.
            q_start: Configuration [rad or m] near the start pose; the IK starts there.
            samples: Intervals along the line, each one IK solve, in [1, MAX_IK_SAMPLES].
        """
        count = as_count(samples, "samples", 1, maximum=MAX_IK_SAMPLES)
        times = np.linspace(0.0, self.duration, count + 1)
        position, velocity, acceleration = self.sample(times)
        poses = np.repeat(np.eye(4)[None], times.size, axis=0)
        poses[:, :3, :3] = self.orientation
        poses[:, :3, 3] = position
        zeros = np.zeros_like(velocity)
        return follow_tool_path(
            robot,
            times,
            poses,
            np.hstack([velocity, zeros]),
            np.hstack([acceleration, zeros]),
            q_start,
        )
