"""The inputs of the array functions checked: the time argument ``t`` and joint vectors.

As in the Robotics Toolbox, ``t`` is either an int, a number of steps, or a vector of times
[s]. Here a time vector must start at 0 s or later and strictly increase; the profile spans
[0, t[-1]] and is sampled at the given times.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.validation import MAX_DURATION, MIN_DURATION, as_count, as_vector, ndim_of

__all__ = ["MAX_STEPS", "TimeBase", "joint_vectors", "time_base"]

FloatArray = NDArray[np.float64]

#: Most samples an int ``t`` may ask for: a day at one step per second, the longest
#: trajectory optraj holds (MAX_DURATION) when each step is one unit of time.
MAX_STEPS = int(MAX_DURATION) + 1


class TimeBase(NamedTuple):
    """Sample times of a profile and the span it covers.

    Attributes:
        times: Sample times, shape (m,), m >= 2, strictly increasing, the last one ``end``.
        end: The profile's duration, in the unit of ``times``.
        istime: True for a time vector [s]; False for an int number of steps.
    """

    times: FloatArray
    end: float
    istime: bool


def _is_count(t: object) -> bool:
    """Whether ``t`` is an int (NumPy's too) rather than a time vector; bools are neither."""
    return isinstance(t, (int, np.integer)) and not isinstance(t, (bool, np.bool_))


def time_base(t: object, *, normalised: bool = False) -> TimeBase:
    """The sample times that ``t`` gives.

    Args:
        t: An int m >= 2, a number of steps: times 0, 1, ..., m - 1 [steps], or with
            ``normalised``, m times evenly over [0, 1] (as the Robotics Toolbox's
            ``jtraj``). Or a time vector [s], shape (m,), m >= 2, from 0 s or later, strictly
            increasing, ending in [MIN_DURATION, MAX_DURATION] s.
        normalised: Spread an int number of steps over [0, 1] instead of 0 .. m - 1.

    Raises:
        InvalidInputError: A bool, a float scalar, a count outside [2, MAX_STEPS], a vector
            that is not finite, has fewer than 2 times, starts below 0 s, does not strictly
            increase, or ends outside [MIN_DURATION, MAX_DURATION] s; the message names ``t``
            and the bound.
    """
    if _is_count(t):
        m = as_count(t, "t", 2, MAX_STEPS)
        if normalised:
            return TimeBase(np.linspace(0.0, 1.0, m), 1.0, False)
        return TimeBase(np.arange(m, dtype=float), float(m - 1), False)
    if ndim_of(t) != 1:
        raise InvalidInputError(
            f"t must be an int number of steps or a vector of times [s], got {t!r}",
            name="t",
            value=t,
        )
    times = as_vector(t, "t")  # type: ignore[arg-type]  # NumPy decides; errors are typed
    if times.size < 2:
        raise InvalidInputError(f"t must hold at least 2 times, got {times.size}", name="t")
    if times[0] < 0.0:
        raise InvalidInputError(f"t must start at 0 s or later, got {times[0]:.6g} s", name="t")
    steps = np.diff(times)
    if np.any(steps <= 0.0):
        i = int(np.argmax(steps <= 0.0))
        raise InvalidInputError(
            f"t must strictly increase: t[{i + 1}] = {times[i + 1]:.6g} s follows "
            f"t[{i}] = {times[i]:.6g} s",
            name="t",
        )
    end = float(times[-1])
    if not MIN_DURATION <= end <= MAX_DURATION:
        raise InvalidInputError(
            f"t must end in [{MIN_DURATION:.6g}, {MAX_DURATION:.6g}] s, got {end:.6g} s",
            name="t",
        )
    return TimeBase(times, end, True)


def joint_vectors(q0: ArrayLike, qf: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Start and goal positions [rad or m] as vectors of one length n >= 1.

    Raises:
        InvalidInputError: Not numeric, not finite, empty, or of different lengths (the
            message names ``qf`` and the length of ``q0``).
    """
    start = as_vector(q0, "q0")
    if start.size == 0:
        raise InvalidInputError("q0 must hold at least one joint position", name="q0")
    return start, as_vector(qf, "qf", start.size)
