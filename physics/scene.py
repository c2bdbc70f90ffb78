r"""MuJoCo worlds for a strike, built with ``mujoco.MjSpec`` from our own URDF files.

A :class:`StrikeScene` is the recipe of one world: the arm from its URDF (or, with
``kinematic=True``, only its tool as a free body that is moved along a prescribed path), the
tool's striking geometry (a cue with a round tip, or a paddle), the still solids of a
:class:`problems.Scene` (the description the planners, the checker and the viewer read too: for
pool by default :func:`problems.pool_table`, cloth, cushions and floor) and a free ball. It is
a small frozen value that pickles; :meth:`StrikeScene.build` compiles it into a
:class:`mujoco.MjModel` with the indices the plant and the outcome need (:class:`World`).

>>> scene = physics.pool_scene(robot, ball=[0.75, 0.15, -0.05])
>>> world = scene.build()
>>> world.model.opt.timestep      # the coarse physics step [s]

Contacts are explicit MuJoCo contact pairs, so that nothing else touches: tool tip and ball,
ball and every still solid (:mod:`optraj.physics.static_objects`). The arm's links carry no
geometry (the URDFs have none). The tool sizes are :mod:`robots.collision`'s, the table's
:mod:`problems.scenes`'.

Contact parameters and why:

* Tool on ball: frictionless (``condim=1``), so that the ball leaves along the contact normal
  and the heading error of an off-line tip is :math:`\arcsin(d / (R + r))` (tip friction would
  add spin, which is not modelled). ``solref = (2 ms, 0.07)``: the damping ratio 0.07 gives a
  restitution of about 0.81, the cue-ball value of about 0.8 the strike outcome is specified
  with; the time constant gives a contact of about 0.4 ms, the order of a real cue-ball
  contact (about 1 ms).
* Ball on cloth: sliding friction 0.2, rolling resistance 0.01 (a length of 0.01 R in MuJoCo)
  and spin friction 0.005 R, the usual ball-cloth values (Alciatore, "Pool and billiards
  physics resources", useful constants); critically damped, 4 ms (resolved by the 2e-4 s
  step of the roll-out).
* Ball on cushion: restitution about 0.75 (damping ratio 0.09), friction 0.2 (the same source
  gives 0.6 to 0.9 for the rail).
* Friction cones are elliptic (a sliding ball's friction opposes its slip exactly; the default
  pyramid biases it and bends the ball's path).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from importlib import resources
from typing import Literal

import mujoco
import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.physics.static_objects import (
    CLOTH_FRICTION,
    CLOTH_SOLREF,
    CUSHION_FRICTION,
    CUSHION_SOLREF,
    add_objects,
    add_pair,
    inert,
)
from optraj.problems import Scene
from optraj.problems.pool_strike import POOL_BALL_RADIUS
from optraj.problems.scenes import BALL_FROM_NEAR_END, CUSHION_HEIGHT, TABLE_SIZE, pool_table
from optraj.robots import Robot
from optraj.robots.collision import (
    CUE_TIP_RADIUS,
    PADDLE_BALL_RADIUS,
    PADDLE_RADIUS,
    PADDLE_THICKNESS,
)
from optraj.robots.loading import SAWYER_CUE_RADIUS, urdf_model
from optraj.robots.paddle_ik import BALL_OFFSET
from optraj.validation import (
    as_array,
    as_choice,
    as_flag,
    as_number,
    as_positive,
    as_vector,
    ndim_of,
)

__all__ = [
    "BALL_FROM_NEAR_END",
    "CLOTH_FRICTION",
    "CLOTH_SOLREF",
    "CUE_SHAFT_RADIUS",
    "CUE_TIP_RADIUS",
    "CUSHION_FRICTION",
    "CUSHION_HEIGHT",
    "CUSHION_SOLREF",
    "KINEMATIC_TOOL_MASS",
    "PADDLE_BALL_MASS",
    "PADDLE_BALL_RADIUS",
    "PADDLE_RADIUS",
    "PADDLE_THICKNESS",
    "POOL_BALL_MASS",
    "TABLE_SIZE",
    "StrikeScene",
    "World",
    "paddle_scene",
    "pool_scene",
    "scene_for",
]

FloatArray = NDArray[np.float64]

#: Pool ball mass [kg] (WPA: 5.5 to 6 oz, 156 to 170 g).
POOL_BALL_MASS = 0.17
#: Table-tennis ball mass [kg] (ITTF: 2.7 g); its radius is robots.collision's.
PADDLE_BALL_MASS = 0.0027
#: Cue shaft radius [m]: the model's cue.
CUE_SHAFT_RADIUS = SAWYER_CUE_RADIUS
#: Mass of each striking geom [kg]: next to nothing, since the tool's mass is the robot
#: model's (see StrikeScene.build) or, kinematic, the free body's.
GEOM_MASS = 1e-6
#: Mass of the free tool body of a kinematic scene [kg]: so heavy that the ball's impulse
#: does not slow it (its path is prescribed anyway).
KINEMATIC_TOOL_MASS = 1000.0
#: Physics steps [s]: coarse (away from contact) and fine (around it).
STEP = 1e-4
FINE_STEP = 2e-6
#: Range of both physics steps [s]. MuJoCo's guidance is a contact time constant of at least
#: twice the timestep (XML reference, solref): the tool-ball contact's 2 ms allows 1 ms.
#: Below 0.1 us a strike's 10 ms around contact takes more than 1e5 fine steps.
MIN_STEP = 1e-7
MAX_STEP = 1e-3

#: Tool-ball contact parameters (see the module docstring).
TOOL_BALL_SOLREF = (0.002, 0.07)
TOOL_BALL_SOLIMP = (0.99, 0.999, 0.0001, 0.5, 2.0)

Kind = Literal["pool", "paddle"]


@dataclass(frozen=True)
class World:
    """A compiled scene and the indices into it.

    Attributes:
        scene: The recipe it was built from.
        model: The MuJoCo model.
        arm_qpos: Addresses of the arm joints in ``qpos``, shape (n,) (empty when kinematic).
        arm_dof: Addresses of the arm joints in ``qvel``, shape (n,).
        tool_body: Body that carries the striking geometry.
        tool_geom: The striking geom (cue tip sphere or paddle blade).
        tool_offset: Tool frame in ``tool_body``'s frame, shape (4, 4).
        ball_body: The ball's body.
        ball_geom: The ball's geom.
        ball_qpos: Address of the ball's free joint in ``qpos`` (7 numbers).
        ball_dof: Address of the ball's free joint in ``qvel`` (6 numbers).
        tool_qpos: Address of the free tool joint (kinematic scenes; -1 otherwise).
        tool_dof: Address of its velocity (kinematic scenes; -1 otherwise).
    """

    scene: StrikeScene
    model: mujoco.MjModel
    arm_qpos: NDArray[np.int64]
    arm_dof: NDArray[np.int64]
    tool_body: int
    tool_geom: int
    tool_offset: FloatArray
    ball_body: int
    ball_geom: int
    ball_qpos: int
    ball_dof: int
    tool_qpos: int
    tool_dof: int


@dataclass(frozen=True, eq=False)
class StrikeScene:
    """The recipe of a strike world; :func:`pool_scene` and :func:`paddle_scene` make one.

    Attributes:
        robot: The robot whose URDF and tool frame are used.
        kind: ``"pool"`` (cue, table with cushions, pool ball) or ``"paddle"`` (paddle and a
            table-tennis ball held at the top of its toss: its gravity is compensated).
        ball: Ball centre at the start [m], shape (3,).
        ball_radius: [m].
        ball_mass: [kg].
        kinematic: Only the tool, as a free heavy body moved along a prescribed path (no arm).
        tool_mass: Mass of the free tool body of a kinematic scene [kg].
        mass_scale: Factor on every arm link's mass and inertia (model error), shape (n,)
            or a scalar; 1 is the URDF.
        payload: Extra point mass at the tool frame [kg] (model error), >= 0.
        step: Coarse physics step [s], in [MIN_STEP, MAX_STEP].
        fine_step: Physics step around tool-ball contact [s], in [MIN_STEP, step].
        surroundings: The still solids around (a :class:`problems.Scene`: table, cushions,
            floor, blocks), built as MuJoCo geoms that the ball touches
            (:mod:`optraj.physics.static_objects`); None: the ready-made ones
            (:attr:`static_scene`). Its object ``ball``, if any, is not built: the ball is
            the free body at ``ball``.
    """

    robot: Robot
    kind: Kind
    ball: ArrayLike
    ball_radius: float
    ball_mass: float
    kinematic: bool = False
    tool_mass: float = KINEMATIC_TOOL_MASS
    mass_scale: ArrayLike = 1.0
    payload: float = 0.0
    step: float = STEP
    fine_step: float = FINE_STEP
    surroundings: Scene | None = None
    _tool_parent: str = field(init=False, repr=False, default="")

    def __post_init__(self) -> None:
        if not isinstance(self.robot, Robot):
            raise InvalidInputError(
                f"robot must be a robots.Robot, got {type(self.robot).__name__}", name="robot"
            )
        as_choice(self.kind, "scene kind", ("pool", "paddle"))
        set_ = object.__setattr__
        set_(self, "ball", as_vector(self.ball, "ball", 3))
        set_(self, "ball_radius", as_positive(self.ball_radius, "ball_radius", "m"))
        set_(self, "ball_mass", as_positive(self.ball_mass, "ball_mass", "kg"))
        set_(self, "tool_mass", as_positive(self.tool_mass, "tool_mass", "kg"))
        set_(self, "kinematic", as_flag(self.kinematic, "kinematic"))
        scale = np.broadcast_to(
            as_array(self.mass_scale, "mass_scale", (None,) if ndim_of(self.mass_scale) else ()),
            (self.robot.dof,),
        ).copy()
        if np.any(scale <= 0.0) or np.any(scale > 10.0):
            raise InvalidInputError(
                f"mass_scale must lie in (0, 10], got {np.array2string(scale, precision=4)}",
                name="mass_scale",
            )
        scale.setflags(write=False)
        set_(self, "mass_scale", scale)
        set_(self, "payload", as_number(self.payload, "payload", "kg", minimum=0.0))
        for name in ("step", "fine_step"):
            value = as_number(getattr(self, name), name, "s", minimum=MIN_STEP, maximum=MAX_STEP)
            set_(self, name, value)
        if self.fine_step > self.step:
            raise InvalidInputError(
                f"fine_step {self.fine_step:.6g} s must be <= step {self.step:.6g} s",
                name="fine_step",
            )
        if self.surroundings is not None and not isinstance(self.surroundings, Scene):
            raise InvalidInputError(
                "surroundings must be a problems.Scene or None, got "
                f"{type(self.surroundings).__name__}",
                name="surroundings",
            )
        set_(self, "_tool_parent", _tool_parent(self.robot))

    # ------------------------------------------------------------------------------ geometry

    @property
    def tool_offset(self) -> FloatArray:
        """The tool frame in the frame of the body that carries it, shape (4, 4)."""
        model = self.robot.model
        tool = model.frames[self.robot.tool_frame_id]
        parent = model.frames[model.getFrameId(self._tool_parent)]
        return np.asarray((parent.placement.inverse() * tool.placement).homogeneous)

    @property
    def static_scene(self) -> Scene | None:
        """The still solids the world is built with.

        :attr:`surroundings` when given; else, for pool, the ready-made table under the ball
        (:func:`problems.pool_table`: cloth, cushions, floor), which follows the ball
        (:meth:`with_ball`); for a paddle, none.
        """
        if self.surroundings is not None:
            return self.surroundings
        if self.kind == "pool":
            return pool_table(np.asarray(self.ball), float(self.ball_radius))
        return None

    @property
    def table_height(self) -> float:
        """Height of the table surface (pool) [m]: the ball rests on it."""
        return float(np.asarray(self.ball)[2]) - float(self.ball_radius)

    @property
    def contact_offset(self) -> float:
        """How far ahead of the tool frame, along its z axis, the ball centre is met [m].

        Pool: one ball radius (the tool frame is the front of the cue tip). Paddle: the
        ECE486 ``BALL_OFFSET`` from the paddle centre, as the plans place the ball.
        """
        return float(self.ball_radius) if self.kind == "pool" else BALL_OFFSET

    def with_ball(self, ball: ArrayLike) -> StrikeScene:
        """The same scene with the ball elsewhere."""
        return dataclasses.replace(self, ball=ball)

    def as_kinematic(self, tool_mass: float = KINEMATIC_TOOL_MASS) -> StrikeScene:
        """The same world with only the tool, as a free body of ``tool_mass`` [kg]."""
        return dataclasses.replace(self, kinematic=True, tool_mass=tool_mass)

    def nominal(self) -> StrikeScene:
        """The same world without its model error (no mass scale, no payload)."""
        return dataclasses.replace(self, mass_scale=1.0, payload=0.0)

    @property
    def has_model_error(self) -> bool:
        """Whether link masses are scaled or a payload is carried."""
        return bool(np.any(np.asarray(self.mass_scale) != 1.0)) or self.payload > 0.0

    # ------------------------------------------------------------------------------ build

    def build(self) -> World:
        """Compile the scene into a MuJoCo model (a few milliseconds)."""
        if self.kinematic:
            spec = mujoco.MjSpec()
            tool = spec.worldbody.add_body(name="tool")
            tool.add_freejoint(name="tool_free")
            tool.gravcomp = 1.0
            tool.mass = float(self.tool_mass)
            tool.inertia = [self.tool_mass * 0.01] * 3  # a heavy block's rotational inertia
            tool.explicitinertial = True
            offset = np.eye(4)
        else:
            spec = self._arm_spec()
            tool = spec.body(self._tool_parent)
            offset = self.tool_offset
            self._add_tool_inertia(tool)
        spec.option.timestep = float(self.step)
        spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
        # Elliptic friction cones: MuJoCo's default pyramid pulls a sliding ball's friction
        # towards the pyramid's edges, which turns the ball off a heading that is not along
        # one of them (tests/test_replay.py shoots along oblique headings).
        spec.option.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
        striking = (
            self._add_cue(tool, offset) if self.kind == "pool" else self._add_paddle(tool, offset)
        )
        if self.payload > 0.0:
            weight = tool.add_geom(name="payload", type=mujoco.mjtGeom.mjGEOM_SPHERE)
            weight.size = [0.01, 0, 0]
            weight.pos = offset[:3, 3]
            weight.mass = self.payload
            inert(weight)
        if not self.kinematic:
            self._add_servos(spec)
        _, ball_geom = self._add_ball(spec)
        add_pair(spec, striking, ball_geom, 1, TOOL_BALL_SOLREF, TOOL_BALL_SOLIMP)
        table = self.static_scene
        if table is not None:
            add_objects(spec, table, ball_geom)
        model = spec.compile()
        return self._world(model, offset)

    def _arm_spec(self) -> mujoco.MjSpec:
        urdf = resources.files("optraj.robots") / "urdf" / f"{self.robot.name}.urdf"
        with resources.as_file(urdf) as path:
            spec = mujoco.MjSpec.from_file(str(path))
        spec.compiler.fusestatic = False  # keep the tool's parent body (e.g. right_hand)
        names = self.robot.joint_names
        for joint, scale in zip(names, np.asarray(self.mass_scale), strict=True):
            body = spec.joint(joint).parent
            body.mass = body.mass * float(scale)
            body.fullinertia = [v * float(scale) for v in body.fullinertia]
            body.inertia = [v * float(scale) for v in body.inertia]
        return spec

    def _add_tool_inertia(self, parent: mujoco.MjsBody) -> None:
        """The tool's mass as the robot model has it (e.g. Sawyer's cue), welded to its link.

        The URDF has no tool; :func:`robots.load` adds its inertia to the last joint's body.
        The difference between that body and the URDF's is the tool, attached here as a
        child of the link that carries the tool frame.
        """
        model = self.robot.model
        parent_frame = model.frames[model.getFrameId(self._tool_parent)]
        joint = parent_frame.parentJoint
        urdf = urdf_model(self.robot.name)
        tool = model.inertias[joint] - urdf.inertias[joint]
        if tool.mass <= 1e-9:
            return
        in_link = parent_frame.placement.actInv(tool)
        body = parent.add_body(name="tool_inertia")
        body.explicitinertial = True
        body.mass = float(in_link.mass)
        body.ipos = list(np.asarray(in_link.lever))
        inertia = np.asarray(in_link.inertia)
        body.fullinertia = [
            inertia[i, j] for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
        ]

    def _add_servos(self, spec: mujoco.MjSpec) -> None:
        """One torque actuator per arm joint, clipped at the effort limit.

        ``force = gain * ctrl + bias0 + bias2 * qd``; the plant sets the gain and the biases
        at every control step (a velocity servo with gravity compensation and feed-forward),
        so that MuJoCo's implicit integrator sees the servo's damping.
        """
        for joint, effort in zip(self.robot.joint_names, self.robot.limits.effort, strict=True):
            actuator = spec.add_actuator(name=joint, target=joint)
            actuator.trntype = mujoco.mjtTrn.mjTRN_JOINT
            actuator.gaintype = mujoco.mjtGain.mjGAIN_FIXED
            actuator.biastype = mujoco.mjtBias.mjBIAS_AFFINE
            actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
            actuator.forcerange = [-float(effort), float(effort)]
            actuator.ctrllimited = mujoco.mjtLimited.mjLIMITED_FALSE

    def _add_cue(self, body: mujoco.MjsBody, offset: FloatArray) -> str:
        axis = offset[:3, 2]
        tip = offset[:3, 3]
        centre = tip - CUE_TIP_RADIUS * axis  # the tool frame is the front of the tip
        length = float(np.linalg.norm(tip)) if not self.kinematic else 0.3
        shaft = body.add_geom(name="cue_shaft", type=mujoco.mjtGeom.mjGEOM_CAPSULE)
        shaft.size = [CUE_SHAFT_RADIUS, 0, 0]
        back = centre - max(length - CUE_TIP_RADIUS, 0.01) * axis
        shaft.fromto = [*back, *(centre - 0.5 * CUE_TIP_RADIUS * axis)]
        shaft.mass = GEOM_MASS
        shaft.rgba = [0.8, 0.65, 0.4, 1]
        inert(shaft)
        tip_geom = body.add_geom(name="cue_tip", type=mujoco.mjtGeom.mjGEOM_SPHERE)
        tip_geom.size = [CUE_TIP_RADIUS, 0, 0]
        tip_geom.pos = centre
        tip_geom.mass = GEOM_MASS
        tip_geom.rgba = [0.2, 0.4, 0.8, 1]
        inert(tip_geom)
        return "cue_tip"

    def _add_paddle(self, body: mujoco.MjsBody, offset: FloatArray) -> str:
        normal = offset[:3, 2]
        # The face sits one ball radius short of where the plan puts the ball centre, so
        # that this ball touches there.
        face = offset[:3, 3] + (self.contact_offset - float(self.ball_radius)) * normal
        blade = body.add_geom(name="paddle_blade", type=mujoco.mjtGeom.mjGEOM_CYLINDER)
        blade.size = [PADDLE_RADIUS, PADDLE_THICKNESS / 2, 0]
        blade.pos = face - (PADDLE_THICKNESS / 2) * normal
        blade.quat = _quat_z_to(normal)
        blade.mass = GEOM_MASS
        blade.rgba = [0.75, 0.1, 0.1, 1]
        inert(blade)
        return "paddle_blade"

    def _add_ball(self, spec: mujoco.MjSpec) -> tuple[mujoco.MjsBody, str]:
        body = spec.worldbody.add_body(name="ball", pos=list(np.asarray(self.ball)))
        body.add_freejoint(name="ball_free")
        if self.kind == "paddle":
            body.gravcomp = 1.0
        geom = body.add_geom(name="ball", type=mujoco.mjtGeom.mjGEOM_SPHERE)
        geom.size = [float(self.ball_radius), 0, 0]
        geom.mass = float(self.ball_mass)
        geom.rgba = [0.95, 0.95, 0.9, 1] if self.kind == "pool" else [1.0, 0.55, 0.1, 1]
        inert(geom)
        return body, "ball"

    def _world(self, model: mujoco.MjModel, offset: FloatArray) -> World:
        names = () if self.kinematic else self.robot.joint_names
        joints = [model.joint(name).id for name in names]
        ball_joint = model.joint("ball_free").id
        tool_joint = model.joint("tool_free").id if self.kinematic else -1
        striking = "cue_tip" if self.kind == "pool" else "paddle_blade"
        geom = model.geom(striking).id
        return World(
            scene=self,
            model=model,
            arm_qpos=np.array([model.jnt_qposadr[j] for j in joints], dtype=np.int64),
            arm_dof=np.array([model.jnt_dofadr[j] for j in joints], dtype=np.int64),
            tool_body=int(model.geom_bodyid[geom]),
            tool_geom=geom,
            tool_offset=offset,
            ball_body=model.body("ball").id,
            ball_geom=model.geom("ball").id,
            ball_qpos=int(model.jnt_qposadr[ball_joint]),
            ball_dof=int(model.jnt_dofadr[ball_joint]),
            tool_qpos=int(model.jnt_qposadr[tool_joint]) if tool_joint >= 0 else -1,
            tool_dof=int(model.jnt_dofadr[tool_joint]) if tool_joint >= 0 else -1,
        )


def pool_scene(robot: Robot, ball: ArrayLike, **options: object) -> StrikeScene:
    """A pool world: the arm holding its cue (tool frame = cue tip), a table, a pool ball.

    Args:
        robot: A robot whose tool is a cue tip (``robots.load("sawyer")``).
        ball: Ball centre [m], shape (3,); the table's cloth is one radius below it.
        **options: Further :class:`StrikeScene` fields (``kinematic``, ``mass_scale``,
            ``payload``, ``step``, ``fine_step``, ``surroundings``).
    """
    # **options are StrikeScene fields of several types, checked there.
    return StrikeScene(robot, "pool", ball, POOL_BALL_RADIUS, POOL_BALL_MASS, **options)  # type: ignore[arg-type]


def paddle_scene(robot: Robot, ball: ArrayLike, **options: object) -> StrikeScene:
    """A paddle world: the arm with its paddle (tool frame = paddle centre), a table-tennis ball.

    The ball floats where it is met (gravity compensated: the top of a toss), so that its
    launch direction is the paddle's doing alone.

    Args:
        robot: A robot whose tool is a paddle (``robots.load("paddle4")``).
        ball: Ball centre [m], shape (3,).
        **options: Further :class:`StrikeScene` fields.
    """
    return StrikeScene(robot, "paddle", ball, PADDLE_BALL_RADIUS, PADDLE_BALL_MASS, **options)  # type: ignore[arg-type]


def _tool_parent(robot: Robot) -> str:
    """The URDF link that carries the tool frame (walking up from the tool frame)."""
    frames = robot.model.frames
    index = robot.tool_frame_id
    while frames[index].type != pin.FrameType.BODY:
        if index == 0:  # the universe: no link above the tool frame
            raise InvalidInputError(
                f"robot {robot.name!r}: no URDF link carries its tool frame", name="robot"
            )
        index = frames[index].parentFrame
    return str(frames[index].name)


def _quat_z_to(axis: FloatArray) -> list[float]:
    """Quaternion (w, x, y, z) turning +z onto ``axis`` (unit)."""
    z = np.array([0.0, 0.0, 1.0])
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    c = float(z @ a)
    if c < -1.0 + 1e-12:
        return [0.0, 1.0, 0.0, 0.0]
    v = np.cross(z, a)
    w = 1.0 + c
    q = np.array([w, *v])
    return list(q / np.linalg.norm(q))


def scene_for(problem: object, **options: object) -> StrikeScene:
    """The scene of a strike problem: a pool scene for a PoolStrike, a paddle one otherwise.

    The still solids are the problem's ``scene`` when it has one (:class:`problems.Scene`),
    else the ready-made ones (:attr:`StrikeScene.static_scene`).

    Args:
        problem: A :class:`problems.PoolStrike` or :class:`problems.PaddleStrike`.
        **options: Further :class:`StrikeScene` fields.

    Raises:
        InvalidInputError: Another kind of problem.
    """
    from optraj.problems.paddle_strike import PaddleStrike
    from optraj.problems.pool_strike import PoolStrike

    if isinstance(problem, (PoolStrike, PaddleStrike)):
        options.setdefault("surroundings", getattr(problem, "scene", None))
        make = pool_scene if isinstance(problem, PoolStrike) else paddle_scene
        return make(problem.robot, problem.ball, **options)
    raise InvalidInputError(
        f"problem must be a PoolStrike or a PaddleStrike, got {type(problem).__name__}",
        name="problem",
    )
