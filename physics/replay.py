"""A tool moved along a prescribed path through the ball: plans alone, and the ideal shot.

In a kinematic scene (:meth:`StrikeScene.as_kinematic`) the tool is a free heavy body. Two
ways to move it:

* :func:`replay`: along a planned trajectory's tool motion (the plan alone, as if tracked
  perfectly by an infinitely stiff arm): its pose and twist are imposed at every step;
* :func:`straight_cue`: thrown along a straight line at a constant speed and left to coast
  (the ideal shot; with ``tool_mass`` equal to the arm's effective mass it is the ideal of an
  arm strike).

Both return the :class:`~physics.contact_watch.ContactWatch` record with the ball's state, the
form :func:`physics.outcome` reads.
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.physics.contact_watch import ContactWatch
from optraj.physics.scene import StrikeScene, World
from optraj.planners.trajectory import Trajectory, fitted_to
from optraj.validation import as_number, as_positive, as_vector

__all__ = ["replay", "straight_cue"]

FloatArray = NDArray[np.float64]

#: How long a straight cue starts before it touches the ball [s] (coarse steps, then fine).
RUN_UP_TIME = 5e-3
#: Time after the contact ends that the ball is still followed [s].
AFTER = 2e-3
#: Fastest tool speed thrown [m/s]: ten times the fastest strike the shipped arms plan
#: (a few m/s); far beyond it the run-up starts kilometres from the table.
MAX_SPEED = 100.0
#: Longest run-up and settle [s]: a second of run-up crosses any table at a strike's speed,
#: and physics.outcome follows the ball to rest itself.
MAX_RUN_UP = 1.0
MAX_SETTLE = 10.0


def straight_cue(
    scene: StrikeScene,
    direction: ArrayLike,
    speed: float,
    *,
    tool_mass: float | None = None,
    offset: ArrayLike = (0.0, 0.0, 0.0),
    run_up_time: float = RUN_UP_TIME,
) -> dict[str, Any]:
    """Throw the scene's tool straight through the ball centre at ``speed``; the contact record.

    The tool's axis lies along ``direction``; it starts ``run_up_time * speed`` before touching
    the ball, its path shifted by ``offset`` (a lateral offset turns the ball), and coasts
    (gravity compensated) through the contact.

    Args:
        scene: The world (its kinematic version is used).
        direction: Direction of motion, shape (3,) (normalised here).
        speed: [m/s], in (0, MAX_SPEED].
        tool_mass: Mass of the free tool [kg]; the scene's kinematic tool mass when None.
        offset: Shift of the tool's path from the ball centre [m], shape (3,).
        run_up_time: How long before contact it starts [s], in (0, MAX_RUN_UP].

    Raises:
        InvalidInputError: Bad direction, speed, mass or offset.
    """
    d = as_vector(direction, "direction", 3)
    norm = float(np.linalg.norm(d))
    if norm < 1e-12:
        raise InvalidInputError("direction must not be zero", name="direction")
    d = d / norm
    v = as_positive(speed, "speed", "m/s", maximum=MAX_SPEED)
    shift = as_vector(offset, "offset", 3)
    lead = as_positive(run_up_time, "run_up_time", "s", maximum=MAX_RUN_UP)
    kinematic = scene.as_kinematic(scene.tool_mass if tool_mass is None else tool_mass)
    world = kinematic.build()
    data = mujoco.MjData(world.model)
    _place_ball(world, data)
    ball = np.asarray(scene.ball)
    start = ball + shift - (scene.contact_offset + lead * v) * d
    _set_tool(world, data, _frame_along(d, start), np.concatenate([v * d, np.zeros(3)]))
    mujoco.mj_forward(world.model, data)
    watch = ContactWatch(world)
    watch.advance(data, 2 * lead)
    _follow(watch, data)
    return _record(world, data, watch)


def replay(scene: StrikeScene, trajectory: Trajectory, *, settle: float = 0.05) -> dict[str, Any]:
    """Move the scene's tool as the trajectory's tool frame moves; the contact record.

    The pose and twist of the tool frame (the robot's forward kinematics of the plan) are
    imposed before every physics step, so the tool follows the plan exactly whatever the
    ball does.

    Args:
        scene: The world (its kinematic version is used).
        trajectory: A plan for the scene's robot.
        settle: Time after the plan's end that the ball is followed [s], in [0, MAX_SETTLE].

    Raises:
        InvalidInputError: A bad settle, or a trajectory for another joint count.
    """
    settle = as_number(settle, "settle", "s", minimum=0.0, maximum=MAX_SETTLE)
    robot = scene.robot
    fitted_to(trajectory, robot)
    world = scene.as_kinematic().build()
    data = mujoco.MjData(world.model)
    _place_ball(world, data)
    end = trajectory.duration

    def place(d: mujoco.MjData) -> None:
        t = min(float(d.time), end)
        sample = trajectory.sample(np.array([t]))
        q, qd = sample.q[0], sample.qd[0] if t < end else np.zeros(robot.dof)
        T = robot.tool_pose(q)
        twist = robot.jacobian(q) @ qd
        _set_tool(world, d, T, twist)

    place(data)
    mujoco.mj_forward(world.model, data)
    watch = ContactWatch(world)
    step = 1e-3
    while data.time < end + settle - 1e-12:
        watch.advance(data, min(step, end + settle - data.time), before_step=place)
    _follow(watch, data)
    return _record(world, data, watch)


def _follow(watch: ContactWatch, data: mujoco.MjData) -> None:
    """Keep stepping while the tool touches the ball, then :data:`AFTER` more."""
    limit = 0.05
    while watch.touching and limit > 0.0:
        watch.advance(data, 1e-4)
        limit -= 1e-4
    watch.advance(data, AFTER)


def _place_ball(world: World, data: mujoco.MjData) -> None:
    data.qpos[world.ball_qpos : world.ball_qpos + 3] = np.asarray(world.scene.ball)
    data.qpos[world.ball_qpos + 3 : world.ball_qpos + 7] = (1.0, 0.0, 0.0, 0.0)


def _set_tool(world: World, data: mujoco.MjData, T: FloatArray, twist: FloatArray) -> None:
    """Pose the free tool body at the tool frame ``T`` moving with ``twist = [v; w]`` (world).

    The free body's origin is the tool frame; MuJoCo's free-joint velocity is the origin's
    linear velocity in world axes and the angular velocity in body axes.
    """
    a = world.tool_qpos
    data.qpos[a : a + 3] = T[:3, 3]
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(T[:3, :3]).ravel())
    data.qpos[a + 3 : a + 7] = quat
    b = world.tool_dof
    data.qvel[b : b + 3] = twist[:3]
    data.qvel[b + 3 : b + 6] = T[:3, :3].T @ twist[3:]


def _frame_along(direction: FloatArray, origin: FloatArray) -> FloatArray:
    """A frame at ``origin`` whose z axis is ``direction``, shape (4, 4)."""
    z = direction
    helper = np.array([0.0, 0.0, 1.0]) if abs(z[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    T[:3, 3] = origin
    return T


def _record(world: World, data: mujoco.MjData, watch: ContactWatch) -> dict[str, Any]:
    out = watch.record()
    out["scene"] = world.scene
    out["ball_qpos"] = np.array(data.qpos[world.ball_qpos : world.ball_qpos + 7])
    out["ball_qvel"] = np.array(data.qvel[world.ball_dof : world.ball_dof + 6])
    out["time"] = np.array([float(data.time)])
    out["ball"] = np.concatenate([out["ball_qpos"][:3], out["ball_qvel"][:3]])[None, :]
    return out
