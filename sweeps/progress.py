"""The sweep's progress bar: tqdm on stderr, shown on a terminal only, with the time left."""

from __future__ import annotations

from typing import Any, TextIO

__all__ = ["Progress"]


class Progress:
    """Counts finished shots and shows ``sweep: 40%|####  | 4/10 [00:02<00:03, ...]``.

    The bar is tqdm's: drawn only when ``stream`` is a terminal (nothing, not even a carriage
    return, goes to a pipe or a file), with the elapsed time and an estimate of the time left.

    Args:
        total: Shots to do.
        enabled: Draw nothing when False (when True, still only on a terminal).
        stream: Where to draw; stderr when None.
    """

    def __init__(self, total: int, enabled: bool = True, stream: TextIO | None = None) -> None:
        from tqdm import tqdm

        self.total = total
        self.done = 0
        self.enabled = enabled and total > 0
        # disable=None: tqdm draws only when the stream is a terminal.
        self._bar: Any = tqdm(
            total=total,
            desc="sweep",
            unit="shot",
            file=stream,
            disable=None if self.enabled else True,
            leave=True,
            dynamic_ncols=True,
        )

    def advance(self, count: int = 1) -> None:
        """Count ``count`` more finished shots and redraw; close the bar on the last one."""
        self.done += count
        self._bar.update(count)
        if self.done >= self.total:
            self.close()

    def close(self) -> None:
        """End the bar's line (once; later calls do nothing)."""
        self._bar.close()
