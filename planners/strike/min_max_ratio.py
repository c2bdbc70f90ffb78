r"""The least largest entry among the solutions of a linear system: the twist ratio's LP.

Among the solutions y of :math:`M y = b`, :class:`MinMaxRatio` finds one with the smallest
:math:`\max_i |y_i|`, the linear programme (LP)

.. math::

    \min_{y,\, s} s \quad \text{s.t.} \quad M y = b, \quad -s \le y_i \le s.

With M a strike's task rows scaled by the velocity limits, y is the joint velocity (over the
limits) that gives the strike motion with the smallest largest velocity-limit ratio
(:func:`planners.strike.twist_ratio.twist_ratio`). It is solved over the null-space
coordinates of M, so the equalities hold to rounding: exactly in NumPy by enumerating the LP's
vertices when the null space has one or two dimensions, returning the least-norm minimiser,
and by HiGHS through CasADi otherwise. A column of M far shorter than the others (a joint that
moves nothing the rows hold) is left at zero. Usage::

    lp = MinMaxRatio()
    y = lp(M, b)  # shape (n,), or None when M y = b has no solution
"""

from __future__ import annotations

import functools
import itertools
import math

import casadi as ca
import numpy as np
from numpy.typing import NDArray

from optraj.errors import SolverError

__all__ = ["MinMaxRatio", "idle_columns"]

FloatArray = NDArray[np.float64]

#: Singular values below this fraction of the largest count as zero in the task rows.
_RANK_TOLERANCE = 1e-10
#: A joint whose column of the task rows is shorter than this fraction of the longest one
#: moves nothing the rows hold, up to rounding and the IK tolerance (a cue's roll about its own
#: axis): it is left still and the LP solved for the other joints. Otherwise the minimiser
#: would spin it at the limit ratio for a gain of about 1e-9 in the ratio.
_IDLE_COLUMN = 1e-7
#: Relative residual above which the task rows cannot give the motion (ratio = inf).
_RESIDUAL_TOLERANCE = 1e-9
#: HiGHS primal and dual feasibility tolerances (its defaults are 1e-7).
_LP_TOLERANCE = 1e-10


