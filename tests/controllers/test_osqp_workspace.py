from __future__ import annotations

import numpy as np

from optraj.controllers.osqp_workspace import OSQP_INFINITY, OSQPWorkspace
from optraj.controllers.qp_terms import QP


def _qp(c: np.ndarray, upper: float) -> QP:
    n = c.size
    return QP(2.0 * np.eye(n), c, np.eye(n), np.full(n, -upper), np.full(n, upper), ())


def test_solves_a_box_qp_and_its_updates_in_place() -> None:
    # min x'x + c'x in a box: x = clip(-c / 2, box).
    c = np.array([1.0, -4.0, 0.5])
    workspace = OSQPWorkspace(_qp(c, 1.0), 1e-9, 4000)
    solved, status, iterations, x, y = workspace.solve(_qp(c, 1.0))
    assert solved and iterations > 0 and status
    np.testing.assert_allclose(x, np.clip(-c / 2, -1.0, 1.0), atol=1e-6)
    assert y[1] > 0.0  # the upper bound of joint 1 holds (-c / 2 = 2 > 1)
    new = np.array([-1.0, 0.2, 3.0])
    solved, _, _, x, _ = workspace.solve(_qp(new, 1.0))
    assert solved
    np.testing.assert_allclose(x, np.clip(-new / 2, -1.0, 1.0), atol=1e-6)


def test_infinite_bounds_reach_osqp_as_its_infinity() -> None:
    c = np.array([2.0, -2.0])
    qp = _qp(c, np.inf)
    workspace = OSQPWorkspace(qp, 1e-9, 4000)
    solved, _, _, x, _ = workspace.solve(qp)
    assert solved
    np.testing.assert_allclose(x, -c / 2, atol=1e-6)
    assert OSQP_INFINITY >= 1e30
