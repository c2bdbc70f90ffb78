r"""Where the ball went: launch heading and speed against the commanded shot.

>>> result = controllers.simulate(robot, traj, controller, plant=physics.MujocoPlant(scene))
>>> shot = physics.outcome(result, problem)
>>> shot.heading_error, shot.speed_error, shot.within     # [deg], [-], bool

The *commanded shot* is the problem's: a pool strike sends the ball along ``direction`` (its
heading in the table plane), a paddle strike along the paddle normal. Its *ideal speed* is
calibrated in the same scene: a perfectly straight tool at the commanded speed, with the
effective mass the striking tool has along the shot at the contact
(:math:`m = 1 / (d^T J M^{-1} J^T d)`, MuJoCo's inertia of the true arm), coasting into the
ball (:func:`physics.replay.straight_cue`). For an arm that mass is finite (about 2 kg for
Sawyer's cue tip), so the ideal ball speed is below a kinematic cue's :math:`(1 + e) v`.

A ball that the tool never touches is an outcome, ``hit=False`` with infinite errors; it
raises nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from optraj.controllers.simulation import Result
from optraj.errors import InvalidInputError
from optraj.physics.replay import straight_cue
from optraj.physics.scene import StrikeScene
from optraj.problems.paddle_strike import PaddleStrike
from optraj.problems.pool_strike import PoolStrike

__all__ = ["HEADING_TOLERANCE", "SPEED_TOLERANCE", "Outcome", "outcome"]

FloatArray = NDArray[np.float64]

#: A shot is on target within this heading error [deg] and relative speed error [-].
HEADING_TOLERANCE = 0.5
SPEED_TOLERANCE = 0.02
#: The ball is rolled out until slower than this [m/s], or for at most this long [s].
REST_SPEED = 1e-3
REST_TIME = 30.0
#: Physics step of the roll-out [s]: resolves the cloth's and cushions' 4 ms contacts.
ROLL_STEP = 2e-4
#: A paddle ball's final position is taken this long after contact [s].
FLIGHT_TIME = 0.5
#: The roll-out's positions are kept this often [s].
ROLL_SAMPLE = 0.02


@dataclass(frozen=True)
class Outcome:
    """What the ball did.

    Attributes:
        hit: Whether the tool touched the ball.
        contacts: How many separate tool-ball contacts there were (1 for a clean strike).
        contact_time: When the first contact began [s] (``inf`` when missed).
        contact_point: Where [m], shape (3,) (zeros when missed).
        launch_velocity: Ball velocity when the tool let go [m/s], shape (3,).
        launch_speed: Its norm (pool: in the table plane) [m/s].
        heading_error: Angle between the launch and the commanded direction [deg] (pool: in
            the table plane, signed counter-clockwise about +z; paddle: unsigned, 3-D);
            ``inf`` when missed.
        speed_error: ``launch_speed / ideal_speed - 1`` [-]; ``inf`` when missed.
        ideal_speed: The calibrated ideal launch speed [m/s].
        effective_mass: The tool's effective mass along the shot at contact [kg].
        tool_speed: The tool's speed along the shot at the contact point [m/s].
        rest_position: Pool: where the ball comes to rest on the table [m]; paddle: where it
            is :data:`FLIGHT_TIME` after contact on its (gravity-free) flight; shape (3,).
        path: The ball's positions over a :class:`physics.MujocoPlant` run, one per control
            step [m], shape (m, 3); from :func:`physics.replay` or
            :func:`physics.straight_cue`, only its position at the end, shape (1, 3).
        direction: The commanded launch direction (unit), shape (3,).
        start: Where the ball was before the strike [m], shape (3,).
        roll: Pool: the ball's positions every :data:`ROLL_SAMPLE` s from the end of the
            run to rest [m], shape (k, 3); paddle: the run's end and ``rest_position``;
            missed: ``start`` alone, shape (1, 3).
        kind: The scene's kind, ``"pool"`` or ``"paddle"``.
    """

    hit: bool
    contacts: int
    contact_time: float
    contact_point: FloatArray
    launch_velocity: FloatArray
    launch_speed: float
    heading_error: float
    speed_error: float
    ideal_speed: float
    effective_mass: float
    tool_speed: float
    rest_position: FloatArray
    path: FloatArray
    direction: FloatArray
    start: FloatArray
    roll: FloatArray
    kind: str

    @property
    def within(self) -> bool:
        """On target: hit, heading within 0.5 deg and speed within 2 % of the ideal."""
        return (
            self.hit
            and abs(self.heading_error) <= HEADING_TOLERANCE
            and abs(self.speed_error) <= SPEED_TOLERANCE
        )

    def summary(self) -> str:
        """One line for a table or the demo."""
        if not self.hit:
            return "missed: the tool never touched the ball"
        x, y, z = self.rest_position
        return (
            f"ball off at {self.launch_speed:.3f} m/s ({100 * self.speed_error:+.2f} % of the "
            f"ideal {self.ideal_speed:.3f}), heading {self.heading_error:+.3f} deg, to "
            f"({x:.3f}, {y:.3f}, {z:.3f}) m; {'on target' if self.within else 'off target'}"
        )


def outcome(run: Result | dict[str, Any], problem: PoolStrike | PaddleStrike) -> Outcome:
    """Judge a strike by the ball.

    Args:
        run: A :func:`controllers.simulate` result on a :class:`physics.MujocoPlant` (its
            ``record``), or a record from :func:`physics.replay.replay` or
            :func:`physics.replay.straight_cue`.
        problem: The strike that was commanded.

    Raises:
        InvalidInputError: A run without a MuJoCo record, or a problem that is not a strike.
    """
    record = run.record if isinstance(run, Result) else run
    if not isinstance(record, dict) or "launch" not in record or "scene" not in record:
        raise InvalidInputError(
            "run must come from a physics.MujocoPlant simulation or physics.replay (it has no "
            "ball record); pass plant=physics.MujocoPlant(scene) to controllers.simulate",
            name="run",
        )
    direction, speed = _commanded(problem)
    scene: StrikeScene = record["scene"]
    path = np.asarray(record["ball"], dtype=float)[:, :3]
    start = np.asarray(scene.ball, dtype=float).copy()
    if int(record["contacts"]) == 0 or not np.isfinite(record["launch"]).all():
        return Outcome(
            hit=False,
            contacts=0,
            contact_time=math.inf,
            contact_point=np.zeros(3),
            launch_velocity=np.zeros(3),
            launch_speed=0.0,
            heading_error=math.inf,
            speed_error=math.inf,
            ideal_speed=0.0,
            effective_mass=0.0,
            tool_speed=0.0,
            rest_position=start.copy(),
            path=path,
            direction=direction.copy(),
            start=start,
            roll=start[None, :].copy(),
            kind=scene.kind,
        )
    launch = np.asarray(record["launch"], dtype=float)
    inverse = np.asarray(record["inverse_inertia"], dtype=float)
    mass = float(1.0 / (direction @ inverse @ direction))
    ideal = straight_cue(scene, direction, speed, tool_mass=mass)
    ideal_speed = _speed(scene, np.asarray(ideal["launch"]))
    launch_speed = _speed(scene, launch)
    roll = _rest(scene, record)
    return Outcome(
        hit=True,
        contacts=int(record["contacts"]),
        contact_time=float(record["contact_start"]),
        contact_point=np.asarray(record["contact_point"], dtype=float),
        launch_velocity=launch,
        launch_speed=launch_speed,
        heading_error=_heading(scene, launch, direction),
        speed_error=launch_speed / ideal_speed - 1.0,
        ideal_speed=ideal_speed,
        effective_mass=mass,
        tool_speed=float(np.asarray(record["tool_velocity"]) @ direction),
        rest_position=roll[-1].copy(),
        path=path,
        direction=direction.copy(),
        start=start,
        roll=roll,
        kind=scene.kind,
    )


def _commanded(problem: PoolStrike | PaddleStrike) -> tuple[FloatArray, float]:
    if isinstance(problem, PoolStrike):
        return np.asarray(problem.direction, dtype=float), float(problem.speed)
    if isinstance(problem, PaddleStrike):
        if float(problem.speed) <= 0.0:
            raise InvalidInputError(
                "a paddle strike with speed 0 arrives at rest and sends no ball: give speed > 0",
                name="problem",
            )
        return np.asarray(problem.normal, dtype=float), float(problem.speed)
    raise InvalidInputError(
        f"problem must be a PoolStrike or a PaddleStrike, got {type(problem).__name__}",
        name="problem",
    )


def _speed(scene: StrikeScene, velocity: FloatArray) -> float:
    v = velocity[:2] if scene.kind == "pool" else velocity
    return float(np.linalg.norm(v))


def _heading(scene: StrikeScene, launch: FloatArray, direction: FloatArray) -> float:
    if scene.kind == "pool":
        angle = math.atan2(launch[1], launch[0]) - math.atan2(direction[1], direction[0])
        return math.degrees(math.remainder(angle, 2 * math.pi))
    cosine = float(launch @ direction) / max(float(np.linalg.norm(launch)), 1e-300)
    return math.degrees(math.acos(min(1.0, max(-1.0, cosine))))


def _rest(scene: StrikeScene, record: dict[str, Any]) -> FloatArray:
    """The ball rolled out alone (pool) or flown on (paddle) from its state at the end.

    Returns its positions from the end of the run to rest (the last row), shape (k, 3).
    """
    qpos = np.asarray(record["ball_qpos"], dtype=float)
    qvel = np.asarray(record["ball_qvel"], dtype=float)
    if scene.kind == "paddle":
        elapsed = float(record["time"][-1]) - float(record["contact_end"])
        return np.stack([qpos[:3], qpos[:3] + qvel[:3] * max(FLIGHT_TIME - elapsed, 0.0)])
    world = scene.as_kinematic().build()
    model, data = world.model, mujoco.MjData(world.model)
    data.qpos[world.tool_qpos : world.tool_qpos + 3] = (0.0, 0.0, 50.0)  # out of the way
    data.qpos[world.tool_qpos + 3 : world.tool_qpos + 7] = (1.0, 0.0, 0.0, 0.0)
    data.qpos[world.ball_qpos : world.ball_qpos + 7] = qpos
    data.qvel[world.ball_dof : world.ball_dof + 6] = qvel
    model.opt.timestep = ROLL_STEP
    chunk = round(ROLL_SAMPLE / ROLL_STEP)
    ball = slice(world.ball_qpos, world.ball_qpos + 3)
    positions = [np.array(data.qpos[ball])]
    for _ in range(int(REST_TIME / ROLL_SAMPLE)):
        mujoco.mj_step(model, data, nstep=chunk)
        positions.append(np.array(data.qpos[ball]))
        speed = np.linalg.norm(data.qvel[world.ball_dof : world.ball_dof + 3])
        if speed < REST_SPEED:
            break
    return np.stack(positions)