class MinMaxRatio:
    r"""Smallest :math:`\max_i |y_i|` over the solutions of :math:`M y = b`.

    With :math:`y = y_0 + N z` (:math:`y_0` the minimum-norm solution, N an orthonormal basis
    of the null space of M, k columns) the equalities hold by construction, and what is left is
    the LP in (z, s): minimise s subject to :math:`-s \le y_0 + N z \le s`. For k <= 2 it is
    solved exactly in NumPy by enumerating its vertices (:func:`_min_max_on_line`,
    :func:`_min_max_on_plane`; a Sawyer cue on its line has k = 1 once its idle roll joint is
    set aside, paddle4 k = 1, Sawyer elsewhere k = 2); otherwise HiGHS solves it through
    CasADi, with solvers built once per problem size and kept by this object: keep one for the
    LPs of one search, and share none between threads. Among several minimisers the one of
    least norm is returned.
    """

    def __init__(self) -> None:
        self._solvers: dict[tuple[int, int], ca.Function] = {}

    def _solver(self, n: int, k: int) -> ca.Function:
        if (n, k) not in self._solvers:
            highs: dict[str, bool | str | float] = {
                "output_flag": False,
                "presolve": "off",  # a small LP: presolve only costs time
                "primal_feasibility_tolerance": _LP_TOLERANCE,
                "dual_feasibility_tolerance": _LP_TOLERANCE,
            }
            self._solvers[n, k] = ca.conic(
                "min_max_ratio",
                "highs",
                {"a": ca.Sparsity.dense(2 * n, k + 1), "h": ca.Sparsity(k + 1, k + 1)},
                {"highs": highs, "error_on_fail": False},
            )
        return self._solvers[n, k]

    def __call__(self, M: FloatArray, b: FloatArray) -> FloatArray | None:
        """The minimiser y, shape (n,), or None when ``M y = b`` has no solution."""
        idle = idle_columns(M)
        if not np.count_nonzero(idle):
            return self._solve(M, b)
        # Idle joints stay still (see _IDLE_COLUMN): solve for the others.
        moving = ~idle
        y = np.zeros(M.shape[1])
        if not np.count_nonzero(moving):  # nothing moves: only b = 0 has a solution
            return None if np.count_nonzero(b) else y
        inner = self._solve(M[:, moving], b)
        if inner is None:
            return None
        y[moving] = inner
        return y

    def _solve(self, M: FloatArray, b: FloatArray) -> FloatArray | None:
        U, S, Vt = np.linalg.svd(M)
        singular_values = S.tolist()
        largest = singular_values[0] if singular_values else 0.0
        rank = sum(value > _RANK_TOLERANCE * largest for value in singular_values)
        y0 = Vt[:rank].T @ ((U[:, :rank].T @ b) / S[:rank])
        if rank < M.shape[0]:  # with full row rank every b has a solution
            scale = math.sqrt(b @ b) + (largest * math.sqrt(y0 @ y0) if rank else 0.0)
            residual = M @ y0 - b
            if math.sqrt(residual @ residual) > _RESIDUAL_TOLERANCE * scale:
                return None
        null = Vt[rank:].T  # (n, k)
        k = null.shape[1]
        if k == 0 or not np.count_nonzero(y0):
            return y0
        if k == 1:
            return _min_max_on_line(y0, null[:, 0])
        if k == 2:
            return _min_max_on_plane(y0, null)
        return self.highs(y0, null)

    def highs(self, y0: FloatArray, null: FloatArray) -> FloatArray:
        r"""The minimiser of :math:`\max_i |y_0 + N z|_i` by HiGHS, shape (n,).

        Args:
            y0: Offset, shape (n,).
            null: N, shape (n, k), orthonormal columns, k >= 1.

        Raises:
            SolverError: HiGHS fails (not expected: the LP is always feasible and bounded).
        """
        n, k = null.shape
        ones = np.ones((n, 1))
        solver = self._solver(n, k)
        out = solver(
            g=np.r_[np.zeros(k), 1.0],
            a=np.block([[null, -ones], [-null, -ones]]),
            lba=-np.inf,
            uba=np.r_[-y0, y0],
            lbx=np.r_[np.full(k, -np.inf), 0.0],
            ubx=np.inf,
        )
        stats = solver.stats()
        if not stats.get("success", False):
            raise SolverError("highs", str(stats.get("return_status", "unknown")))
        return y0 + null @ np.asarray(out["x"]).ravel()[:k]


# The LP in (z, s) behind MinMaxRatio: minimise s subject to -s <= y0 + N z <= s, N of full
# column rank k. Its feasible set contains no line, so the optimum s* is attained at a vertex,
# where k + 1 constraints are active, on distinct rows r_0..r_k with signs sigma_j: two on one
# row would force s = 0, hence y0 = 0, which the caller handles. The sign of r_0 can be taken
# +1 (the opposite signs give the same z with -s), and eliminating s leaves the k equations
# (e_r0 - sigma_j e_rj)^T (y0 + N z) = 0. Every such candidate is solved for in closed form
# and max_i |y0 + N z|_i evaluated there; the smallest value is s*, since the optimal vertex is
# a candidate and any z gives an upper bound. Candidates with singular equations are skipped.
#
# The minimisers can be more than one point (paddle4 moving its paddle straight up leaves
# three joints free within the ratio of the fourth). Of them the one nearest z = 0 is
# returned, which is the joint velocity of least norm (y0 is orthogonal to N).


@functools.cache
def _line_candidates(n: int) -> FloatArray:
    r"""Equations of the 2 C(n, 2) candidate vertices for k = 1, shape (c, n).

    Row i is :math:`e_{r_0} - \sigma e_{r_1}` of candidate i, which therefore solves
    :math:`(P_i d) z = -P_i y_0`.
    """
    pairs = list(itertools.combinations(range(n), 2))
    operator = np.zeros((2 * len(pairs), n))
    for i, (first, second) in enumerate(pairs):
        operator[2 * i : 2 * i + 2, first] = 1.0
        operator[2 * i, second] = -1.0
        operator[2 * i + 1, second] = 1.0
    operator.setflags(write=False)
    return operator


