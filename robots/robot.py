"""The Robot: a Pinocchio model with its limits, tool frame, named poses and kinematics.

Conventions used throughout optraj:

* Poses are 4x4 homogeneous matrices ``T_world_frame`` that map frame coordinates to world
  (robot base) coordinates.
* Jacobians are world-aligned (Pinocchio's ``LOCAL_WORLD_ALIGNED``): rows ``[linear; angular]``,
  the linear rows giving the velocity of the frame origin in world axes, shape (6, n).
* The tool frame's z axis is the tool axis: the cue axis (Sawyer), the paddle normal (paddle4),
  the approach direction between the fingers (youBot).
"""

from __future__ import annotations

import functools
import hashlib
import threading
from collections.abc import Mapping
from typing import Any, Literal

import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, UnknownNameError, UnsupportedModelError
from optraj.robots.limits import JointLimits
from optraj.validation import as_batch, as_vector

__all__ = ["Robot"]

FloatArray = NDArray[np.float64]

_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_ROWS = {"full": slice(0, 6), "translation": slice(0, 3), "rotation": slice(3, 6)}


class Robot:
    """A fixed-base arm with one-degree-of-freedom joints.

    Build one with :func:`robots.load`. The object is picklable (the Pinocchio data is rebuilt
    on unpickling), so it can be shipped to worker processes.

    Attributes:
        name: Robot name, e.g. ``"sawyer"``.
        model: The Pinocchio model; its position/velocity/effort limits equal :attr:`limits`.
        limits: Joint limits used for planning.
        tool_frame: Name of the tool frame (its z axis is the tool axis).
        tool_frame_id: Pinocchio index of the tool frame.
        poses: Named configurations, e.g. ``{"home": ..., "neutral": ...}``; always has "home".
        description: One line on where the model comes from.
    """

    def __init__(
        self,
        name: str,
        model: pin.Model,
        limits: JointLimits,
        tool_frame: str,
        poses: Mapping[str, ArrayLike],
        description: str = "",
    ) -> None:
        if model.nq != model.nv:
            raise UnsupportedModelError(
                f"robot {name!r}: nq = {model.nq} differs from nv = {model.nv}; optraj handles "
                "fixed-base arms with one-degree-of-freedom joints only"
            )
        joint_names = tuple(model.names[i] for i in range(1, model.njoints))
        if len(joint_names) != model.nv:
            raise UnsupportedModelError(
                f"robot {name!r}: {len(joint_names)} joints for {model.nv} degrees of freedom; "
                "every joint must have exactly one degree of freedom"
            )
        if limits.names != joint_names:
            raise InvalidInputError(
                f"robot {name!r}: limits are given for joints {limits.names}, "
                f"the model has {joint_names}",
                name="limits",
            )
        if "home" not in poses:
            raise InvalidInputError(
                f"robot {name!r}: poses must include 'home', got {sorted(poses)}", name="poses"
            )
        self.name = name
        self.model = model.copy()
        self.limits = limits
        self.description = description
        self.model.lowerPositionLimit = limits.lower.copy()
        self.model.upperPositionLimit = limits.upper.copy()
        self.model.velocityLimit = limits.velocity.copy()
        self.model.effortLimit = limits.effort.copy()
        self.tool_frame = tool_frame
        self.tool_frame_id = self.frame_id(tool_frame)
        checked: dict[str, FloatArray] = {}
        for pose_name, q in poses.items():
            value = as_vector(q, f"pose {pose_name!r}", self.dof)
            limits.check_position(value, tolerance=1e-9, context=f"{name} pose {pose_name!r}")
            value.setflags(write=False)
            checked[pose_name] = value
        self.poses: dict[str, FloatArray] = checked
        self._local = threading.local()

    # ------------------------------------------------------------------ basics

    def __repr__(self) -> str:
        return f"Robot({self.name!r}, dof={self.dof}, tool_frame={self.tool_frame!r})"

    def __getstate__(self) -> dict[str, Any]:
        state = self.__dict__.copy()
        del state["_local"]
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._local = threading.local()

    @functools.cached_property
    def fingerprint(self) -> str:
        """A digest of everything a plan for this robot depends on (hex, 64 characters).

        Two robots share it only if their joints (names, types, placements), link inertias,
        frames, gravity, armature, tool frame and limits are bit for bit the same: the key of
        every cache of compiled models, whatever the robot's name (a Sawyer with a longer cue
        has another).
        """
        digest = hashlib.sha256()

        def add(*values: object) -> None:
            for value in values:
                if isinstance(value, np.ndarray):
                    digest.update(np.ascontiguousarray(value, dtype=float).tobytes())
                else:
                    digest.update(repr(value).encode())
                digest.update(b"|")

        m = self.model
        add(self.name, self.tool_frame, m.nq, m.nv, m.gravity.vector, np.asarray(m.armature))
        for i in range(1, m.njoints):
            inertia = m.inertias[i]
            add(m.names[i], m.joints[i].shortname(), int(m.parents[i]))
            add(m.jointPlacements[i].homogeneous, inertia.mass, inertia.lever, inertia.inertia)
        for frame in m.frames:
            add(frame.name, int(frame.parentJoint), str(frame.type), frame.placement.homogeneous)
        limits = self.limits
        add(limits.names, limits.kinds)
        add(limits.lower, limits.upper, limits.velocity, limits.acceleration)
        add(limits.jerk, limits.effort)
        return digest.hexdigest()

    @property
    def dof(self) -> int:
        """Number of joints (degrees of freedom)."""
        return int(self.model.nv)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Joint names in configuration order."""
        return self.limits.names

    @property
    def home(self) -> FloatArray:
        """The home configuration [rad or m], shape (n,)."""
        return self.poses["home"]

    @property
    def data(self) -> pin.Data:
        """Pinocchio workspace of the calling thread (one per thread, created on first use)."""
        data = getattr(self._local, "data", None)
        if data is None:
            data = self._local.data = self.model.createData()
        return data

    def frame_id(self, frame: str | None = None) -> int:
        """Pinocchio index of a frame; ``None`` means the tool frame.

        Raises:
            UnknownNameError: No frame of that name; the message lists the frames.
        """
        if frame is None:
            return self.tool_frame_id
        if not isinstance(frame, str):
            raise InvalidInputError(
                f"frame must be a frame name (str) or None, got {frame!r}", name="frame"
            )
        if not self.model.existFrame(frame):
            raise UnknownNameError(
                f"frame of robot {self.name!r}", frame, [f.name for f in self.model.frames]
            )
        return int(self.model.getFrameId(frame))

    def random_configurations(self, count: int, rng: np.random.Generator) -> FloatArray:
        """Configurations drawn uniformly within the position limits, shape (count, n).

        Args:
            count: How many, >= 0.
            rng: A seeded ``np.random.default_rng(seed)`` for reproducible draws.
        """
        return self.limits.sample(rng, count)

    # ------------------------------------------------------------ kinematics

    def frame_pose(self, q: ArrayLike, frame: str | None = None) -> FloatArray:
        """Pose of a frame in the world (base) frame.

        Args:
            q: Joint positions [rad or m], shape (n,) or (m, n).
            frame: Frame name; the tool frame when ``None``.

        Returns:
            ``T_world_frame``, shape (4, 4), or (m, 4, 4) for a stack of configurations.
        """
        batch, single = as_batch(q, "q", self.dof)
        fid = self.frame_id(frame)
        out = np.empty((batch.shape[0], 4, 4))
        for k, qk in enumerate(batch):
            pin.forwardKinematics(self.model, self.data, qk)
            out[k] = pin.updateFramePlacement(self.model, self.data, fid).homogeneous
        return out[0] if single else out

    def tool_pose(self, q: ArrayLike) -> FloatArray:
        """Pose of the tool frame ``T_world_tool``, shape (4, 4) or (m, 4, 4)."""
        return self.frame_pose(q)

    def tool_position(self, q: ArrayLike) -> FloatArray:
        """Tool frame origin in world coordinates [m], shape (3,) or (m, 3)."""
        return self.frame_pose(q)[..., :3, 3]

    def jacobian(self, q: ArrayLike, frame: str | None = None) -> FloatArray:
        r"""World-aligned frame Jacobian.

        .. math:: [\dot p; \omega] = J(q) \dot q

        with :math:`\dot p` the velocity of the frame origin and :math:`\omega` the angular
        velocity, both in world axes.

        Args:
            q: Joint positions [rad or m], shape (n,) or (m, n).
            frame: Frame name; the tool frame when ``None``.

        Returns:
            J, shape (6, n) or (m, 6, n); rows [linear [m/s]; angular [rad/s]] per unit joint rate.
        """
        batch, single = as_batch(q, "q", self.dof)
        fid = self.frame_id(frame)
        out = np.empty((batch.shape[0], 6, self.dof))
        for k, qk in enumerate(batch):
            out[k] = pin.computeFrameJacobian(self.model, self.data, qk, fid, _WORLD_ALIGNED)
        return out[0] if single else out

    def manipulability(
        self,
        q: ArrayLike,
        frame: str | None = None,
        part: Literal["full", "translation", "rotation"] = "full",
    ) -> float | FloatArray:
        r"""Yoshikawa's manipulability: the product of the Jacobian's singular values.

        Equals :math:`\sqrt{\det(J J^T)}` when the arm has at least as many joints as task
        rows; it is 0 at a singularity of the chosen rows.

        Args:
            q: Joint positions [rad or m], shape (n,) or (m, n).
            frame: Frame name; the tool frame when ``None``.
            part: Which rows of J: ``"full"`` (6), ``"translation"`` or ``"rotation"`` (3).

        Returns:
            A float, or shape (m,) for a stack of configurations.
        """
        if not isinstance(part, str) or part not in _ROWS:
            raise UnknownNameError("manipulability part", str(part), _ROWS)
        jac = self.jacobian(q, frame)
        rows = jac[..., _ROWS[part], :]
        values = np.prod(np.linalg.svd(rows, compute_uv=False), axis=-1)
        return float(values) if values.ndim == 0 else values

    # --------------------------------------------------------------- dynamics

    def inverse_dynamics(self, q: ArrayLike, v: ArrayLike, a: ArrayLike) -> FloatArray:
        """Joint torques/forces for a motion, by Pinocchio's RNEA (gravity included).

        Args:
            q: Joint positions [rad or m], shape (n,) or (m, n).
            v: Joint velocities [rad/s or m/s], same shape as q.
            a: Joint accelerations [rad/s^2 or m/s^2], same shape as q.

        Returns:
            Torques [N m] / forces [N], same shape as q.
        """
        qs, single = as_batch(q, "q", self.dof)
        vs, _ = as_batch(v, "v", self.dof)
        accs, _ = as_batch(a, "a", self.dof)
        if not (qs.shape == vs.shape == accs.shape):
            raise InvalidInputError(
                f"q, v and a must have the same shape, got {qs.shape}, {vs.shape}, {accs.shape}",
                name="v",
            )
        out = np.empty_like(qs)
        for k in range(qs.shape[0]):
            out[k] = pin.rnea(self.model, self.data, qs[k], vs[k], accs[k])
        _require_finite(out, "inverse dynamics")
        return out[0] if single else out

    def gravity_torque(self, q: ArrayLike) -> FloatArray:
        """Torques/forces that hold the arm still against gravity [N m or N], like q's shape."""
        qs, single = as_batch(q, "q", self.dof)
        out = np.empty_like(qs)
        for k in range(qs.shape[0]):
            out[k] = pin.computeGeneralizedGravity(self.model, self.data, qs[k])
        _require_finite(out, "gravity torque")
        return out[0] if single else out


def _require_finite(values: FloatArray, what: str) -> None:
    """Raise when a computation overflowed (inputs too large to be physical)."""
    if not np.all(np.isfinite(values)):
        raise InvalidInputError(
            f"{what} overflowed to a non-finite value; the velocities or accelerations given "
            "are far beyond anything physical",
            name="v",
        )
