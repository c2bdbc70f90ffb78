r"""A pool strike's clearance as NLP rows: spheres above the cloth, the cue tip behind the ball.

:class:`ClearanceRows` writes, at every node after the first (the first is the pinned start),
one row per sphere of :func:`planners.ocp.clearance.pool_spheres`: :math:`c_z(q) \ge f_i +
s_i(c_x)`, the sphere's floor (cloth, radius, margin and node extra:
:func:`planners.ocp.clearance.sphere_floors`) and its rise over the near cushion
(:func:`planners.ocp.clearance.step_height`, 0 without one), leaving out the cue tip at the
nodes of the strike window (it meets the ball there) and giving back most of the node extra
there (the strike line holds the motion between those nodes nearly straight); and at the
approach's nodes after the first, one half-space row for the cue tip's sphere: :math:`d \cdot
(c - b) \le -o`, the offset :math:`o` of :func:`planners.ocp.clearance.ball_offset`. The
numbers are the NLP parameters ``clearance_floor`` and ``clearance_reach`` (one per sphere),
``clearance_cushion`` (face, height), ``clearance_extra``, ``clearance_ball``,
``clearance_direction`` and ``clearance_behind``, so every shot with the same spheres shares
one compiled NLP.

With ``Clearance.shoulder``, one more row per pair of a shoulder sphere
(:func:`planners.ocp.clearance.shoulder_spheres`) and a wrist or cue sphere whose shapes may
not touch, at every node after the first: :math:`\lVert c_i - c_j \rVert^2 \ge a_k`, the
square of their radii, the margin and the node extra summed (``clearance_apart``; no more
than the start holds them apart).

Example::

    rows = ClearanceRows.of(problem, Clearance(), ("approach", "strike", "stop"))
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.ocp.clearance import (
    STEP_WIDTH,
    Clearance,
    Sphere,
    ball_offset,
    cushion_step,
    pool_spheres,
    self_pairs,
    shoulder_spheres,
    sphere_centres,
    sphere_floors,
)
from optraj.planners.ocp.task_rows.base import TaskContext, TaskRows
from optraj.problems import PoolStrike

if TYPE_CHECKING:
    from optraj.planners.ocp.rows import Rows

FloatArray = NDArray[np.float64]

#: Most spheres of :func:`planners.ocp.clearance.pool_spheres` (the last is the cue tip):
#: the size of the parameters ``clearance_floor`` and ``clearance_reach``, whose unused
#: entries are 0 (Sawyer's wrist has 11, its cue 3).
SPHERES = 16
#: Most shoulder-to-wrist or -cue sphere pairs (Sawyer has 131): the size of the parameter
#: ``clearance_apart``.
PAIRS = 160


#: Extra height kept at the strike window's nodes [m]: the cue runs straight there, the arm's
#: links nearly so (a link on the margin at the nodes dipped 0.02 mm between them).
WINDOW_EXTRA = 0.001


@dataclass(frozen=True)
class ClearanceRows(TaskRows):
    """The clearance rows of a pool strike.

    Attributes:
        window: Index of the strike window's phase (the cue tip is free of the cloth rows
            at its nodes).
        spheres: The spheres (constants of the NLP: rows compare by them and the window).
        floors: Lowest height of each sphere's centre [m], shape (:data:`SPHERES`,): the
            spheres' first, then zeros.
        reach: Each sphere's radius plus the margin [m], shape (:data:`SPHERES`,).
        cushion: The near cushion's face along x and height above the cloth [m], shape (2,).
        shoulder: Spheres on the shoulder (:func:`planners.ocp.clearance.shoulder_spheres`),
            kept apart from the other spheres (``Clearance.shoulder``); else none.
        pairs: (shoulder index, sphere index) of each pair kept apart.
        apart: Least squared distance between the centres of each pair [m^2], shape
            (:data:`PAIRS`,).
        extra: The part of the node extra given back in the strike window [m], all of it but
            :data:`WINDOW_EXTRA`: the strike line holds the motion between its nodes nearly
            straight.
        ball: Ball centre [m], shape (3,).
        direction: Shot direction (unit), shape (3,).
        behind: Least distance of the tip sphere's centre behind the ball's centre along
            the shot on the approach [m].
    """

    window: int
    spheres: tuple[Sphere, ...]
    shoulder: tuple[Sphere, ...]
    pairs: tuple[tuple[int, int], ...]
    floors: FloatArray = field(compare=False, repr=False)
    reach: FloatArray = field(compare=False, repr=False)
    cushion: FloatArray = field(compare=False, repr=False)
    apart: FloatArray = field(compare=False, repr=False)
    extra: float = field(compare=False, repr=False)
    ball: FloatArray = field(compare=False, repr=False)
    direction: FloatArray = field(compare=False, repr=False)
    behind: float = field(compare=False, repr=False)

    parameters = (
        ("clearance_floor", SPHERES),
        ("clearance_reach", SPHERES),
        ("clearance_cushion", 2),
        ("clearance_extra", 1),
        ("clearance_apart", PAIRS),
        ("clearance_ball", 3),
        ("clearance_direction", 3),
        ("clearance_behind", 1),
    )

    @classmethod
    def of(cls, problem: PoolStrike, clearance: Clearance, phases: Sequence[str]) -> ClearanceRows:
        """The rows of ``problem`` with the window in its phase ``"strike"`` of ``phases``."""
        spheres = pool_spheres(problem.robot, wrist=clearance.keeps_wrist(problem))
        if len(spheres) > SPHERES:
            raise InvalidInputError(
                f"the robot has {len(spheres)} clearance spheres, at most {SPHERES} fit",
                name="clearance",
            )
        floors, reach = np.zeros(SPHERES), np.zeros(SPHERES)
        floors[: len(spheres)] = sphere_floors(problem, spheres, clearance)
        reach[: len(spheres)] = [sphere.radius + clearance.margin for sphere in spheres]
        shoulder = shoulder_spheres(problem.robot) if clearance.keeps_shoulder(problem) else ()
        pairs = self_pairs(problem.robot, shoulder, spheres)
        if len(pairs) > PAIRS:
            raise InvalidInputError(
                f"the robot has {len(pairs)} shoulder sphere pairs, at most {PAIRS} fit",
                name="clearance",
            )
        apart = np.zeros(PAIRS)
        if pairs:
            start = problem.q_start
            at_start = sphere_centres(problem.robot, shoulder, start)[0]
            mine = sphere_centres(problem.robot, spheres, start)[0]
            gap = clearance.margin + clearance.node_extra
            for k, (i, j) in enumerate(pairs):
                wanted = shoulder[i].radius + spheres[j].radius + gap
                now = float(np.linalg.norm(at_start[i] - mine[j]))
                apart[k] = min(wanted, now) ** 2  # no lower than the start holds them
        return cls(
            window=list(phases).index("strike"),
            spheres=spheres,
            shoulder=shoulder,
            pairs=pairs,
            apart=apart,
            floors=floors,
            reach=reach,
            cushion=np.array(cushion_step(problem)),
            extra=max(0.0, clearance.node_extra - WINDOW_EXTRA),
            ball=np.asarray(problem.ball, dtype=float),
            direction=np.asarray(problem.direction, dtype=float),
            behind=ball_offset(problem, spheres[-1], clearance),
        )

    def values(self) -> dict[str, FloatArray]:
        """Floors, reaches, cushion, ball centre and offset [m]; the shot direction."""
        return {
            "clearance_floor": self.floors,
            "clearance_reach": self.reach,
            "clearance_cushion": self.cushion,
            "clearance_extra": np.array([self.extra]),
            "clearance_apart": self.apart,
            "clearance_ball": self.ball,
            "clearance_direction": self.direction,
            "clearance_behind": np.array([self.behind]),
        }

    def add(self, rows: Rows, nlp: TaskContext) -> None:
        """Sphere heights at every node but the first; the tip's half-space on the approach."""
        symbolic, params = nlp.symbolic, nlp.parameters
        frames = {s.frame for s in (*self.spheres, *self.shoulder)}
        pose = {f: (symbolic.frame_position(f), symbolic.frame_rotation(f)) for f in frames}
        first = nlp.layout.first_node
        window = range(int(first[self.window]), int(first[self.window + 1]) + 1)
        floors, reach = params["clearance_floor"], params["clearance_reach"]
        face, height = params["clearance_cushion"][0], params["clearance_cushion"][1]
        for node in range(1, nlp.layout.nodes):
            q, _, _ = nlp.state(node)
            # Each frame's pose once per node: SX calls are inlined, not shared.
            at_node = {f: (position(q), rotation(q)) for f, (position, rotation) in pose.items()}
            centres = []
            for sphere in self.spheres:
                p, r = at_node[sphere.frame]
                centres.append(p + r @ ca.DM(sphere.offset))
            if self.pairs:
                shoulder = [
                    at_node[s.frame][0] + at_node[s.frame][1] @ ca.DM(s.offset)
                    for s in self.shoulder
                ]
                wanted = params["clearance_apart"]
                for k, (i, j) in enumerate(self.pairs):  # a group per pair: a failure names it
                    apart = ca.sumsqr(shoulder[i] - centres[j]) - wanted[k]
                    name = f"clearance self: {self.spheres[j].name} from {self.shoulder[i].name}"
                    rows.add(name, apart, 0.0, np.inf, at=node)
            kept = len(self.spheres) - 1 if node in window else len(self.spheres)
            given = params["clearance_extra"] if node in window else 0.0
            for i, c in enumerate(centres[:kept]):  # a group per sphere, as above
                rise = 0.5 * (
                    1.0 + ca.tanh((face + reach[i] + 2.0 * STEP_WIDTH - c[0]) / STEP_WIDTH)
                )
                above = c[2] - floors[i] - height * rise + given
                name = f"clearance cloth: {self.spheres[i].name}"
                rows.add(name, above, 0.0, np.inf, at=node)
            if node < window[0]:
                ahead = ca.dot(
                    params["clearance_direction"], centres[-1] - params["clearance_ball"]
                )
                rows.add(
                    "clearance ball", ahead + params["clearance_behind"], -np.inf, 0.0, at=node
                )
