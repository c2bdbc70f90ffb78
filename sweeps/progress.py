"""A one-line progress bar on stderr with an estimate of the time left."""

from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["Progress"]


class Progress:
    """Counts finished shots and redraws ``[####....] done/total, ~N s left`` on a stream.

    Args:
        total: Shots to do.
        enabled: Draw nothing when False.
        stream: Where to draw; stderr when None.
    """

    WIDTH = 30

    def __init__(self, total: int, enabled: bool = True, stream: TextIO | None = None) -> None:
        self.total = total
        self.done = 0
        self.enabled = enabled and total > 0
        self._stream = stream
        self._start = time.monotonic()

    def advance(self, count: int = 1) -> None:
        """Count ``count`` more finished shots and redraw."""
        self.done += count
        if not self.enabled:
            return
        stream = self._stream or sys.stderr
        filled = int(self.WIDTH * self.done / self.total)
        elapsed = time.monotonic() - self._start
        left = elapsed / self.done * (self.total - self.done) if self.done else 0.0
        bar = "#" * filled + "." * (self.WIDTH - filled)
        stream.write(f"\rsweep [{bar}] {self.done}/{self.total}, ~{left:.0f} s left ")
        if self.done >= self.total:
            stream.write("\n")
        stream.flush()
