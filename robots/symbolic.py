"""Symbolic (CasADi) kinematics and inverse dynamics built from a Pinocchio model.

The PyPI ``pin`` wheel ships without ``pinocchio.casadi``, so this module walks the kinematic
tree of a :class:`pinocchio.Model` itself and assembles CasADi ``SX`` expressions for

* frame placements (forward kinematics),
* world-aligned frame Jacobians (geometric construction, one column per supporting joint),
* inverse dynamics with the recursive Newton-Euler algorithm (RNEA) in spatial algebra.

All conventions follow Pinocchio so the results can be compared one-to-one:

* Spatial motion vectors are stacked ``[linear; angular]``, spatial forces ``[force; torque]``.
* A placement ``M = (R, p)`` maps child coordinates into parent coordinates:
  ``x_parent = R @ x_child + p``.
* Joint ``i`` sits at ``jointPlacements[i]`` in the frame of its parent joint and then moves
  by its own joint transform (rotation about, or translation along, its axis).
* The RNEA base acceleration is ``-model.gravity`` and the returned torque includes the
  reflected rotor inertia ``model.armature * a``, exactly like ``pinocchio.rnea``.
* Jacobians match ``pinocchio.computeFrameJacobian(..., ReferenceFrame.LOCAL_WORLD_ALIGNED)``:
  the linear rows give the velocity of the frame origin, both blocks expressed in world axes.

Only single-DOF revolute and prismatic joints (aligned with an axis of the joint frame or
along an arbitrary constant axis) are supported; every other joint type is rejected when the
:class:`SymbolicModel` is constructed.

Example:
    >>> model = example_robot_data.load("panda").model  # doctest: +SKIP
    >>> sym = SymbolicModel(model)  # doctest: +SKIP
    >>> tau = sym.rnea()(q, v, a).full().ravel()  # doctest: +SKIP
"""

from __future__ import annotations

import operator
import re
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import casadi as ca
import numpy as np
import numpy.typing as npt
import pinocchio as pin

from optraj.errors import InvalidInputError, UnknownNameError, UnsupportedModelError
from optraj.robots.robot import Robot

__all__ = ["SymbolicModel"]

FloatArray = npt.NDArray[np.float64]
Motion = tuple[ca.SX, ca.SX]
"""Spatial motion vector as ``(linear, angular)``, each an ``SX`` of shape (3, 1)."""
Force = tuple[ca.SX, ca.SX]
"""Spatial force vector as ``(force, torque)``, each an ``SX`` of shape (3, 1)."""

_REVOLUTE_AXES: dict[str, tuple[float, float, float]] = {
    "JointModelRX": (1.0, 0.0, 0.0),
    "JointModelRY": (0.0, 1.0, 0.0),
    "JointModelRZ": (0.0, 0.0, 1.0),
}
_PRISMATIC_AXES: dict[str, tuple[float, float, float]] = {
    "JointModelPX": (1.0, 0.0, 0.0),
    "JointModelPY": (0.0, 1.0, 0.0),
    "JointModelPZ": (0.0, 0.0, 1.0),
}
_REVOLUTE_UNALIGNED = "JointModelRevoluteUnaligned"
_PRISMATIC_UNALIGNED = "JointModelPrismaticUnaligned"
_SNAP_TOL = 1e-14
_SUPPORTED_JOINTS = (
    *_REVOLUTE_AXES,
    *_PRISMATIC_AXES,
    _REVOLUTE_UNALIGNED,
    _PRISMATIC_UNALIGNED,
)


@dataclass(frozen=True)
class _Joint:
    """Constant description of one supported joint, read once from the Pinocchio model.

    Attributes:
        index: Joint index in the Pinocchio model (>= 1).
        parent: Index of the parent joint (0 is the universe).
        kind: ``"revolute"`` or ``"prismatic"``.
        axis: Unit joint axis in the joint frame [-], shape (3,).
        idx_q: Index of the joint coordinate in ``q``.
        idx_v: Index of the joint velocity in ``v``.
        rotation: Rotation of the joint placement w.r.t. the parent joint [-], shape (3, 3).
        translation: Translation of the joint placement w.r.t. the parent joint [m], shape (3,).
        mass: Body mass [kg].
        com: Body centre of mass in the joint frame [m], shape (3,).
        inertia: Rotational inertia about the centre of mass [kg m^2], shape (3, 3).
        armature: Reflected rotor inertia added to the joint torque [kg m^2 or kg].
    """

    index: int
    parent: int
    kind: Literal["revolute", "prismatic"]
    axis: FloatArray
    idx_q: int
    idx_v: int
    rotation: FloatArray
    translation: FloatArray
    mass: float
    com: FloatArray
    inertia: FloatArray
    armature: float


