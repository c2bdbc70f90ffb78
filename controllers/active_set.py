"""The active set of a bounds-only QP: which bounds hold, and the exact solution on them."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import lapack

from optraj.controllers.qp_terms import QP

__all__ = ["ActiveSet"]

FloatArray = NDArray[np.float64]


class ActiveSet:
    """Which bounds hold as equalities, and the exact QP solution on them.

    Args:
        upper: Joints held at their upper bound, shape (n,) bool.
        lower: Joints held at their lower bound, shape (n,) bool.
    """

    #: Slack of the optimality checks, relative to ``max(1, |c|)``; round-off is far smaller.
    SLACK = 1e-9

    def __init__(self, upper: NDArray[np.bool_], lower: NDArray[np.bool_]) -> None:
        self.upper = upper
        self.lower = lower
        self.fixed = upper | lower
        self.empty = not self.fixed.any()

    @classmethod
    def none(cls, n: int) -> ActiveSet:
        """No bound held: the unconstrained solution."""
        return cls(np.zeros(n, dtype=bool), np.zeros(n, dtype=bool))

    @classmethod
    def from_multipliers(cls, qp: QP, y: FloatArray, tolerance: float) -> ActiveSet:
        """The bounds whose OSQP multiplier is clearly non-zero (positive: upper)."""
        n = qp.c.size
        scale = max(1.0, float(np.abs(qp.c).max()))
        return cls(y[:n] > tolerance * scale, y[:n] < -tolerance * scale)

    def solve(self, qp: QP) -> FloatArray | None:
        """The QP's exact solution if this is its active set, else None (bounds-only QPs).

        With the held joints fixed at their bounds the rest is one linear solve. The result
        is the solution only if it meets the optimality conditions: every joint within its
        bounds, and every held joint's cost gradient pointing outwards (a multiplier of the
        right sign). ADMM stops at a tolerance; along weakly weighted directions (a redundant
        arm's self-motion, held only by the damping and posture terms) its ``x`` may be off
        by tolerance / weight, which this removes.
        """
        x = self.on_bounds(qp)
        if x is None or self.next_set(qp, x) is not self:
            return None
        return np.minimum(np.maximum(x, qp.lower), qp.upper)  # round-off within the slack

    def search(self, qp: QP, tries: int) -> tuple[ActiveSet, FloatArray] | None:
        """The active set and exact solution reached from this one, or None.

        A primal-dual active-set method for a bounds-only QP: solve with the held joints at
        their bounds; then hold every free joint that left its bounds and release every held
        joint whose multiplier has the wrong sign; repeat until nothing changes, which is
        exactly when the optimality conditions hold. It usually takes one or two changes
        when the active set moved since the last step. None after ``tries`` solves (this set
        and ``tries - 1`` changes), on a cycle or a singular system: let OSQP decide.
        """
        active, seen = self, {self.upper.tobytes() + self.lower.tobytes()}
        for _ in range(tries):
            x = active.on_bounds(qp)
            if x is None:
                return None
            following = active.next_set(qp, x)
            if following is active:
                return active, np.minimum(np.maximum(x, qp.lower), qp.upper)
            key = following.upper.tobytes() + following.lower.tobytes()
            if key in seen:
                return None
            seen.add(key)
            active = following
        return None

    def on_bounds(self, qp: QP) -> FloatArray | None:
        """The QP's minimiser with the held joints fixed at their bounds; None if singular."""
        if self.empty:
            _, x, info = lapack.dposv(qp.H, qp.c)
            x = -x
        else:
            K = qp.H.copy()  # the held joints' rows become "x_j = bound"
            K[self.fixed] = 0.0
            K[self.fixed, self.fixed] = 1.0
            rhs = np.where(self.upper, qp.upper, np.where(self.lower, qp.lower, -qp.c))
            _, _, x, info = lapack.dgesv(K, rhs)
        return None if info != 0 else x

    def next_set(self, qp: QP, x: FloatArray) -> ActiveSet:
        """This set if x (its solution) is optimal, else the set to try next.

        Optimal: free joints within their bounds; held joints' cost gradient pointing out of
        the box (at an upper bound no larger than 0, at a lower one no smaller), each up to
        :data:`SLACK` relative to ``max(1, |c|)``. Next: hold the free joints that left, at
        the bound they passed; release the held joints whose gradient points inwards.
        """
        slack = self.SLACK * max(1.0, float(np.abs(qp.c).max()))
        above = x > qp.upper + slack
        below = x < qp.lower - slack
        if self.empty:
            if not (above.any() or below.any()):
                return self
            return ActiveSet(above, below)
        gradient = qp.H @ x + qp.c
        # A joint whose bounds meet stays held whatever its multiplier's sign (kept as an
        # upper bound), rather than being freed only to be held again at the other one.
        pinned = self.fixed & (qp.lower >= qp.upper)
        upper = above | (self.upper & (gradient <= slack)) | pinned
        lower = (below | (self.lower & (gradient >= -slack))) & ~pinned
        if np.array_equal(upper, self.upper | pinned) and np.array_equal(
            lower, self.lower & ~pinned
        ):
            return self
        return ActiveSet(upper, lower)
