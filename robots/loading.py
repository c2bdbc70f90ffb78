"""Load robots by name: the three models optraj ships and arms from example-robot-data.

Shipped (URDF files in ``robots/urdf``): ``paddle4``, ``sawyer``, ``youbot``. With the
``examples`` extra installed: ``panda`` and ``ur5`` from the example-robot-data package.

Where a source publishes no acceleration or jerk limit, the values below are our documented
choices. Jerk limits are set so that the full acceleration is reached in 50 ms
(jerk = 20 1/s x acceleration) unless a source gives them.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from dataclasses import dataclass
from importlib import resources
from typing import Any

import numpy as np
import pinocchio as pin

from optraj.errors import MissingDependencyError, UnknownNameError
from optraj.robots.limits import JointLimits
from optraj.robots.robot import Robot
from optraj.validation import as_number, as_positive

__all__ = ["known_robots", "load", "urdf_model"]

#: Jerk = this factor x acceleration where no jerk limit is published [1/s] (our choice).
JERK_PER_ACCELERATION = 20.0

#: Sawyer acceleration limits, intera SDK "fast" motion preset (the SDK default) [rad/s^2].
SAWYER_ACCELERATION = (7.0, 5.0, 8.0, 8.0, 8.0, 8.0, 8.0)
#: Sawyer "neutral" pose of the intera SDK [rad].
SAWYER_NEUTRAL = (0.0, -1.18, 0.0, 2.18, 0.0, 0.57, 3.3161)
#: Default cue length from the flange (right_hand) to the cue tip, along right_hand z [m].
#: Our choice: the part of a cue that sticks out of a wrist-mounted holder.
SAWYER_CUE_LENGTH = 0.30
#: Mass of that cue section [kg], carried as a uniform rod of the cue's length. Our choice:
#: about the front fifth of a 0.54 kg, 1.47 m cue (a cue weighs 18 to 21 oz, 0.51 to 0.6 kg).
SAWYER_CUE_MASS = 0.1
#: Cue shaft radius [m] (a 13 mm tip; only the rod's axial inertia depends on it).
SAWYER_CUE_RADIUS = 0.0065
#: Longest cue accepted [m] (a full pool cue is about 1.47 m long).
SAWYER_MAX_CUE_LENGTH = 1.5
#: Heaviest cue accepted [kg] (a whole cue is about 0.6 kg).
SAWYER_MAX_CUE_MASS = 1.0

#: youBot planning ranges: youbot_driver encoder limits, tighter than the URDF's [rad].
YOUBOT_LOWER = (0.0100692, 0.0100692, -5.02655, 0.0221239, 0.110619)
YOUBOT_UPPER = (5.84014, 2.61799, -0.015708, 3.4292, 5.64159)
#: youBot acceleration limits [rad/s^2]; none is published. Our choice: vmax 1.57 rad/s is
#: reached in about 0.4 s by J1-J3 and 0.26 s by the light wrist joints J4-J5. They are
#: kinematic limits only: with the arm stretched out, gravity alone needs 91 % of J2's
#: 9.5 N m, and all joints accelerating at these limits can need up to 110 % of it, so torque
#: is checked on its own (planners.check's "torque" finding).
YOUBOT_ACCELERATION = (4.0, 4.0, 4.0, 6.0, 6.0)
#: youBot "candle" pose (arm straight up) [rad].
YOUBOT_CANDLE = (2.949606, 1.134464, -2.548181, 1.788962, 2.923426)

#: paddle4 accelerations [m/s^2, rad/s^2, m/s^2, rad/s^2]; the ECE486 task gives none. Our choice,
#: sized to the efforts in paddle4.urdf: J1 lifts 7.75 kg at 9.81 + 5 m/s^2 (115 N of 150 N);
#: J2 turns about 5.2 kg m^2 fully extended at 6 rad/s^2 (31 N m of 40 N m).
PADDLE4_ACCELERATION = (5.0, 6.0, 8.0, 30.0)
#: paddle4 home configuration of the ECE486 task [m, rad, m, rad].
PADDLE4_HOME = (0.45, 0.0, 0.0, 0.0)

#: Franka Panda acceleration and jerk limits published by Franka [rad/s^2, rad/s^3].
PANDA_ACCELERATION = (15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0)
PANDA_JERK = (7500.0, 3750.0, 5000.0, 6250.0, 7500.0, 10000.0, 10000.0)
#: Panda reference pose q0 of example-robot-data [rad].
PANDA_HOME = (0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4)

#: UR5 accelerations [rad/s^2]; example-robot-data gives none. Our choice: 2 x vmax per second.
UR5_ACCELERATION_PER_VELOCITY = 2.0
#: UR5 home: shoulder up, elbow bent, wrist down (our choice; q = 0 is a stretched singularity).
UR5_HOME = (0.0, -np.pi / 2, np.pi / 2, -np.pi / 2, -np.pi / 2, 0.0)


@dataclass(frozen=True)
class _Entry:
    build: Callable[..., Robot]
    summary: str


def urdf_model(name: str) -> pin.Model:
    """The Pinocchio model of a shipped URDF file as it is (no tool frame, no tool mass)."""
    urdf = resources.files("optraj.robots") / "urdf" / f"{name}.urdf"
    with resources.as_file(urdf) as path:
        return pin.buildModelFromUrdf(str(path))


def _joint_kinds(model: pin.Model) -> tuple[str, ...]:
    # Prismatic joints are JointModelPX/PY/PZ and JointModelPrismaticUnaligned.
    return tuple(
        "m" if model.joints[i].shortname().startswith("JointModelP") else "rad"
        for i in range(1, model.njoints)
    )


def _limits(
    model: pin.Model,
    acceleration: tuple[float, ...] | np.ndarray,
    *,
    jerk: tuple[float, ...] | np.ndarray | None = None,
    lower: tuple[float, ...] | None = None,
    upper: tuple[float, ...] | None = None,
) -> JointLimits:
    accel = np.asarray(acceleration, dtype=float)
    return JointLimits(
        names=tuple(model.names[i] for i in range(1, model.njoints)),
        kinds=_joint_kinds(model),
        lower=np.asarray(lower if lower is not None else model.lowerPositionLimit, dtype=float),
        upper=np.asarray(upper if upper is not None else model.upperPositionLimit, dtype=float),
        velocity=np.asarray(model.velocityLimit, dtype=float),
        acceleration=accel,
        jerk=np.asarray(jerk, dtype=float) if jerk is not None else JERK_PER_ACCELERATION * accel,
        effort=np.asarray(model.effortLimit, dtype=float),
    )


def _add_tool_frame(model: pin.Model, name: str, parent_frame: str, offset: pin.SE3) -> None:
    parent = model.frames[model.getFrameId(parent_frame)]
    model.addFrame(
        pin.Frame(
            name,
            parent.parentJoint,
            model.getFrameId(parent_frame),
            parent.placement * offset,
            pin.FrameType.OP_FRAME,
        )
    )


# ----------------------------------------------------------------------------- shipped robots


def _paddle4() -> Robot:
    model = urdf_model("paddle4")
    return Robot(
        "paddle4",
        model,
        _limits(model, PADDLE4_ACCELERATION),
        tool_frame="paddle",
        poses={"home": PADDLE4_HOME},
        description=(
            "4-DOF P-R-P-R table-tennis paddle robot (ECE486 paddle task); tool: paddle centre"
        ),
    )


def _sawyer(cue_length: float = SAWYER_CUE_LENGTH, cue_mass: float = SAWYER_CUE_MASS) -> Robot:
    """Sawyer holding a pool cue.

    Args:
        cue_length: Distance from the flange (right_hand) to the cue tip along right_hand's
            z axis [m], in (0, 1.5].
        cue_mass: Mass of that cue section [kg], >= 0, a uniform rod from the flange to the
            tip; it is part of the model's dynamics (torques, the plan's feed-forward).
    """
    length = as_positive(cue_length, "cue_length", "m", maximum=SAWYER_MAX_CUE_LENGTH)
    mass = as_number(cue_mass, "cue_mass", "kg", minimum=0.0, maximum=SAWYER_MAX_CUE_MASS)
    model = urdf_model("sawyer")
    _add_tool_frame(model, "cue_tip", "right_hand", pin.SE3(np.eye(3), np.array([0, 0, length])))
    if mass > 0.0:
        hand = model.frames[model.getFrameId("right_hand")]
        rod = pin.Inertia.FromCylinder(mass, SAWYER_CUE_RADIUS, length)  # axis z, about centre
        centre = pin.SE3(np.eye(3), np.array([0.0, 0.0, length / 2]))
        model.appendBodyToJoint(hand.parentJoint, rod, hand.placement * centre)
    return Robot(
        "sawyer",
        model,
        _limits(model, SAWYER_ACCELERATION),
        tool_frame="cue_tip",
        poses={"home": SAWYER_NEUTRAL, "neutral": SAWYER_NEUTRAL},
        description=(
            f"Rethink Sawyer, 7-DOF; tool: pool-cue tip {length:.3g} m past the flange, "
            f"cue {mass:.3g} kg"
        ),
    )


def _youbot() -> Robot:
    model = urdf_model("youbot")
    return Robot(
        "youbot",
        model,
        _limits(model, YOUBOT_ACCELERATION, lower=YOUBOT_LOWER, upper=YOUBOT_UPPER),
        tool_frame="tcp",
        poses={"home": YOUBOT_CANDLE, "candle": YOUBOT_CANDLE},
        description="KUKA youBot arm, 5-DOF, driver ranges; tool: TCP between the fingers",
    )


# ------------------------------------------------------------------ example-robot-data arms


def _erd_model(name: str) -> pin.Model:
    try:
        import example_robot_data
    except ImportError as exc:
        raise MissingDependencyError(
            "example-robot-data", "examples", f"robots.load({name!r})"
        ) from exc
    return example_robot_data.load(name).model


def _panda() -> Robot:
    full = _erd_model("panda")
    fingers = [full.getJointId(f"panda_finger_joint{i}") for i in (1, 2)]
    model = pin.buildReducedModel(full, fingers, pin.neutral(full))
    return Robot(
        "panda",
        model,
        _limits(model, PANDA_ACCELERATION, jerk=PANDA_JERK),
        tool_frame="panda_hand_tcp",
        poses={"home": PANDA_HOME, "ready": PANDA_HOME},
        description="Franka Panda, 7-DOF, fingers locked (example-robot-data); tool: hand TCP",
    )


def _ur5() -> Robot:
    model = _erd_model("ur5")
    accel = UR5_ACCELERATION_PER_VELOCITY * np.asarray(model.velocityLimit, dtype=float)
    return Robot(
        "ur5",
        model,
        _limits(model, accel),
        tool_frame="tool0",
        poses={"home": UR5_HOME},
        description="Universal Robots UR5, 6-DOF (example-robot-data); tool: tool0 flange",
    )


_REGISTRY: dict[str, _Entry] = {
    "paddle4": _Entry(_paddle4, "4-DOF P-R-P-R paddle robot"),
    "sawyer": _Entry(_sawyer, "Rethink Sawyer, 7-DOF, with a pool cue"),
    "youbot": _Entry(_youbot, "KUKA youBot arm, 5-DOF"),
    "panda": _Entry(_panda, "Franka Panda, 7-DOF (needs optraj[examples])"),
    "ur5": _Entry(_ur5, "Universal Robots UR5, 6-DOF (needs optraj[examples])"),
}


def known_robots() -> dict[str, str]:
    """Names of the robots :func:`load` knows, with a one-line summary each."""
    return {name: entry.summary for name, entry in _REGISTRY.items()}


def load(name: str, **options: Any) -> Robot:
    """Load a robot by name.

    Args:
        name: One of :func:`known_robots` (case-insensitive).
        **options: Robot-specific options, e.g. ``cue_length`` [m] for ``"sawyer"``.

    Returns:
        A new :class:`robots.Robot`.

    Raises:
        UnknownNameError: Unknown robot name or option; the message lists the known ones.
        MissingDependencyError: The robot needs an optional package that is not installed.
        InvalidInputError: An option value is out of range.

    Example:
        >>> from optraj import robots
        >>> robot = robots.load("sawyer", cue_length=0.4)
        >>> robot.tool_frame
        'cue_tip'
    """
    key = str(name).lower()
    if key not in _REGISTRY:
        raise UnknownNameError("robot", str(name), _REGISTRY)
    build = _REGISTRY[key].build
    accepted = list(inspect.signature(build).parameters)
    for option in options:
        if option not in accepted:
            raise UnknownNameError(f"option of robot {key!r}", option, accepted)
    return build(**options)
