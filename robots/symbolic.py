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
from typing import Any

import casadi as ca
import pinocchio as pin

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.robots.joints import Joint, joint_transform, read_joints
from optraj.robots.rnea import rnea_expression
from optraj.robots.robot import Robot
from optraj.robots.spatial import const, cross, snap

__all__ = ["SymbolicModel"]


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
        self._joints: list[Joint] = read_joints(self._model)
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
                axis_world = kin.rotations[joint_index] @ const(joint.axis)
                if joint.kind == "revolute":
                    lin = cross(axis_world, p_frame - kin.positions[joint_index])
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
                local = joint_transform(joint, q)
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
        rot = rot_j @ const(snap(placement.rotation))
        pos = pos_j + rot_j @ const(snap(placement.translation).reshape(3))
        return rot, pos

    def _rnea_expression(self, q: ca.SX, v: ca.SX, a: ca.SX) -> ca.SX:
        """The RNEA joint torques of this model as expressions of ``q``, ``v`` and ``a``."""
        return rnea_expression(self._joints, self._model.gravity, self.nv, q, v, a)
