"""The scene around an arm in 3-D plots: a pool table, ball and strike line; blocks and pile.

Planners sit below :mod:`physics` and cannot import its scene, so the table's numbers are
repeated here: the same 9-ft playing surface (WPA: 100 x 50 in), placed as
:func:`physics.pool_scene` places it (the ball 0.35 m in from the near cushion, centred
across, the cloth one ball radius below the ball's centre); a test checks that the two agree.

>>> draw_scene(ax, problem, view)         # view: ViewBox of the arm's points and the scene's
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.problems import PickAndPlace, PoolStrike
from optraj.problems.scenes import BALL_FROM_NEAR_END, TABLE_SIZE

__all__ = [
    "BALL_FROM_NEAR_END",
    "TABLE_SIZE",
    "ViewBox",
    "draw_scene",
    "floor_height",
    "scene_points",
    "view_box",
]

FloatArray = NDArray[np.float64]

#: Length of the arrow of the shot's heading, drawn from the ball [m].
HEADING_ARROW = 0.25
#: Smallest half-size of a view [m].
MIN_HALF = 0.1
#: Drawing order (matplotlib zorder; the 3-D axes must not compute their own, as they sort
#: by mean depth and a large floor polygon would then cover the ball): the floor first, the
#: blocks and the ball over it, the task's lines on top. The arm goes between (2).
Z_FLOOR = 0.0
Z_SOLID = 3.0
Z_LINES = 5.0


@dataclass(frozen=True)
class ViewBox:
    """A cube of equal scale on x, y and z [m]: ``low`` and ``high`` corners, shape (3,)."""

    low: FloatArray
    high: FloatArray

    def apply(self, ax: Any) -> None:
        """Set the 3-D axes' limits to the box (equal aspect)."""
        ax.set_xlim(self.low[0], self.high[0])
        ax.set_ylim(self.low[1], self.high[1])
        ax.set_zlim(self.low[2], self.high[2])
        ax.set_box_aspect((1.0, 1.0, 1.0))


def floor_height(problem: object, points: FloatArray) -> float:
    """Height of the floor of the view [m]: the cloth, the blocks' bottom, or the lowest point.

    Nothing drawn lies below it: for a problem it is the surface the ball or blocks rest on
    (lowered to the lowest drawn point should the arm go below it).
    """
    lowest = float(np.min(points[:, 2]))
    if isinstance(problem, PoolStrike):
        return min(float(problem.ball[2]) - float(problem.ball_radius), lowest)
    if isinstance(problem, PickAndPlace):
        bottom = float(np.min(np.asarray(problem.picks)[:, 2])) - problem.block_height / 2
        return min(bottom, lowest)
    return lowest


def scene_points(problem: object) -> FloatArray:
    """Points of the scene that the view must hold [m], shape (k, 3) (none without a problem)."""
    if isinstance(problem, PoolStrike):
        ball = np.asarray(problem.ball)
        ahead = ball + HEADING_ARROW * np.asarray(problem.direction)
        return np.array([problem.entry_point, problem.exit_point, ball, ahead])
    if isinstance(problem, PickAndPlace):
        places = [problem.place_point(k) for k in range(problem.count)]
        return np.vstack([np.asarray(problem.picks), *places])
    return np.zeros((0, 3))


def view_box(points: FloatArray, floor: float) -> ViewBox:
    """The smallest cube around ``points`` [m] whose bottom is the floor (nothing below it)."""
    low = points.min(axis=0)
    high = points.max(axis=0)
    half = max(float(np.max(high - low)) / 2, float(high[2] - floor) / 2, MIN_HALF)
    centre = (low + high) / 2
    return ViewBox(
        low=np.array([centre[0] - half, centre[1] - half, floor]),
        high=np.array([centre[0] + half, centre[1] + half, floor + 2 * half]),
    )


