"""What the via-point fits share: broken limits of a segment timing, and the segments' phases.

A fit (:mod:`optraj.planners.profiles.via_lspb`, :mod:`optraj.planners.profiles.via_quintic`)
times the segments between via points. Each limit a timing breaks is a :class:`TimingIssue`:
where, which joint, the value needed and the limit, and by how much to lengthen which
segments to mend it; :meth:`TimingIssue.error` reports it as an
:class:`optraj.errors.InfeasibleError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InfeasibleError
from optraj.planners.trajectory import Phase
from optraj.robots import JointLimits

__all__ = [
    "ROUND_OFF",
    "TimingIssue",
    "floor_durations",
    "limit_unit",
    "segment_issues",
    "segment_phases",
    "worst_issue",
]

FloatArray = NDArray[np.float64]

#: Relative excess over a limit that is taken as round-off, not a violation; also the
#: shortest piece kept in an LSPB trajectory, as a fraction of its duration.
ROUND_OFF = 1e-12


@dataclass(frozen=True)
class TimingIssue:
    """One broken limit of a candidate timing, and how to lengthen segments to mend it.

    Attributes:
        limit: ``velocity``, ``acceleration``, ``blend_time``, ``via_tolerance`` or
            ``position``.
        where: Where it happens, e.g. ``segment 2`` or ``via point 1``.
        joint: Joint index, or None.
        required: The value needed [unit].
        allowed: The limit [unit].
        unit: Unit text with a leading space, e.g. `` rad/s``.
        segments: Segments whose lengthening mends it.
        growth: Factor by which to lengthen them (may be inf when lengthening cannot help).
        fit: Whether this is a segment too short for its blends (required and allowed are
            durations [s]).
    """

    limit: str
    where: str
    joint: int | None
    required: float
    allowed: float
    unit: str
    segments: tuple[int, ...]
    growth: float
    fit: bool = False

    @property
    def ratio(self) -> float:
        """The ratio required / allowed [-]."""
        return self.required / self.allowed if self.allowed > 0.0 else math.inf

    def error(self, profile: str, names: tuple[str, ...], hint: str = "") -> InfeasibleError:
        """The InfeasibleError that reports this issue (joint, place, required and allowed).

        Args:
            profile: The via-point profile, for the message (``lspb`` or ``quintic``).
            names: The joint names.
            hint: Text appended to the message.
        """
        joint = None if self.joint is None else names[self.joint]
        head = f"via points ({profile}), {self.where}"
        required = f"{self.required:.6g}{self.unit}"
        allowed = f"{self.allowed:.6g}{self.unit}"
        if self.fit:
            why = f" (joint {joint!r} blending at its acceleration limit)" if joint else ""
            message = f"{head} lasts {allowed}, but its blends need {required}{why}"
        elif self.limit == "via_tolerance":
            message = (
                f"{head}: the blend passes joint {joint!r} {required} from the via point, "
                f"via_tolerance {allowed}"
            )
        else:
            message = f"{head}: needs joint {joint!r} at {required}, limit {allowed}"
        return InfeasibleError(
            message + hint,
            limit=self.limit,
            joint=joint,
            required=float(self.required),
            allowed=float(self.allowed),
        )


def limit_unit(limits: JointLimits, quantity: str, joint: int | None) -> str:
    """`` rad/s`` etc. for a joint, `` s`` for a duration (joint None)."""
    return " s" if joint is None else f" {limits.unit(quantity, joint)}"


def worst_issue(issues: list[TimingIssue]) -> TimingIssue:
    """The issue with the largest required / allowed (the first of equals)."""
    return max(issues, key=lambda issue: issue.ratio)


def segment_issues(
    quantity: str, values: FloatArray, bound: FloatArray, limits: JointLimits
) -> list[TimingIssue]:
    """The worst joint of each segment whose peak breaks its limit beyond round-off.

    Args:
        quantity: ``velocity`` or ``acceleration``.
        values: Peak |value| per segment and joint [rad/s or m/s, /s^2], shape (m, n).
        bound: The limits, shape (n,).
        limits: The joint limits (for the units).

    Returns:
        One issue per such segment, in segment order; lengthening that segment by
        value / limit mends it.
    """
    issues = []
    for i in range(values.shape[0]):
        ratio = values[i] / bound
        j = int(np.argmax(ratio))
        if ratio[j] > 1.0 + ROUND_OFF:
            issues.append(
                TimingIssue(
                    quantity,
                    f"segment {i + 1}",
                    j,
                    float(values[i, j]),
                    float(bound[j]),
                    limit_unit(limits, quantity, j),
                    (i,),
                    float(ratio[j]),
                )
            )
    return issues


def floor_durations(h: FloatArray) -> FloatArray:
    """Zero-length segments (repeated waypoints) get a small positive start value [s].

    The value is 1/1000 of the longest segment, or 1 s when no segment moves.
    """
    positive = h[h > 0.0]
    floor = 1e-3 * float(np.max(positive)) if positive.size else 1.0
    return np.where(h > 0.0, h, floor)


def segment_phases(times: FloatArray) -> list[Phase]:
    """One phase ``segment k`` per segment between consecutive via times, k from 1 [s].

    The names are those of :class:`problems.Waypoints` and :class:`planners.OptimalControl`,
    so that a plan warm-starts another.
    """
    return [Phase(f"segment {i + 1}", times[i], times[i + 1]) for i in range(times.size - 1)]
