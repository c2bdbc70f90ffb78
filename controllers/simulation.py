"""Closed-loop simulation: a controller follows a planned trajectory on a simulated robot.

>>> result = controllers.simulate(robot, traj, controllers.DiffIKQP(robot), dt=1e-3)
>>> result.metrics.position_max        # [m]
>>> planners.check(result.command_trajectory(), robot, quantities=["velocity"])

Each step: the plant's state is measured (plus seeded Gaussian noise), the controller turns it
and the plan into a command (a joint velocity and, optionally, a feed-forward joint torque),
the command waits ``latency`` steps, and the plant integrates it for ``dt`` (with a force at
the tool while a disturbance lasts). A plant that simulates more than the arm hands it over at
the end through :meth:`~controllers.plants.Plant.record`, kept in ``Result.record``. The plant is
pluggable: ``"dynamic"`` (rigid-body dynamics under a velocity servo, torques saturated),
``"kinematic"`` (a first-order actuator lag), or any :class:`~controllers.plants.Plant`.
"""

from __future__ import annotations

import math
import sys
import time
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any, TextIO

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.controllers.controller import (
    Command,
    Controller,
    References,
    State,
    sample_references,
)
from optraj.controllers.metrics import Metrics, tracking_metrics
from optraj.controllers.plants import DynamicPlant, KinematicPlant, Plant, PlantState
from optraj.errors import InvalidInputError, SolverError
from optraj.planners.trajectory import Trajectory
from optraj.problems.common import check_robot
from optraj.robots import Robot
from optraj.validation import (
    MAX_DURATION,
    as_choice,
    as_count,
    as_duration,
    as_flag,
    as_number,
    as_vector,
)

__all__ = ["PLANTS", "Impulse", "Noise", "Result", "simulate"]

FloatArray = NDArray[np.float64]

#: Plants chosen by name.
PLANTS: tuple[str, ...] = ("dynamic", "kinematic")
#: Runs longer than this many steps show a progress bar when stderr is a terminal.
PROGRESS_STEPS = 20_000
#: Most control steps one run may take: 1000 s at 1 kHz, whose time series (states,
#: commands, references and tool poses of 7 joints, about 1 kB a step) take about 1 GB.
MAX_STEPS = 1_000_000


@dataclass(frozen=True)
class Noise:
    """Gaussian measurement noise, seeded.

    Attributes:
        position: Standard deviation on measured joint positions [rad or m].
        velocity: Standard deviation on measured joint velocities [rad/s or m/s].
        seed: Seed of the generator; the same seed gives the same run.
    """

    position: float = 1e-4
    velocity: float = 1e-3
    seed: int = 0

    def __post_init__(self) -> None:
        for name, unit in (("position", "rad or m"), ("velocity", "rad/s or m/s")):
            label = f"noise {name} standard deviation"
            value = as_number(getattr(self, name), label, unit, minimum=0.0)
            object.__setattr__(self, name, value)
        as_count(self.seed, "seed", maximum=None)


@dataclass(frozen=True)
class Impulse:
    """A force pushing on the tool frame origin for a while (a bump, a ball hitting back).

    Attributes:
        time: When it starts [s].
        force: Force in world axes [N], shape (3,).
        duration: How long it lasts [s]; the impulse is ``force * duration`` [N s].
    """

    time: float
    force: ArrayLike
    duration: float = 0.01

    def __post_init__(self) -> None:
        start = as_number(self.time, "impulse time", "s", minimum=0.0, maximum=MAX_DURATION)
        object.__setattr__(self, "time", start)
        force = as_vector(self.force, "force", 3)
        force.setflags(write=False)
        object.__setattr__(self, "force", force)
        object.__setattr__(self, "duration", as_duration(self.duration, "impulse duration"))

    def force_during(self, t0: float, t1: float) -> FloatArray | None:
        """The mean force over the step ``[t0, t1)`` [N], or None when it does not act."""
        overlap = min(t1, self.time + self.duration) - max(t0, self.time)
        if overlap <= 0.0:
            return None
        return np.asarray(self.force) * (overlap / (t1 - t0))


