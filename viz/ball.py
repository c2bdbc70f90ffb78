"""The ball's path from a strike outcome, and its motion along that path in time.

:class:`physics.Outcome` holds where the ball went: ``path`` (its positions over the run),
``roll`` (pool: every ``physics.outcome.ROLL_SAMPLE`` s from the run's end to rest; paddle:
the run's end and where it is ``FLIGHT_TIME`` after contact). It keeps no clock for ``path``;
the viewer lets the ball leave at the contact time and reach the roll-out's first point at the
launch speed, then follow the roll-out's own clock. Before contact the ball rests at its start.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from optraj.physics import Outcome
from optraj.physics.outcome import FLIGHT_TIME, ROLL_SAMPLE
from optraj.viz.shapes import Shape, polyline

__all__ = ["ball_motion", "ball_path", "path_shapes", "path_times"]

FloatArray = NDArray[np.float64]

PATH_COLOUR = (0.95, 0.25, 0.6, 1.0)
#: Radius of the drawn path [m].
PATH_RADIUS = 0.005


def ball_path(outcome: Outcome) -> FloatArray:
    """Start, then the run's and the roll-out's positions [m], shape (k, 3)."""
    start = np.asarray(outcome.start, dtype=float)[None, :]
    if not outcome.hit:
        return start
    parts = [start, np.asarray(outcome.path, dtype=float), np.asarray(outcome.roll, dtype=float)]
    return np.concatenate([part.reshape(-1, 3) for part in parts])


def path_times(outcome: Outcome) -> tuple[FloatArray, FloatArray]:
    """Positions [m], shape (k, 3), and the times they are reached [s], shape (k,), increasing.

    The start is held until contact; the roll-out's first point is reached at the launch
    speed; the roll-out follows its own sampling.
    """
    start = np.asarray(outcome.start, dtype=float)
    if not outcome.hit:
        return start[None, :], np.zeros(1)
    roll = np.asarray(outcome.roll, dtype=float).reshape(-1, 3)
    t0 = float(outcome.contact_time)
    reach = float(np.linalg.norm(roll[0] - start)) / max(float(outcome.launch_speed), 1e-9)
    first = t0 + reach
    if outcome.kind == "pool":
        rest = first + ROLL_SAMPLE * np.arange(len(roll))
    else:
        rest = np.linspace(first, max(first, t0 + FLIGHT_TIME), len(roll))
    times = np.concatenate([[t0], rest])
    # Equal times (a ball already at rest) would make the interpolation ambiguous.
    times = np.maximum.accumulate(times + 1e-9 * np.arange(len(times)))
    return np.vstack([start, roll]), times


def ball_motion(outcome: Outcome, times: FloatArray) -> FloatArray:
    """The ball's poses at ``times`` [s], shape (m, 4, 4) (translation only)."""
    points, reached = path_times(outcome)
    poses = np.tile(np.eye(4), (len(times), 1, 1))
    for axis in range(3):
        poses[:, axis, 3] = np.interp(times, reached, points[:, axis])
    return poses


def path_shapes(outcome: Outcome) -> list[Shape]:
    """The ball's path as thin capsules, named ``ball_path/<k>`` (none when missed)."""
    return polyline("ball_path", ball_path(outcome), PATH_RADIUS, PATH_COLOUR)
