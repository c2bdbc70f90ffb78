"""Sweeps: plan a batch of shots and tabulate which ones a robot can make, and how.

A :class:`ShotSet` describes pool shots over the table (a grid or a seeded random set of
ball positions, headings and speeds); :func:`run` plans each one, serially, in local
worker processes or on a Dask cluster (``scheduler=``), with a per-shot time limit, and
returns one flat row per shot whose columns :data:`COLUMNS` documents. Given ``out``, rows
go to an append-only JSON-lines file as they arrive, and a restarted run skips the shots
already there. :func:`to_frame` turns rows into a pandas DataFrame when pandas is installed.

>>> from optraj import sweeps
>>> rows = sweeps.run(sweeps.ShotSet(grid=(2, 2)), planner="ruckig")  # doctest: +SKIP
"""

from optraj.sweeps.columns import COLUMNS, STATUSES
from optraj.sweeps.frame import to_frame
from optraj.sweeps.run import run
from optraj.sweeps.shots import Shot, ShotSet
from optraj.sweeps.store import read_rows

__all__ = ["COLUMNS", "STATUSES", "Shot", "ShotSet", "read_rows", "run", "to_frame"]
