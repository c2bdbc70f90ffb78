"""One OSQP problem with a fixed sparsity pattern, updated in place at every control step."""

from __future__ import annotations

from typing import Any

import numpy as np
import osqp
import scipy.sparse as sparse
from numpy.typing import NDArray

from optraj.controllers.qp_terms import QP

__all__ = ["OSQP_INFINITY", "USABLE", "OSQPWorkspace"]

FloatArray = NDArray[np.float64]

#: OSQP's infinity.
OSQP_INFINITY = 1e30
#: OSQP outcomes whose ``x`` is used: solved, solved inaccurately, or stopped at the iteration
#: cap; the latter two only when the solution then passes the bound check.
USABLE = frozenset(
    int(status)
    for status in (
        osqp.SolverStatus.OSQP_SOLVED,
        osqp.SolverStatus.OSQP_SOLVED_INACCURATE,
        osqp.SolverStatus.OSQP_MAX_ITER_REACHED,
    )
)


class OSQPWorkspace:
    """One OSQP problem with a fixed sparsity pattern, updated in place at every step.

    ``H``'s upper triangle and ``A`` are stored dense (every entry structural), so that new
    numbers always fit the pattern OSQP factorised. The updates go straight to OSQP's
    compiled solver when its Python wrapper exposes it (the wrapper re-validates and copies
    on every call, which costs more than the solve of a 7-joint QP); otherwise through the
    wrapper's public ``update``/``solve``.
    """

    def __init__(self, qp: QP, tolerance: float, max_iterations: int) -> None:
        """Set OSQP up on ``qp``'s pattern with these tolerances and iteration cap."""
        n = qp.c.size
        columns = np.concatenate([np.full(j + 1, j) for j in range(n)])
        rows = np.concatenate([np.arange(j + 1) for j in range(n)])
        self.upper = (rows, columns)  # H's upper triangle in OSQP's column order
        a_rows, a_columns = np.nonzero(np.ones_like(qp.A))
        order = np.lexsort((a_rows, a_columns))  # OSQP stores A column by column
        self.a_index = (a_rows[order], a_columns[order])
        self.rows = qp.A.shape[0]
        P = sparse.csc_matrix((qp.H[self.upper], self.upper), shape=(n, n))
        A = sparse.csc_matrix((qp.A[self.a_index], self.a_index), shape=qp.A.shape)
        self.wrapper = osqp.OSQP()
        self.wrapper.setup(
            P,
            qp.c,
            A,
            *self._finite(qp),
            verbose=False,
            eps_abs=tolerance,
            eps_rel=tolerance,
            max_iter=max_iterations,
            check_termination=5,
            polishing=False,  # replaced by _refine (OSQP skips polishing with no active set)
            warm_starting=True,
        )
        compiled = getattr(self.wrapper, "_solver", None)
        needed = ("update_data_vec", "update_data_mat", "solve", "info", "solution")
        self.compiled = compiled if all(hasattr(compiled, a) for a in needed) else None

    @staticmethod
    def _finite(qp: QP) -> tuple[FloatArray, FloatArray]:
        """The QP's bounds clipped to OSQP's infinity."""
        return np.maximum(qp.lower, -OSQP_INFINITY), np.minimum(qp.upper, OSQP_INFINITY)

    def solve(self, qp: QP) -> tuple[bool, str, int, FloatArray, FloatArray]:
        """Update the numbers, solve from the last solution: (solved, status, iterations, x, y)."""
        px = qp.H[self.upper]
        ax = qp.A[self.a_index] if self.rows > qp.c.size else None
        lower, upper = self._finite(qp)
        if self.compiled is not None:
            self.compiled.update_data_vec(q=qp.c, l=lower, u=upper)
            self.compiled.update_data_mat(P_x=px, P_i=None, A_x=ax, A_i=None)
            self.compiled.solve()
            info = self.compiled.info
            x, y = self.compiled.solution.x, self.compiled.solution.y
        else:
            update: dict[str, Any] = {"Px": px, "q": qp.c, "l": lower, "u": upper}
            if ax is not None:
                update["Ax"] = ax
            self.wrapper.update(**update)
            result = self.wrapper.solve(raise_error=False)
            info, x, y = result.info, result.x, result.y
        solved = int(info.status_val) in USABLE and x is not None
        return solved, str(info.status), int(info.iter), np.array(x), np.array(y)
