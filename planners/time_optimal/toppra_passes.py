"""TOPPRA's two passes over the grid, driving toppra's Seidel solver with plain Python floats.

TOPPRA (Pham & Pham, IEEE T-RO 2018) finds the fastest path velocity on a grid with small
linear programs over the path acceleration u and the squared path velocity x = sd^2:

* backwards from the end, the controllable set [x_low, x_high] of each gridpoint (the
  squared path velocities from which the end can still be reached), two programs per stage;
* forwards from the start, greedily the largest u whose next x stays in the next
  controllable set, one program per stage.

toppra's own loop (``ReachabilityAlgorithm.compute_parameterization``) spends most of its
time on NumPy temporaries and checks around each solve. :func:`controllable_sets` and
:func:`forward_pass` make the same solver calls (same stage programs, same bounds, same
order, same clamps and retries, the same constants) with Python floats between them, so
they give the same numbers. ``toppra_classes.SeidelTOPPRA`` runs them.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray
from toppra.constants import MAX_TRIES, SMALL, TINY

__all__ = ["controllable_sets", "forward_pass", "start_controllable"]

FloatArray = NDArray[np.float64]

#: Weight of u in the objective of a controllable-set bound (the bound maximises or minimises
#: x; the small weight on u picks one optimum), as toppra 0.6's ``_one_step`` sets it.
_U_WEIGHT = 1e-9
#: When a forward stage is infeasible (round-off: the next controllable set is missed by a
#: hair), x is lowered to the larger of x - TINY and this share of x and the stage solved
#: again, at most MAX_TRIES times in a row (toppra 0.6's ``compute_parameterization``).
_RETRY_SHARE = 0.999
#: Each next x is lowered to the larger of x - TINY and this share of x before it is
#: clamped into its controllable set (the same source), against round-off growing.
_NEXT_SHARE = 0.9999


def _objective(solver: Any, first: float, second: float) -> FloatArray:
    """The linear objective g of a stage program: weights of u and x, zero on the rest."""
    g = np.zeros(solver.get_no_vars())
    g[0] = first
    g[1] = second
    return g


def controllable_sets(solver: Any, stages: int, sd_end: float) -> FloatArray:
    """The controllable sets of the squared path velocity, from the end backwards.

    Args:
        solver: toppra's Seidel solver wrapper of the problem.
        stages: Number of grid intervals N.
        sd_end: Path velocity at the end [path units/s], >= 0.

    Returns:
        K, shape (N + 1, 2): the lowest (clamped to >= 0) and the highest controllable x at
        each gridpoint. Where a stage's programs fail (NaN), that row holds the NaN and the
        rows before it stay zero.
    """
    sets = np.zeros((stages + 1, 2))
    x_end = sd_end**2
    sets[stages] = [x_end, x_end]
    solve = solver.solve_stagewise_optim
    highest = _objective(solver, _U_WEIGHT, -1.0)
    lowest = -highest
    nan = math.nan
    low = high = x_end
    solver.setup_solver()
    for i in range(stages - 1, -1, -1):
        x_high = solve(i, None, highest, nan, nan, low, high)[1]
        x_low = solve(i, None, lowest, nan, nan, low, high)[1]
        if x_low < 0:
            x_low = 0.0
        sets[i, 0] = x_low
        sets[i, 1] = x_high
        if math.isnan(x_low) or math.isnan(x_high):
            return sets  # the solver is left open, as toppra leaves it
        low, high = x_low, x_high
    solver.close_solver()
    return sets


def start_controllable(sets: FloatArray, sd_start: float) -> bool:
    """Whether the start's squared path velocity lies in its controllable set.

    Within toppra's slack ``SMALL`` (in x) on either side, as toppra judges it.
    """
    x_start = sd_start**2
    return not (x_start + SMALL < sets[0, 0] or sets[0, 1] + SMALL < x_start)


def forward_pass(
    solver: Any, sets: FloatArray, sd_start: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The greedy forward pass: the largest path acceleration at each stage.

    Args:
        solver: toppra's Seidel solver wrapper of the problem.
        sets: The controllable sets from :func:`controllable_sets`, without NaN.
        sd_start: Path velocity at the start [path units/s], within its controllable set.

    Returns:
        Path accelerations u, shape (N,); squared path velocities x, shape (N + 1,), NaN
        from the stage on where the retries ran out; and the solver's extra variables per
        stage, shape (N, no_vars - 2).
    """
    stages = solver.get_no_stages()
    deltas = solver.get_deltas().tolist()
    lows = sets[:, 0].tolist()
    highs = sets[:, 1].tolist()
    xs = np.zeros(stages + 1)
    us = np.zeros(stages)
    extra = np.zeros((stages, solver.get_no_vars() - 2))
    solve = solver.solve_stagewise_optim
    g = _objective(solver, 0.0, -1.0)
    x = sd_start**2
    xs[0] = x
    tries = 0
    solver.setup_solver()
    i = 0
    while i < stages:
        g[0] = -2 * deltas[i]
        result = solve(i, None, g, x, x, lows[i + 1], highs[i + 1]) if x == x else [math.nan]
        u = result[0]
        if math.isnan(u):
            if tries >= MAX_TRIES:
                xs[i + 1 :] = math.nan
                break
            x = max(x - TINY, _RETRY_SHARE * x)
            xs[i] = x
            tries += 1
            continue
        tries = 0
        us[i] = u
        x_next = x + 2 * deltas[i] * u
        x_next = max(x_next - TINY, _NEXT_SHARE * x_next)
        x = min(highs[i + 1], max(lows[i + 1], x_next))
        xs[i + 1] = x
        extra[i] = result[2:]
        i += 1
    solver.close_solver()
    return us, xs, extra
