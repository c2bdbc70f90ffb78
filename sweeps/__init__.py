"""Sweeps: plan a batch of shots and tabulate which ones a robot can make, and how.

A :class:`ShotSet` describes pool shots over the table (a grid or a seeded random set of
ball positions, headings and speeds), a :class:`PaddleShotSet` paddle4 strikes over its
workspace; :func:`run` plans each one, serially, in local worker processes or on a Dask
cluster (``scheduler=``), with a per-shot time limit, and returns one flat row per shot
whose columns :data:`COLUMNS` documents: among them the fastest strike speed the velocity
limits allow at the shot's contact and, with ``outcome=True``, where the ball went when the
plan is tracked in MuJoCo. Given ``out``, rows go to an append-only JSON-lines file as they
arrive, and a restarted run skips the shots already there; an ``out`` ending in
``.parquet`` is a typed Parquet table instead (:func:`write_parquet`, :func:`read_parquet`).
:func:`to_frame` and :func:`read_table` give a pandas DataFrame when pandas is installed;
:func:`plot_max_speed` and :func:`plot_motion_time` draw heat maps over the table.

>>> from optraj import sweeps
>>> rows = sweeps.run(sweeps.ShotSet(grid=(2, 2)), planner="ruckig")  # doctest: +SKIP
"""

from optraj.sweeps.columns import COLUMNS, OUTCOME_COLUMNS, STATUSES
from optraj.sweeps.frame import read_table, to_frame
from optraj.sweeps.job import ShotJob
from optraj.sweeps.paddle_shots import PaddleShotSet
from optraj.sweeps.parquet import read_parquet, write_parquet
from optraj.sweeps.plot import plot_max_speed, plot_motion_time
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
    "plot_max_speed",
    "plot_motion_time",
    "read_parquet",
    "read_rows",
    "read_table",
    "run",
    "to_frame",
    "write_parquet",
]