@dataclass
class _Kinematics:
    """Symbolic forward kinematics shared by all frame functions.

    Attributes:
        q: Joint position symbol [rad or m], shape (nq, 1).
        rotations: World rotation of every joint frame (index 0 is the universe).
        positions: World position of every joint origin [m] (index 0 is the universe).
    """

    q: ca.SX
    rotations: list[ca.SX]
    positions: list[ca.SX]


@dataclass
class _LocalPlacement:
    """Placement of a joint frame in its parent joint frame, ``jointPlacements[i] * M_joint(q)``.

    The rotation is available both factored (``fixed_rot @ joint_rot``, cheaper when chaining
    world rotations) and multiplied out once (``rot``, cheaper when the same rotation is
    applied to many vectors as in the RNEA).

    Attributes:
        fixed_rot: Constant rotation of the joint placement [-], shape (3, 3).
        joint_rot: Rotation about the joint axis [-], shape (3, 3), or ``None`` (prismatic).
        rot: ``fixed_rot @ joint_rot`` [-], shape (3, 3).
        trans: Joint origin in the parent frame [m], shape (3, 1).
    """

    fixed_rot: ca.SX
    joint_rot: ca.SX | None
    rot: ca.SX
    trans: ca.SX

    def rotate(self, x: ca.SX) -> ca.SX:
        """Rotate a child-frame vector into the parent frame, shape (3, 1) -> (3, 1)."""
        return self.rot @ x

    def rotate_inv(self, x: ca.SX) -> ca.SX:
        """Rotate a parent-frame vector into the child frame, shape (3, 1) -> (3, 1)."""
        return self.rot.T @ x


# ---------------------------------------------------------------------------------------------
# Small 3-D and spatial-algebra helpers on CasADi SX expressions.
# ---------------------------------------------------------------------------------------------


def _const(values: npt.ArrayLike) -> ca.SX:
    """Wrap a numeric array as a dense SX constant (zeros stay as explicit constants).

    Args:
        values: Numeric vector or matrix.

    Returns:
        Dense SX constant with the same shape (vectors become columns).
    """
    return ca.SX(ca.DM(np.asarray(values, dtype=float)))


def _snap(values: npt.ArrayLike) -> FloatArray:
    """Replace round-off noise (e.g. ``cos(pi/2)`` from URDF ``rpy``) by exact zeros.

    Exact zeros let CasADi drop the corresponding products, which keeps graphs compact; the
    change is below 1e-14 and thus far beneath any meaningful tolerance.

    Args:
        values: Numeric array read from the Pinocchio model.

    Returns:
        Float copy with entries of magnitude below 1e-14 set to 0.
    """
    out = np.array(values, dtype=float)
    out[np.abs(out) < _SNAP_TOL] = 0.0
    return out


def _cross(a: ca.SX, b: ca.SX) -> ca.SX:
    """Cross product of two 3-vectors.

    Args:
        a: First vector, shape (3, 1).
        b: Second vector, shape (3, 1).

    Returns:
        ``a x b``, shape (3, 1).
    """
    return ca.vertcat(
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    )


def _skew(w: npt.ArrayLike) -> FloatArray:
    """Numeric skew-symmetric matrix such that ``skew(w) @ x == w x x``.

    Args:
        w: Vector, shape (3,).

    Returns:
        Skew-symmetric matrix, shape (3, 3).
    """
    x, y, z = np.asarray(w, dtype=float)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _axis_rotation(axis: FloatArray, cos_q: ca.SX, sin_q: ca.SX) -> ca.SX:
    """Rotation matrix about a constant unit axis (Rodrigues), assembled entry by entry.

    Each entry is ``(delta_ij - a_i a_j) cos + skew(a)_ij sin + a_i a_j``; terms whose numeric
    coefficient vanishes are dropped so aligned axes give the familiar sparse matrices.

    Args:
        axis: Unit rotation axis [-], shape (3,).
        cos_q: Cosine of the joint angle.
        sin_q: Sine of the joint angle.

    Returns:
        Rotation matrix, shape (3, 3).
    """
    outer = np.outer(axis, axis)
    cos_coeff = np.eye(3) - outer
    sin_coeff = _skew(axis)
    rows = []
    for i in range(3):
        row = []
        for j in range(3):
            entry = ca.SX(float(outer[i, j]))
            if cos_coeff[i, j] != 0.0:
                entry = entry + float(cos_coeff[i, j]) * cos_q
            if sin_coeff[i, j] != 0.0:
                entry = entry + float(sin_coeff[i, j]) * sin_q
            row.append(entry)
        rows.append(ca.horzcat(*row))
    return ca.vertcat(*rows)


