import json
import sys

import pytest
from sweeps_support import SMALL

from optraj import sweeps
from optraj.errors import MissingDependencyError
from optraj.sweeps.columns import empty_row
from optraj.sweeps.parquet import read_parquet, write_parquet
from optraj.sweeps.store import RowFile, is_parquet, journal_path, read_rows


def test_rows_are_appended_and_read_back_by_id(tmp_path):
    path = tmp_path / "rows.jsonl"
    assert read_rows(path) == {}
    with RowFile(path) as file:
        file.write({"shot_id": "a", "status": "planned"})
        assert read_rows(path) == {"a": {"shot_id": "a", "status": "planned"}}  # flushed
    with RowFile(path) as file:
        file.write({"shot_id": "b", "status": "refused"})
        file.write({"shot_id": "a", "status": "failed"})
    rows = read_rows(path)
    assert list(rows) == ["a", "b"] and rows["a"]["status"] == "planned"  # the first row wins
    assert len(path.read_text().splitlines()) == 3


def test_a_line_cut_short_is_ignored_and_ended(tmp_path):
    path = tmp_path / "rows.jsonl"
    path.write_text(json.dumps({"shot_id": "a"}) + "\n" + '{"shot_id": "b", "sta')
    assert list(read_rows(path)) == ["a"]
    with RowFile(path) as file:
        file.write({"shot_id": "b"})
    assert list(read_rows(path)) == ["a", "b"]


def test_no_path_writes_nothing(tmp_path):
    with RowFile(None) as file:
        file.write({"shot_id": "a"})
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------------ Parquet tables


def test_a_parquet_path_journals_rows_then_folds_them_into_the_table(tmp_path):
    pytest.importorskip("pyarrow")
    path = tmp_path / "m.parquet"
    assert is_parquet(path) and not is_parquet(tmp_path / "m.jsonl")
    assert journal_path(path) == tmp_path / "m.parquet.jsonl"
    with RowFile(path) as file:
        file.write(empty_row() | {"shot_id": "a", "status": "planned"})
        assert not path.exists()
        assert list(read_rows(path)) == ["a"]  # read from the journal while running
    assert [p.name for p in tmp_path.iterdir()] == ["m.parquet"]
    with RowFile(path) as file:
        file.write(empty_row() | {"shot_id": "b", "status": "refused"})
        file.write(empty_row() | {"shot_id": "a", "status": "failed"})
    rows = read_rows(path)
    assert list(rows) == ["a", "b"] and rows["a"]["status"] == "planned"  # the first row wins
    assert [row["status"] for row in read_parquet(path)] == ["planned", "refused"]
    written = (path.stat().st_ino, path.stat().st_mtime_ns)
    with RowFile(path):
        pass  # nothing new: the table is left as it is
    assert (path.stat().st_ino, path.stat().st_mtime_ns) == written  # not replaced
    assert not journal_path(path).exists()


def test_a_journal_left_by_a_killed_run_is_read_and_folded_in(tmp_path):
    pytest.importorskip("pyarrow")
    path = tmp_path / "m.parquet"
    write_parquet([empty_row() | {"shot_id": "a"}], path)
    journal = journal_path(path)
    journal.write_text(json.dumps(empty_row() | {"shot_id": "b"}) + "\n" + '{"shot_id": "c", "s')
    assert list(read_rows(path)) == ["a", "b"]  # the line cut short is ignored
    with RowFile(path) as file:
        file.write(empty_row() | {"shot_id": "c"})
    assert [row["shot_id"] for row in read_parquet(path)] == ["a", "b", "c"]
    assert not journal.exists()


def test_a_sweep_to_parquet_reads_back_equal_to_its_rows(tmp_path):
    pytest.importorskip("pyarrow")
    out = tmp_path / "m.parquet"
    rows = sweeps.run(SMALL, planner="cubic", workers=0, out=out, progress=False)
    assert [row["shot_id"] for row in rows] == [shot.shot_id for shot in SMALL]
    assert list(read_rows(out).values()) == rows == read_parquet(out)
    assert {row["status"] for row in rows} == {"planned", "refused"}
    assert [p.name for p in tmp_path.iterdir()] == ["m.parquet"]


def test_a_parquet_sweep_stopped_and_restarted_has_every_shot_once(tmp_path):
    pytest.importorskip("pyarrow")
    out = tmp_path / "m.parquet"
    first = sweeps.run(SMALL, planner="cubic", workers=0, out=out, max_shots=3, progress=False)
    assert len(read_parquet(out)) == len(first) == 3
    rest = sweeps.run(SMALL, planner="cubic", workers=0, out=out, progress=False)
    assert rest[:3] == first  # read back, not planned again
    ids = [row["shot_id"] for row in read_parquet(out)]
    assert sorted(ids) == sorted(shot.shot_id for shot in SMALL)


def test_a_sweep_to_parquet_without_pyarrow_fails_before_planning(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow now fails
    with pytest.raises(MissingDependencyError, match=r"optraj\[sweeps\]"):
        sweeps.run(SMALL, planner="cubic", workers=0, out=tmp_path / "m.parquet", progress=False)
    assert list(tmp_path.iterdir()) == []


def test_a_sweep_resumes_from_the_journal_of_a_killed_parquet_run(tmp_path):
    pytest.importorskip("pyarrow")
    out = tmp_path / "m.parquet"
    # A killed run leaves only its journal: the rows it planned, as JSON lines.
    done = sweeps.run(
        SMALL, planner="cubic", workers=0, out=journal_path(out), max_shots=5, progress=False
    )
    rows = sweeps.run(SMALL, planner="cubic", workers=0, out=out, progress=False)
    assert rows[:5] == done
    assert [row["shot_id"] for row in read_parquet(out)] == [shot.shot_id for shot in SMALL]
    assert not journal_path(out).exists()
