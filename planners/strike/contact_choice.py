"""What a contact choice returns, and the errors with which it refuses a strike.

:class:`ContactChoice` is the configuration at which a strike meets the ball, as
:func:`planners.strike.contact.choose_contact` and its pool and paddle searches return it.
:func:`too_fast_error` and :func:`contact_refusal` build the
:class:`optraj.errors.InfeasibleError` of a strike the choice refuses before any solve
(``found_by`` :data:`optraj.errors.CONTACT_CHOICE`); :func:`as_margin` checks the share of
the velocity limits a caller keeps in reserve.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.errors import CONTACT_CHOICE, InfeasibleError, InvalidInputError
from optraj.robots import JointLimits
from optraj.validation import as_number

__all__ = ["ContactChoice", "as_margin", "contact_refusal", "too_fast_error"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class ContactChoice:
    """The configuration at which a strike meets the ball, and how fast it can strike.

    Attributes:
        q: Contact configuration [rad or m], shape (n,).
        qd: Joint velocity at contact that gives the strike motion at the requested speed with
            the smallest largest velocity-limit ratio [rad/s or m/s], shape (n,); zero for a
            paddle arriving at rest.
        ratio: Largest ``|qd_i| / qd_max_i`` the strike needs at the requested speed [-]: for
            a pool shot the largest over the contact, entry and exit configurations (so at
            least that of ``qd``), for a paddle shot at contact. At most 1 - margin.
        max_speed: Fastest strike this choice allows within the velocity limits [m/s]
            (1 / the ratio at unit speed; inf if no joint needs to move).
        binding_joint: The joint with the largest ratio, the first to reach its limit as the
            speed rises (at the optimum several joints usually bind together); empty if no
            joint velocity gives the motion (a singular paddle contact at rest).
        candidates: Contact configurations evaluated (IK solutions and pattern-search trials).
        q_entry: Pool: configuration at the line's entry point near ``q`` [rad], shape (n,);
            None for a paddle strike.
        q_exit: Pool: configuration at the line's exit point near ``q`` [rad], shape (n,);
            None for a paddle strike.
    """

    q: FloatArray
    qd: FloatArray
    ratio: float
    max_speed: float
    binding_joint: str
    candidates: int
    q_entry: FloatArray | None = None
    q_exit: FloatArray | None = None


def as_margin(value: float) -> float:
    """A share of the velocity limits kept in reserve, checked to lie in [0, 1) [-].

    Raises:
        InvalidInputError: Not a number (a bool or a string neither), or outside [0, 1).
    """
    reserve = as_number(value, "margin", minimum=0.0)
    if not reserve < 1.0:
        raise InvalidInputError(f"margin must be in [0, 1), got {reserve:.6g}", name="margin")
    return reserve


def contact_refusal(
    message: str,
    *,
    limit: str,
    max_speed: float,
    joint: str | None = None,
    required: float | None = None,
    allowed: float | None = None,
) -> InfeasibleError:
    """The error of a strike the contact choice refuses (``found_by`` the contact choice).

    Args:
        message: What is refused and why, naming the values and the limit.
        limit: The binding limit, ``"velocity"`` or ``"position"``.
        max_speed: The fastest strike speed the finding allows [m/s].
        joint: The binding joint, if one is known.
        required: What the joint needs [rad/s or m/s, or rad or m for a position].
        allowed: What it has, in the unit of ``required``.
    """
    return InfeasibleError(
        message,
        limit=limit,
        joint=joint,
        required=required,
        allowed=allowed,
        max_speed=max_speed,
        found_by=CONTACT_CHOICE,
    )


def too_fast_error(
    limits: JointLimits,
    speed: float,
    r1: float,
    binding: tuple[int, ...] | list[int],
    qd1: FloatArray,
    margin: float,
    which: str,
) -> InfeasibleError:
    """The error for a strike faster than the velocity limits allow anywhere searched.

    Args:
        limits: The joint limits.
        speed: The strike speed [m/s].
        r1: The smallest ratio found at unit speed [s/m].
        binding: Its binding joints (:func:`planners.strike.twist_ratio.binding_joints`);
            empty when no joint velocity gives the motion.
        qd1: Its joint velocity at unit speed, shape (n,).
        margin: The share of the velocity limits kept in reserve [-].
        which: Where it was searched, in words (``"the contact configuration"``).
    """
    fastest = (1.0 - margin) / r1 if r1 > 0.0 else math.inf
    if not binding:  # singular everywhere: no joint velocity gives the motion
        return contact_refusal(
            f"strike speed {speed:.3g} m/s: {which} cannot move the tool along the strike "
            f"direction at all (singular)",
            limit="velocity",
            max_speed=0.0,
        )
    j = binding[0]
    name = limits.names[j]
    unit = limits.unit("velocity", j)
    required = abs(float(qd1[j])) * speed
    limit = float(limits.velocity[j])
    allowed = (1.0 - margin) * limit
    others = [limits.names[i] for i in binding[1:]]
    also = (
        f"; {', '.join(others)} {'is' if len(others) == 1 else 'are'} as far over" if others else ""
    )
    kept = f" (with margin {margin:.3g}: {allowed:.4g} {unit})" if margin > 0.0 else ""
    message = (
        f"strike speed {speed:.3g} m/s needs {name} at {required:.3g} {unit}, limit "
        f"{limit:.4g} {unit}{kept}{also}; the fastest strike {which} allows is {fastest:.3g} m/s"
    )
    return contact_refusal(
        message, limit="velocity", max_speed=fastest, joint=name, required=required, allowed=allowed
    )
