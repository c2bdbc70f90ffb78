"""A plan's wall-time deadline and the solver callback that stops a solve past it."""

from __future__ import annotations

import contextlib
import math
import threading
import time
from collections.abc import Iterator, Sequence
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


#: The deadline of the solver calls made on each thread, as a ``time.perf_counter()`` value
#: [s]; absent (no deadline) outside :func:`deadline`.
_DEADLINE = threading.local()


@contextlib.contextmanager
def deadline(seconds: float) -> Iterator[None]:
    """Solver calls on this thread inside the block stop ``seconds`` [s] from now.

    A solver built with :func:`stop_callback` asks its solver to stop at the first iteration
    past the deadline (IPOPT then returns ``User_Requested_Stop``); :func:`time_left` tells
    the caller how much is left. Nested blocks keep the earlier deadline; ``math.inf`` sets
    none.
    """
    previous = getattr(_DEADLINE, "at", math.inf)
    _DEADLINE.at = min(previous, time.perf_counter() + seconds)
    try:
        yield
    finally:
        _DEADLINE.at = previous


def time_left() -> float:
    """Seconds until this thread's :func:`deadline` [s]; ``math.inf`` without one."""
    return getattr(_DEADLINE, "at", math.inf) - time.perf_counter()


class _Stop(ca.Callback):
    """An NLP solver's iteration callback: nonzero (stop) once the thread's deadline passed."""

    def __init__(self, variables: int, constraints: int, parameters: int) -> None:
        ca.Callback.__init__(self)
        self._sizes = {
            "x": variables,
            "lam_x": variables,
            "g": constraints,
            "lam_g": constraints,
            "lam_p": parameters,
            "f": 1,
        }
        self.construct("optraj_deadline", {})

    def get_n_in(self) -> int:
        return int(ca.nlpsol_n_out())

    def get_n_out(self) -> int:
        return 1

    def get_name_in(self, i: int) -> str:
        return str(ca.nlpsol_out(i))

    def get_name_out(self, i: int) -> str:
        return "stop"

    def get_sparsity_in(self, i: int) -> ca.Sparsity:
        return ca.Sparsity.dense(self._sizes.get(ca.nlpsol_out(i), 0), 1)

    def eval(self, arg: Sequence[Any]) -> list[float]:
        return [1.0 if time_left() <= 0.0 else 0.0]


def stop_callback(variables: int, constraints: int, parameters: int) -> ca.Callback:
    """An ``iteration_callback`` for ``casadi.nlpsol`` that stops the solve at the deadline.

    The solver keeps a reference only: the caller must keep the returned object alive as
    long as the solver.

    Args:
        variables: Decision variables of the NLP.
        constraints: Constraint rows.
        parameters: Parameters.
    """
    return _Stop(variables, constraints, parameters)