def _motion_act_inv(placement: _LocalPlacement, m: Motion) -> Motion:
    """Express a motion given in parent coordinates in child coordinates (``M.actInv``).

    Args:
        placement: Placement of the child frame in the parent frame.
        m: Motion ``(linear, angular)`` in parent coordinates.

    Returns:
        The same motion in child coordinates.
    """
    lin, ang = m
    return placement.rotate_inv(lin - _cross(placement.trans, ang)), placement.rotate_inv(ang)


def _force_act(placement: _LocalPlacement, f: Force) -> Force:
    """Express a force given in child coordinates in parent coordinates (``M.act``).

    Args:
        placement: Placement of the child frame in the parent frame.
        f: Force ``(force, torque)`` in child coordinates.

    Returns:
        The same force in parent coordinates.
    """
    lin = placement.rotate(f[0])
    return lin, placement.rotate(f[1]) + _cross(placement.trans, lin)


def _motion_cross_motion(m1: Motion, m2: Motion) -> Motion:
    """Spatial cross product of two motions, ``m1 x m2``.

    Args:
        m1: Motion ``(v1, w1)``.
        m2: Motion ``(v2, w2)``.

    Returns:
        ``(w1 x v2 + v1 x w2, w1 x w2)``.
    """
    v1, w1 = m1
    v2, w2 = m2
    return _cross(w1, v2) + _cross(v1, w2), _cross(w1, w2)


def _motion_cross_force(m: Motion, f: Force) -> Force:
    """Dual spatial cross product of a motion and a force, ``m x* f``.

    Args:
        m: Motion ``(v, w)``.
        f: Force ``(force, torque)``.

    Returns:
        ``(w x force, w x torque + v x force)``.
    """
    v, w = m
    lin, ang = f
    return _cross(w, lin), _cross(w, ang) + _cross(v, lin)


def _inertia_times_motion(joint: _Joint, m: Motion) -> Force:
    """Apply the spatial inertia of a body to a motion (momentum or ``I a``).

    With mass ``mass``, centre of mass ``c`` and rotational inertia ``I_c`` about ``c``:
    ``force = mass (v - c x w)`` and ``torque = I_c w + c x force``.

    Args:
        joint: Joint carrying the body (holds mass, COM and inertia).
        m: Motion ``(v, w)`` in the joint frame.

    Returns:
        Spatial force in the joint frame.
    """
    v, w = m
    com = _const(joint.com)
    lin = joint.mass * (v - _cross(com, w))
    return lin, _const(joint.inertia) @ w + _cross(com, lin)


def _add(a: tuple[ca.SX, ca.SX], b: tuple[ca.SX, ca.SX]) -> tuple[ca.SX, ca.SX]:
    """Add two spatial vectors of the same kind component by component.

    Args:
        a: First spatial vector.
        b: Second spatial vector.

    Returns:
        Component-wise sum.
    """
    return a[0] + b[0], a[1] + b[1]


# ---------------------------------------------------------------------------------------------
# Public class.
# ---------------------------------------------------------------------------------------------