@dataclass(frozen=True, eq=False)
class Result:
    """One closed-loop run.

    Attributes:
        robot: Name of the robot.
        joint_names: Its joint names.
        controller: Name of the controller.
        plant: Name of the plant.
        dt: Control period [s].
        t: Sample times [s], shape (m,): the start and the end of every step.
        q: Realised joint positions, shape (m, n).
        qd: Realised joint velocities, shape (m, n).
        T_world_tool: Realised tool poses, shape (m, 4, 4).
        measured_q: Joint positions the controller saw, shape (m - 1, n).
        measured_qd: Joint velocities the controller saw, shape (m - 1, n).
        command: The controller's joint velocity commands, shape (m - 1, n).
        applied: The commands the plant got (after the latency), shape (m - 1, n).
        tau: Joint torques applied by (or needed for) the motion, shape (m - 1, n).
        step_time: Controller wall time per step [s], shape (m - 1,).
        fallbacks: ``(time, reason)`` of every step that sent a fallback command.
        references: The plan at every sample time.
        metrics: The tracking metrics.
        record: What the plant simulated beyond the arm (:meth:`Plant.record
            <controllers.plants.Plant.record>` at the end of the run); empty for the
            kinematic and dynamic plants.
    """

    robot: str
    joint_names: tuple[str, ...]
    controller: str
    plant: str
    dt: float
    t: FloatArray
    q: FloatArray
    qd: FloatArray
    T_world_tool: FloatArray
    measured_q: FloatArray
    measured_qd: FloatArray
    command: FloatArray
    applied: FloatArray
    tau: FloatArray
    step_time: FloatArray
    fallbacks: tuple[tuple[float, str], ...]
    references: References
    metrics: Metrics
    record: Mapping[str, Any] = field(default_factory=dict)

    def __repr__(self) -> str:
        m = self.metrics
        return (
            f"Result({self.controller!r} on {self.robot!r}, {self.plant} plant, "
            f"{self.t.size - 1} steps of {self.dt:g} s: position error max "
            f"{m.position_max * 1e3:.3g} mm, within limits {m.within_limits})"
        )

    def command_trajectory(self) -> Trajectory:
        """The commanded motion as a Trajectory, for :func:`planners.check`.

        Positions are the commands integrated from the start (piecewise linear), so the
        trajectory's velocity is exactly the command on every step.
        """
        q = self.q[0] + np.concatenate(
            [np.zeros((1, self.q.shape[1])), np.cumsum(self.command * np.diff(self.t)[:, None], 0)]
        )
        coefficients = np.stack([q[:-1], self.command], axis=1)
        return Trajectory(
            self.t - self.t[0],
            coefficients,
            joint_names=self.joint_names,
            metadata={"planner": f"{self.controller} (command)"},
        )

    def trajectory(self) -> Trajectory:
        """The realised motion as a Trajectory (cubic Hermite through every sample)."""
        return Trajectory.from_hermite(
            self.t - self.t[0],
            self.q,
            self.qd,
            joint_names=self.joint_names,
            metadata={"planner": f"{self.controller} (realised)"},
        )


def _plant(robot: Robot, plant: str | Plant) -> Plant:
    """The plant to simulate: ``plant`` itself, checked for ``robot``, or one by name."""
    if isinstance(plant, Plant):
        if plant.robot.dof != robot.dof:
            raise InvalidInputError(
                f"the plant simulates {plant.robot.dof} joints, robot {robot.name!r} has "
                f"{robot.dof}",
                name="plant",
            )
        return plant
    kind = as_choice(plant, "plant", PLANTS)
    return DynamicPlant(robot) if kind == "dynamic" else KinematicPlant(robot)


