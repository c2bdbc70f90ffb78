"""Tests of planners.strike.min_max_ratio: the LP's NumPy path against HiGHS and vertices."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import null_space
from strike_support import by_vertices

from optraj.planners.strike.min_max_ratio import MinMaxRatio, idle_columns


def _random_lp(rng, kind):
    """A consistent system M y = b with a null space of dimension 1 or 2, of one of 6 kinds.

    0 generic; 1 a repeated row (rank below the row count); 2 a zero column (a joint that moves
    nothing); 3 entries in {-1, 0, 1} (ties between rows); 4 b = 0; 5 a column scaled by 1e-12.
    """
    n = int(rng.integers(3, 9))
    k = int(rng.integers(1, 3))
    M = rng.normal(size=(n - k, n))
    if kind == 1 and M.shape[0] >= 2:
        M = np.vstack([M, M[0] * rng.normal()])
    elif kind == 2:
        M[:, rng.integers(n)] = 0.0
    elif kind == 3:
        M = rng.integers(-1, 2, size=(n - k, n)).astype(float)
    elif kind == 5:
        M[:, rng.integers(n)] *= 1e-12
    b = np.zeros(M.shape[0]) if kind == 4 else M @ rng.normal(size=n)
    return M, b


def _null_space_problem(M, b):
    """y0 and N as MinMaxRatio builds them (independently: lstsq and scipy's null_space)."""
    null = null_space(M, rcond=1e-10)
    y0 = np.linalg.lstsq(M, b, rcond=1e-10)[0]
    return y0 - null @ (null.T @ y0), null


@pytest.mark.parametrize("seed", range(6))
def test_numpy_lp_agrees_with_highs_on_random_and_degenerate_problems(seed):
    rng = np.random.default_rng(100 + seed)
    lp = MinMaxRatio()
    checked = 0
    for trial in range(150):
        kind = trial % 6
        M, b = _random_lp(rng, kind)
        y = lp(M, b)
        assert y is not None
        scale = 1.0 + float(np.abs(b).max())
        np.testing.assert_allclose(M @ y, b, rtol=0, atol=1e-9 * scale)
        y0, null = _null_space_problem(M, b)
        if not np.any(np.abs(y0) > 1e-14) or null.shape[1] == 0:
            np.testing.assert_allclose(y, 0.0, atol=1e-12)  # b = 0: standing still is optimal
            continue
        ratio = float(np.abs(y).max())
        highs = float(np.abs(lp.highs(y0, null)).max())
        reference = by_vertices(M, b, np.ones(M.shape[1]))
        assert ratio == pytest.approx(highs, rel=1e-9)
        assert ratio == pytest.approx(reference, rel=1e-9)
        checked += 1
    assert checked >= 100


def test_numpy_lp_returns_the_least_norm_minimiser_and_leaves_idle_joints_still():
    lp = MinMaxRatio()
    # Only the first joint moves the row: the others are free up to its ratio (a square of
    # minimisers for k = 2, an interval for k = 1); the least-norm one keeps them still.
    for M in (np.array([[2.0, 0.0, 0.0]]), np.array([[2.0, 0.0], [0.0, 0.0]])):
        y = lp(M, np.r_[1.0, np.zeros(M.shape[0] - 1)])
        np.testing.assert_allclose(y, np.r_[0.5, np.zeros(M.shape[1] - 1)], rtol=0, atol=1e-15)
    # The ratio is set by joints 0 and 1 together (y0 + y1 = 1): 0.5 each, and joint 2, free up
    # to 0.5, stays still although every y2 in [-0.5, 0.5] is optimal.
    y = lp(np.array([[1.0, 1.0, 0.0]]), np.array([1.0]))
    np.testing.assert_allclose(y, [0.5, 0.5, 0.0], rtol=0, atol=1e-15)
    # A column far shorter than the others (a joint that moves nothing) stays exactly still.
    rng = np.random.default_rng(7)
    M = rng.normal(size=(5, 7))
    M[:, 6] = 1e-11 * rng.normal(size=5)
    b = M @ rng.normal(size=7)
    y = lp(M, b)
    assert y[6] == 0.0
    np.testing.assert_allclose(M @ y, b, rtol=0, atol=1e-9)
    reduced = lp(M[:, :6], b)
    np.testing.assert_array_equal(y[:6], reduced)


def test_numpy_lp_reports_a_motion_the_rows_cannot_give():
    lp = MinMaxRatio()
    assert lp(np.array([[1.0, 0.0], [1.0, 0.0]]), np.array([1.0, 2.0])) is None
    assert lp(np.zeros((2, 3)), np.array([1.0, 0.0])) is None
    np.testing.assert_array_equal(lp(np.zeros((2, 3)), np.zeros(2)), np.zeros(3))


def test_idle_columns_are_those_far_shorter_than_the_longest():
    rows = np.array([[1.0, 0.0, 1e-8, 0.5], [0.0, 0.0, 0.0, 0.5]])
    np.testing.assert_array_equal(idle_columns(rows), [False, True, True, False])
    np.testing.assert_array_equal(idle_columns(np.zeros((2, 3))), [True, True, True])
