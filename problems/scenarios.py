"""Ready-made problems: the course documents' set-ups and a few reusable test cases."""

from __future__ import annotations

import dataclasses
from typing import cast

import numpy as np
from numpy.typing import NDArray

from optraj import robots
from optraj.errors import InvalidInputError
from optraj.problems.paddle_strike import PaddleStrike
from optraj.problems.pick_and_place import RETREAT, PickAndPlace
from optraj.problems.pool_strike import PoolStrike
from optraj.problems.scene import AllowedPair, Scene
from optraj.problems.scenes import pick_and_place_scene
from optraj.validation import as_number

__all__ = ["block_clearance_scene", "ece486_paddle_strike", "sawyer_pool_shot", "youbot_two_blocks"]

#: Clearance every robot shape keeps from every block it does not hold [m] (issue 37).
BLOCK_CLEARANCE = 0.02
#: Name patterns of the robot's own shape pairs (robots.collision: links, then the tool's).
_ROBOT_SELF = (("link_*", "link_*"), ("link_*", "tool/*"), ("tool/*", "tool/*"))

#: The four workspace corners the ECE486 paddle task tabulates (ball centres) [m].
ECE486_PADDLE_BALLS = ((1.1, 0.8, 0.7), (1.1, -0.8, 0.7), (1.1, -0.8, -0.1), (1.1, 0.8, -0.1))


def _array(value: object) -> NDArray[np.float64]:
    """``value`` as the problems' array fields are typed; the problem checks and converts it."""
    return cast(NDArray[np.float64], value)


def ece486_paddle_strike(ball: tuple[float, float, float] = ECE486_PADDLE_BALLS[0]) -> PaddleStrike:
    """The ECE486 paddle4 task: from home, reach the ball at rest in 2 s (C = 0)."""
    return PaddleStrike(robots.load("paddle4"), ball=_array(ball))


def youbot_two_blocks(*, with_scene: bool = False, margin: float = 0.0) -> PickAndPlace:
    """Two 3 cm blocks, one on each side in front of the youBot, stacked on a pile.

    Positions are in arm_link_0 coordinates: the blocks lie 3 cm below the arm's base plane,
    where a top-down grip is within reach (our set-up in the spirit of Coursework 3).

    Args:
        with_scene: Give the problem its scene (:func:`problems.pick_and_place_scene`: the
            blocks, the work surface, the gripper allowed on the block it carries) and the
            interim pose chosen from it (:attr:`PickAndPlace.q_interim`); the blocks are
            turned as the gripper grips them in that problem. False: no scene, the interim
            pose is the start pose.
        margin: The scene's clearance for every other pair [m] (with ``with_scene``).

    Raises:
        InvalidInputError: ``with_scene`` not a bool, or a margin that is not a finite
            number >= 0.
    """
    if not isinstance(with_scene, bool):
        raise InvalidInputError(f"with_scene must be a bool, got {with_scene!r}", name="with_scene")
    problem = PickAndPlace(
        robots.load("youbot"),
        picks=_array([(0.22, 0.10, -0.03), (0.22, -0.10, -0.03)]),
        pile=_array((0.12, 0.14, -0.03)),
    )
    if not with_scene:
        return problem
    # The scene sets the interim pose, the interim pose the grips (IK from it), and the grips
    # turn the blocks: the second scene is the first with the blocks turned as gripped.
    first = pick_and_place_scene(problem, margin=margin)
    problem = dataclasses.replace(problem, scene=first, q_interim=_array(None))
    return dataclasses.replace(problem, scene=pick_and_place_scene(problem, margin=margin))


def block_clearance_scene(problem: PickAndPlace, margin: float = BLOCK_CLEARANCE) -> Scene:
    """The blocks of a pick-and-place scene alone, for the clearance the robot keeps from them.

    The problem's scene (its :func:`problems.pick_and_place_scene`) says what may not touch
    at all; this one says how far the robot stays from the blocks: every robot shape keeps
    ``margin`` from every block, except the gripper (``tool/*``) from block k while it goes
    down onto it, holds it, puts it down and rises from it (``descend_<k>`` to
    ``retreat_<k>``), and from the block under it on the pile while it puts block k there
    and rises (``release_<k>``, ``retreat_<k>``). The work surface and the robot's own
    links against each other are left to the problem's scene; blocks may touch blocks.

    Args:
        problem: A pick-and-place problem with its scene.
        margin: The clearance [m], >= 0.

    Raises:
        InvalidInputError: A problem without a scene, or a bad margin.
    """
    if problem.scene is None:
        raise InvalidInputError(
            "block_clearance_scene needs a problem with a scene (pick_and_place_scene)",
            name="problem",
        )
    blocks = tuple(item for item in problem.scene.objects if item.name.startswith("block_"))
    held = ("descend", "grasp", "back_to_interim", "turn_to_target", "release", RETREAT)
    # The robot against itself is the problem scene's business; blocks may touch blocks.
    allowed = [AllowedPair(a, b) for a, b in _ROBOT_SELF] + [AllowedPair("block_*", "block_*")]
    for k in range(problem.count):
        allowed.append(AllowedPair("tool/*", f"block_{k}", tuple(f"{p}_{k}" for p in held)))
        if k > 0:
            under = (f"release_{k}", f"{RETREAT}_{k}")
            allowed.append(AllowedPair("tool/*", f"block_{k - 1}", under))
    attachments = tuple(a for a in problem.scene.attachments if a.object.startswith("block_"))
    return Scene(blocks, attachments, tuple(allowed), margin=margin)


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
