from __future__ import annotations

import numpy as np
from scipy.optimize import lsq_linear

from optraj.controllers.active_set import ActiveSet
from optraj.controllers.qp_terms import QP


def _box(n: int, rng: np.random.Generator) -> QP:
    A = rng.normal(size=(6, n))
    b = rng.normal(size=6)
    H = A.T @ A + 1e-6 * np.eye(n)
    return QP(H, -A.T @ b, np.eye(n), -np.ones(n), np.ones(n), ())


def test_the_empty_set_solves_a_box_qp_whose_minimiser_is_inside() -> None:
    rng = np.random.default_rng(4)
    qp = _box(7, rng)
    wide = qp._replace(lower=np.full(7, -1e9), upper=np.full(7, 1e9))
    x = ActiveSet.none(7).solve(wide)
    assert x is not None
    np.testing.assert_allclose(qp.H @ x, -qp.c, atol=1e-9)


def test_from_multipliers_holds_the_bounds_with_clear_multipliers() -> None:
    rng = np.random.default_rng(5)
    qp = _box(4, rng)
    y = np.array([1.0, -1.0, 1e-12, 0.0])
    active = ActiveSet.from_multipliers(qp, y, 1e-7)
    np.testing.assert_array_equal(active.upper, [True, False, False, False])
    np.testing.assert_array_equal(active.lower, [False, True, False, False])
    assert not active.empty and ActiveSet.none(4).empty


def test_active_set_search_on_random_boxes_some_of_them_points():
    # Box QPs of the controller's form (H = A'A + damping): every result the search returns
    # is bounded least squares; joints whose bounds meet are held from either side.
    rng = np.random.default_rng(24)
    settled = 0
    for _ in range(300):
        n = 7
        A = rng.normal(size=(6, n))
        b = rng.normal(size=6)
        H = A.T @ A + 1e-6 * np.eye(n)
        lower = -rng.uniform(0.05, 1.0, n)
        upper = rng.uniform(0.05, 1.0, n)
        points = rng.random(n) < 0.3
        lower[points] = upper[points] = rng.uniform(-0.5, 0.5, int(points.sum()))
        qp = QP(H, -A.T @ b, np.eye(n), lower, upper, ())
        guess = ActiveSet(rng.random(n) < 0.3, np.zeros(n, dtype=bool))
        guess = ActiveSet(guess.upper, (rng.random(n) < 0.3) & ~guess.upper)
        found = guess.search(qp, 7)
        if found is None:
            continue  # OSQP would decide
        settled += 1
        # Reference: the points' joints fixed, bounded least squares (scipy's bvls) over the
        # others, with the damping as least-squares rows.
        stacked = np.vstack([A, 1e-3 * np.eye(n)])
        target = np.concatenate([b, np.zeros(n)]) - stacked[:, points] @ lower[points]
        free = ~points
        expected = lower.copy()
        expected[free] = lsq_linear(
            stacked[:, free], target, bounds=(lower[free], upper[free]), method="bvls", tol=1e-14
        ).x
        np.testing.assert_allclose(found[1], expected, atol=1e-7, rtol=0)
        assert np.all(found[1] >= lower) and np.all(found[1] <= upper)
    assert settled >= 270  # random guesses, up to 7 bounds off: most settle without OSQP
