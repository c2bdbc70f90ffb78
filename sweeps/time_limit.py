"""A per-shot time limit inside one process: interrupt the shot when it runs too long.

:func:`time_limit` raises :class:`ShotTimeout` in the calling thread when the block runs
longer than the limit. On the main thread it uses ``SIGALRM``, which also cuts a sleep or a
blocking system call short. On any other thread (a Dask worker runs tasks on a thread pool)
a timer raises the exception asynchronously in that thread, which Python delivers at the
next bytecode: it stops Python code, but neither a sleep nor a long call inside a C library
until that call returns. Executors that must stop those too watch from outside and stop the
worker (:mod:`optraj.sweeps.processes`, :mod:`optraj.sweeps.cluster`).
"""

from __future__ import annotations

import ctypes
import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

__all__ = ["ShotTimeout", "time_limit"]


class ShotTimeout(Exception):  # noqa: N818  # the name says what happened, as TimeoutError
    """A shot ran past its time limit.

    Attributes:
        seconds: The limit [s], or None when raised without it.
    """

    def __init__(self, seconds: float | None = None) -> None:
        self.seconds = seconds
        limit = "its time limit" if seconds is None else f"the time limit of {seconds:.6g} s"
        super().__init__(f"the shot ran past {limit}")


@contextmanager
def time_limit(seconds: float | None) -> Iterator[None]:
    """Raise :class:`ShotTimeout` in the block after ``seconds``; no limit when None."""
    if seconds is None:
        yield
    elif hasattr(signal, "SIGALRM") and threading.current_thread() is threading.main_thread():
        with _alarm(seconds):
            yield
    else:
        with _timer(seconds):
            yield


@contextmanager
def _alarm(seconds: float) -> Iterator[None]:
    def _expired(signum: int, frame: FrameType | None) -> None:
        raise ShotTimeout(seconds)

    previous = signal.signal(signal.SIGALRM, _expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)


class _Expired(ShotTimeout):
    """The exception a timer raises in another thread (Python creates it with no argument)."""

    limit: float | None = None

    def __init__(self) -> None:
        super().__init__(self.limit)


def _raise_in(thread_id: int, error: type[BaseException] | None) -> None:
    """Set (or, with None, clear) the exception pending in the thread ``thread_id``."""
    ctypes.pythonapi.PyThreadState_SetAsyncExc(
        ctypes.c_ulong(thread_id), ctypes.py_object(error) if error else None
    )


@contextmanager
def _timer(seconds: float) -> Iterator[None]:
    thread_id = threading.get_ident()
    expired = type("ShotTimeout", (_Expired,), {"limit": seconds})
    lock = threading.Lock()
    inside = [True]

    def _expire() -> None:
        with lock:
            if inside[0]:
                _raise_in(thread_id, expired)

    timer = threading.Timer(seconds, _expire)
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        with lock:
            inside[0] = False
            _raise_in(thread_id, None)  # drop an exception not yet delivered
        timer.cancel()
