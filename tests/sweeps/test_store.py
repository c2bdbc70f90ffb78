import json

from optraj.sweeps.store import RowFile, read_rows


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
