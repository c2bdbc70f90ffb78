"""An append-only JSON-lines file of rows: written as they arrive, read back to resume.

One row per line. A line cut short by a crash (the last one) is ignored on reading, so a
restarted sweep plans that shot again; a shot id met twice keeps its first row.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import IO

__all__ = ["RowFile", "read_rows"]


def read_rows(path: str | os.PathLike[str]) -> dict[str, dict[str, object]]:
    """The rows in ``path`` by shot id (none if the file does not exist)."""
    rows: dict[str, dict[str, object]] = {}
    file = Path(path)
    if not file.exists():
        return rows
    with file.open(encoding="utf-8") as lines:
        for line in lines:
            try:
                row = json.loads(line)
            except json.JSONDecodeError:  # a line cut short when a run was stopped
                continue
            if isinstance(row, dict) and isinstance(row.get("shot_id"), str):
                rows.setdefault(row["shot_id"], row)
    return rows


class RowFile:
    """Appends rows to a JSON-lines file, one flushed line each; a no-op for ``path=None``."""

    def __init__(self, path: str | os.PathLike[str] | None) -> None:
        self._file: IO[str] | None = None
        if path is not None:
            file = Path(path)
            if file.exists() and file.stat().st_size and not _ends_a_line(file):
                with file.open("a", encoding="utf-8") as tail:
                    tail.write("\n")  # end a line cut short, so the next row starts clean
            self._file = file.open("a", encoding="utf-8")

    def write(self, row: dict[str, object]) -> None:
        """Append one row and flush it to the operating system."""
        if self._file is not None:
            self._file.write(json.dumps(row) + "\n")
            self._file.flush()

    def close(self) -> None:
        """Close the file."""
        if self._file is not None:
            self._file.close()
            self._file = None

    def __enter__(self) -> RowFile:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _ends_a_line(file: Path) -> bool:
    with file.open("rb") as raw:
        raw.seek(-1, os.SEEK_END)
        return raw.read(1) == b"\n"
