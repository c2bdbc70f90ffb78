"""Planners for the Dask and process sweep tests, importable by their worker processes."""

from __future__ import annotations

import os

from optraj.planners import registry

#: Times a planner of this module was unpickled in this process.
LOADS = {"count": 0}


class Spinning:
    """Loops in Python forever: a hang that a time limit can interrupt on any thread."""

    def plan(self, problem):
        while True:
            sum(range(1000))


class CountingLoads:
    """Plans with ruckig; counts how often it is unpickled in each process."""

    def __init__(self):
        self.ruckig = registry.make_planner("pool-shot", "ruckig")

    def __setstate__(self, state):
        LOADS["count"] += 1
        self.__dict__.update(state)

    def plan(self, problem):
        return self.ruckig.plan(problem)


def loads():
    """This process's id and unpickle count (run on each worker)."""
    return os.getpid(), LOADS["count"]


def register():
    """Register the planners above for pool shots, in the registry copy the test set up."""
    registry.register_planner("pool-shot", "test-spin", Spinning)
    registry.register_planner("pool-shot", "test-count", CountingLoads)


class ThreadsReporting:
    """Raises with the BLAS thread settings of the process it plans in."""

    def plan(self, problem):
        names = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
        raise RuntimeError(",".join(str(os.environ.get(name)) for name in names))
