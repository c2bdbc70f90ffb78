"""What each robot stands on: the floor and a pedestal, at the real heights.

Heights in the robot's base frame [m]:

* Sawyer: its base sits about 0.914 m above the floor on its pedestal (robots.md).
* youBot: the blocks of the pick-and-place set-up lie on a work surface 3 cm below the arm's
  base plane (``problems.youbot_two_blocks``: block centres at z = -0.03, 3 cm blocks), and the
  arm stands on a plinth on that surface.
* paddle4: its lift starts at z = 0 and the paddle reaches down to z = -0.275 (paddle centre
  0.2 m below the joint-4 axis, a 75 mm blade), so the floor is a little lower still and a
  plinth carries the lift.
* Other robots stand on the floor (z = 0).

A task may lower the floor further (:func:`optraj.viz.scene.build_scene` keeps every tool
point and object above it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from optraj.robots import Robot
from optraj.viz.shapes import Shape, box, segment

__all__ = ["MOUNTS", "Mount", "mount_of", "mount_shapes"]

FLOOR_COLOUR = (0.82, 0.82, 0.80, 1.0)
PEDESTAL_COLOUR = (0.30, 0.30, 0.33, 1.0)
#: Floor tile size [m] and thickness [m].
FLOOR_SIZE = 5.0
FLOOR_THICKNESS = 0.02


@dataclass(frozen=True)
class Mount:
    """Floor height and pedestal of a robot [m], in its base frame.

    Attributes:
        floor: Height of the floor (or work surface) [m].
        pedestal: Radius of the pedestal from the floor to the base [m]; 0 for none.
    """

    floor: float
    pedestal: float


MOUNTS = {
    "sawyer": Mount(floor=-0.914, pedestal=0.12),
    "youbot": Mount(floor=-0.045, pedestal=0.07),
    "paddle4": Mount(floor=-0.35, pedestal=0.06),
}
DEFAULT_MOUNT = Mount(floor=0.0, pedestal=0.0)


def mount_of(robot: Robot) -> Mount:
    """The mount of a robot (by name; the floor at its base for the others)."""
    return MOUNTS.get(robot.name, DEFAULT_MOUNT)


def mount_shapes(robot: Robot, centre: np.ndarray, floor: float) -> list[Shape]:
    """The floor at height ``floor`` [m] and the robot's pedestal from it up to the base.

    The floor tile is centred under ``centre`` [m] (x, y used).
    """
    mount = mount_of(robot)
    shapes = [
        box(
            "floor",
            (float(centre[0]), float(centre[1]), floor - FLOOR_THICKNESS / 2),
            (FLOOR_SIZE, FLOOR_SIZE, FLOOR_THICKNESS),
            FLOOR_COLOUR,
        )
    ]
    if mount.pedestal > 0.0:
        pedestal = segment(
            "pedestal", (0.0, 0.0, floor), (0.0, 0.0, 0.0), mount.pedestal, PEDESTAL_COLOUR
        )
        if pedestal is not None:
            shapes.append(pedestal)
    return shapes
