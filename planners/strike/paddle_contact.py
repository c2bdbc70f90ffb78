"""The contact choice of a paddle strike, and the room a joint needs to pass a configuration.

A paddle4 contact is fixed by its closed-form inverse kinematics (``problem.q_contact``), so
there is nothing to search: :func:`paddle_choice` computes its twist ratio with the ball point
moving along the normal and the normal held still, refuses a strike faster than the velocity
limits allow, and refuses one whose contact leaves a joint too little room to start from rest
and come back to rest around it (:func:`stopping_speeds`).
:func:`planners.strike.contact.choose_contact` is the entry point for both strike kinds.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.planners.strike.contact_choice import ContactChoice, contact_refusal, too_fast_error
from optraj.planners.strike.min_max_ratio import MinMaxRatio
from optraj.planners.strike.twist_ratio import binding_joints, unit_ratio
from optraj.problems import PaddleStrike
from optraj.problems.common import normal_pair
from optraj.robots import JointLimits
from optraj.robots.paddle_ik import BALL_OFFSET
from optraj.validation import as_vector

__all__ = ["paddle_choice", "stopping_speeds"]

FloatArray = NDArray[np.float64]


def paddle_choice(problem: PaddleStrike, margin: float) -> ContactChoice:
    """The contact of a paddle strike: its closed-form configuration and joint velocity.

    Args:
        problem: The paddle strike.
        margin: Share of the velocity limits kept in reserve, in [0, 1) (checked by the
            caller).

    Raises:
        InfeasibleError: The strike needs a joint faster than its velocity limit, or more room
            to its position limits than the contact leaves (both ``found_by`` the contact
            choice).
    """
    limits = problem.limits
    velocity_limit = np.asarray(limits.velocity, dtype=float)
    q = np.asarray(problem.q_contact, dtype=float)
    normal = np.asarray(problem.normal, dtype=float)
    lp = MinMaxRatio()
    # Hold the normal still at contact (as planners.profiles.cartesian.paddle_contact_velocity
    # does); paddle4 always can, but should a robot not, let the paddle turn.
    r1, qd1 = unit_ratio(
        lp, problem.robot, q, normal, velocity_limit, BALL_OFFSET, normal_pair(normal)
    )
    if math.isinf(r1):
        r1, qd1 = unit_ratio(lp, problem.robot, q, normal, velocity_limit, BALL_OFFSET, None)
    binding = binding_joints(qd1, velocity_limit)
    speed = float(problem.speed)
    if speed > 0.0 and speed * r1 > 1.0 - margin:
        raise too_fast_error(
            limits, speed, r1, tuple(binding), qd1, margin, "the contact configuration"
        )
    if speed > 0.0:
        _check_room(problem, lp, q, normal, speed, margin)
    return ContactChoice(
        q=q,
        qd=speed * qd1 if speed > 0.0 else np.zeros(q.size),
        ratio=speed * r1 if speed > 0.0 else 0.0,
        max_speed=1.0 / r1 if r1 > 0.0 else math.inf,
        binding_joint=limits.names[binding[0]] if binding else "",
        candidates=1,
    )


def stopping_speeds(limits: JointLimits, q: ArrayLike) -> FloatArray:
    r"""Fastest speed at which each joint can pass q on a motion from rest to rest.

    A joint that passes q at speed v within its position limits, with
    :math:`|\ddot q| \le a`, on a motion that starts and ends at rest, reached v from rest
    behind q and comes to rest ahead of it: it needs :math:`v^2 / (2 a)` of room on both sides
    of q, so

    .. math::

        v \le \sqrt{2 a \min(q - q_{lower}, q_{upper} - q)}.

    The jerk limit asks for more room still, so this is a bound, not a speed that can always
    be reached.

    Args:
        limits: The joint limits.
        q: Configuration within the position limits [rad or m], shape (n,).

    Returns:
        The speeds [rad/s or m/s], shape (n,).
    """
    here = as_vector(q, "q", limits.n)
    room = np.maximum(np.minimum(here - limits.lower, limits.upper - here), 0.0)
    return np.sqrt(2.0 * np.asarray(limits.acceleration, dtype=float) * room)


def _check_room(
    problem: PaddleStrike,
    lp: MinMaxRatio,
    q: FloatArray,
    normal: FloatArray,
    speed: float,
    margin: float,
) -> None:
    """Refuse a paddle strike whose contact leaves a joint too little room to pass it.

    The contact configuration is the paddle's only one, and the contact fixes the ball
    point's velocity but not the paddle's turning: a joint velocity that gives the strike
    within the velocity limits and :func:`stopping_speeds` exists, or no motion from rest to
    rest makes the strike within the position and acceleration limits.
    """
    limits = problem.limits
    kept = (1.0 - margin) * np.asarray(limits.velocity, dtype=float)
    allowed = np.minimum(kept, stopping_speeds(limits, q))
    r1, qd1 = unit_ratio(lp, problem.robot, q, normal, allowed, BALL_OFFSET, None)
    if speed * r1 <= 1.0:
        return
    binding = binding_joints(qd1, allowed) or list(range(limits.n))
    tight = [j for j in binding if allowed[j] < kept[j]]
    j = (tight or binding)[0]
    unit = limits.unit("position", j)
    room = float(min(q[j] - limits.lower[j], limits.upper[j] - q[j]))
    side = "lower" if q[j] - limits.lower[j] <= limits.upper[j] - q[j] else "upper"
    need = abs(float(qd1[j])) * speed if math.isfinite(r1) else math.inf
    acceleration = float(limits.acceleration[j])
    required = need * need / (2.0 * acceleration)
    fastest = 1.0 / r1 if r1 > 0.0 else 0.0
    name = limits.names[j]
    message = (
        f"paddle strike at {speed:.3g} m/s: at the contact configuration {name} is "
        f"{room:.4g} {unit} from its {side} limit; the joint velocity that gives the strike "
        f"with the least excess over the joints' rooms still moves it at {need:.3g} "
        f"{limits.unit('velocity', j)}, which needs {required:.4g} {unit} on both sides to "
        f"start from and come back to rest at {acceleration:.4g} "
        f"{limits.unit('acceleration', j)}; the fastest strike this contact allows is at "
        f"most {fastest:.3g} m/s (the jerk limit asks for more room still)"
    )
    raise contact_refusal(
        message, limit="position", max_speed=fastest, joint=name, required=required, allowed=room
    )
