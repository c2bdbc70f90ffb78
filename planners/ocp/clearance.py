r"""Clearance of a pool strike: spheres on the arm and cue kept above the cloth, off the ball.

:class:`Clearance` is the setting of :class:`planners.ocp.optimal_control.OptimalControl`
(``clearance=Clearance()`` by default, None for none); :func:`pool_spheres` places the
spheres on a robot: the wrist (the ends and middles of the collision capsules of
:data:`WRIST_LINKS`, :mod:`robots.collision`; with a scene by default), the cue butt, the middle
of the cue and the cue tip, each a fixed point in a frame of the robot. The rows that keep them
clear are :class:`planners.ocp.task_rows.clearance.ClearanceRows`.

The cloth is the plane :math:`z = z_{ball} - r_{ball}` of the base frame (the ball rests on
it). A sphere of centre :math:`c` and radius :math:`r` is clear of it when
:math:`c_z \ge z_{cloth} + r + m`, :math:`m` the margin. A capsule's lowest point above a
plane is at one of its ends, so the spheres at a capsule's ends keep all of it clear. With a
scene holding :func:`problems.pool_table`'s near cushion (``cushion_near``, the table's
end behind the ball along x), the floor rises smoothly by the cushion's height over it:
:math:`f(c) = z_{cloth} + r + m + h\,\sigma((x_n + r + m + 2w - c_x) / w)`, :math:`x_n` the
cushion's face, :math:`h` its height, :math:`\sigma(u) = (1 + \tanh u) / 2` and
:math:`w` :data:`STEP_WIDTH` (the floor is 98 % risen where a sphere would touch the face).

The cue tip stays behind the ball on the approach: the centre of the tip sphere keeps :math:`d
\cdot (c - b) \le -(r_{ball} + r_{tip} + g)`, :math:`d` the shot direction, :math:`b` the ball
centre and :math:`g` the ball gap, a half-space (linear in :math:`c`, so the rows stay smooth
and a tip that moves fast between two nodes cannot pass through the ball unseen, as it could
with a distance row at the nodes).

Example::

    spheres = pool_spheres(robots.load("sawyer"))
    [s.name for s in spheres][-4:]  # ['link_tool end 1', 'cue butt', 'cue middle', 'cue tip']
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import coal
import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.problems import PoolStrike
from optraj.problems.scene_shapes import Box
from optraj.robots import Robot
from optraj.robots.collision import collision_geometry, collision_model
from optraj.robots.loading import SAWYER_CUE_RADIUS
from optraj.validation import as_flag, as_number

__all__ = [
    "BALL_GAP",
    "CLOTH_MARGIN",
    "NODE_EXTRA",
    "SHOULDER_LINKS",
    "STEP_WIDTH",
    "TIP_RADIUS",
    "WRIST_LINKS",
    "Clearance",
    "Sphere",
    "ball_offset",
    "checked_clearance",
    "cushion_step",
    "pool_spheres",
    "self_pairs",
    "shoulder_spheres",
    "sphere_centres",
    "sphere_floors",
]

FloatArray = NDArray[np.float64]

#: Least distance between a sphere and the cloth [m] (issue 37: 1 cm).
CLOTH_MARGIN = 0.01
#: Least distance between the cue tip and the ball's surface on the approach [m].
BALL_GAP = 0.01
#: Extra height the rows keep at the nodes [m], for the dips of the motion between them: on
#: 20 seeded level shots at 1 kHz a sphere dipped at most 2.2 mm below its height at the nodes,
#: on shots over a table (a raised cue, an arm starting cue up) the tip 4.1 mm
#: (``tests/planners/ocp/test_clearance.py`` and ``test_pool_table.py`` check 1 cm).
NODE_EXTRA = 0.005
#: Cue tip radius [m] (the MuJoCo scene's rounded tip, ``physics.scene.CUE_TIP_RADIUS``).
TIP_RADIUS = 0.006
#: The collision capsules (:mod:`robots.collision`) of the wrist: the links that come near
#: the cloth with the cue (on 20 seeded shots over a table, link_6 dipped 25 mm into it and 54
#: mm into the near cushion when only the cue was kept clear).
WRIST_LINKS = ("link_5", "link_6", "link_7", "link_tool")
#: The collision shapes (:mod:`robots.collision`) of the shoulder and upper arm, which a
#: fast swing can fold the wrist or the cue into (on 20 seeded shots over a table, 8 plans
#: did so, into link_2 or link_3; kept from those, one folded the tip into link_4).
SHOULDER_LINKS = ("link_1", "link_2", "link_3", "link_4")
#: Width of the smooth rise of the floor towards the near cushion [m]: it rises over 4 widths
#: (2 % to 98 %), about the 5 cm a fast swing of the cue carries a sphere between two nodes
#: (with 5 mm, spheres dipped 25 mm into the cushion between nodes).
STEP_WIDTH = 0.0125
#: The near cushion of :func:`problems.pool_table`, by name.
NEAR_CUSHION = "cushion_near"
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
        wrist: Whether the wrist's capsules (:data:`WRIST_LINKS`) are kept clear too. None
            (the default): when the problem has a scene, whose contact choice keeps them
            clear at the strike line. Without one the cue may be level, and a level cue holds
            Sawyer's wrist below the cloth (``problems.sawyer_pool_shot(with_table=True)``
            tilts it).
        shoulder: Whether the wrist's and the cue's spheres are kept ``margin`` (plus the
            node extra) from the shoulder's (:func:`shoulder_spheres`), so that a fast swing
            does not fold the arm through itself. None (the default): as ``wrist``. The rows
            are not convex: on 20 seeded shots over a table IPOPT took 100 to 250 iterations
            instead of about 45, about 7 times the solve time.

    Raises:
        InvalidInputError: A value that is not a finite number in [0, 1] m, or a flag that
            is not a bool or None.
    """

    margin: float = CLOTH_MARGIN
    ball_gap: float = BALL_GAP
    node_extra: float = NODE_EXTRA
    wrist: bool | None = None
    shoulder: bool | None = None

    def __post_init__(self) -> None:
        for name in ("wrist", "shoulder"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, as_flag(getattr(self, name), name))
        for name in ("margin", "ball_gap", "node_extra"):
            value = as_number(getattr(self, name), name, "m", minimum=0.0, maximum=MAX_CLEARANCE)
            object.__setattr__(self, name, value)

    def keeps_wrist(self, problem: PoolStrike) -> bool:
        """Whether the wrist's capsules are kept clear in ``problem``."""
        return problem.scene is not None if self.wrist is None else bool(self.wrist)

    def keeps_shoulder(self, problem: PoolStrike) -> bool:
        """Whether the wrist and the cue are kept apart from the shoulder in ``problem``."""
        return self.keeps_wrist(problem) if self.shoulder is None else bool(self.shoulder)


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
    """The wrist's (when ``wrist``), cue butt, cue middle and cue tip spheres of a cue robot.

    The cue runs along the tool z axis from the tool frame's parent frame (the flange: the
    cue butt) to the tool frame (the front of the tip). The tip sphere's centre is
    :data:`TIP_RADIUS` behind the front; the butt and middle spheres have the cue's radius
    (``robots.loading.SAWYER_CUE_RADIUS``). The wrist's spheres (:func:`wrist_spheres`) come
    first, the cue tip last.
    """
    model = robot.model
    tool = model.frames[model.getFrameId(robot.tool_frame)]
    flange = model.frames[tool.parentFrame]
    # The flange's origin in the tool frame: the cue's length back along the tool z axis.
    length = float(np.linalg.norm(flange.placement.actInv(tool.placement).translation))
    return (
        *(wrist_spheres(robot) if wrist else ()),
        Sphere("cue butt", robot.tool_frame, (0.0, 0.0, -length), SAWYER_CUE_RADIUS),
        Sphere("cue middle", robot.tool_frame, (0.0, 0.0, -0.5 * length), SAWYER_CUE_RADIUS),
        Sphere("cue tip", robot.tool_frame, (0.0, 0.0, -TIP_RADIUS), TIP_RADIUS),
    )


