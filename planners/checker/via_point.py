"""The ``via point k`` finding of a :class:`problems.ViaPoint`: the closest approach.

The distance from the trajectory to the via point is the largest joint distance
``max_j |q_j(t) - q_via_j|``; the finding is its minimum over time, found exactly on the
segments that can beat the best sample (a piecewise polynomial minimum: at a segment end, a
root or stationary point of one joint's error, or where two joints' errors are equal in
magnitude).

Example::

    evaluations.append(via_point_check(via, ctx))
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from optraj.planners.checker.context import CheckContext
from optraj.planners.checker.polynomials import (
    critical_points,
    evaluate_piecewise,
    polyval,
    real_roots,
    segment_index,
)
from optraj.planners.checker.report import Finding
from optraj.planners.checker.task import (
    Evaluation,
    constraint_tolerance,
    constraint_vector,
    task_finding,
)
from optraj.problems.constraints import ViaPoint

__all__ = ["via_point_check"]

FloatArray = NDArray[np.float64]

#: Most segments whose via-point distance is examined exactly (the closest samples' segments).
_MAX_REFINED = 64


def via_point_check(via: ViaPoint, ctx: CheckContext) -> Evaluation:
    """``via point k``: the closest approach, as the largest joint distance, to ``via.q``."""
    target = constraint_vector(via.q, "ViaPoint.q", ctx.limits.n)
    tolerance = constraint_tolerance(via.tolerance, "ViaPoint.tolerance", "rad")
    name = f"via point {via.index}"

    def evaluate() -> list[Finding]:
        q = evaluate_piecewise(ctx.derivatives[0], ctx.knots, ctx.grid)
        distance = np.max(np.abs(q - target[None, :]), axis=1)
        i = int(np.argmin(distance))
        best = (float(distance[i]), float(ctx.grid[i]))
        for k in _segments_to_refine(ctx, distance, best[0]):
            closest = _closest_on_segment(ctx, k, target)
            if closest[0] < best[0]:
                best = closest
        value, time = best
        q_at = evaluate_piecewise(ctx.derivatives[0], ctx.knots, np.array([time]))[0]
        j = int(np.argmax(np.abs(q_at - target)))
        unit = ctx.limits.unit("position", j)
        detail = (
            f"closest approach {value:.4g} {unit} at t = {time:.6g} s, largest on joint "
            f"{ctx.names[j]!r}"
        )
        return [task_finding(name, value, tolerance, time, unit, detail, joint=ctx.names[j])]

    return evaluate


def _segments_to_refine(ctx: CheckContext, distance: FloatArray, best: float) -> list[int]:
    """The segments whose exact minimum distance may beat the best sample's ``best``.

    Every instant lies within spacing / 2 of a sample, and the distance changes no faster
    than the fastest joint: its exact peak speed (a factor 2 to spare). The segments of the
    closest samples come first, at most ``_MAX_REFINED // 4`` of them.
    """
    slack = ctx.peak_speed * ctx.spacing + 1e-15
    segment = segment_index(ctx.knots, ctx.grid)
    close = np.argsort(distance, kind="stable")
    close = close[distance[close] <= best + slack]
    return list(dict.fromkeys(segment[close].tolist()))[: _MAX_REFINED // 4]


def _closest_on_segment(ctx: CheckContext, k: int, target: FloatArray) -> tuple[float, float]:
    """Exact minimum of the max-abs joint distance to ``target`` on segment ``k``.

    The distance is piecewise polynomial; its minimum lies at a segment end, a root or a
    stationary point of one joint's error, or where two joints' errors are equal in
    magnitude (a root of their sum or difference).

    Returns:
        (distance [rad or m], time [s]) of the minimum.
    """
    length = float(ctx.knots[k + 1] - ctx.knots[k])
    errors = ctx.derivatives[0][k].copy()  # (d + 1, n)
    errors[0] -= target
    polys = [errors[:, a] for a in range(errors.shape[1])]
    polys += [
        errors[:, a] + sign * errors[:, b]
        for a in range(errors.shape[1])
        for b in range(a + 1, errors.shape[1])
        for sign in (1.0, -1.0)
    ]
    taus = np.concatenate(
        [np.array([0.0, length])]
        + [real_roots(p, length) for p in polys]
        + [critical_points(p, length) for p in polys[: errors.shape[1]]]
    )
    values = np.max(
        np.abs(np.stack([polyval(errors[:, a], taus) for a in range(errors.shape[1])])),
        axis=0,
    )
    m = int(np.argmin(values))
    return float(values[m]), float(ctx.knots[k] + taus[m])
