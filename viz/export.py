"""The viewer's outputs: a self-contained HTML page, a file, and a notebook cell.

>>> from optraj import viz
>>> viz.write_html("shot.html", shot.robot, traj, problem=shot, outcome=ball)
>>> viz.notebook_view(shot.robot, traj, problem=shot)     # last line of a Jupyter cell

Each call starts a MeshCat server on the loopback interface, asks it for the page and stops
it (about a second). The page needs no server and no network: open it in a browser, where
the animation plays once on opening and replays from the Animations panel ("Open Controls").
"""

from __future__ import annotations

import html
from pathlib import Path
from typing import Any

from numpy.typing import ArrayLike

from optraj.errors import InvalidInputError
from optraj.physics import Outcome
from optraj.planners import Trajectory
from optraj.robots import Robot
from optraj.validation import as_number
from optraj.viz.meshcat_viewer import MeshcatViewer, import_meshcat
from optraj.viz.scene import Problem, build_scene

__all__ = ["notebook_view", "scene_html", "write_html"]

#: Height of the notebook view [px], allowed range.
MIN_HEIGHT = 100.0
MAX_HEIGHT = 4000.0


def scene_html(
    robot: Robot,
    trajectory: Trajectory,
    problem: Problem | None = None,
    outcome: Outcome | None = None,
    *,
    fps: float = 30.0,
    view: ArrayLike | None = None,
    at: float | None = None,
) -> str:
    """The animated scene as one self-contained HTML page (a few MB: the viewer is inlined).

    Arguments as for :func:`optraj.viz.build_scene`.

    Raises:
        MissingDependencyError: meshcat is not installed (``pip install "optraj[viz]"``).
        InvalidInputError: As :func:`optraj.viz.build_scene`.
    """
    import_meshcat()
    scene = build_scene(robot, trajectory, problem, outcome, fps=fps, view=view, at=at)
    with MeshcatViewer() as viewer:
        viewer.show(scene)
        return viewer.static_html()


def write_html(
    path: str | Path,
    robot: Robot,
    trajectory: Trajectory,
    problem: Problem | None = None,
    outcome: Outcome | None = None,
    *,
    fps: float = 30.0,
    view: ArrayLike | None = None,
    at: float | None = None,
) -> Path:
    """Write the animated scene to ``path`` as a self-contained HTML page; returns the path.

    The folder must exist. Other arguments as for :func:`optraj.viz.build_scene`.

    Raises:
        MissingDependencyError: meshcat is not installed.
        InvalidInputError: A path that is not a str or Path, a folder that does not exist, or
            as :func:`optraj.viz.build_scene`.
    """
    if not isinstance(path, (str, Path)):
        raise InvalidInputError(
            f"path must be a str or pathlib.Path, got {type(path).__name__}", name="path"
        )
    target = Path(path)
    if not target.parent.is_dir():
        raise InvalidInputError(
            f"path {str(target)!r}: folder {str(target.parent)!r} does not exist", name="path"
        )
    page = scene_html(robot, trajectory, problem, outcome, fps=fps, view=view, at=at)
    target.write_text(page, encoding="utf-8")
    return target


def notebook_view(
    robot: Robot,
    trajectory: Trajectory,
    problem: Problem | None = None,
    outcome: Outcome | None = None,
    *,
    fps: float = 30.0,
    view: ArrayLike | None = None,
    at: float | None = None,
    height: float = 480.0,
) -> Any:
    """The animated scene for a Jupyter cell, as an ``IPython.display.HTML``.

    The page sits in an iframe (``srcdoc``), so the saved notebook shows it with no server
    running.

    Args:
        robot: As for :func:`optraj.viz.build_scene`.
        trajectory: As for :func:`optraj.viz.build_scene`.
        problem: As for :func:`optraj.viz.build_scene`.
        outcome: As for :func:`optraj.viz.build_scene`.
        fps: As for :func:`optraj.viz.build_scene` [1/s].
        view: As for :func:`optraj.viz.build_scene`.
        at: As for :func:`optraj.viz.build_scene` [s].
        height: Height of the view [px], in [MIN_HEIGHT, MAX_HEIGHT].

    Raises:
        MissingDependencyError: meshcat is not installed.
        InvalidInputError: A bad height, or as :func:`optraj.viz.build_scene`.
    """
    pixels = as_number(height, "height", "px", minimum=MIN_HEIGHT, maximum=MAX_HEIGHT)
    page = scene_html(robot, trajectory, problem, outcome, fps=fps, view=view, at=at)
    from IPython.display import HTML

    return HTML(iframe(page, pixels))


def iframe(page: str, height: float) -> str:
    """``page`` in an iframe of ``height`` [px] and full width, in a div, as HTML text."""
    return (
        f'<div style="width: 100%"><iframe srcdoc="{html.escape(page, quote=True)}" '
        f'style="width: 100%; height: {height:.0f}px; border: none"></iframe></div>'
    )