def _held_at_rest(references: References, t: FloatArray, end: float) -> References:
    """After the plan ends, the reference is its final pose at rest (for ``settle``).

    At rest the feed-forward torque (the inverse dynamics without gravity) is zero too.
    """
    after = t > end + 1e-12
    if not after.any():
        return references
    moving = {}
    for name in ("qd", "qdd", "twist", "tau"):
        values = getattr(references, name)
        if values is None:
            continue
        values = values.copy()
        values[after] = 0.0
        moving[name] = values
    return replace(references, t=t.copy(), **moving)


class _Progress:
    """A one-line progress bar on a stream, redrawn at most every percent."""

    def __init__(self, total: int, label: str, stream: TextIO) -> None:
        self.total = total
        self.label = label
        self.stream = stream
        self.shown = -1

    def update(self, done: int) -> None:
        percent = 100 * done // max(self.total, 1)
        if percent == self.shown:
            return
        self.shown = percent
        filled = percent * 30 // 100
        bar = "#" * filled + "." * (30 - filled)
        self.stream.write(f"\r{self.label} [{bar}] {percent:3d}%")
        if done >= self.total:
            self.stream.write("\n")
        self.stream.flush()


def _check_parts(
    robot: Robot,
    trajectory: Trajectory,
    controller: Controller,
    noise: Noise | None,
    disturbance: Impulse | None,
    progress: bool | None,
) -> None:
    """Check the types of the run's parts and that the controller is for ``robot``."""
    for value, kind, name in ((noise, Noise, "noise"), (disturbance, Impulse, "disturbance")):
        if value is not None and not isinstance(value, kind):
            raise InvalidInputError(
                f"{name} must be a controllers.{kind.__name__} or None, got "
                f"{type(value).__name__} {value!r}",
                name=name,
            )
    if not isinstance(controller, Controller):
        raise InvalidInputError(
            f"controller must be a controllers.Controller, got {type(controller).__name__}",
            name="controller",
        )
    if not isinstance(trajectory, Trajectory):
        raise InvalidInputError(
            f"trajectory must be a planners.Trajectory, got {type(trajectory).__name__}",
            name="trajectory",
        )
    own = getattr(controller, "robot", None)
    if not isinstance(own, Robot) or own.fingerprint != robot.fingerprint:
        mine = f"{own.name!r} ({own.dof} joints)" if isinstance(own, Robot) else repr(own)
        other = " (another model of it: links, tool or limits differ)" if (
            isinstance(own, Robot) and own.name == robot.name
        ) else ""  # fmt: skip
        raise InvalidInputError(
            f"the controller is for robot {mine}, the simulation for {robot.name!r} "
            f"({robot.dof} joints){other}; build the controller with the simulated robot",
            name="controller",
        )
    if progress is not None:
        as_flag(progress, "progress")


def _step_count(end: float, extra: float, step: float, dt: float) -> int:
    """The number of control steps covering the plan and the settle time (at least one)."""
    count = max(math.ceil((end + extra) / step - 1e-9), 1)
    if count > MAX_STEPS:
        raise InvalidInputError(
            f"a run of {end + extra:.6g} s (plan and settle) at dt = {step:.6g} s takes {count} "
            f"steps, more than {MAX_STEPS}; use dt >= {(end + extra) / MAX_STEPS:.3g} s or a "
            "shorter settle",
            name="dt",
            value=dt,
        )
    return count


def _checked_command(
    controller: Controller, out: Command, time_k: float, n: int
) -> tuple[FloatArray, FloatArray | None]:
    """The controller's joint velocity and feed-forward torque, checked finite of shape (n,)."""
    qd_command = np.asarray(out.qd, dtype=float)
    if qd_command.shape != (n,) or not np.all(np.isfinite(qd_command)):
        raise SolverError(
            controller.name,
            "bad command",
            detail=f"at t = {time_k:.4g} s it returned {qd_command!r}; expected {n} finite "
            "joint velocities",
        )
    tau_command = None if out.tau is None else np.asarray(out.tau, dtype=float)
    if tau_command is not None and (
        tau_command.shape != (n,) or not np.all(np.isfinite(tau_command))
    ):
        raise SolverError(
            controller.name,
            "bad command",
            detail=f"at t = {time_k:.4g} s it returned the feed-forward torque "
            f"{tau_command!r}; expected {n} finite joint torques or None",
        )
    return qd_command, tau_command


