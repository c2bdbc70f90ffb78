"""One-joint trajectories of one duration stacked into one trajectory of all the joints.

Each joint keeps its own polynomials; they are re-expanded about the union of every joint's
breakpoints (a Taylor shift: exact, up to round-off), breakpoints closer than 1e-12 of the
duration being merged so that no sliver of a segment is left.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from math import comb
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.trajectory import Trajectory

__all__ = ["MERGE_GAP", "shifted_coefficients", "stack_joints"]

FloatArray = NDArray[np.float64]

#: Breakpoints of different joints closer than this fraction of the duration are merged.
MERGE_GAP = 1e-12


def shifted_coefficients(coefficients: FloatArray, shift: FloatArray) -> FloatArray:
    """Coefficients about t0 + shift of polynomials given about t0.

    Args:
        coefficients: Shape (m, d + 1, n): row i multiplies (t - t0)^i.
        shift: Shape (m,), the new expansion points minus the old ones, in the unit of t.

    Returns:
        Shape (m, d + 1, n): c'_i = sum_{j >= i} C(j, i) c_j shift^(j - i).
    """
    d = coefficients.shape[1] - 1
    out = np.zeros_like(coefficients)
    for i in range(d + 1):
        for j in range(i, d + 1):
            out[:, i] += comb(j, i) * coefficients[:, j] * shift[:, None] ** (j - i)
    return out


def _merged_knots(trajectories: Sequence[Trajectory], duration: float) -> FloatArray:
    """The union of every breakpoint, neighbours within MERGE_GAP * duration merged."""
    candidates = np.unique(np.concatenate([traj.breakpoints for traj in trajectories]))
    gap = MERGE_GAP * duration
    knots = [0.0]
    for t in candidates[1:-1]:
        if t - knots[-1] > gap and duration - t > gap:
            knots.append(float(t))
    knots.append(duration)
    return np.array(knots)


def stack_joints(
    trajectories: Sequence[Trajectory], *, metadata: Mapping[str, Any] | None = None
) -> Trajectory:
    """The trajectory whose joint j is ``trajectories[j]`` (each of one joint, one duration).

    Args:
        trajectories: One-joint trajectories, each lasting the same time (within round-off).
        metadata: Metadata of the result.

    Returns:
        A trajectory of ``len(trajectories)`` joints on the merged breakpoints, of the highest
        degree among them.

    Raises:
        InvalidInputError: No trajectories, one that is not of one joint, or durations that
            differ by more than round-off.
    """
    if not trajectories or any(traj.dof != 1 for traj in trajectories):
        raise InvalidInputError(
            "stack_joints needs one or more one-joint trajectories", name="trajectories"
        )
    duration = trajectories[0].duration
    for j, traj in enumerate(trajectories):
        if abs(traj.duration - duration) > MERGE_GAP * duration:
            raise InvalidInputError(
                f"every joint must last {duration:.12g}, joint {j} lasts {traj.duration:.12g}",
                name="trajectories",
            )
    knots = _merged_knots(trajectories, duration)
    degree = max(traj.degree for traj in trajectories)
    middles = 0.5 * (knots[:-1] + knots[1:])
    coefficients = np.zeros((knots.size - 1, degree + 1, len(trajectories)))
    for j, traj in enumerate(trajectories):
        own = traj.breakpoints
        # The joint's own segment holding each new segment's middle, re-expanded at its start.
        k = np.clip(np.searchsorted(own, middles, side="right") - 1, 0, own.size - 2)
        rows = traj.coefficients[k]
        shifted = shifted_coefficients(rows, knots[:-1] - own[k])
        coefficients[:, : shifted.shape[1], j] = shifted[:, :, 0]
    return Trajectory(knots, coefficients, metadata=metadata)