def wrist_spheres(robot: Robot) -> tuple[Sphere, ...]:
    """Spheres at the ends and middle of each capsule of :data:`WRIST_LINKS` the robot has.

    Each has its capsule's radius, on the joint that carries it; a short capsule (its half
    length at most its radius) has no middle one. Names: ``"link_6 end 0"``,
    ``"link_6 middle"``, ``"link_6 end 1"``.
    """
    model = robot.model
    found: list[Sphere] = []
    for item in collision_geometry(robot).geometryObjects:
        shape = item.geometry
        if item.name not in WRIST_LINKS or not isinstance(shape, coal.Capsule):
            continue
        frame = str(model.names[item.parentJoint])
        radius, half = float(shape.radius), float(shape.halfLength)
        ends = {"end 0": -half, "middle": 0.0, "end 1": half}
        if half <= radius:
            del ends["middle"]
        for label, z in ends.items():
            centre = item.placement.act(np.array([0.0, 0.0, z]))
            place = (float(centre[0]), float(centre[1]), float(centre[2]))
            found.append(Sphere(f"{item.name} {label}", frame, place, radius))
    return tuple(found)


def shoulder_spheres(robot: Robot) -> tuple[Sphere, ...]:
    r"""Spheres that cover the shapes of :data:`SHOULDER_LINKS` the robot has.

    A capsule of radius r and half length h: spheres at its ends and middle of radius
    :math:`\sqrt{r^2 + (h/2)^2}`, which cover the capsule between them (they reach that much
    beyond it at their centres: 26 mm on Sawyer's link_2); a cylinder: one sphere through its
    rims. Each is named by its shape (``"link_2 end 0"``) and rides on the joint that carries
    the shape.
    """
    model = robot.model
    found: list[Sphere] = []
    for item in collision_geometry(robot).geometryObjects:
        shape = item.geometry
        if item.name not in SHOULDER_LINKS:
            continue
        frame = str(model.names[item.parentJoint])  # "universe" for the base's shape
        radius, half = float(shape.radius), float(shape.halfLength)
        if isinstance(shape, coal.Capsule):
            places = {"end 0": -half, "middle": 0.0, "end 1": half}
            size = float(np.hypot(radius, half / 2.0))
        else:  # a cylinder: its centre, the sphere through its rims
            places, size = {"middle": 0.0}, float(np.hypot(radius, half))
        for label, z in places.items():
            centre = item.placement.act(np.array([0.0, 0.0, z]))
            place = (float(centre[0]), float(centre[1]), float(centre[2]))
            found.append(Sphere(f"{item.name} {label}", frame, place, size))
    return tuple(found)