class SymbolicModel:
    """CasADi kinematics and inverse dynamics of a Pinocchio model with 1-DOF joints.

    Functions are built lazily on first request and cached, so repeated calls are cheap.
    All returned :class:`casadi.Function` objects are ``SX`` based, take column vectors and
    return ``casadi.DM`` values when called with numbers (use ``.full()`` for NumPy).

    Functions are safe to request from several threads (building is serialised).

    Args:
        model: A :class:`robots.Robot`, or a Pinocchio model whose joints (except the
            universe) are all of type ``JointModelR{X,Y,Z}``, ``JointModelP{X,Y,Z}``,
            ``JointModelRevoluteUnaligned`` or ``JointModelPrismaticUnaligned``. A private copy
            is kept.

    Raises:
        UnsupportedModelError: If the model contains any other joint type.
        InvalidInputError: If ``model`` is neither a Robot nor a pinocchio.Model.
    """

    def __init__(self, model: pin.Model | Robot) -> None:
        """Validate ``model`` and prepare lazy construction (see the class docstring)."""
        if isinstance(model, Robot):
            model = model.model
        if not isinstance(model, pin.Model):
            raise InvalidInputError(
                f"SymbolicModel needs a robots.Robot or a pinocchio.Model, got "
                f"{type(model).__name__}",
                name="model",
            )
        self._setup(model)

    def _setup(self, model: pin.Model) -> None:
        """Copy and validate the model and reset all lazily built expressions."""
        self._model: pin.Model = pin.Model(model)
        self._joints: list[_Joint] = _read_joints(self._model)
        self._kin: _Kinematics | None = None
        self._cache: dict[tuple[str, int], ca.Function] = {}
        self._lock = threading.RLock()

    # -- pickling ---------------------------------------------------------------------------

    def __getstate__(self) -> dict[str, Any]:
        """Return the picklable state: only the Pinocchio model (functions are rebuilt)."""
        return {"model": self._model}

    def __setstate__(self, state: dict[str, Any]) -> None:
        """Restore from :meth:`__getstate__`; CasADi functions are rebuilt on demand."""
        self._setup(state["model"])

    def __repr__(self) -> str:
        """Short description with the model name and dimensions."""
        return f"SymbolicModel(name={self._model.name!r}, nq={self.nq}, nv={self.nv})"

    # -- basic properties -------------------------------------------------------------------

    @property
    def model(self) -> pin.Model:
        """pin.Model: The (copied) Pinocchio model the expressions are built from.

        Treat it as read-only: cached functions are not rebuilt if it is modified.
        """
        return self._model

    @property
    def nq(self) -> int:
        """int: Number of joint position coordinates."""
        return int(self._model.nq)

    @property
    def nv(self) -> int:
        """int: Number of joint velocity coordinates (equal to ``nq`` for supported joints)."""
        return int(self._model.nv)

    def frame_id(self, frame: str | int) -> int:
        """Resolve a frame name or index to a Pinocchio frame index.

        Args:
            frame: Frame name, or frame index in ``model.frames``.

        Returns:
            Frame index.

        Raises:
            UnknownNameError: If the name is unknown (the message lists the frames).
            InvalidInputError: If the index is out of range or not an integer.
        """
        model = self._model
        names = [f.name for f in model.frames]
        if isinstance(frame, str):
            if model.existFrame(frame):
                return int(model.getFrameId(frame))
            raise UnknownNameError(f"frame of model {model.name!r}", frame, names)
        if isinstance(frame, bool):
            raise InvalidInputError(
                f"Frame must be a name or an index, got {frame!r}.", name="frame", value=frame
            )
        try:
            index = operator.index(frame)
        except TypeError:
            raise InvalidInputError(
                f"Frame must be a name (str) or an index (int), got {type(frame).__name__}.",
                name="frame",
                value=frame,
            ) from None
        if not 0 <= index < len(names):
            raise InvalidInputError(
                f"Frame index {index} out of range: model {model.name!r} has {len(names)} "
                f"frames (0..{len(names) - 1}).",
                name="frame",
                value=frame,
            )
        return index

    # -- kinematics -------------------------------------------------------------------------

    def frame_pose(self, frame: str | int) -> ca.Function:
        """Forward kinematics of one frame as a homogeneous transform.

        Args:
            frame: Frame name or index.

        Returns:
            Function ``frame_pose_<name>``: ``q`` [rad or m], shape (nq,) ->
            ``T`` = T_world_frame, shape (4, 4) (rotation [-], translation [m]).

        Raises:
            UnknownNameError: If the frame is unknown.
        """

        def build(fid: int) -> ca.SX:
            rot, pos = self._frame_placement(fid)
            return ca.vertcat(ca.horzcat(rot, pos), ca.horzcat(ca.SX.zeros(1, 3), ca.SX(1.0)))

        return self._frame_function("pose", frame, "T", build)

    def frame_position(self, frame: str | int) -> ca.Function:
        """World position of a frame origin.

        Args:
            frame: Frame name or index.

        Returns:
            Function ``frame_position_<name>``: ``q`` [rad or m], shape (nq,) ->
            ``p`` [m], shape (3,).

        Raises:
            UnknownNameError: If the frame is unknown.
        """
        return self._frame_function(
            "position", frame, "p", lambda fid: self._frame_placement(fid)[1]
        )

    def frame_rotation(self, frame: str | int) -> ca.Function:
        """World orientation of a frame.

        Args:
            frame: Frame name or index.

        Returns:
            Function ``frame_rotation_<name>``: ``q`` [rad or m], shape (nq,) ->
            ``R`` = R_world_frame [-], shape (3, 3).

        Raises:
            UnknownNameError: If the frame is unknown.
        """
        return self._frame_function(
            "rotation", frame, "R", lambda fid: self._frame_placement(fid)[0]
        )

    def frame_jacobian(self, frame: str | int) -> ca.Function:
        """World-aligned geometric Jacobian of a frame.

        Column ``k`` maps joint velocity ``v[k]`` to the spatial velocity of the frame:
        rows 0-2 are the linear velocity of the frame origin and rows 3-5 the angular
        velocity, both expressed in world axes (Pinocchio's ``LOCAL_WORLD_ALIGNED``).

        Args:
            frame: Frame name or index.

        Returns:
            Function ``frame_jacobian_<name>``: ``q`` [rad or m], shape (nq,) ->
            ``J`` [m/rad or -], shape (6, nv).

        Raises:
            UnknownNameError: If the frame is unknown.
        """

        def build(fid: int) -> ca.SX:
            kin = self._kinematics()
            _, p_frame = self._frame_placement(fid)
            columns = [ca.SX.zeros(6, 1) for _ in range(self.nv)]
            joint_index = int(self._model.frames[fid].parentJoint)
            while joint_index > 0:
                joint = self._joints[joint_index - 1]
                axis_world = kin.rotations[joint_index] @ _const(joint.axis)
                if joint.kind == "revolute":
                    lin = _cross(axis_world, p_frame - kin.positions[joint_index])
                    columns[joint.idx_v] = ca.vertcat(lin, axis_world)
                else:
                    columns[joint.idx_v] = ca.vertcat(axis_world, ca.SX.zeros(3, 1))
                joint_index = joint.parent
            return ca.horzcat(*columns) if columns else ca.SX.zeros(6, 0)

        return self._frame_function("jacobian", frame, "J", build)

    # -- dynamics ---------------------------------------------------------------------------

    def rnea(self) -> ca.Function:
        """Inverse dynamics by the recursive Newton-Euler algorithm.

        Equals ``pinocchio.rnea(model, data, q, v, a)``: gravity, Coriolis/centrifugal and
        inertial torques plus ``model.armature * a``.

        Returns:
            Function ``rnea``: (``q`` [rad or m], shape (nq,); ``v`` [rad/s or m/s], shape
            (nv,); ``a`` [rad/s^2 or m/s^2], shape (nv,)) -> ``tau`` [N m or N], shape (nv,).
        """
        key = ("rnea", 0)
        with self._lock:
            if key not in self._cache:
                q = ca.SX.sym("q", self.nq)
                v = ca.SX.sym("v", self.nv)
                a = ca.SX.sym("a", self.nv)
                tau = self._rnea_expression(q, v, a)
                self._cache[key] = ca.Function("rnea", [q, v, a], [tau], ["q", "v", "a"], ["tau"])
            return self._cache[key]

    def gravity_torque(self) -> ca.Function:
        """Static joint torques that hold the robot against gravity (RNEA with v = a = 0).

        Returns:
            Function ``gravity_torque``: ``q`` [rad or m], shape (nq,) ->
            ``tau`` [N m or N], shape (nv,).
        """
        key = ("gravity", 0)
        with self._lock:
            if key not in self._cache:
                q = ca.SX.sym("q", self.nq)
                zeros = ca.SX.zeros(self.nv, 1)
                tau = self._rnea_expression(q, zeros, zeros)
                self._cache[key] = ca.Function("gravity_torque", [q], [tau], ["q"], ["tau"])
            return self._cache[key]

    # -- internals --------------------------------------------------------------------------

    def _frame_function(
        self, kind: str, frame: str | int, output: str, build: Callable[[int], ca.SX]
    ) -> ca.Function:
        """Build (once) and cache the function ``q -> build(frame)`` named after the frame.

        Args:
            kind: What the function gives (``"pose"``, ``"jacobian"``, ...), part of its name.
            frame: Frame name or index.
            output: Name of the function's output.
            build: Expression of the kinematics symbol ``q`` for a frame index.
        """
        fid = self.frame_id(frame)
        key = (kind, fid)
        with self._lock:
            if key not in self._cache:
                q = self._kinematics().q
                expression = ca.densify(build(fid))
                self._cache[key] = ca.Function(
                    f"frame_{kind}_{self._tag(fid)}", [q], [expression], ["q"], [output]
                )
            return self._cache[key]

    def _tag(self, fid: int) -> str:
        """Turn a frame name into a valid CasADi function-name suffix."""
        tag = re.sub(r"[^0-9A-Za-z]+", "_", self._model.frames[fid].name).strip("_")
        return tag or f"frame{fid}"

    def _joint_transform(self, joint: _Joint, q: ca.SX) -> _LocalPlacement:
        """Placement of a joint frame in its parent joint frame at position ``q``.

        Args:
            joint: Joint description.
            q: Full joint-position vector [rad or m], shape (nq, 1).

        Returns:
            ``jointPlacements[i] * joint_motion(q_i)`` in factored form.
        """
        q_i = q[joint.idx_q]
        fixed_rot = _const(joint.rotation)
        trans = _const(joint.translation)
        if joint.kind == "revolute":
            joint_rot = _axis_rotation(joint.axis, ca.cos(q_i), ca.sin(q_i))
            return _LocalPlacement(
                fixed_rot=fixed_rot, joint_rot=joint_rot, rot=fixed_rot @ joint_rot, trans=trans
            )
        shift = _const(_snap(joint.rotation @ joint.axis)) * q_i
        return _LocalPlacement(
            fixed_rot=fixed_rot, joint_rot=None, rot=fixed_rot, trans=trans + shift
        )

    def _kinematics(self) -> _Kinematics:
        """Build (once) the symbolic world placement of every joint frame."""
        with self._lock:
            return self._build_kinematics()

    def _build_kinematics(self) -> _Kinematics:
        if self._kin is None:
            q = ca.SX.sym("q", self.nq)
            rotations: list[ca.SX] = [ca.SX.eye(3)]
            positions: list[ca.SX] = [ca.SX.zeros(3, 1)]
            for joint in self._joints:
                local = self._joint_transform(joint, q)
                if joint.parent == 0:
                    rot = local.fixed_rot
                    pos = local.trans
                else:
                    parent_rot = rotations[joint.parent]
                    rot = parent_rot @ local.fixed_rot
                    pos = positions[joint.parent] + parent_rot @ local.trans
                if local.joint_rot is not None:
                    rot = rot @ local.joint_rot
                rotations.append(rot)
                positions.append(pos)
            self._kin = _Kinematics(q=q, rotations=rotations, positions=positions)
        return self._kin

    def _frame_placement(self, fid: int) -> tuple[ca.SX, ca.SX]:
        """World rotation and position of a frame as SX expressions of the kinematics ``q``.

        Args:
            fid: Frame index.

        Returns:
            ``(R_world_frame, p_world_frame)``, shapes (3, 3) and (3, 1).
        """
        kin = self._kinematics()
        frame = self._model.frames[fid]
        joint_index = int(frame.parentJoint)
        rot_j = kin.rotations[joint_index]
        pos_j = kin.positions[joint_index]
        placement = frame.placement
        rot = rot_j @ _const(_snap(placement.rotation))
        pos = pos_j + rot_j @ _const(_snap(placement.translation).reshape(3))
        return rot, pos

    def _rnea_expression(self, q: ca.SX, v: ca.SX, a: ca.SX) -> ca.SX:
        """RNEA in local joint frames (Featherstone), following Pinocchio's conventions.

        Args:
            q: Joint positions [rad or m], shape (nq, 1).
            v: Joint velocities [rad/s or m/s], shape (nv, 1) (may be numeric zeros).
            a: Joint accelerations [rad/s^2 or m/s^2], shape (nv, 1) (may be numeric zeros).

        Returns:
            Joint torques/forces [N m or N], shape (nv, 1).
        """
        n = len(self._joints)
        gravity = self._model.gravity
        zero = ca.SX.zeros(3, 1)
        base_vel: Motion = (zero, zero)
        base_acc: Motion = (_const(-gravity.linear), _const(-gravity.angular))

        placements: list[_LocalPlacement] = []
        vels: list[Motion] = []
        forces: list[Force] = []
        # Forward pass: velocities, accelerations (gravity folded into the base) and forces.
        accs: list[Motion] = []
        for joint in self._joints:
            local = self._joint_transform(joint, q)
            placements.append(local)
            axis = _const(joint.axis)
            qd = v[joint.idx_v]
            qdd = a[joint.idx_v]
            if joint.kind == "revolute":
                s_qd: Motion = (zero, axis * qd)
                s_qdd: Motion = (zero, axis * qdd)
            else:
                s_qd = (axis * qd, zero)
                s_qdd = (axis * qdd, zero)
            if joint.parent == 0:
                parent_vel, parent_acc = base_vel, base_acc
            else:
                parent_vel, parent_acc = vels[joint.parent - 1], accs[joint.parent - 1]
            vel = _add(_motion_act_inv(local, parent_vel), s_qd)
            acc = _add(
                _add(_motion_act_inv(local, parent_acc), s_qdd),
                _motion_cross_motion(vel, s_qd),
            )
            vels.append(vel)
            accs.append(acc)
            forces.append(
                _add(
                    _inertia_times_motion(joint, acc),
                    _motion_cross_force(vel, _inertia_times_motion(joint, vel)),
                )
            )

        # Backward pass: project on the motion subspace and propagate to the parent.
        tau: list[ca.SX] = [ca.SX(0.0)] * self.nv
        for k in range(n - 1, -1, -1):
            joint = self._joints[k]
            lin, ang = forces[k]
            axis = _const(joint.axis)
            projected = ca.dot(axis, ang if joint.kind == "revolute" else lin)
            if joint.armature != 0.0:
                projected = projected + joint.armature * a[joint.idx_v]
            tau[joint.idx_v] = projected
            if joint.parent > 0:
                forces[joint.parent - 1] = _add(
                    forces[joint.parent - 1], _force_act(placements[k], forces[k])
                )
        return ca.vertcat(*tau) if tau else ca.SX.zeros(0, 1)


