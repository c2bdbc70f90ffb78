from __future__ import annotations

import numpy as np
from conftest import get_robot

from optraj.controllers.controller import Reference, State
from optraj.controllers.diff_ik_qp import DiffIKQP
from optraj.controllers.osqp_workspace import OSQP_INFINITY, OSQPWorkspace
from optraj.controllers.qp_terms import QP

DT = 1e-3


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


def test_the_wrappers_public_path_solves_as_the_compiled_one() -> None:
    # The QPs of a short closed loop, solved warm started by two workspaces: one through the
    # compiled solver (when the wrapper exposes it), one through osqp's public update/solve.
    robot = get_robot("sawyer")
    rng = np.random.default_rng(15)
    controller = DiffIKQP(robot, evaluation="pieces")
    limits = robot.limits
    q = (limits.lower + limits.upper) / 2 + rng.uniform(-0.3, 0.3, robot.dof) * (
        limits.upper - limits.lower
    )
    q_ref = q + rng.normal(0.0, 0.002, robot.dof)
    qd_ref = rng.uniform(-0.2, 0.2, robot.dof) * limits.velocity
    twist = robot.jacobian(q_ref) @ qd_ref
    reference = Reference(
        0.0, q_ref, qd_ref, np.zeros(robot.dof), robot.tool_pose(q_ref), twist, ""
    )
    state = State(0.0, q, np.zeros(robot.dof))
    controller.reset(state)
    fast = slow = None
    for k in range(20):
        qp = controller.build(state, reference, DT)
        if fast is None or slow is None:
            fast, slow = (OSQPWorkspace(qp, 1e-7, 1000) for _ in range(2))
            slow.compiled = None
        a, b = fast.solve(qp), slow.solve(qp)
        assert a[:3] == b[:3]  # solved, status, iterations
        np.testing.assert_allclose(a[3], b[3], rtol=0, atol=1e-9)
        np.testing.assert_allclose(a[4], b[4], rtol=0, atol=1e-9)
        command = controller.step(state, reference, DT)
        state = State((k + 1) * DT, state.q + command.qd * DT, command.qd)
