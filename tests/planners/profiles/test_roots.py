"""Tests of planners.profiles.roots: every real root of every column is among those returned."""

from __future__ import annotations

import numpy as np
import pytest

from optraj.planners.profiles.roots import real_roots


def _columns_from_roots(rng, degree, n):
    """Random polynomials (ascending powers) with known real roots, shape (degree + 1, n)."""
    roots = rng.uniform(-2.0, 2.0, (degree, n))
    kind = rng.integers(0, 3, n)
    roots[1 % degree, kind == 1] = roots[0, kind == 1]  # double roots
    if degree >= 3:
        roots[:, kind == 2] = roots[0, kind == 2]  # triple (or quadruple) roots
    columns = np.stack([np.poly(roots[:, j])[::-1] * rng.uniform(0.1, 10) for j in range(n)], 1)
    return columns, roots


@pytest.mark.parametrize("degree", [1, 2, 3, 4])
def test_every_real_root_is_found(degree):
    rng = np.random.default_rng(40 + degree)
    with np.errstate(all="ignore"):
        for _ in range(200):
            columns, roots = _columns_from_roots(rng, degree, 6)
            found = real_roots(columns)
            for j in range(6):
                # NaN marks a polishing step that failed; its unpolished root is kept
                distance = np.nanmin(np.abs(found[:, j][:, None] - roots[:, j][None, :]), axis=0)
                # a root of multiplicity m is found to about eps^(1/m) of its size at worst
                tolerance = 10.0 * np.finfo(float).eps ** (1.0 / degree)
                assert np.all(distance <= tolerance * (1.0 + np.abs(roots[:, j]))), (degree, j)


def test_factors_and_missing_leading_terms():
    with np.errstate(all="ignore"):
        # x (x - 0.5)(x - 0.25): no constant term, solved as x times a quadratic
        cubic = np.poly([0.0, 0.5, 0.25])[::-1][:, None]
        np.testing.assert_allclose(np.sort(real_roots(cubic)[:, 0]), [0.0, 0.25, 0.5], atol=1e-15)
        # a quartic whose leading term vanishes in one column: that column's cubic roots
        quartic = np.zeros((5, 2))
        quartic[:4, 0] = np.poly([0.1, 0.2, 0.3])[::-1]
        quartic[:, 1] = np.poly([0.1, 0.2, 0.3, 0.4])[::-1]
        found = real_roots(quartic)
        for j, expected in enumerate(([0.1, 0.2, 0.3], [0.1, 0.2, 0.3, 0.4])):
            values = found[:, j][np.isfinite(found[:, j])]
            assert np.abs(values[:, None] - np.array(expected)).min(axis=0).max() < 1e-9
        # an all-zero column has no roots and breaks nothing
        assert not np.any(np.isfinite(real_roots(np.zeros((5, 1)))))
