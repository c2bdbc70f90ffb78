"""The task's objects: the scene's solids, the strike line, the balls, the pile.

The solids (the pool table's cloth and cushions, the blocks) come from the problem's scene
description (:func:`static_scene`), the one the checker measures and the MuJoCo world is
built from; carried blocks ride with the frame their :class:`~problems.Attachment` names.
The table's apron and legs are drawn under its cloth for the picture only: no check or
physics knows them.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from optraj import physics
from optraj.planners import Trajectory
from optraj.problems import (
    Box,
    PaddleStrike,
    PickAndPlace,
    PoolStrike,
    Scene,
    pick_and_place_scene,
)
from optraj.robots import Robot
from optraj.robots.collision import PADDLE_BALL_RADIUS
from optraj.viz.scene_objects import object_shapes
from optraj.viz.shapes import Shape, box, segment, sphere

__all__ = [
    "ball_shape",
    "paddle_shapes",
    "pile_shape",
    "pool_shapes",
    "static_scene",
    "task_objects",
]

FloatArray = NDArray[np.float64]
Problem = PoolStrike | PaddleStrike | PickAndPlace

APRON_COLOUR = (0.3, 0.15, 0.05, 1.0)
POOL_BALL_COLOUR = (0.95, 0.95, 0.9, 1.0)
PADDLE_BALL_COLOUR = (1.0, 0.55, 0.1, 1.0)
STRIKE_COLOUR = (1.0, 0.85, 0.0, 1.0)
HEADING_COLOUR = (1.0, 0.85, 0.0, 0.45)
PILE_COLOUR = (0.2, 0.2, 0.2, 0.35)

#: Drawn depth of the apron under the cloth and side of the legs [m].
APRON_DEPTH = 0.2
LEG_SIZE = 0.12
#: Radius of the strike line and of the commanded heading drawn past the ball [m], and the
#: heading's length [m].
LINE_RADIUS = 0.004
HEADING_LENGTH = 0.6


def static_scene(problem: Problem) -> Scene | None:
    """The solids around a task: the problem's scene, else the ready-made one.

    A strike: the MuJoCo world's (:attr:`physics.StrikeScene.static_scene`: the pool table
    under the ball, nothing for a paddle). A pick-and-place: its blocks and work surface
    (:func:`problems.pick_and_place_scene`).
    """
    if isinstance(problem, PickAndPlace):
        return problem.scene if problem.scene is not None else pick_and_place_scene(problem)
    return physics.scene_for(problem).static_scene


def task_objects(
    problem: Problem, robot: Robot, trajectory: Trajectory, times: FloatArray, floor: float
) -> list[Shape]:
    """The solids of the task's scene (:func:`static_scene`), carried ones moving.

    Args:
        problem: The task.
        robot: Its robot.
        trajectory: The robot's motion.
        times: Frame times [s], shape (m,).
        floor: Height of the drawn floor [m].
    """
    scene = static_scene(problem)
    return [] if scene is None else object_shapes(scene, robot, trajectory, times, floor)


def _table_stand(problem: PoolStrike, floor: float) -> list[Shape]:
    """The apron under the scene's ``cloth`` (a box) and legs down to ``floor`` [m]."""
    scene = static_scene(problem)
    if scene is None or "cloth" not in scene.names:
        return []
    cloth = scene.object("cloth")
    if not isinstance(cloth, Box):
        return []
    half = np.asarray(cloth.half_extents)
    centre = np.asarray(cloth.pose)[:3, 3]
    top = float(centre[2] - half[2])  # the apron hangs from the cloth's bottom
    shapes = [
        box(
            "table/apron",
            (centre[0], centre[1], top - APRON_DEPTH / 2),
            (2 * half[0], 2 * half[1], APRON_DEPTH),
            APRON_COLOUR,
        )
    ]
    bottom = top - APRON_DEPTH
    if bottom > floor:
        for i, (sx, sy) in enumerate(((-1, -1), (-1, 1), (1, -1), (1, 1))):
            x = centre[0] + sx * (half[0] - LEG_SIZE)
            y = centre[1] + sy * (half[1] - LEG_SIZE)
            shapes.append(
                box(
                    f"table/leg_{i}",
                    (x, y, (bottom + floor) / 2),
                    (LEG_SIZE, LEG_SIZE, bottom - floor),
                    APRON_COLOUR,
                )
            )
    return shapes


def pool_shapes(problem: PoolStrike, floor: float) -> list[Shape]:
    """The table's apron and legs, the strike line and the commanded heading of a pool shot.

    The apron and legs stand under the scene's cloth, down to ``floor`` [m] (the cloth and
    cushions themselves are :func:`task_objects`'). The strike line runs through the contact
    point; the heading goes on past the ball (the ball itself is :func:`ball_shape`'s).
    """
    shapes = _table_stand(problem, floor)
    ball = np.asarray(problem.ball, dtype=float)
    direction = np.asarray(problem.direction, dtype=float)
    lines = (
        segment(
            "strike_line",
            problem.entry_point,
            problem.exit_point,
            LINE_RADIUS,
            STRIKE_COLOUR,
            "capsule",
        ),
        segment(
            "shot_heading", ball, ball + HEADING_LENGTH * direction, LINE_RADIUS / 2, HEADING_COLOUR
        ),
    )
    shapes.extend(line for line in lines if line is not None)
    return shapes


def paddle_shapes(problem: PaddleStrike) -> list[Shape]:
    """The commanded launch direction (the paddle normal at contact) from the ball."""
    ball = np.asarray(problem.ball, dtype=float)
    normal = np.asarray(problem.normal, dtype=float)
    line = segment(
        "shot_heading", ball, ball + HEADING_LENGTH * normal, LINE_RADIUS, HEADING_COLOUR
    )
    return [line] if line is not None else []


def ball_shape(problem: PoolStrike | PaddleStrike, motion: FloatArray | None) -> Shape:
    """The ball at its start, moving as ``motion`` (poses per frame) says when given."""
    if isinstance(problem, PoolStrike):
        radius, rgba = float(problem.ball_radius), POOL_BALL_COLOUR
    else:
        radius, rgba = PADDLE_BALL_RADIUS, PADDLE_BALL_COLOUR
    shape = sphere("ball", problem.ball, radius, rgba)
    if motion is None:
        return shape
    return Shape(shape.name, shape.kind, shape.size, motion[0], shape.rgba, motion)


def pile_shape(problem: PickAndPlace) -> Shape:
    """A faint square where the pile's first block is put."""
    size = float(problem.block_height)
    pile = np.asarray(problem.pile, dtype=float)
    return box(
        "pile",
        pile - [0.0, 0.0, size / 2 - 0.001],
        (1.4 * size, 1.4 * size, 0.002),
        PILE_COLOUR,
    )
