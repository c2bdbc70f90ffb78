"""Sweeps: plan a batch of shots and tabulate which ones a robot can make, and how.

A :class:`ShotSet` describes pool shots over the table (a grid or a seeded random set of
ball positions, headings and speeds), a :class:`PaddleShotSet` paddle4 strikes over its
workspace; :func:`run` plans each one, serially or in local worker processes, with a
per-shot time limit, and returns one flat row per shot whose columns :data:`COLUMNS`
documents: among them the fastest strike speed the velocity limits allow at the shot's
contact and, for a job that tracks its plans in MuJoCo (:class:`ShotJob` with
``outcome=True``), where the ball went. Given ``out``, rows go to an append-only JSON-lines
file as they arrive, and a restarted run skips the shots already there. :func:`to_frame`
turns rows into a pandas DataFrame when pandas is installed.

>>> from optraj import sweeps
>>> rows = sweeps.run(sweeps.ShotSet(grid=(2, 2)), planner="ruckig")  # doctest: +SKIP
"""

from optraj.sweeps.columns import COLUMNS, OUTCOME_COLUMNS, STATUSES
from optraj.sweeps.frame import to_frame
from optraj.sweeps.job import ShotJob
from optraj.sweeps.paddle_shots import PaddleShotSet
from optraj.sweeps.run import run
from optraj.sweeps.shots import Shot, ShotSet
from optraj.sweeps.store import read_rows

__all__ = [
    "COLUMNS",
    "OUTCOME_COLUMNS",
    "STATUSES",
    "PaddleShotSet",
    "Shot",
    "ShotJob",
    "ShotSet",
    "read_rows",
    "run",
    "to_frame",
]
