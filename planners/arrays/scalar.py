r"""Scalar profiles from numbers: ``quintic`` and ``trapezoidal``, in the Robotics Toolbox's shape.

``quintic(q0, qf, t, qd0, qdf)`` is the quintic meeting the end positions and velocities with
zero end accelerations
(:func:`~optraj.planners.profiles.polynomial_coefficients.quintic_coefficients`);
``trapezoidal(q0, qf, t, V)`` is a linear segment with parabolic blends whose cruise velocity
is V (default 1.5 |qf - q0| / T), built from optraj's LSPB closed forms
(:func:`~optraj.planners.profiles.lspb_timing.lspb_fixed_blend`,
:func:`~optraj.planners.profiles.lspb.lspb_trajectory`). With the duration T = t[-1], a cruise
at V needs the blend time

.. math:: t_b = T - |q_f - q_0| / V, \qquad |q_f - q_0| / T < V \le 2 |q_f - q_0| / T,

the upper bound being the triangle (t_b = T / 2). The Robotics Toolbox accepts V equal to the
lower bound, a blend of zero time and an infinite acceleration; here the blend lasts at least
MIN_DURATION (in the unit of t).

At a sample on a breakpoint the values are those of the segment that starts there (the
Robotics Toolbox's ``trapezoidal`` takes the blend that ends there): only the acceleration,
which jumps there, can differ.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from optraj.errors import InvalidInputError
from optraj.planners.arrays.inputs import TimeBase, time_base
from optraj.planners.arrays.result import SampledProfile, sample_fields
from optraj.planners.base import stamp
from optraj.planners.profiles.lspb import lspb_trajectory
from optraj.planners.profiles.lspb_timing import ROUND_OFF, lspb_fixed_blend
from optraj.planners.profiles.polynomial_coefficients import quintic_coefficients
from optraj.planners.trajectory import Trajectory
from optraj.validation import MIN_DURATION, as_number

__all__ = ["TrapezoidalProfile", "quintic", "time_unit", "trapezoidal"]

#: The Robotics Toolbox's default cruise velocity, as a multiple of the mean |qf - q0| / T.
DEFAULT_SPEED_RATIO = 1.5


@dataclass(frozen=True, repr=False)
class TrapezoidalProfile(SampledProfile):
    """A trapezoidal profile's samples, with its blend time and cruise velocity.

    Attributes:
        tblend: Blend time t_b [unit of t]; 0 when q0 equals qf (no motion).
        V: Cruise velocity [unit of q per unit of t], signed like qf - q0; 0 when q0 equals qf.
    """

    tblend: float
    V: float


def time_unit(base: TimeBase, steps: str = "step") -> str:
    """The unit of time of a profile on ``base``: ``"s"``, or ``steps`` for an int count."""
    return "s" if base.istime else steps


def quintic(
    q0: float, qf: float, t: int | ArrayLike, qd0: float = 0.0, qdf: float = 0.0
) -> SampledProfile:
    r"""Scalar quintic from q0 to qf over [0, T]: end velocities qd0 and qdf, end accelerations 0.

    Args:
        q0: Start position [rad or m].
        qf: End position [rad or m].
        t: An int m >= 2: m steps 0 .. m - 1, T = m - 1 [steps], velocities per step; or a
            time vector [s] from 0 s or later, strictly increasing: T = t[-1].
        qd0: Start velocity [unit of q per unit of t].
        qdf: End velocity [unit of q per unit of t].

    Returns:
        The samples (shape (m,) each) and the one-joint Trajectory. At rest ends,
        :math:`q = q_0 + (q_f - q_0)(10 x^3 - 15 x^4 + 6 x^5)`, x = t / T.

    Raises:
        InvalidInputError: A value that is not a finite number, or a bad ``t`` (see
            :func:`~optraj.planners.arrays.inputs.time_base`).
    """
    started = time.perf_counter()
    values = [
        as_number(v, name) for v, name in ((q0, "q0"), (qf, "qf"), (qd0, "qd0"), (qdf, "qdf"))
    ]
    base = time_base(t)
    start, goal, v0, v1 = ([v] for v in values)
    coefficients = quintic_coefficients(start, goal, base.end, v0, v1)
    traj = stamp(
        Trajectory([0.0, base.end], coefficients[None]),
        "quintic",
        started,
        time_unit=time_unit(base),
    )
    return SampledProfile("quintic", *sample_fields(traj, base, scalar=True), base.istime, traj)


def _cruise_speed(dist: float, duration: float, V: float | None) -> float:
    """|V| checked against the bounds of a trapezoid of ``dist`` in ``duration`` (unit of t)."""
    if V is None:
        return DEFAULT_SPEED_RATIO * dist / duration
    speed = abs(as_number(V, "V"))
    low = dist / (duration - MIN_DURATION)  # a blend of at least MIN_DURATION
    high = 2.0 * dist / duration
    if speed < low:
        raise InvalidInputError(
            f"V = {speed:.6g} is too small: a trapezoid of |qf - q0| = {dist:.6g} in "
            f"T = {duration:.6g} needs V > |qf - q0| / T = {dist / duration:.6g} (a blend of "
            f"at least {MIN_DURATION:.3g}: V >= {low:.6g})",
            name="V",
            value=V,
        )
    if speed > high * (1.0 + ROUND_OFF):
        raise InvalidInputError(
            f"V = {speed:.6g} is too large: a trapezoid of |qf - q0| = {dist:.6g} in "
            f"T = {duration:.6g} needs V <= 2 |qf - q0| / T = {high:.6g} (the triangle)",
            name="V",
            value=V,
        )
    return speed


def trapezoidal(
    q0: float, qf: float, t: int | ArrayLike, V: float | None = None
) -> TrapezoidalProfile:
    """Scalar trapezoidal-velocity profile (linear segment, parabolic blends) from q0 to qf.

    Args:
        q0: Start position [rad or m].
        qf: End position [rad or m].
        t: An int m >= 2 (steps 0 .. m - 1, T = m - 1 [steps]) or a time vector [s] from
            0 s or later, strictly increasing: T = t[-1].
        V: Cruise speed [unit of q per unit of t], its sign ignored (the motion goes from q0
            to qf); None: 1.5 |qf - q0| / T, a blend of T / 3. Ignored when q0 equals qf.

    Returns:
        The samples (shape (m,) each), the one-joint Trajectory, the blend time ``tblend``
        and the signed cruise velocity ``V``. Starts and ends at rest.

    Raises:
        InvalidInputError: V outside (|qf - q0| / T, 2 |qf - q0| / T] (the message says
            which bound and its value), a value that is not a finite number, or a bad ``t``
            (one spanning less than 3 MIN_DURATION too).
    """
    started = time.perf_counter()
    start, goal = as_number(q0, "q0"), as_number(qf, "qf")
    base = time_base(t)
    T = base.end
    delta = goal - start
    if delta == 0.0:
        if V is not None:
            as_number(V, "V")
        traj = Trajectory.constant([start], T)
        blend, velocity = 0.0, 0.0
    else:
        if T < 3.0 * MIN_DURATION:  # two blends and a cruise of MIN_DURATION at least
            raise InvalidInputError(
                f"t must span at least {3.0 * MIN_DURATION:.3g} s for a trapezoid, got {T:.6g} s",
                name="t",
            )
        speed = _cruise_speed(abs(delta), T, V)
        # Round-off may put the triangle's blend a hair past T / 2.
        blend = T / 3.0 if V is None else min(T - abs(delta) / speed, 0.5 * T)
        timing = lspb_fixed_blend([delta], T, blend)
        traj = lspb_trajectory([start], [goal], timing)
        velocity = float(np.copysign(speed, delta))
    stamp(traj, "trapezoidal", started, time_unit=time_unit(base))
    fields = sample_fields(traj, base, scalar=True)
    return TrapezoidalProfile("trapezoidal", *fields, base.istime, traj, blend, velocity)
