r"""Clearance of a pool strike: spheres on the arm and cue kept above the cloth, off the ball.

:class:`Clearance` is the setting of :class:`planners.ocp.optimal_control.OptimalControl`
(``clearance=Clearance()`` by default, None for none); :func:`pool_spheres` places the
spheres on a robot: the wrist (on request), the cue butt, the middle of the cue and the cue
tip, each a fixed point in a frame of the robot. The rows that keep them clear are
:class:`planners.ocp.task_rows.clearance.ClearanceRows`.

The cloth is the plane :math:`z = z_{ball} - r_{ball}` of the base frame (the ball rests on
it). A sphere of centre :math:`c` and radius :math:`r` is clear of it when
:math:`c_z \ge z_{cloth} + r + m`, :math:`m` the margin. The cue tip stays behind the ball on
the approach: the centre of the tip sphere keeps :math:`d \cdot (c - b) \le -(r_{ball} + r_{tip}
+ g)`, :math:`d` the shot direction, :math:`b` the ball centre and :math:`g` the ball gap, a
half-space (linear in :math:`c`, so the rows stay smooth and a tip that moves fast between two
nodes cannot pass through the ball unseen, as it could with a distance row at the nodes).

Example::

    spheres = pool_spheres(robots.load("sawyer"))
    [s.name for s in spheres]  # ['wrist', 'cue butt', 'cue middle', 'cue tip']
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.problems import PoolStrike
from optraj.robots import Robot
from optraj.robots.loading import SAWYER_CUE_RADIUS
from optraj.validation import as_flag, as_number

__all__ = [
    "BALL_GAP",
    "CLOTH_MARGIN",
    "NODE_EXTRA",
    "TIP_RADIUS",
    "WRIST_RADIUS",
    "Clearance",
    "Sphere",
    "ball_offset",
    "checked_clearance",
    "pool_spheres",
    "sphere_centres",
    "sphere_floors",
]

FloatArray = NDArray[np.float64]

#: Least distance between a sphere and the cloth [m] (issue 37: 1 cm).
CLOTH_MARGIN = 0.01
#: Least distance between the cue tip and the ball's surface on the approach [m].
BALL_GAP = 0.01
#: Extra height the rows keep at the nodes [m], for the dips of the motion between them:
#: on 20 seeded pool shots at 1 kHz a sphere dipped at most 2.2 mm below its height at the
#: nodes (``tests/planners/ocp/test_clearance.py`` checks 1 cm at 1 kHz).
NODE_EXTRA = 0.003
#: Cue tip radius [m] (the MuJoCo scene's rounded tip, ``physics.scene.CUE_TIP_RADIUS``).
TIP_RADIUS = 0.006
#: Radius of the wrist sphere [m]. Our choice: about half the width of Sawyer's wrist
#: housing (about 90 mm); the URDF carries no collision geometry.
WRIST_RADIUS = 0.045
#: Largest margin, gap or extra height accepted [m].
MAX_CLEARANCE = 1.0


@dataclass(frozen=True)
class Clearance:
    """How far the arm and cue keep from the cloth and the ball in a pool strike.

    Attributes:
        margin: Least distance of every sphere from the cloth [m] (the cue tip's in the
            strike window excepted: it strikes the ball there).
        ball_gap: Least distance of the cue tip from the ball's surface on the approach [m],
            at most half the run-up (the approach ends at the strike line's entry).
        node_extra: Extra height kept at the grid nodes for the motion between them [m].
        wrist: Whether a sphere of :data:`WRIST_RADIUS` at the wrist is kept clear too. Off
            by default: the contact configuration is chosen without it, and from the chosen
            one IPOPT finds half of the seeded benchmark shots infeasible with it (the
            wrist of the time-optimal plans passes below the cloth).

    Raises:
        InvalidInputError: A value that is not a finite number in [0, 1] m.
    """

    margin: float = CLOTH_MARGIN
    ball_gap: float = BALL_GAP
    node_extra: float = NODE_EXTRA
    wrist: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "wrist", as_flag(self.wrist, "wrist"))
        for name in ("margin", "ball_gap", "node_extra"):
            value = as_number(getattr(self, name), name, "m", minimum=0.0, maximum=MAX_CLEARANCE)
            object.__setattr__(self, name, value)


def checked_clearance(value: object) -> Clearance | None:
    """``value`` checked to be a :class:`Clearance` or None (no clearance rows)."""
    if value is not None and not isinstance(value, Clearance):
        raise InvalidInputError(
            f"clearance must be a planners.ocp.clearance.Clearance or None, got {value!r}",
            name="clearance",
        )
    return value


@dataclass(frozen=True)
class Sphere:
    """A sphere fixed to a frame of the robot.

    Attributes:
        name: What it covers.
        frame: The frame it moves with.
        offset: Its centre in that frame [m], 3 numbers.
        radius: [m].
    """

    name: str
    frame: str
    offset: tuple[float, float, float]
    radius: float


def pool_spheres(robot: Robot, wrist: bool = True) -> tuple[Sphere, ...]:
    """The wrist (when ``wrist``), cue butt, cue middle and cue tip spheres of a cue robot.

    The cue runs along the tool z axis from the tool frame's parent frame (the flange: the
    cue butt) to the tool frame (the front of the tip). The tip sphere's centre is
    :data:`TIP_RADIUS` behind the front; the butt and middle spheres have the cue's radius
    (``robots.loading.SAWYER_CUE_RADIUS``); the wrist sphere (:data:`WRIST_RADIUS`) sits at
    the axis of the joint before the last one (Sawyer's ``right_j5``), off the cue axis.
    """
    model = robot.model
    tool = model.frames[model.getFrameId(robot.tool_frame)]
    flange = model.frames[tool.parentFrame]
    # The flange's origin in the tool frame: the cue's length back along the tool z axis.
    length = float(np.linalg.norm(flange.placement.actInv(tool.placement).translation))
    wrist_joint = model.parents[tool.parentJoint]
    wrist_sphere = Sphere("wrist", str(model.names[wrist_joint]), (0.0, 0.0, 0.0), WRIST_RADIUS)
    return (
        *((wrist_sphere,) if wrist else ()),
        Sphere("cue butt", robot.tool_frame, (0.0, 0.0, -length), SAWYER_CUE_RADIUS),
        Sphere("cue middle", robot.tool_frame, (0.0, 0.0, -0.5 * length), SAWYER_CUE_RADIUS),
        Sphere("cue tip", robot.tool_frame, (0.0, 0.0, -TIP_RADIUS), TIP_RADIUS),
    )


def sphere_centres(robot: Robot, spheres: Sequence[Sphere], q: FloatArray) -> FloatArray:
    """The spheres' centres in the base frame [m], shape (m, len(spheres), 3).

    Args:
        robot: The robot.
        spheres: The spheres.
        q: Joint positions [rad or m], shape (m, n).
    """
    q = np.atleast_2d(np.asarray(q, dtype=float))
    out = np.empty((q.shape[0], len(spheres), 3))
    for i, sphere in enumerate(spheres):
        poses = robot.frame_pose(q, sphere.frame).reshape(-1, 4, 4)
        out[:, i] = poses[:, :3, 3] + poses[:, :3, :3] @ np.asarray(sphere.offset)
    return out


def sphere_floors(
    problem: PoolStrike, spheres: Sequence[Sphere], clearance: Clearance
) -> FloatArray:
    """The lowest height of each sphere's centre the rows allow [m], shape (len(spheres),).

    The cloth plus the sphere's radius, the margin and the node extra; a sphere that starts
    lower (a start pose in the table) is held no lower than it starts, as no plan can lift
    it at its first node.
    """
    cloth = float(problem.ball[2]) - float(problem.ball_radius)
    radii = np.array([sphere.radius for sphere in spheres])
    wanted = cloth + radii + clearance.margin + clearance.node_extra
    start = sphere_centres(problem.robot, spheres, problem.q_start)[0, :, 2]
    return np.minimum(wanted, start)


def ball_offset(problem: PoolStrike, tip: Sphere, clearance: Clearance) -> float:
    """How far behind the ball's centre along the shot the tip sphere's centre stays [m].

    Ball radius, tip radius and the ball gap (at most half the run-up, so that the
    strike line's entry keeps clear); less when the start is nearer, as for the floors.
    """
    gap = min(clearance.ball_gap + clearance.node_extra, 0.5 * float(problem.run_up))
    wanted = float(problem.ball_radius) + tip.radius + gap
    centre = sphere_centres(problem.robot, [tip], problem.q_start)[0, 0]
    behind = -float(np.dot(np.asarray(problem.direction), centre - np.asarray(problem.ball)))
    return min(wanted, behind)