def _read_joints(model: pin.Model) -> list[_Joint]:
    """Read and validate the joints of a Pinocchio model.

    Args:
        model: Pinocchio model.

    Returns:
        One :class:`_Joint` per joint, universe excluded, in model order.

    Raises:
        UnsupportedModelError: If a joint type is not a supported 1-DOF revolute/prismatic.
    """
    joints: list[_Joint] = []
    for index in range(1, model.njoints):
        jmodel = model.joints[index]
        jtype = jmodel.shortname()
        name = model.names[index]
        if jtype not in _SUPPORTED_JOINTS or jmodel.nq != 1 or jmodel.nv != 1:
            raise UnsupportedModelError(
                f"Joint {name!r} (index {index}) of model {model.name!r} has type {jtype}, "
                f"which SymbolicModel does not support. Supported joint types: "
                f"{', '.join(_SUPPORTED_JOINTS)}."
            )
        kind: Literal["revolute", "prismatic"]
        if jtype in _REVOLUTE_AXES:
            kind, axis = "revolute", np.array(_REVOLUTE_AXES[jtype])
        elif jtype in _PRISMATIC_AXES:
            kind, axis = "prismatic", np.array(_PRISMATIC_AXES[jtype])
        else:
            kind = "revolute" if jtype == _REVOLUTE_UNALIGNED else "prismatic"
            axis = np.array(jmodel.extract().axis, dtype=float).reshape(3)
        placement = model.jointPlacements[index]
        inertia = model.inertias[index]
        joints.append(
            _Joint(
                index=index,
                parent=int(model.parents[index]),
                kind=kind,
                axis=axis,
                idx_q=int(jmodel.idx_q),
                idx_v=int(jmodel.idx_v),
                rotation=_snap(placement.rotation),
                translation=_snap(placement.translation).reshape(3),
                mass=float(inertia.mass),
                com=_snap(inertia.lever).reshape(3),
                inertia=_snap(inertia.inertia),
                armature=float(model.armature[jmodel.idx_v]),
            )
        )
    return joints
