"""Joint-space profiles from arrays: ``jtraj`` and ``mtraj``, as the Robotics Toolbox calls them.

``jtraj(q0, qf, t, qd0, qd1)`` moves every joint on the quintic that meets the end positions
and velocities with zero end accelerations
(:func:`~optraj.planners.profiles.polynomial_coefficients.quintic_coefficients`).
``mtraj(tfunc, q0, qf, t)`` applies a scalar profile (:func:`~optraj.planners.arrays.quintic`,
:func:`~optraj.planners.arrays.trapezoidal`) to each joint and stacks the results.

With an int ``t``, ``jtraj`` spreads the m samples over the normalised time [0, 1] and its
``t`` is that time (the Robotics Toolbox reports ``t = linspace(0, m, m)`` there, while its
velocities are per unit of normalised time); ``mtraj`` uses steps 0 .. m - 1, as its scalar
profiles do.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from optraj.errors import InvalidInputError
from optraj.planners.arrays.inputs import joint_vectors, time_base
from optraj.planners.arrays.result import SampledProfile, sample_fields
from optraj.planners.arrays.scalar import time_unit
from optraj.planners.arrays.stacking import stack_joints
from optraj.planners.base import stamp
from optraj.planners.profiles.polynomial_coefficients import quintic_coefficients
from optraj.planners.trajectory import Trajectory
from optraj.validation import as_vector

__all__ = ["ScalarProfile", "jtraj", "mtraj"]

#: A scalar profile function: ``(q0, qf, t) -> SampledProfile``, e.g. ``quintic``.
ScalarProfile = Callable[[float, float, "int | ArrayLike"], SampledProfile]


def jtraj(
    q0: ArrayLike,
    qf: ArrayLike,
    t: int | ArrayLike,
    qd0: ArrayLike | None = None,
    qd1: ArrayLike | None = None,
) -> SampledProfile:
    """Joint-space quintic from q0 to qf: end velocities qd0 and qd1, end accelerations 0.

    Args:
        q0: Start positions [rad or m], shape (n,).
        qf: End positions [rad or m], shape (n,).
        t: An int m >= 2: m samples evenly over the normalised time [0, 1] (velocities per
            unit of it); or a time vector [s] from 0 s or later, strictly increasing, the
            motion lasting t[-1].
        qd0: Start velocities [unit of q per unit of t], shape (n,); None: zero.
        qd1: End velocities [unit of q per unit of t], shape (n,); None: zero.

    Returns:
        The samples (shape (m, n) each) and the Trajectory (one quintic segment).

    Raises:
        InvalidInputError: Arrays of the wrong length (the message names the argument and
            the length n of q0), values that are not finite, or a bad ``t``.
    """
    started = time.perf_counter()
    start, goal = joint_vectors(q0, qf)
    n = start.size
    v0 = np.zeros(n) if qd0 is None else as_vector(qd0, "qd0", n)
    v1 = np.zeros(n) if qd1 is None else as_vector(qd1, "qd1", n)
    base = time_base(t, normalised=True)
    coefficients = quintic_coefficients(start, goal, base.end, v0, v1)
    traj = stamp(
        Trajectory([0.0, base.end], coefficients[None]),
        "jtraj",
        started,
        time_unit=time_unit(base, "normalised"),
    )
    return SampledProfile("jtraj", *sample_fields(traj, base, scalar=False), base.istime, traj)


def mtraj(tfunc: ScalarProfile, q0: ArrayLike, qf: ArrayLike, t: int | ArrayLike) -> SampledProfile:
    """A scalar profile applied to each joint: ``tfunc(q0[j], qf[j], t)`` for joint j.

    Args:
        tfunc: A scalar profile of this package, :func:`~optraj.planners.arrays.quintic` or
            :func:`~optraj.planners.arrays.trapezoidal`, or a function of ``(q0, qf, t)``
            returning what they return (e.g. ``lambda a, b, t: trapezoidal(a, b, t, V=0.5)``).
        q0: Start positions [rad or m], shape (n,).
        qf: End positions [rad or m], shape (n,).
        t: As for ``tfunc``: an int number of steps or a time vector [s].

    Returns:
        The samples (shape (m, n) each) and the joints' trajectories stacked into one.

    Raises:
        InvalidInputError: ``tfunc`` not callable or not returning a SampledProfile with
            the same times for every joint, q0 and qf of different lengths, and any error
            of ``tfunc``.
    """
    if not callable(tfunc):
        raise InvalidInputError(
            f"tfunc must be a scalar profile function such as quintic or trapezoidal, got "
            f"{type(tfunc).__name__}",
            name="tfunc",
        )
    started = time.perf_counter()
    start, goal = joint_vectors(q0, qf)
    profiles = [tfunc(float(a), float(b), t) for a, b in zip(start, goal, strict=True)]
    first = profiles[0]
    for profile in profiles:
        if not isinstance(profile, SampledProfile) or profile.q.ndim != 1:
            raise InvalidInputError(
                f"tfunc must return a scalar SampledProfile (as quintic and trapezoidal do), "
                f"got {type(profile).__name__}",
                name="tfunc",
            )
        if not np.array_equal(profile.t, first.t):
            raise InvalidInputError(
                "tfunc returned different times for different joints", name="tfunc"
            )
    unit = first.trajectory.metadata.get("time_unit", "s" if first.istime else "step")
    traj = stack_joints(
        [profile.trajectory for profile in profiles],
        metadata={"profile": first.name},
    )
    stamp(traj, "mtraj", started, time_unit=unit)
    q, qd, qdd = (np.stack([getattr(p, f) for p in profiles], axis=1) for f in ("q", "qd", "qdd"))
    return SampledProfile("mtraj", first.t.copy(), q, qd, qdd, first.istime, traj)
