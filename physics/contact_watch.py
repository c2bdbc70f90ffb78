r"""Stepping a strike world finely around tool-ball contact, and what the contact did.

A cue-ball contact lasts about 0.4 ms in our scenes (:mod:`physics.scene`). With a coarse
physics step the ball's launch speed depends on where within a step the contact starts; a
fine step resolves the contact and makes the launch all but independent of that. So a world
is stepped at the coarse step while the tool is far from the ball and at the fine step from
:data:`LOOKAHEAD` before a possible contact (by the distance between the two geoms and their
closing speed) until they are apart again.

:class:`ContactWatch` decides the step and records the contact: when it starts, where, the
tool's inverse inertia there (for the ideal outcome), and the ball's velocity when the tool
lets go (the launch).
"""

from __future__ import annotations

import math
from typing import Any

import mujoco
import numpy as np
from numpy.typing import NDArray

from optraj.physics.scene import World

__all__ = ["LOOKAHEAD", "ContactWatch"]

FloatArray = NDArray[np.float64]

#: Fine steps start this long before the tool could reach the ball [s].
LOOKAHEAD = 3e-3
#: ... and this far from it in any case [m].
MARGIN = 1e-3
#: Fine steps are taken in batches of this many between contact checks.
BATCH = 5


class ContactWatch:
    """Chooses the physics step and records tool-ball contacts of one world.

    Args:
        world: The compiled scene.
    """

    def __init__(self, world: World) -> None:
        self.world = world
        self._velocity = np.zeros(6)
        self.reset()

    def reset(self) -> None:
        """Forget every contact seen."""
        self.touching = False
        self.contacts = 0
        self.start_time = math.nan
        self.end_time = math.nan
        self.point = np.full(3, math.nan)
        self.normal = np.full(3, math.nan)
        self.inverse_inertia = np.full((3, 3), math.nan)
        self.launch = np.full(3, math.nan)
        self.tool_velocity = np.full(3, math.nan)

    # ------------------------------------------------------------------------------ stepping

    def near(self, data: mujoco.MjData) -> bool:
        """Whether the tool may touch the ball within :data:`LOOKAHEAD` (or touches it)."""
        if self.touching:
            return True
        w = self.world
        limit = MARGIN + LOOKAHEAD * (
            self._speed(data, w.tool_geom) + self._speed(data, w.ball_geom)
        )
        distance = mujoco.mj_geomDistance(w.model, data, w.tool_geom, w.ball_geom, limit, None)
        return bool(distance < limit)

    def _speed(self, data: mujoco.MjData, geom: int) -> float:
        mujoco.mj_objectVelocity(
            self.world.model, data, mujoco.mjtObj.mjOBJ_GEOM, geom, self._velocity, 0
        )
        return float(np.linalg.norm(self._velocity[3:]))

    def advance(self, data: mujoco.MjData, duration: float, before_step: Any = None) -> None:
        """Step ``data`` by ``duration`` [s]: coarse steps, fine ones near contact.

        Args:
            data: The world's data.
            duration: How long [s], > 0.
            before_step: Called as ``before_step(data)`` before every batch of steps (a
                kinematic tool is placed there; far from the ball a batch spans up to half
                of :data:`LOOKAHEAD`); None for nothing.
        """
        model = self.world.model
        scene = self.world.scene
        end = data.time + duration
        while end - data.time > 1e-12:
            left = end - data.time
            if self.near(data):
                h = min(scene.fine_step, left)
                count = max(1, min(BATCH, round(left / h)))
            else:
                # Far from the ball a kinematic tool is only placed once per batch: where it
                # drifts between placements touches nothing.
                h = min(scene.step, left)
                count = max(1, round(left / h))
                # Never step past the point where fine steps should start: the lookahead
                # covers the next LOOKAHEAD seconds only.
                count = min(count, max(1, int(LOOKAHEAD / (2 * h))))
            model.opt.timestep = h
            if before_step is not None:
                before_step(data)
            mujoco.mj_step(model, data, nstep=count)
            self.observe(data)
        model.opt.timestep = scene.step

    # ------------------------------------------------------------------------------ recording

    def observe(self, data: mujoco.MjData) -> None:
        """Update the contact record from the data after a step."""
        w = self.world
        index = self._contact_index(data)
        if index >= 0 and not self.touching:
            self.touching = True
            self.contacts += 1
            if self.contacts == 1:
                contact = data.contact[index]
                self.start_time = float(data.time)
                self.point = np.array(contact.pos, dtype=float)
                normal = np.array(contact.frame[:3], dtype=float)
                if contact.geom[0] == w.ball_geom:  # the frame's normal points from geom1
                    normal = -normal
                self.normal = normal
                self._tool_at_contact(data)
        elif index < 0 and self.touching:
            self.touching = False
            if self.contacts == 1:
                self.end_time = float(data.time)
                self.launch = np.array(data.qvel[w.ball_dof : w.ball_dof + 3], dtype=float)

    def _contact_index(self, data: mujoco.MjData) -> int:
        w = self.world
        for k in range(data.ncon):
            geoms = data.contact.geom[k]
            if (geoms[0] == w.tool_geom and geoms[1] == w.ball_geom) or (
                geoms[0] == w.ball_geom and geoms[1] == w.tool_geom
            ):
                return k
        return -1

    def _tool_at_contact(self, data: mujoco.MjData) -> None:
        """The tool body's ``J M^-1 J^T`` [1/kg] and velocity [m/s] at the contact point."""
        model = self.world.model
        jacp = np.zeros((3, model.nv))
        mujoco.mj_jac(model, data, jacp, None, self.point, self.world.tool_body)
        solved = np.zeros((3, model.nv))
        mujoco.mj_solveM(model, data, solved, jacp)
        self.inverse_inertia = jacp @ solved.T
        self.tool_velocity = jacp @ data.qvel

    def record(self) -> dict[str, Any]:
        """What the contact did, as plain numbers and arrays."""
        return {
            "contacts": self.contacts,
            "contact_start": self.start_time,
            "contact_end": self.end_time,
            "contact_point": self.point.copy(),
            "contact_normal": self.normal.copy(),
            "inverse_inertia": self.inverse_inertia.copy(),
            "tool_velocity": self.tool_velocity.copy(),
            "launch": self.launch.copy(),
        }
