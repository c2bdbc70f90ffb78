"""The shortest duration in a bracket: a bisection, and the same bisection run on a found root.

A polynomial whose ends move changes shape with its duration T, so whether it fits the limits
is found by trying durations. :func:`bisect` halves a bracket (``low`` does not fit, ``high``
fits) until it is 1e-9 of ``high`` wide and returns ``high``; each step costs one exact
check. :func:`shortest_in` returns the same number with far fewer checks: it narrows the
bracket to round-off around the crossing of a continuous margin (positive where the move
does not fit) by the Illinois variant of regula falsi (Dowell & Jarratt, BIT 11, 1971,
168-174), then runs the bisection's steps against that crossing. A step that lands inside
the narrowed bracket, and the result, are checked for real; should the result not fit (a
bracket with more than one crossing), the plain bisection decides.
"""

from __future__ import annotations

import math
from collections.abc import Callable

__all__ = ["bisect", "shortest_in"]

#: Relative width at which the bisection stops [-].
WIDTH = 1e-9
#: Relative width of the bracket around the crossing [-], far below WIDTH.
_NARROW = 1e-13
#: Most margin evaluations spent narrowing.
_STEPS = 60


def bisect(fits: Callable[[float], bool], low: float, high: float) -> float:
    """Halve [low, high] (``fits(high)``, not ``fits(low)``) down to WIDTH; the fitting end [s]."""
    for _ in range(60):
        middle = 0.5 * (low + high)
        if middle <= 0.0:
            break
        if fits(middle):
            high = middle
        else:
            low = middle
        if high - low < WIDTH * high:
            break
    return high


def _narrowed(
    margin: Callable[[float], float], low: float, high: float
) -> tuple[float, float] | None:
    """A bracket [a, b] of width _NARROW b or less around a crossing of ``margin``.

    ``margin`` must be > 0 at low and <= 0 at high; None if it is not, or if the Illinois
    steps (taken in log T, as margin is best a logarithm of peak ratios) do not narrow the
    bracket enough.
    """
    a, b = math.log(low), math.log(high)  # peaks go as powers of T: near lines in log T
    fa, fb = margin(low), margin(high)
    if not (fa > 0.0 >= fb):
        return None
    side = 0
    for _ in range(_STEPS):
        if b - a <= _NARROW:
            return math.exp(a), math.exp(b)
        c = b - fb * (b - a) / (fb - fa)
        if not a < c < b:
            c = 0.5 * (a + b)
        fc = margin(math.exp(c))
        if fc > 0.0:
            a, fa = c, fc
            if side < 0:
                fb *= 0.5
            side = -1
        else:
            b, fb = c, fc
            if side > 0:
                fa *= 0.5
            side = 1
    return None


def shortest_in(
    fits: Callable[[float], bool],
    margin: Callable[[float], float],
    low: float,
    high: float,
) -> float:
    """What :func:`bisect` returns on [low, high], found with few calls of ``fits``.

    Args:
        fits: Whether a duration [s] fits the limits (the exact check).
        margin: Continuous in the duration, > 0 exactly where ``fits`` is False; the root
            is found fastest when it is nearly linear in log T.
        low: A duration that does not fit [s], > 0.
        high: A duration that fits [s].
    """
    bracket = _narrowed(margin, low, high)
    if bracket is None:
        return bisect(fits, low, high)
    a, b = bracket

    def replayed(duration: float) -> bool:
        if duration >= b:
            return True
        if duration <= a:
            return False
        return fits(duration)

    found = bisect(replayed, low, high)
    return found if fits(found) else bisect(fits, low, high)