@dataclass
class _Series:
    """The time series one run fills, step by step (``count`` steps of ``n`` joints)."""

    q: FloatArray
    qd: FloatArray
    measured_q: FloatArray
    measured_qd: FloatArray
    command: FloatArray
    applied: FloatArray
    tau: FloatArray
    step_time: FloatArray
    fallbacks: list[tuple[float, str]] = field(default_factory=list)
    saturated: int = 0

    @classmethod
    def empty(cls, count: int, n: int) -> _Series:
        """Uninitialised series for ``count`` steps of ``n`` joints."""
        return cls(
            q=np.empty((count + 1, n)),
            qd=np.empty((count + 1, n)),
            measured_q=np.empty((count, n)),
            measured_qd=np.empty((count, n)),
            command=np.empty((count, n)),
            applied=np.empty((count, n)),
            tau=np.empty((count, n)),
            step_time=np.empty(count),
        )


def _measure(
    state: PlantState, noise: Noise | None, rng: np.random.Generator | None, n: int
) -> tuple[FloatArray, FloatArray]:
    """The joint positions and velocities the controller sees (the state plus noise)."""
    mq, mqd = state.q, state.qd
    if rng is not None and noise is not None:
        mq = mq + rng.normal(0.0, noise.position, n)
        mqd = mqd + rng.normal(0.0, noise.velocity, n)
    return mq, mqd


def _run_steps(
    model: Plant,
    controller: Controller,
    references: References,
    state: PlantState,
    t: FloatArray,
    step: float,
    *,
    delay: int,
    noise: Noise | None,
    disturbance: Impulse | None,
    bar: _Progress | None,
) -> _Series:
    """Close the loop for every step: measure, command, delay, integrate; the time series."""
    count, n = t.size - 1, state.q.size
    rng = np.random.default_rng(noise.seed) if noise is not None else None
    series = _Series.empty(count, n)
    series.q[0], series.qd[0] = state.q, state.qd
    # Until the first command arrives, the plant holds its start velocity without feed-forward.
    queue: deque[tuple[FloatArray, FloatArray | None]] = deque([(state.qd.copy(), None)] * delay)
    for k in range(count):
        mq, mqd = _measure(state, noise, rng, n)
        measured = State(float(t[k]), mq, mqd)
        if k == 0:
            controller.reset(measured)
        started = time.perf_counter()
        out = controller.step(measured, references[k], step)
        series.step_time[k] = time.perf_counter() - started
        qd_command, tau_command = _checked_command(controller, out, t[k], n)
        if out.status != "ok":
            series.fallbacks.append((float(t[k]), out.status))
        queue.append((qd_command, tau_command))
        sent, sent_tau = queue.popleft()
        force = disturbance.force_during(t[k], t[k + 1]) if disturbance is not None else None
        state = model.step(sent, step, force, torque=sent_tau)
        series.measured_q[k], series.measured_qd[k] = mq, mqd
        series.command[k], series.applied[k], series.tau[k] = qd_command, sent, state.tau
        series.saturated += bool(state.saturated)
        series.q[k + 1], series.qd[k + 1] = state.q, state.qd
        if bar is not None:
            bar.update(k + 1)
    return series


