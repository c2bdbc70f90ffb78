"""Where a sweep's rows are kept: an append-only JSON-lines file, or a Parquet table.

A JSON-lines file holds one row per line. A line cut short by a crash (the last one) is
ignored on reading, so a restarted sweep plans that shot again; a shot id met twice keeps
its first row.

A path ending in ``.parquet`` is a typed table (:mod:`optraj.sweeps.parquet`). Rows
arriving during a run are appended, as above, to a journal beside it
(:func:`journal_path`, ``map.parquet.jsonl``); on close the table is rewritten atomically
from the rows already in it and the journal's, and the journal removed. A run that was
killed leaves its journal, which :func:`read_rows` reads as well.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import IO

from optraj.sweeps import parquet

__all__ = ["PARQUET_SUFFIX", "RowFile", "is_parquet", "journal_path", "read_rows"]

#: A path ending so is written as a Parquet table.
PARQUET_SUFFIX = ".parquet"


def is_parquet(path: str | os.PathLike[str]) -> bool:
    """Whether rows for ``path`` go to a Parquet table (the name ends in ``.parquet``)."""
    return Path(path).suffix.lower() == PARQUET_SUFFIX


def journal_path(path: str | os.PathLike[str]) -> Path:
    """The JSON-lines journal of the Parquet table ``path``: its name plus ``.jsonl``."""
    table = Path(path)
    return table.with_name(table.name + ".jsonl")


def _read_lines(file: Path, rows: dict[str, dict[str, object]]) -> None:
    """Add the rows of the JSON-lines ``file`` to ``rows``, keeping rows already there."""
    if not file.exists():
        return
    with file.open(encoding="utf-8") as lines:
        for line in lines:
            try:
                row = json.loads(line)
            except json.JSONDecodeError:  # a line cut short when a run was stopped
                continue
            if isinstance(row, dict) and isinstance(row.get("shot_id"), str):
                rows.setdefault(row["shot_id"], row)


def read_rows(path: str | os.PathLike[str]) -> dict[str, dict[str, object]]:
    """The rows kept at ``path`` by shot id, in the order written (none if there are none).

    For a ``.parquet`` path: the table's rows, then those of a journal a killed run left.

    Raises:
        MissingDependencyError: A Parquet table or journal, and pyarrow is not installed.
        InvalidInputError: ``path`` ends in ``.parquet`` but is no Parquet file.
    """
    rows: dict[str, dict[str, object]] = {}
    file = Path(path)
    if not is_parquet(file):
        _read_lines(file, rows)
        return rows
    if file.exists():
        for row in parquet.read_parquet(file):
            if isinstance(row.get("shot_id"), str):
                rows.setdefault(str(row["shot_id"]), row)
    _read_lines(journal_path(file), rows)
    return rows


class RowFile:
    """Appends rows to a JSON-lines file, one flushed line each; a no-op for ``path=None``.

    For a ``.parquet`` path the lines go to its journal, and :meth:`close` rewrites the
    table with them (see the module docstring).

    Raises:
        MissingDependencyError: A ``.parquet`` path, and pyarrow is not installed (said on
            opening, before any shot is planned).
    """

    def __init__(self, path: str | os.PathLike[str] | None) -> None:
        self._file: IO[str] | None = None
        self._table: Path | None = None
        if path is None:
            return
        file = Path(path)
        if is_parquet(file):
            parquet.pyarrow()
            self._table, file = file, journal_path(file)
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
        """Close the file; for a Parquet table, fold the journal into it and remove it."""
        if self._file is not None:
            self._file.close()
            self._file = None
        if self._table is not None:
            table, self._table = self._table, None
            journal = journal_path(table)
            if not table.exists() or journal.stat().st_size:  # else nothing new to fold in
                parquet.write_parquet(read_rows(table).values(), table)
            journal.unlink(missing_ok=True)

    def __enter__(self) -> RowFile:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _ends_a_line(file: Path) -> bool:
    with file.open("rb") as raw:
        raw.seek(-1, os.SEEK_END)
        return raw.read(1) == b"\n"
