r"""A :class:`controllers.Plant` whose arm, tool and ball are integrated by MuJoCo.

:class:`MujocoPlant` has the face and the servo of :class:`controllers.DynamicPlant`: each
joint's actuator applies

.. math:: \tau = g(q) + \tau_{ff} + b \, \mathrm{diag}(M(q)) \, (u - \dot q),

clipped to the effort limits, with :math:`u` the joint velocity command and
:math:`\tau_{ff}` the command's feed-forward torque. Gravity and ``diag(M)`` come from the
*nominal* scene (the URDF with the tool, without the scene's model error), evaluated at the
start of every control step; the motion is MuJoCo's rigid-body dynamics of the *true* scene
(link masses scaled, a payload), with the ball free and the tool touching it through the
contact pairs of :mod:`physics.scene`. The servo's damping term is integrated implicitly
(``implicitfast``). Around contact the physics step drops to the scene's fine step
(:class:`~physics.contact_watch.ContactWatch`).

>>> plant = physics.MujocoPlant(physics.pool_scene(robot, ball=shot.ball))
>>> result = controllers.simulate(robot, traj, controller, plant=plant)
>>> physics.outcome(result, shot).heading_error   # [deg]

:meth:`MujocoPlant.record` hands the ball's path and the contact to
:func:`physics.outcome` (through ``Result.record``).
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.controllers.plant import Plant, PlantState, frozen_state
from optraj.errors import InvalidInputError
from optraj.physics.contact_watch import ContactWatch
from optraj.physics.scene import StrikeScene, World
from optraj.validation import as_flag, as_positive

__all__ = ["MujocoPlant"]

FloatArray = NDArray[np.float64]


class MujocoPlant(Plant):
    """An arm in a MuJoCo strike world, driven by a velocity servo per joint.

    Attributes:
        scene: The world's recipe (its robot is the plant's).
        bandwidth: Servo bandwidth :math:`b` [rad/s], > 0 (the same default as
            :class:`controllers.DynamicPlant`, 200 rad/s).
        saturate: Whether actuator torques are clipped to the effort limits.
        world: The compiled true world.
        data: Its MuJoCo data (the state of arm and ball).
    """

    def __init__(self, scene: StrikeScene, bandwidth: float = 200.0, saturate: bool = True) -> None:
        """Build the plant.

        Args:
            scene: A scene with the arm (not ``kinematic``).
            bandwidth: Servo bandwidth [rad/s], > 0.
            saturate: Clip the actuator torques to the robot's effort limits.

        Raises:
            InvalidInputError: A kinematic scene, a bad bandwidth or saturate.
        """
        if not isinstance(scene, StrikeScene):
            raise InvalidInputError(
                f"scene must be a physics.StrikeScene, got {type(scene).__name__}", name="scene"
            )
        if scene.kinematic:
            raise InvalidInputError(
                "a MujocoPlant needs the arm: the scene is kinematic (tool only)", name="scene"
            )
        super().__init__(scene.robot)
        self.scene = scene
        self.bandwidth = as_positive(bandwidth, "bandwidth", "rad/s")
        self.saturate = as_flag(saturate, "saturate")
        self._build()

    def _build(self) -> None:
        self.world: World = self.scene.build()
        # The servo's model: the true world itself unless it carries a model error (the
        # servo reads only masses and gravity, which the actuator settings do not touch).
        self._nominal = self.scene.nominal().build() if self.scene.has_model_error else self.world
        self.data = mujoco.MjData(self.world.model)
        self._nominal_data = mujoco.MjData(self._nominal.model)
        self._watch = ContactWatch(self.world)
        self._mass = np.zeros((self._nominal.model.nv, self._nominal.model.nv))
        self._times: list[float] = []
        self._ball: list[FloatArray] = []
        # The scene clips every actuator at its effort limit; saturate=False lifts that.
        self.world.model.actuator_forcelimited[:] = 1 if self.saturate else 0

    def __getstate__(self) -> dict[str, Any]:
        return {"scene": self.scene, "bandwidth": self.bandwidth, "saturate": self.saturate}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.scene = state["scene"]
        self.robot = self.scene.robot
        self.bandwidth = state["bandwidth"]
        self.saturate = state["saturate"]
        self._state = None
        self._build()

    @property
    def name(self) -> str:
        """Short name for tables and plots."""
        return "mujoco"

    # ------------------------------------------------------------------------------ state

    def reset(self, q: ArrayLike, qd: ArrayLike | None = None) -> PlantState:
        """Place the arm at ``q`` moving at ``qd``, the ball at rest where the scene puts it."""
        state = super().reset(q, qd)
        w, data = self.world, self.data
        mujoco.mj_resetData(w.model, data)
        data.qpos[w.arm_qpos] = state.q
        data.qvel[w.arm_dof] = state.qd
        data.qpos[w.ball_qpos : w.ball_qpos + 3] = np.asarray(self.scene.ball)
        data.qpos[w.ball_qpos + 3 : w.ball_qpos + 7] = (1.0, 0.0, 0.0, 0.0)
        mujoco.mj_forward(w.model, data)
        self._watch.reset()
        self._times = [0.0]
        self._ball = [self._ball_state()]
        return state

    def _ball_state(self) -> FloatArray:
        w = self.world
        return np.concatenate(
            [
                self.data.qpos[w.ball_qpos : w.ball_qpos + 3],
                self.data.qvel[w.ball_dof : w.ball_dof + 3],
            ]
        )

    def step(
        self,
        command: ArrayLike,
        dt: float,
        tool_force: ArrayLike | None = None,
        torque: ArrayLike | None = None,
    ) -> PlantState:
        """Advance by ``dt`` [s] under the joint velocity ``command``; see :meth:`Plant.step`.

        Args:
            command: Joint velocity command [rad/s or m/s], shape (n,).
            dt: Step length [s], > 0.
            tool_force: Force at the tool frame origin [N], world axes, shape (3,).
            torque: Feed-forward joint torque [N m or N], shape (n,), added to the servo's.
        """
        state, u, dt, force, torque_ff = self._begin_step(command, dt, tool_force, torque)
        feedforward = np.zeros(self.robot.dof) if torque_ff is None else torque_ff
        w, data = self.world, self.data
        gravity, diagonal = self._nominal_terms(state.q)
        gain = self.bandwidth * diagonal
        model = w.model
        model.actuator_gainprm[:, 0] = gain
        model.actuator_biasprm[:, 0] = gravity + feedforward
        model.actuator_biasprm[:, 2] = -gain
        data.ctrl[:] = u
        data.qfrc_applied[:] = 0.0
        if force is not None:
            point = (self._tool_pose()[:3, 3]).copy()
            mujoco.mj_applyFT(
                model, data, force, np.zeros(3), point, w.tool_body, data.qfrc_applied
            )
        self._watch.advance(data, dt)
        q = np.array(data.qpos[w.arm_qpos])
        qd = np.array(data.qvel[w.arm_dof])
        if not (np.isfinite(q).all() and np.isfinite(qd).all()):
            raise InvalidInputError(
                f"the MuJoCo simulation diverged with dt = {dt:.6g} s; the command "
                f"{np.array2string(u, precision=4)} is far beyond anything physical",
                name="command",
            )
        applied = np.array(data.actuator_force)
        unclipped = gain * u + gravity + feedforward - gain * qd
        saturated = self.saturate and bool(
            np.any(np.abs(unclipped) > self.robot.limits.effort * (1.0 + 1e-9))
        )
        self._times.append(float(data.time))
        self._ball.append(self._ball_state())
        self._state = frozen_state(q, qd, (qd - state.qd) / dt, applied, saturated)
        return self._state

    def _nominal_terms(self, q: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Gravity torque and the inertia matrix's diagonal of the nominal arm at ``q``."""
        nominal, data = self._nominal, self._nominal_data
        data.qpos[nominal.arm_qpos] = q
        data.qvel[:] = 0.0
        mujoco.mj_fwdPosition(nominal.model, data)
        mujoco.mj_fwdVelocity(nominal.model, data)
        mujoco.mj_fullM(nominal.model, data, self._mass)
        dofs = nominal.arm_dof
        return np.array(data.qfrc_bias[dofs]), np.array(self._mass[dofs, dofs])

    def _tool_pose(self) -> FloatArray:
        """The tool frame's pose in the world, shape (4, 4)."""
        w = self.world
        T = np.eye(4)
        T[:3, :3] = self.data.xmat[w.tool_body].reshape(3, 3)
        T[:3, 3] = self.data.xpos[w.tool_body]
        return T @ w.tool_offset

    # ------------------------------------------------------------------------------ record

    def record(self) -> dict[str, Any]:
        """The ball's path and the tool-ball contact, for :func:`physics.outcome`.

        Keys: ``"scene"``; ``"time"`` [s], shape (m,); ``"ball"`` (position [m] and velocity
        [m/s] at every control time), shape (m, 6); ``"ball_qpos"``, ``"ball_qvel"`` (its
        free joint at the end); and :meth:`ContactWatch.record`'s keys.
        """
        w = self.world
        out: dict[str, Any] = {
            "scene": self.scene,
            "time": np.array(self._times),
            "ball": np.array(self._ball) if self._ball else np.zeros((0, 6)),
            "ball_qpos": np.array(self.data.qpos[w.ball_qpos : w.ball_qpos + 7]),
            "ball_qvel": np.array(self.data.qvel[w.ball_dof : w.ball_dof + 6]),
        }
        out.update(self._watch.record())
        return out

    def __repr__(self) -> str:
        kind = self.scene.kind
        return f"MujocoPlant({self.robot.name!r}, {kind} scene, bandwidth {self.bandwidth:g} rad/s)"