def simulate(
    robot: Robot,
    trajectory: Trajectory,
    controller: Controller,
    dt: float = 1e-3,
    *,
    plant: str | Plant = "dynamic",
    noise: Noise | None = None,
    latency: int = 0,
    disturbance: Impulse | None = None,
    settle: float = 0.0,
    q_start: ArrayLike | None = None,
    progress: bool | None = None,
) -> Result:
    """Run a controller in closed loop along a planned trajectory.

    Args:
        robot: The robot (the plan's and the controller's).
        trajectory: The plan; sampled at every control time with its tool pose and twist.
        controller: The controller; it is reset at the start.
        dt: Control period [s], in [MIN_DURATION, MAX_DURATION] (1 us to a day).
        plant: ``"dynamic"``, ``"kinematic"`` or a :class:`~controllers.plants.Plant`.
        noise: Measurement noise; none when None.
        latency: Steps between a command and its arrival at the plant, in [0, MAX_STEPS];
            the plant keeps the start velocity until the first command arrives.
        disturbance: A force on the tool for a while; none when None.
        settle: Time to run after the plan ends [s], in [0, MAX_DURATION]; the reference is
            then the plan's final pose at rest.
        q_start: Start configuration [rad or m]; the plan's start when None (an offset
            shows how the controller closes an initial error).
        progress: Show a progress bar on stderr; by default only for runs of more than
            20,000 steps with stderr a terminal.

    Returns:
        The :class:`Result`, with time series and :class:`~controllers.metrics.Metrics`.

    Raises:
        InvalidInputError: A robot that is not a robots.Robot; bad dt, latency, settle,
            start, noise, disturbance or progress; a run of more than MAX_STEPS steps; a plan
            that is not a Trajectory, or a plan or controller for another robot (or another
            model of it).
        JointLimitError: ``q_start`` beyond a position limit.
        UnknownNameError: An unknown plant name.
        SolverError: The controller returned a joint velocity or feed-forward torque that is
            not a finite (n,) vector.
    """
    check_robot(robot)
    step = as_duration(dt, "dt")
    delay = as_count(latency, "latency", maximum=MAX_STEPS)
    extra = as_number(settle, "settle", "s", minimum=0.0, maximum=MAX_DURATION)
    _check_parts(robot, trajectory, controller, noise, disturbance, progress)
    end = trajectory.duration
    count = _step_count(end, extra, step, dt)
    model = _plant(robot, plant)
    t: FloatArray = np.arange(count + 1, dtype=np.float64) * step
    references = _held_at_rest(sample_references(robot, trajectory, np.minimum(t, end)), t, end)
    n = robot.dof
    if q_start is None:
        q0 = references.q[0]
    else:  # a start beyond a joint limit is no run of this robot
        q0 = as_vector(q_start, "q_start", n)
        robot.limits.check_position(q0, tolerance=1e-9, context="q_start")
    state = model.reset(q0, references.qd[0])
    show = progress if progress is not None else count > PROGRESS_STEPS and sys.stderr.isatty()
    bar = _Progress(count, f"simulate {controller.name}", sys.stderr) if show else None
    series = _run_steps(
        model,
        controller,
        references,
        state,
        t,
        step,
        delay=delay,
        noise=noise,
        disturbance=disturbance,
        bar=bar,
    )
    poses = robot.tool_pose(series.q)
    metrics = tracking_metrics(
        robot,
        t,
        references,
        series.q,
        series.qd,
        series.command,
        series.tau,
        series.step_time,
        fallbacks=len(series.fallbacks),
        saturated_steps=series.saturated,
        poses=poses,
    )
    return Result(
        robot=robot.name,
        joint_names=robot.joint_names,
        controller=controller.name,
        plant=model.name,
        dt=step,
        t=t,
        q=series.q,
        qd=series.qd,
        T_world_tool=poses,
        measured_q=series.measured_q,
        measured_qd=series.measured_qd,
        command=series.command,
        applied=series.applied,
        tau=series.tau,
        step_time=series.step_time,
        fallbacks=tuple(series.fallbacks),
        references=references,
        metrics=metrics,
        record=model.record(),
    )
