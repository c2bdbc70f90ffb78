"""Helpers of the viewer tests: the three scenes, and reading a MeshCat page's commands."""

from __future__ import annotations

import base64
import re
from typing import Any

import numpy as np

from optraj import planners, problems
from optraj.physics import Outcome

_COMMAND = re.compile(r"octet-binary;base64,([A-Za-z0-9+/=]+)")


def pool_case() -> tuple[problems.PoolStrike, planners.Trajectory]:
    """Sawyer's pool shot at 1 m/s and a time-optimal strike plan (about 0.1 s)."""
    shot = problems.sawyer_pool_shot(speed=1.0)
    return shot, planners.TimeOptimalStrike(contact="choose").plan(shot)


def paddle_case() -> tuple[problems.PaddleStrike, planners.Trajectory]:
    """The ECE486 paddle task and its cubic plan."""
    problem = problems.ece486_paddle_strike()
    return problem, planners.Cubic().plan(problem)


def youbot_case() -> tuple[problems.PickAndPlace, planners.Trajectory]:
    """The youBot's two blocks and a quintic pick-and-place plan."""
    problem = problems.youbot_two_blocks()
    return problem, planners.PickAndPlacePlanner(planners.Quintic()).plan(problem)


def rolled_outcome(shot: problems.PoolStrike, contact_time: float) -> Outcome:
    """A made-up pool outcome: the ball leaves at 1 m/s along the shot and rolls 0.3 m."""
    start = np.asarray(shot.ball, dtype=float)
    direction = np.asarray(shot.direction, dtype=float)
    roll = start + np.linspace(0.02, 0.3, 15)[:, None] * direction
    return Outcome(
        hit=True,
        contacts=1,
        contact_time=contact_time,
        contact_point=start - shot.ball_radius * direction,
        launch_velocity=direction.copy(),
        launch_speed=1.0,
        heading_error=0.0,
        speed_error=0.0,
        ideal_speed=1.0,
        effective_mass=2.0,
        tool_speed=1.0,
        rest_position=roll[-1].copy(),
        path=start[None, :].copy(),
        direction=direction,
        start=start,
        roll=roll,
        kind="pool",
    )


def page_commands(page: str) -> list[dict[str, Any]]:
    """The MeshCat drawing commands inlined in a static page, decoded."""
    import umsgpack

    return [umsgpack.unpackb(base64.b64decode(data)) for data in _COMMAND.findall(page)]


def object_paths(page: str) -> set[str]:
    """Paths of the objects a page draws (``/meshcat/optraj/scene/ball``, ...)."""
    return {c["path"] for c in page_commands(page) if c["type"] == "set_object"}


def animated_paths(page: str) -> set[str]:
    """Paths of the nodes the page's animation moves."""
    return {
        animation["path"]
        for c in page_commands(page)
        if c["type"] == "set_animation"
        for animation in c["animations"]
    }
