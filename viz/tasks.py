"""The task's objects: the pool table and ball, the strike line, the paddle's ball, the blocks.

Numbers are those of the MuJoCo scene (:mod:`optraj.physics.scene`: a 9-ft table placed with
the ball 0.35 m in from the near cushion, cushion height, ball radii) and of the problems.
Blocks of a pick-and-place ride with the gripper from the start of their grasp phase to the
end of their release phase.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from optraj.physics.scene import (
    BALL_FROM_NEAR_END,
    CUSHION_HEIGHT,
    PADDLE_BALL_RADIUS,
    TABLE_SIZE,
)
from optraj.planners import Trajectory
from optraj.problems import PaddleStrike, PickAndPlace, PoolStrike
from optraj.robots import Robot
from optraj.viz.shapes import Shape, box, segment, sphere

__all__ = ["ball_shape", "block_shapes", "paddle_shapes", "pool_shapes"]

FloatArray = NDArray[np.float64]

CLOTH_COLOUR = (0.05, 0.45, 0.2, 1.0)
CUSHION_COLOUR = (0.3, 0.15, 0.05, 1.0)
POOL_BALL_COLOUR = (0.95, 0.95, 0.9, 1.0)
PADDLE_BALL_COLOUR = (1.0, 0.55, 0.1, 1.0)
STRIKE_COLOUR = (1.0, 0.85, 0.0, 1.0)
HEADING_COLOUR = (1.0, 0.85, 0.0, 0.45)
BLOCK_COLOURS = ((0.9, 0.3, 0.3, 1.0), (0.3, 0.5, 0.95, 1.0), (0.95, 0.75, 0.2, 1.0))
PILE_COLOUR = (0.2, 0.2, 0.2, 0.35)

#: Drawn thickness of the cloth slab, the cushions' width and the apron's depth [m].
CLOTH_THICKNESS = 0.04
CUSHION_WIDTH = 0.1
APRON_DEPTH = 0.2
LEG_SIZE = 0.12
#: Radius of the strike line and of the commanded heading drawn past the ball [m], and the
#: heading's length [m].
LINE_RADIUS = 0.004
HEADING_LENGTH = 0.6


def _cloth_top(problem: PoolStrike) -> float:
    return float(problem.ball[2]) - float(problem.ball_radius)


def pool_shapes(problem: PoolStrike, floor: float) -> list[Shape]:
    """The table, the strike line and the commanded heading of a pool shot.

    The table: cloth, cushions, apron, legs down to ``floor`` [m]. The strike line runs
    through the contact point; the heading goes on past the ball (the ball itself is
    :func:`ball_shape`'s).
    """
    length, width = TABLE_SIZE
    ball = np.asarray(problem.ball, dtype=float)
    x0, y0 = float(ball[0]) - BALL_FROM_NEAR_END, float(ball[1])
    top = _cloth_top(problem)
    cx = x0 + length / 2
    outer = (length + 2 * CUSHION_WIDTH, width + 2 * CUSHION_WIDTH)
    shapes = [
        box(
            "table/cloth",
            (cx, y0, top - CLOTH_THICKNESS / 2),
            (*outer, CLOTH_THICKNESS),
            CLOTH_COLOUR,
        ),
        box(
            "table/apron",
            (cx, y0, top - CLOTH_THICKNESS - APRON_DEPTH / 2),
            (*outer, APRON_DEPTH),
            CUSHION_COLOUR,
        ),
    ]
    h = CUSHION_HEIGHT
    rails = {
        "near": ((x0 - CUSHION_WIDTH / 2, y0), (CUSHION_WIDTH, outer[1])),
        "far": ((x0 + length + CUSHION_WIDTH / 2, y0), (CUSHION_WIDTH, outer[1])),
        "left": ((cx, y0 + (width + CUSHION_WIDTH) / 2), (outer[0], CUSHION_WIDTH)),
        "right": ((cx, y0 - (width + CUSHION_WIDTH) / 2), (outer[0], CUSHION_WIDTH)),
    }
    for name, ((x, y), (sx, sy)) in rails.items():
        shapes.append(
            box(f"table/cushion_{name}", (x, y, top + h / 2), (sx, sy, h), CUSHION_COLOUR)
        )
    bottom = top - CLOTH_THICKNESS - APRON_DEPTH
    if bottom > floor:
        for i, (sx, sy) in enumerate(((-1, -1), (-1, 1), (1, -1), (1, 1))):
            x = cx + sx * (outer[0] / 2 - LEG_SIZE)
            y = y0 + sy * (outer[1] / 2 - LEG_SIZE)
            shapes.append(
                box(
                    f"table/leg_{i}",
                    (x, y, (bottom + floor) / 2),
                    (LEG_SIZE, LEG_SIZE, bottom - floor),
                    CUSHION_COLOUR,
                )
            )
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


def block_shapes(
    problem: PickAndPlace, robot: Robot, trajectory: Trajectory, times: FloatArray
) -> list[Shape]:
    """Each block as a cube, carried by the gripper between its grasp and its release.

    A trajectory without the phases ``grasp_<k>`` and ``release_<k>`` leaves block k where
    it is picked. The pile's first place is marked by a faint square.
    """
    size = float(problem.block_height)
    picks = np.asarray(problem.picks, dtype=float)
    q = trajectory.sample(np.clip(times, 0.0, trajectory.duration)).q
    tool = robot.tool_pose(q).reshape(-1, 4, 4)
    names = {phase.name: phase for phase in trajectory.phases}
    pile = np.asarray(problem.pile, dtype=float)
    shapes = [
        box(
            "pile",
            pile - [0.0, 0.0, size / 2 - 0.001],
            (1.4 * size, 1.4 * size, 0.002),
            PILE_COLOUR,
        )
    ]
    for k in range(problem.count):
        rgba = BLOCK_COLOURS[k % len(BLOCK_COLOURS)]
        start = box(f"block_{k}", picks[k], (size, size, size), rgba)
        grasp, release = names.get(f"grasp_{k}"), names.get(f"release_{k}")
        if grasp is None or release is None:
            shapes.append(start)
            continue
        at_grasp = robot.tool_pose(trajectory.sample(np.array([grasp.t_start])).q[0])
        held = np.linalg.solve(at_grasp, start.pose)  # block in the tool frame
        carried = tool @ held
        motion = np.where((times < grasp.t_start)[:, None, None], start.pose, carried)
        placed = robot.tool_pose(trajectory.sample(np.array([release.t_end])).q[0]) @ held
        motion[times > release.t_end] = placed
        shapes.append(Shape(start.name, "box", start.size, motion[0], rgba, motion))
    return shapes
