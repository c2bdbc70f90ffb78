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
from optraj.problems.scenes import pick_and_place_scene, pool_table
from optraj.validation import as_number

__all__ = ["block_clearance_scene", "ece486_paddle_strike", "sawyer_pool_shot", "youbot_two_blocks"]

#: Clearance every robot shape keeps from every block it does not hold [m] (issue 37).
BLOCK_CLEARANCE = 0.02
#: Clearance between Sawyer's arm or cue and the pool table [m] (issue 37: 1 cm).
TABLE_CLEARANCE = 0.01
#: The cue's default angle below the horizontal over a table [deg]. Sawyer's wrist capsules
#: lie on the cue axis up to 0.325 m behind the tip, 3.5 cm in radius: a level cue at the ball's
#: height holds them 6 mm into the cloth, and a tilt of asin(16.4 mm / 0.325 m) = 2.9 deg lifts
#: them 1 cm clear; 4 deg leaves room for the entry and exit of the strike line. The ball
#: leaves along the heading all the same (the cloth takes the downward push).
CUE_ELEVATION = 4.0
#: Steepest cue accepted [deg]: a steeper cue drives the ball into the cloth (a masse shot).
MAX_ELEVATION = 60.0
#: Sawyer's home with the shoulder (right_j1) raised to -1.35 rad [rad]: the cue tip 62 mm
#: above the cloth of the default shot's ball, 12.6 mm above that of the benchmarks' highest
#: ball (z = 0); home holds it 5.7 mm below the default shot's cloth.
SAWYER_CUE_UP = (0.0, -1.35, 0.0, 2.18, 0.0, 0.57, 3.3161)
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
    *,
    with_table: bool = False,
    elevation_deg: float | None = None,
    margin: float = TABLE_CLEARANCE,
) -> PoolStrike:
    """A cue shot on Sawyer, ball ahead of the robot on a table below the base.

    Without the table the cue is level and the arm starts at Sawyer's home. With it
    (:func:`problems.pool_table` under the ball, every pair but the cue and the ball kept
    ``margin`` apart) the cue's butt is raised by :data:`CUE_ELEVATION` (a level cue holds
    Sawyer's wrist on the cloth) and the arm starts at :data:`SAWYER_CUE_UP`, the cue above
    the cushions.

    Args:
        speed: Cue speed [m/s].
        ball: Ball centre in the base frame [m].
        heading_deg: Shot direction from +x about +z [deg].
        with_table: Give the problem its pool table.
        elevation_deg: Angle of the cue below the horizontal, butt up [deg], in [0, 60);
            None: :data:`CUE_ELEVATION` with the table, 0 without.
        margin: Least distance between the arm or cue and the table [m] (with the table).

    Raises:
        InvalidInputError: A heading or elevation that is not a finite number, bad speed,
            ball or margin, or ``with_table`` not a bool.
        CollisionError: With the table, the cue is in it at contact.
    """
    if not isinstance(with_table, bool):
        raise InvalidInputError(f"with_table must be a bool, got {with_table!r}", name="with_table")
    heading = np.radians(as_number(heading_deg, "heading_deg", "deg"))
    default = CUE_ELEVATION if with_table else 0.0
    elevation = np.radians(
        default
        if elevation_deg is None
        else as_number(elevation_deg, "elevation_deg", "deg", minimum=0.0, maximum=MAX_ELEVATION)
    )
    down = np.cos(elevation)
    direction = (down * np.cos(heading), down * np.sin(heading), -np.sin(elevation))
    robot = robots.load("sawyer")
    shot = PoolStrike(robot, ball=_array(ball), direction=_array(direction), speed=speed)
    if not with_table:
        return shot
    clearance = as_number(margin, "margin", "m", minimum=0.0, maximum=1.0)
    return dataclasses.replace(
        shot,
        q_start=_array(SAWYER_CUE_UP),
        scene=pool_table(shot.ball, shot.ball_radius, margin=clearance),
    )
