"""A viewer scene as data: the robot's geometry and motion, the task's shapes, the camera.

>>> scene = viz.build_scene(robot, trajectory, problem=shot, outcome=ball)
>>> [shape.name for shape in scene.shapes]      # floor, pedestal, table/..., ball, ...
>>> scene.q.shape                               # (frames, n): the robot at each frame

Frames are evenly spaced at ``fps`` over the trajectory, and on past its end while the
ball of an outcome still rolls (at most :data:`MAX_AFTER` s more); the robot holds its last
configuration there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.physics import Outcome
from optraj.planners import Trajectory
from optraj.planners.trajectory import fitted_to
from optraj.problems import PaddleStrike, PickAndPlace, PoolStrike
from optraj.problems.common import unit_vector
from optraj.robots import Robot
from optraj.validation import as_number
from optraj.viz.ball import ball_motion, path_shapes, path_times
from optraj.viz.mounts import mount_of, mount_shapes
from optraj.viz.robot_geometry import robot_geometry
from optraj.viz.shapes import Shape
from optraj.viz.tasks import ball_shape, paddle_shapes, pile_shape, pool_shapes, task_objects

__all__ = ["MAX_AFTER", "MAX_FPS", "MIN_FPS", "Scene", "build_scene"]

FloatArray = NDArray[np.float64]
Problem = PoolStrike | PaddleStrike | PickAndPlace

#: Frame rates accepted [1/s].
MIN_FPS = 1.0
MAX_FPS = 120.0
#: Longest the animation runs past the trajectory's end for the ball to roll [s].
MAX_AFTER = 4.0
#: Most frames in one animation (a long plan at a high rate is thinned to this).
MAX_FRAMES = 3000
#: Camera placement: the direction it looks from (base frame) and its distance from the
#: target as a multiple of the scene's extent; by default from the front left, above.
CAMERA_DIRECTION = np.array([0.55, -1.0, 0.55])
CAMERA_DISTANCE = 1.2
#: Per task: the pool shot from the robot's right, behind the cue; the paddle from its
#: right, a little ahead (ball and blade both in sight); the blocks from the front right.
TASK_VIEWS = {
    PoolStrike: (np.array([-0.2, -1.0, 0.75]), 1.3),
    PaddleStrike: (np.array([0.35, -1.0, 0.45]), 0.8),
    PickAndPlace: (np.array([1.0, -0.8, 0.9]), 1.0),
}
#: The floor stays this far below the lowest tool point and object centre [m].
FLOOR_MARGIN = 0.01
#: Smallest extent the camera frames [m].
MIN_EXTENT = 0.35


@dataclass(frozen=True)
class Scene:
    """Everything a viewer draws.

    Attributes:
        robot: The robot.
        geometry: Its visual geometry (:func:`viz.robot_geometry`).
        times: Frame times [s], shape (m,).
        q: Configuration at each frame [rad or m], shape (m, n).
        shapes: The other solids, still or moving (their ``motion`` has m poses).
        target: Point the camera looks at [m], shape (3,).
        camera: Camera position [m], shape (3,).
        fps: Frames per second [1/s].
    """

    robot: Robot
    geometry: pin.GeometryModel
    times: FloatArray
    q: FloatArray
    shapes: tuple[Shape, ...]
    target: FloatArray
    camera: FloatArray
    fps: float

    def shape(self, name: str) -> Shape:
        """The shape of that name.

        Raises:
            InvalidInputError: No such shape; lists the names.
        """
        for shape in self.shapes:
            if shape.name == name:
                return shape
        names = ", ".join(shape.name for shape in self.shapes)
        raise InvalidInputError(f"no shape {name!r} in the scene; it has: {names}", name="name")


def build_scene(
    robot: Robot,
    trajectory: Trajectory,
    problem: Problem | None = None,
    outcome: Outcome | None = None,
    *,
    fps: float = 30.0,
    view: ArrayLike | None = None,
    at: float | None = None,
) -> Scene:
    """The scene of a robot moving along a trajectory, with its task and the ball's path.

    Args:
        robot: The robot (the problem's, when a problem is given).
        trajectory: A plan for it.
        problem: A :class:`problems.PoolStrike` (table, ball, strike line),
            :class:`problems.PaddleStrike` (ball, launch direction) or
            :class:`problems.PickAndPlace` (blocks, carried); None for the robot alone.
        outcome: Where the ball went (:func:`physics.outcome`): its path is drawn and the
            ball follows it.
        fps: Animation frames per second [1/s], in [MIN_FPS, MAX_FPS].
        view: Direction from the target towards the camera (base frame), shape (3,);
            the task's (:data:`TASK_VIEWS`) or :data:`CAMERA_DIRECTION` when None. The
            distance follows the scene's size.
        at: A still scene at this time [s] (one frame, no animation), within the frames'
            span; the animation when None.

    Raises:
        InvalidInputError: A wrong type, a trajectory or problem for another robot, or a bad
            frame rate.
    """
    _check(robot, trajectory, problem, outcome)
    rate = as_number(fps, "fps", "1/s", minimum=MIN_FPS, maximum=MAX_FPS)
    times = _frame_times(trajectory.duration, outcome, rate)
    if at is not None:
        instant = as_number(at, "at", "s", minimum=0.0, maximum=float(times[-1]))
        times = np.array([instant])
    q = trajectory.sample(np.minimum(times, trajectory.duration)).q
    points = _points_of_interest(robot, q, problem)
    floor = min(mount_of(robot).floor, float(points[:, 2].min()) - FLOOR_MARGIN)
    shapes = mount_shapes(robot, points.mean(axis=0), floor)
    shapes += _task_shapes(robot, trajectory, problem, outcome, times, floor)
    default, distance = TASK_VIEWS.get(type(problem), (CAMERA_DIRECTION, CAMERA_DISTANCE))
    direction = default if view is None else unit_vector(view, "view")
    target, camera = _camera(points, direction, distance)
    return Scene(
        robot=robot,
        geometry=robot_geometry(robot),
        times=times,
        q=q,
        shapes=tuple(shapes),
        target=target,
        camera=camera,
        fps=rate,
    )


def _check(robot: Robot, trajectory: Trajectory, problem: object, outcome: object) -> None:
    if not isinstance(robot, Robot):
        raise InvalidInputError(
            f"robot must be a robots.Robot, got {type(robot).__name__}", name="robot"
        )
    fitted_to(trajectory, robot)
    if problem is not None:
        if not isinstance(problem, (PoolStrike, PaddleStrike, PickAndPlace)):
            raise InvalidInputError(
                "problem must be a PoolStrike, PaddleStrike, PickAndPlace or None, got "
                f"{type(problem).__name__}",
                name="problem",
            )
        if problem.robot.fingerprint != robot.fingerprint:
            raise InvalidInputError(
                f"the problem is for robot {problem.robot.name!r}, not this {robot.name!r} "
                "(pass problem.robot)",
                name="problem",
            )
    if outcome is not None and not isinstance(outcome, Outcome):
        raise InvalidInputError(
            f"outcome must be a physics.Outcome or None, got {type(outcome).__name__}",
            name="outcome",
        )


def _frame_times(duration: float, outcome: Outcome | None, fps: float) -> FloatArray:
    end = duration
    if outcome is not None:
        _, reached = path_times(outcome)
        end = max(end, min(float(reached[-1]), duration + MAX_AFTER))
    count = min(int(np.ceil(end * fps)) + 1, MAX_FRAMES)
    return np.linspace(0.0, end, max(count, 2))


def _task_shapes(
    robot: Robot,
    trajectory: Trajectory,
    problem: Problem | None,
    outcome: Outcome | None,
    times: FloatArray,
    floor: float,
) -> list[Shape]:
    shapes: list[Shape] = []
    if problem is not None:
        shapes += task_objects(problem, robot, trajectory, times, floor)
    if isinstance(problem, PoolStrike):
        shapes += pool_shapes(problem, floor)
    elif isinstance(problem, PaddleStrike):
        shapes += paddle_shapes(problem)
    elif isinstance(problem, PickAndPlace):
        shapes.append(pile_shape(problem))
    motion = ball_motion(outcome, times) if outcome is not None else None
    if isinstance(problem, (PoolStrike, PaddleStrike)):
        shapes.append(ball_shape(problem, motion))
    if outcome is not None:
        shapes += path_shapes(outcome)
    return shapes


def _points_of_interest(robot: Robot, q: FloatArray, problem: Problem | None) -> FloatArray:
    """Base, joints, tool path and the task's objects [m], shape (k, 3).

    What the camera frames (the ball's path beyond may leave the picture).
    """
    points = [np.zeros((1, 3)), robot.tool_position(q).reshape(-1, 3)]
    model, data = robot.model, robot.model.createData()
    for index in np.unique(np.linspace(0, len(q) - 1, 5).round().astype(int)):
        pin.forwardKinematics(model, data, q[index])
        points.append(np.array([data.oMi[j].translation for j in range(1, model.njoints)]))
    if isinstance(problem, (PoolStrike, PaddleStrike)):
        points.append(np.asarray(problem.ball, dtype=float)[None, :])
    if isinstance(problem, PickAndPlace):
        points.append(np.asarray(problem.picks, dtype=float))
    return np.concatenate(points)


def _camera(
    points: FloatArray, direction: FloatArray, distance: float
) -> tuple[FloatArray, FloatArray]:
    low, high = points.min(axis=0), points.max(axis=0)
    target = (low + high) / 2
    extent = max(float(np.linalg.norm(high - low)), MIN_EXTENT)
    unit = direction / np.linalg.norm(direction)
    return target, target + distance * extent * unit
