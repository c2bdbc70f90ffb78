"""Ready-made scenes from the tasks' own numbers: the pool table, the youBot's blocks, a floor.

* :func:`pool_table`: the cloth at the ball's bottom, four cushions and the ball, placed as
  the MuJoCo scene of :mod:`optraj.physics.scene` places them (the numbers live here), and
  Sawyer's floor; the cue tip may touch the ball.
* :func:`pick_and_place_scene`: the blocks of a :class:`PickAndPlace` where they are gripped,
  each carried by the tool frame from its grasp to its release, and the work surface they
  stand on; the gripper may touch a block from its descent onto it to its release.
  The pile is the spot on the work surface where the blocks are put (no solid of its own):
  the placed blocks are the pile.
* :func:`floor`: a half-space below a robot's base.

Example::

    shot = dataclasses.replace(shot, scene=pool_table(shot.ball, shot.ball_radius))
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from optraj.problems.pick_and_place import PickAndPlace
from optraj.problems.pool_strike import POOL_BALL_RADIUS
from optraj.problems.scene import AllowedPair, Attachment, Scene
from optraj.problems.scene_shapes import Box, Plane, Sphere, translation
from optraj.validation import as_number, as_vector

__all__ = [
    "BALL_FROM_NEAR_END",
    "BLOCK_HALF_WIDTH",
    "CUSHION_HEIGHT",
    "SAWYER_FLOOR",
    "TABLE_SIZE",
    "YOUBOT_FLOOR",
    "floor",
    "pick_and_place_scene",
    "pool_table",
]

#: Playing surface of a 9-ft pool table [m] (WPA: 100 x 50 in).
TABLE_SIZE = (2.54, 1.27)
#: The table is placed with the ball this far in from the near cushion [m], centred across:
#: on the head string, a quarter of the playing length from the head cushion (WPA), where a
#: break is played from. Nearer, the wrist of an arm behind the cue reaches over the cushion.
BALL_FROM_NEAR_END = 0.635
#: Cushion nose height above the cloth [m] (WPA: 63.5 % of the ball diameter).
CUSHION_HEIGHT = 0.0363
#: The cloth's slab and the cushions' width [m], and how far the cloth runs under the
#: cushions [m] (the MuJoCo scene's).
CLOTH_THICKNESS = 0.04
CUSHION_WIDTH = 0.1
CLOTH_OVERHANG = 0.1
#: Height of the floor in Sawyer's base frame [m]: the base sits about 0.914 m above the floor
#: on its pedestal (robots.md).
SAWYER_FLOOR = -0.914
#: Height of the floor in the youBot's arm_link_0 frame [m]: arm_link_0 is 0.046 m above
#: base_link, base_link 0.0815 m above the floor (robots.md).
YOUBOT_FLOOR = -(0.046 + 0.0815)
#: Half the width of a youBot block across the gripper [m]: our choice, a 2 cm block fits
#: between the fingers opened 2 x 0.0115 m (robots.md) with 1.5 mm to spare on each side.
BLOCK_HALF_WIDTH = 0.01


def floor(height: float, name: str = "floor") -> Plane:
    """The half-space below ``height`` [m] (world z), e.g. :data:`SAWYER_FLOOR`."""
    z = as_number(height, "height", "m")
    return Plane(name, point=np.array([0.0, 0.0, z]), normal=np.array([0.0, 0.0, 1.0]))


def pool_table(
    ball: ArrayLike,
    ball_radius: float = POOL_BALL_RADIUS,
    *,
    margin: float = 0.0,
    floor_height: float | None = SAWYER_FLOOR,
    near_end: float = BALL_FROM_NEAR_END,
) -> Scene:
    """A pool table under the ball, with its cushions, the ball and the floor.

    Objects: ``cloth`` (a slab whose top is the ball's bottom), ``cushion_far``,
    ``cushion_near``, ``cushion_left``, ``cushion_right``, ``ball``, ``floor``. The near
    cushion is ``near_end`` behind the ball along x, the table centred across on the ball
    (the MuJoCo scene's placement by default). The cue (``tool/*``) may touch ``ball``: the
    tip strikes it, and the shaft follows through where it was.

    A horizontal cue at the ball's height cannot keep Sawyer's wrist clear of the cloth (its
    capsules, 3 to 3.5 cm in radius, lie on the cue axis 2.9 cm above the cloth): raise the
    cue's butt (``problems.sawyer_pool_shot(with_table=True)`` tilts it by
    :data:`problems.scenarios.CUE_ELEVATION`).

    Args:
        ball: Ball centre [m], shape (3,).
        ball_radius: [m].
        margin: Clearance every other pair must keep [m].
        floor_height: Floor height [m]; None for no floor.
        near_end: Distance from the ball to the near cushion's face along x [m], >= 0.
    """
    centre = as_vector(ball, "ball", 3)
    radius = as_number(ball_radius, "ball_radius", "m", minimum=0.0)
    length, width = TABLE_SIZE
    x0 = float(centre[0]) - as_number(near_end, "near_end", "m", minimum=0.0)
    y0 = float(centre[1])
    top = float(centre[2]) - radius
    half_cloth = CLOTH_THICKNESS / 2
    objects: list[Box | Plane | Sphere] = [
        Box(
            "cloth",
            np.array([length / 2 + CLOTH_OVERHANG, width / 2 + CLOTH_OVERHANG, half_cloth]),
            translation((x0 + length / 2, y0, top - half_cloth)),
        )
    ]
    w = CUSHION_WIDTH / 2
    rails = {
        "cushion_far": ((x0 + length + w, y0), (w, width / 2 + CLOTH_OVERHANG)),
        "cushion_near": ((x0 - w, y0), (w, width / 2 + CLOTH_OVERHANG)),
        "cushion_left": ((x0 + length / 2, y0 + width / 2 + w), (length / 2 + CLOTH_OVERHANG, w)),
        "cushion_right": ((x0 + length / 2, y0 - width / 2 - w), (length / 2 + CLOTH_OVERHANG, w)),
    }
    half = CUSHION_HEIGHT / 2
    for name, (xy, size) in rails.items():
        objects.append(Box(name, np.array([*size, half]), translation((*xy, top + half))))
    if radius > 0.0:
        objects.append(Sphere("ball", radius, translation(centre)))
    if floor_height is not None:
        objects.append(floor(floor_height))
    return Scene(tuple(objects), allowed=(AllowedPair("tool/*", "ball"),), margin=margin)


def pick_and_place_scene(
    problem: PickAndPlace,
    *,
    margin: float = 0.0,
    block_half_width: float = BLOCK_HALF_WIDTH,
    floor_height: float | None = None,
) -> Scene:
    """The blocks of ``problem`` where they are gripped, the work surface, and what may touch.

    Block k (``block_<k>``) has the problem's block height, a square footprint of side
    ``2 * block_half_width`` turned as the gripper grips it (its axes those of the tool frame
    at ``q_pick[k]``), and rides with the tool frame from the start of phase ``grasp_<k>`` to
    the end of ``release_<k>`` (the phases of ``planners.PickAndPlacePlanner``). The gripper
    (``tool/*``) may touch it from the start of ``descend_<k>`` to the end of ``release_<k>``;
    the way out after the release is checked (the gripper must leave the block as it came).
    ``work_surface`` is the plane under the lowest block. The blocks may touch each other and
    the work surface (a carried block is checked against the floor only).

    Args:
        problem: The pick-and-place problem.
        margin: Clearance every other pair must keep [m].
        block_half_width: Half a block's side across the gripper [m].
        floor_height: Floor height [m] (e.g. :data:`YOUBOT_FLOOR`); None for no floor.
    """
    half_width = as_number(block_half_width, "block_half_width", "m", minimum=1e-4)
    robot = problem.robot
    tool = robot.model.frames[robot.tool_frame_id].name
    half_height = float(problem.block_height) / 2
    picks = np.asarray(problem.picks)
    objects: list[Box | Plane] = []
    attachments = []
    allowed = []
    for k in range(problem.count):
        pose = robot.tool_pose(np.asarray(problem.q_pick)[k])
        pose[:3, 3] = picks[k]
        name = f"block_{k}"
        objects.append(Box(name, np.array([half_width, half_width, half_height]), pose))
        attachments.append(Attachment(name, tool, f"grasp_{k}", f"release_{k}"))
        phases = ("descend", "grasp", "back_to_interim", "turn_to_target", "release")
        during = tuple(f"{p}_{k}" for p in phases)
        allowed.append(AllowedPair("tool/*", name, during))
    lowest = min(float(np.min(picks[:, 2])), float(np.asarray(problem.pile)[2]))
    objects.append(Plane("work_surface", point=np.array([0.0, 0.0, lowest - half_height])))
    if floor_height is not None:
        objects.append(floor(floor_height))
    # Blocks stand on the surface and on each other where they are picked and put.
    allowed += [AllowedPair("block_*", "block_*"), AllowedPair("block_*", "work_surface")]
    return Scene(tuple(objects), tuple(attachments), tuple(allowed), margin=margin)
