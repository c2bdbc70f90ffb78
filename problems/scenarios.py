"""Ready-made problems: the course documents' set-ups and a few reusable test cases."""

from __future__ import annotations

from typing import cast

import numpy as np
from numpy.typing import NDArray

from optraj import robots
from optraj.problems.paddle_strike import PaddleStrike
from optraj.problems.pick_and_place import PickAndPlace
from optraj.problems.pool_strike import PoolStrike
from optraj.validation import as_number

__all__ = ["ece486_paddle_strike", "sawyer_pool_shot", "youbot_two_blocks"]

#: The four workspace corners the ECE486 paddle task tabulates (ball centres) [m].
ECE486_PADDLE_BALLS = ((1.1, 0.8, 0.7), (1.1, -0.8, 0.7), (1.1, -0.8, -0.1), (1.1, 0.8, -0.1))


def _array(value: object) -> NDArray[np.float64]:
    """``value`` as the problems' array fields are typed; the problem checks and converts it."""
    return cast(NDArray[np.float64], value)


def ece486_paddle_strike(ball: tuple[float, float, float] = ECE486_PADDLE_BALLS[0]) -> PaddleStrike:
    """The ECE486 paddle4 task: from home, reach the ball at rest in 2 s (C = 0)."""
    return PaddleStrike(robots.load("paddle4"), ball=_array(ball))


def youbot_two_blocks() -> PickAndPlace:
    """Two 3 cm blocks, one on each side in front of the youBot, stacked on a pile.

    Positions are in arm_link_0 coordinates: the blocks lie 3 cm below the arm's base plane,
    where a top-down grip is within reach (our set-up in the spirit of Coursework 3).
    """
    return PickAndPlace(
        robots.load("youbot"),
        picks=_array([(0.22, 0.10, -0.03), (0.22, -0.10, -0.03)]),
        pile=_array((0.12, 0.14, -0.03)),
    )


def sawyer_pool_shot(
    speed: float = 1.0,
    ball: tuple[float, float, float] = (0.75, 0.15, -0.05),
    heading_deg: float = 0.0,
) -> PoolStrike:
    """A horizontal cue shot on Sawyer, ball ahead of the robot on a table below the base.

    Args:
        speed: Cue speed [m/s].
        ball: Ball centre in the base frame [m].
        heading_deg: Shot direction from +x about +z [deg].

    Raises:
        InvalidInputError: A heading that is not a finite number, or bad speed or ball.
    """
    heading = np.radians(as_number(heading_deg, "heading_deg", "deg"))
    return PoolStrike(
        robots.load("sawyer"),
        ball=_array(ball),
        direction=_array((np.cos(heading), np.sin(heading), 0.0)),
        speed=speed,
    )