def draw_scene(ax: Any, problem: object, view: ViewBox) -> None:
    """Draw what the problem's task is about on 3-D axes, clipped to ``view``.

    A pool shot: the table's cloth (the part inside the view), the ball (a marker, not to
    scale), the strike line from
    its entry to its exit point and an arrow along the shot's heading. A pick-and-place: each
    block where it is picked (solid) and where it goes on the pile (outline). Anything else:
    a grey floor.
    """
    if isinstance(problem, PoolStrike):
        _pool(ax, problem, view)
    elif isinstance(problem, PickAndPlace):
        _floor(ax, view, view.low[2], "0.85")
        for k in range(problem.count):
            pick = np.asarray(problem.picks)[k]
            _block(ax, pick, problem.block_height, solid=True, label="block" if k == 0 else None)
            _block(
                ax,
                problem.place_point(k),
                problem.block_height,
                solid=False,
                label="on the pile" if k == 0 else None,
            )
    else:
        _floor(ax, view, view.low[2], "0.9")


def _pool(ax: Any, problem: PoolStrike, view: ViewBox) -> None:
    ball = np.asarray(problem.ball)
    radius = float(problem.ball_radius)
    x0 = float(ball[0]) - BALL_FROM_NEAR_END
    y0 = float(ball[1]) - TABLE_SIZE[1] / 2
    table = (np.array([x0, y0]), np.array([x0 + TABLE_SIZE[0], y0 + TABLE_SIZE[1]]))
    low = np.maximum(table[0], view.low[:2])
    high = np.minimum(table[1], view.high[:2])
    if np.all(high > low):
        _rectangle(ax, low, high, float(ball[2]) - radius, "#1c7a45", 0.45, "table cloth")
    ax.scatter(
        *ball[:, None],
        s=90,
        facecolor="white",
        edgecolor="black",
        linewidth=1.0,
        depthshade=False,
        zorder=Z_SOLID,
        label=f"ball (r = {1e3 * radius:.1f} mm)",
    )
    line = np.array([problem.entry_point, problem.exit_point])
    ax.plot(
        *line.T, color="black", linestyle="--", linewidth=1.6, label="strike line", zorder=Z_LINES
    )
    ax.plot(
        *np.asarray(problem.contact_point)[:, None],
        marker="x",
        color="black",
        markersize=7,
        linestyle="none",
        label="contact point",
        zorder=Z_LINES,
    )
    ax.quiver(
        *ball,
        *(HEADING_ARROW * np.asarray(problem.direction)),
        color="#9467bd",
        linewidth=1.5,
        arrow_length_ratio=0.2,
        label="ball heading",
        zorder=Z_LINES,
    )


def _art3d() -> Any:
    """``mpl_toolkits.mplot3d.art3d`` (matplotlib's 3-D artists; it ships without types)."""
    return importlib.import_module("mpl_toolkits.mplot3d.art3d")


def _floor(ax: Any, view: ViewBox, z: float, colour: str) -> None:
    _rectangle(ax, view.low[:2], view.high[:2], z, colour, 0.35, None)


def _rectangle(
    ax: Any,
    low: FloatArray,
    high: FloatArray,
    z: float,
    colour: str,
    alpha: float,
    label: str | None,
) -> None:
    corners = [
        (low[0], low[1], z),
        (high[0], low[1], z),
        (high[0], high[1], z),
        (low[0], high[1], z),
    ]
    patch = _art3d().Poly3DCollection(
        [corners], facecolor=colour, alpha=alpha, edgecolor="none", zorder=Z_FLOOR
    )
    if label is not None:
        patch.set_label(label)
    ax.add_collection3d(patch)


def _block(ax: Any, centre: FloatArray, side: float, *, solid: bool, label: str | None) -> None:
    """A cube of edge ``side`` [m] at ``centre``: filled (solid) or a dashed outline."""
    h = side / 2
    corners = np.array([[x, y, z] for x in (-h, h) for y in (-h, h) for z in (-h, h)]) + centre
    faces = [[0, 1, 3, 2], [4, 5, 7, 6], [0, 1, 5, 4], [2, 3, 7, 6], [0, 2, 6, 4], [1, 3, 7, 5]]
    polygons = [corners[face] for face in faces]
    if solid:
        cube = _art3d().Poly3DCollection(
            polygons,
            facecolor="#e8a33d",
            edgecolor="#7a4a0c",
            alpha=0.9,
            linewidth=0.6,
            zorder=Z_SOLID,
        )
    else:
        cube = _art3d().Poly3DCollection(
            polygons,
            facecolor="none",
            edgecolor="#7a4a0c",
            linestyle="--",
            linewidth=0.9,
            zorder=Z_SOLID,
        )
    if label is not None:
        cube.set_label(label)
    ax.add_collection3d(cube)
