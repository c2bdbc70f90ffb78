"""Pick blocks and stack them on a pile (the youBot task of Coursework 3, Q2)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError, UnreachableError
from optraj.problems.common import check_robot, joint_state, positive, resolve_limits, unit_vector
from optraj.problems.constraints import BoundaryState, Constraint, ToolContact
from optraj.problems.scene import Scene
from optraj.problems.scene_distances import SceneCollision
from optraj.problems.scene_shapes import Box, Cylinder, Sphere
from optraj.robots import JointLimits, Robot, solve_ik
from optraj.validation import as_array, as_duration, as_vector

#: Arrays the problem stores after checking its inputs (it takes any array-like).
FloatArray = NDArray[np.float64]

__all__ = ["PHASES", "RETREAT", "PickAndPlace", "highest_point"]

#: The seven phases of each object, in order (suffixed ``_<object index>`` in trajectories).
PHASES = (
    "interim",  # go to the interim pose
    "turn_to_object",  # turn and reach above the object
    "descend",  # go down onto the object
    "grasp",  # close the gripper (dwell)
    "back_to_interim",  # return to the interim pose with the object
    "turn_to_target",  # turn and reach above the pile
    "release",  # go down onto the pile and open the gripper (dwell)
)
#: The phase after each release in a plan that leaves the block vertically (suffixed too).
RETREAT = "retreat"


@dataclass(frozen=True, eq=False)
class PickAndPlace:
    """Move blocks one by one onto a pile, gripping them from above.

    Object k is gripped at ``picks[k]`` and released at ``pile + k * block_height * z``.
    Every approach comes from ``clearance`` above along the gripper axis ``approach``.

    Attributes:
        robot: The robot (``robots.load("youbot")``); its tool frame is the gripper TCP.
        picks: Block centres where they are gripped [m], shape (k, 3).
        pile: Centre of the first block placed on the pile [m], shape (3,).
        block_height: Height of a block [m].
        clearance: Height above a grip or release point where the descent starts [m].
        approach: Direction of the tool z axis while gripping, shape (3,) (down by default).
        grasp_time: Dwell to close or open the gripper [s].
        q_start: Start (and end) configuration; the robot's home when None.
        q_interim: Interim configuration between objects. When None: with a scene, the
            gripper (along ``approach``) above the middle of the picks and the pile, its TCP
            :meth:`interim_height` high; without one, q_start. (``dataclasses.replace``
            keeps the resolved one: pass ``q_interim=None`` to choose it again.)
        limits: Limits to plan for; the robot's when None.
        position_tolerance: [m].
        angle_tolerance: [rad].
        scene: The surroundings (:class:`problems.Scene`, e.g.
            ``problems.pick_and_place_scene(problem)``) or None (the default: no scene). With
            one, a grip or release configuration (or the one above it) in collision is refused
            and ``planners.check`` adds its ``clearance`` finding.

    Derived (IK when built, shape (k, n)): ``q_above_pick``, ``q_pick``, ``q_above_place``,
    ``q_place`` [rad].
    """

    robot: Robot
    picks: FloatArray
    pile: FloatArray
    block_height: float = 0.03
    clearance: float = 0.05
    approach: FloatArray = (0.0, 0.0, -1.0)  # type: ignore[assignment]  # made an array
    grasp_time: float = 0.5
    q_start: FloatArray = None  # type: ignore[assignment]  # None: resolved in __post_init__
    q_interim: FloatArray = None  # type: ignore[assignment]  # None: resolved in __post_init__
    limits: JointLimits = None  # type: ignore[assignment]  # None: the robot's (__post_init__)
    position_tolerance: float = 1e-6
    angle_tolerance: float = 1e-6
    scene: Scene | None = None
    q_above_pick: FloatArray = field(init=False, repr=False)
    q_pick: FloatArray = field(init=False, repr=False)
    q_above_place: FloatArray = field(init=False, repr=False)
    q_place: FloatArray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        robot = check_robot(self.robot)
        limits = resolve_limits(robot, self.limits)
        set_ = object.__setattr__
        set_(self, "limits", limits)
        picks = as_array(self.picks, "picks", (None, 3))
        if picks.shape[0] < 1:
            raise InvalidInputError("picks needs at least one block", name="picks")
        set_(self, "picks", picks)
        set_(self, "pile", as_vector(self.pile, "pile", 3))
        set_(self, "block_height", positive(self.block_height, "block_height", "m"))
        set_(self, "clearance", positive(self.clearance, "clearance", "m"))
        set_(self, "approach", unit_vector(self.approach, "approach"))
        set_(self, "grasp_time", as_duration(self.grasp_time, "grasp_time"))
        q_start, _, _ = joint_state(
            limits, robot.home if self.q_start is None else self.q_start, None, None, "start"
        )
        set_(self, "q_start", q_start)
        interim = self.q_interim
        if interim is None:
            interim = q_start if self.scene is None else self._scene_interim(q_start)
        set_(self, "q_interim", joint_state(limits, interim, None, None, "interim")[0])

        lift = -self.clearance * np.asarray(self.approach)
        solutions: dict[str, list[np.ndarray]] = {key: [] for key in ("ap", "p", "al", "l")}
        for k in range(picks.shape[0]):
            for key_above, key_at, point, what in (
                ("ap", "p", picks[k], f"pick {k}"),
                ("al", "l", self.place_point(k), f"place {k}"),
            ):
                above = self._ik(point + lift, self.q_interim, f"above {what}")
                solutions[key_above].append(above)
                solutions[key_at].append(self._ik(point, above, what))
        set_(self, "q_above_pick", np.array(solutions["ap"]))
        set_(self, "q_pick", np.array(solutions["p"]))
        set_(self, "q_above_place", np.array(solutions["al"]))
        set_(self, "q_place", np.array(solutions["l"]))
        if self.scene is not None:
            self._require_clear()

    def _require_clear(self) -> None:
        """CollisionError if a target configuration puts the robot inside the scene."""
        if self.scene is None:
            return
        shapes = SceneCollision(self.robot, self.scene)
        shapes.require_clear(self.q_interim, "interim")
        for k in range(self.count):
            for what, q in (
                (f"above pick {k}", self.q_above_pick[k]),
                (f"pick {k}", self.q_pick[k]),
                (f"above place {k}", self.q_above_place[k]),
                (f"place {k}", self.q_place[k]),
            ):
                shapes.require_clear(q, what)

    def interim_height(self) -> float:
        """Height of the TCP at the scene's interim pose [m], world z.

        The highest point of the scene's bounded objects (boxes, spheres, cylinders; planes
        bound the space from below) and of the pile the last block is put on, plus a carried
        block's lower half (the TCP holds a block at its centre), plus ``clearance`` (or the
        scene's margin if larger): a carried block passes as high above everything as it
        starts its descent above the pile.
        """
        pile_top = float(np.asarray(self.pile)[2]) + (self.count - 1.5) * float(self.block_height)
        tops = [pile_top]
        if self.scene is not None:
            bounded = (
                item for item in self.scene.objects if isinstance(item, Box | Sphere | Cylinder)
            )
            tops += [highest_point(item) for item in bounded]
        margin = 0.0 if self.scene is None else float(self.scene.margin)
        return max(tops) + 0.5 * float(self.block_height) + max(float(self.clearance), margin)

    def _scene_interim(self, q_start: np.ndarray) -> np.ndarray:
        """The interim configuration chosen from the scene (see ``q_interim``)."""
        middle = np.vstack([np.asarray(self.picks), np.asarray(self.pile)[None]]).mean(axis=0)
        point = np.array([middle[0], middle[1], self.interim_height()])
        return self._ik(point, q_start, "the interim pose")

    def _ik(self, point: np.ndarray, q_near: np.ndarray, what: str) -> np.ndarray:
        try:
            return solve_ik(self.robot, point, axis=self.approach, q_near=q_near).q
        except UnreachableError as exc:
            raise UnreachableError(
                f"{what} at ({', '.join(f'{v:.4g}' for v in point)}) m is out of reach with "
                f"the gripper along {np.round(self.approach, 3).tolist()}",
                position_error=exc.position_error,
                orientation_error=exc.orientation_error,
                attempts=exc.attempts,
            ) from exc

    @property
    def count(self) -> int:
        """Number of blocks."""
        return int(np.asarray(self.picks).shape[0])

    def place_point(self, k: int) -> np.ndarray:
        """Where block k is released: its centre on top of the pile [m], shape (3,)."""
        return np.asarray(self.pile) + k * float(self.block_height) * np.array([0.0, 0.0, 1.0])

    def constraints(self) -> tuple[Constraint, ...]:
        """Rest at q_start; the gripper on each block while gripping and releasing; rest."""
        n = self.limits.n
        items: list[Constraint] = [BoundaryState("start", np.asarray(self.q_start), np.zeros(n))]
        for k in range(self.count):
            # The grasp is a dwell on the block; the release phase descends and then dwells.
            for phase, at, point in (
                ("grasp", "start", np.asarray(self.picks)[k]),
                ("grasp", "end", np.asarray(self.picks)[k]),
                ("release", "end", self.place_point(k)),
            ):
                items.append(
                    ToolContact(
                        position=point,
                        axis=np.asarray(self.approach),
                        velocity=np.zeros(3),
                        phase=f"{phase}_{k}",
                        at=at,  # type: ignore[arg-type]  # "start"/"end" widened to str
                        label=f"{phase} {k} ({at})",
                        position_tolerance=self.position_tolerance,
                        angle_tolerance=self.angle_tolerance,
                    )
                )
        items.append(BoundaryState("end", None, np.zeros(n)))
        return tuple(items)


def highest_point(item: Box | Sphere | Cylinder) -> float:
    """The largest world z of a bounded scene object [m]."""
    pose = np.asarray(item.pose)
    up = pose[2, :3]  # world z of the object's x, y, z axes
    if isinstance(item, Box):
        return float(pose[2, 3] + np.abs(up) @ np.asarray(item.half_extents))
    if isinstance(item, Sphere):
        return float(pose[2, 3] + item.radius)
    # A cylinder along its z axis: the rim of its higher end.
    tilt = float(np.sqrt(max(0.0, 1.0 - up[2] ** 2)))
    return float(pose[2, 3] + abs(up[2]) * item.half_length + tilt * item.radius)