def _min_max_on_line(y0: FloatArray, direction: FloatArray) -> FloatArray:
    r"""The least-norm minimiser of :math:`\max_i |y_0 + z d|_i` over the scalar z.

    Args:
        y0: Offset, nonzero, orthogonal to d, shape (n,).
        direction: d, a unit vector, shape (n,).

    Returns:
        The minimiser :math:`y_0 + z d`, shape (n,).
    """
    operator = _line_candidates(y0.size)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        z = -(operator @ y0) / (operator @ direction)
        worst = np.abs(direction[:, None] * z + y0[:, None]).max(axis=0)
    worst[~(worst < math.inf)] = math.inf  # singular candidates (and their NaNs)
    optimal = z[worst <= float(worst.min()) * (1.0 + 1e-12)]
    # The minimisers form an interval whose ends are optimal vertices: take 0 if it is inside.
    return y0 + min(max(0.0, float(optimal.min())), float(optimal.max())) * direction


@functools.cache
def _plane_candidates(n: int) -> FloatArray:
    r"""Equations of the 4 C(n, 3) candidate vertices for k = 2, shape (2 c, n).

    Row j c + i is :math:`e_{r_0} - \sigma_j e_{r_j}` of candidate i, which therefore solves
    :math:`(P_i N) z = -P_i y_0` (P_i its two rows).
    """
    triples = list(itertools.combinations(range(n), 3))
    signs = list(itertools.product((1.0, -1.0), repeat=2))
    count = len(triples) * len(signs)
    operator = np.zeros((2, count, n))
    for i, (rows, sign) in enumerate(itertools.product(triples, signs)):
        for j in range(2):
            operator[j, i, rows[0]] += 1.0
            operator[j, i, rows[j + 1]] -= sign[j]
    flat = operator.reshape(2 * count, n)
    flat.setflags(write=False)
    return flat


def _min_max_on_plane(y0: FloatArray, null: FloatArray) -> FloatArray:
    r"""The least-norm minimiser of :math:`\max_i |y_0 + N z|_i` over z in the plane.

    The minimisers form a convex polygon (usually a single vertex). Its point nearest z = 0
    is z = 0, the foot of z = 0 on a line where one constraint is active at s*, or one of
    its vertices: of those feasible (within 1e-12 of s*, relative), the nearest is taken.

    Args:
        y0: Offset, nonzero, orthogonal to the columns of N, shape (n,).
        null: N, shape (n, 2), orthonormal columns.

    Returns:
        The minimiser :math:`y_0 + N z`, shape (n,).
    """
    operator = _plane_candidates(y0.size)
    rows = operator @ np.column_stack([null, y0])  # [P_ij N | P_ij y0] in row j c + i
    count = rows.shape[0] // 2
    (a, b, e0), (c, d, e1) = rows[:count].T, rows[count:].T
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        det = a * d - b * c
        z = np.column_stack([(b * e1 - d * e0) / det, (c * e0 - a * e1) / det])
        worst = np.abs(null @ z.T + y0[:, None]).max(axis=0)
    worst[~(worst < math.inf)] = math.inf  # singular candidates (and their NaNs)
    index = int(np.argmin(worst))
    best = float(worst[index])
    allowed = best * (1.0 + 1e-12)
    optimal = z[worst <= allowed]
    if np.abs(optimal - z[index]).max() <= 1e-12 * (1.0 + np.abs(z[index]).max()):
        return y0 + null @ z[index]  # a single minimiser (all its candidates coincide)
    length2 = (null * null).sum(axis=1)
    usable = length2 > 0.0
    feet = [
        ((level - y0[usable]) / length2[usable])[:, None] * null[usable] for level in (best, -best)
    ]
    points = np.concatenate([np.zeros((1, 2)), *feet, optimal])
    values = np.abs(null @ points.T + y0[:, None]).max(axis=0)
    norms = (points * points).sum(axis=1)
    norms[~(values <= allowed)] = math.inf
    return y0 + null @ points[int(np.argmin(norms))]


def idle_columns(rows: FloatArray) -> NDArray[np.bool_]:
    """Which columns of ``rows`` count as zero: joints that move nothing the rows hold.

    A column shorter than a small fraction (1e-7) of the longest one is idle, up to rounding
    and the IK tolerance (a cue's roll about its own axis); every column is idle when all are
    zero.

    Args:
        rows: Task rows, shape (m, n).

    Returns:
        Shape (n,), True where the column is idle.
    """
    lengths = (rows * rows).sum(axis=0)
    return lengths <= _IDLE_COLUMN**2 * lengths.max()
