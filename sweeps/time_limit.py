"""A per-shot time limit inside one process: an alarm that interrupts the shot.

:func:`time_limit` raises :class:`ShotTimeout` in the calling thread when the block runs
longer than the limit. It uses ``SIGALRM``, so it interrupts Python code (a sleep, a loop)
but not a long call inside a C library, which returns first; the process executor also
stops such a shot from outside (:mod:`optraj.sweeps.processes`). Where there is no
``SIGALRM`` (Windows) or off the main thread, the block runs without a limit.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

__all__ = ["ShotTimeout", "time_limit"]


class ShotTimeout(Exception):  # noqa: N818  # the name says what happened, as TimeoutError
    """A shot ran past its time limit."""

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds
        super().__init__(f"the shot ran past the time limit of {seconds:.6g} s")


@contextmanager
def time_limit(seconds: float | None) -> Iterator[None]:
    """Raise :class:`ShotTimeout` in the block after ``seconds``; no limit when None."""
    usable = hasattr(signal, "SIGALRM") and threading.current_thread() is threading.main_thread()
    if seconds is None or not usable:
        yield
        return

    def _expired(signum: int, frame: FrameType | None) -> None:
        raise ShotTimeout(seconds)

    previous = signal.signal(signal.SIGALRM, _expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)