def _shape_of(sphere: Sphere) -> str:
    """The collision shape a sphere of :func:`pool_spheres` or :func:`shoulder_spheres` covers."""
    if sphere.name.startswith("cue"):
        return "tool/tip" if sphere.name == "cue tip" else "tool/cue"
    return sphere.name.rsplit(" ", 2)[0]


def self_pairs(
    robot: Robot, shoulder: Sequence[Sphere], spheres: Sequence[Sphere]
) -> tuple[tuple[int, int], ...]:
    """(shoulder index, sphere index) of every pair whose shapes may not touch.

    Pairs of shapes the robot's collision model allows (adjacent links) are left out.
    """
    allowed = collision_model(robot).allowed
    pairs = []
    for i, a in enumerate(shoulder):
        for j, b in enumerate(spheres):
            first, second = sorted((_shape_of(a), _shape_of(b)))
            if first != second and (first, second) not in allowed:
                pairs.append((i, j))
    return tuple(pairs)


def cushion_step(problem: PoolStrike) -> tuple[float, float]:
    """The near cushion's face along x and its height above the cloth [m]; (0, 0) without one.

    The cushion is the scene's :data:`NEAR_CUSHION` box (axis-aligned, as
    :func:`problems.pool_table` places it).
    """
    scene = problem.scene
    if scene is None:
        return 0.0, 0.0
    for item in scene.objects:
        if item.name == NEAR_CUSHION and isinstance(item, Box):
            centre = np.asarray(item.pose, dtype=float)[:3, 3]
            half = np.asarray(item.half_extents, dtype=float)
            cloth = float(problem.ball[2]) - float(problem.ball_radius)
            return float(centre[0] + half[0]), max(0.0, float(centre[2] + half[2]) - cloth)
    return 0.0, 0.0


def step_height(x: FloatArray, face: float, height: float, reach: FloatArray) -> FloatArray:
    """How far the floor has risen over the near cushion at x [m] (the module's formula).

    Args:
        x: Sphere centres' x [m].
        face: The cushion's face along x [m].
        height: The cushion's height above the cloth [m].
        reach: Each sphere's radius plus the margin [m].
    """
    return height * 0.5 * (1.0 + np.tanh((face + reach + 2.0 * STEP_WIDTH - x) / STEP_WIDTH))


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

    Before the rise over the near cushion. The cloth plus the sphere's radius, the margin and
    the node extra; a sphere that starts lower (a start pose in the table, or over the near
    cushion) is held that much lower, as no plan can lift it at its first node.
    """
    cloth = float(problem.ball[2]) - float(problem.ball_radius)
    radii = np.array([sphere.radius for sphere in spheres])
    wanted = cloth + radii + clearance.margin + clearance.node_extra
    start = sphere_centres(problem.robot, spheres, problem.q_start)[0]
    face, height = cushion_step(problem)
    rise = step_height(start[:, 0], face, height, radii + clearance.margin)
    return wanted - np.maximum(0.0, wanted + rise - start[:, 2])


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
