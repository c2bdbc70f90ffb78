"""The benchmark scripts run (in their quick form) and write their tables."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _load(name: str, monkeypatch):
    monkeypatch.syspath_prepend(str(ROOT / "benchmarks"))  # the scripts import benchmarking
    spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_time_optimal_quick_run_writes_its_table(tmp_path, monkeypatch):
    module = _load("time_optimal", monkeypatch)
    monkeypatch.setattr(module, "RESULTS", tmp_path)
    assert module.main(["--quick"]) == 0
    table = (tmp_path / "time_optimal.md").read_text()
    assert "| toppra |" in table and "| ruckig |" in table
    # Ruckig, time-optimal under the same velocity/acceleration/jerk limits as the bound, sits
    # on it; the others ignore jerk, so they may undercut it only slightly.
    rows = [line for line in table.splitlines() if line.startswith(("| sawyer", "| youbot"))]
    assert len(rows) == 2
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        ratios = [float(c) for c in cells[2:]]
        assert ratios[-1] == 1.0
        assert min(ratios) > 0.9


def test_strike_quick_run_writes_its_table(tmp_path, monkeypatch):
    module = _load("strike", monkeypatch)
    monkeypatch.setattr(module, "RESULTS", tmp_path)
    assert module.main(["--quick"]) == 0
    text = (tmp_path / "strike.md").read_text()
    table, extras = text.split("## OptimalControl solve times")
    header = next(line for line in table.splitlines() if line.startswith("| planner |"))
    columns = [c.strip() for c in header.strip("|").split("|")]
    assert columns[:4] == ["planner", "success", "motion time [s]", "vs cubic"]
    assert "peak jerk" in columns and "speed error [%]" in columns and "errors" in columns
    rows = {
        cells[0]: dict(zip(columns, cells, strict=True))
        for line in table.splitlines()
        if line.startswith("| ") and not line.startswith(("| planner", "|---"))
        for cells in [[c.strip() for c in line.strip("|").split("|")]]
    }
    expected = [label for label, _ in module.planners_to_compare()]
    assert list(rows) == expected
    assert expected[:6] == [
        "seed (pull back + line)",
        "cubic strike",
        "quintic strike",
        "lspb strike",
        "toppra strike",
        "ruckig strike",
    ]
    for row in rows.values():
        assert row["success"].split()[0].endswith("/4")
    # The seed jumps to full speed at the entry: planned every time, never within the limits.
    solved = int(rows["optimal control (min time)"]["success"].split("/")[0])
    assert solved >= 3  # it chooses its own contact configuration
    assert "| warm |" in extras and "| cold |" in extras
    seed = rows["seed (pull back + line)"]
    assert seed["success"].startswith("0/4") and "acceleration 4" in seed["checker failures"]
    assert seed["errors"] == "-"
    # Ruckig and the quintic keep every limit or raise: none of their trajectories fails.
    assert rows["ruckig strike"]["checker failures"] == "-"
    assert rows["quintic strike"]["checker failures"] == "-"


def test_tracking_quick_run_writes_its_tables(tmp_path, monkeypatch):
    module = _load("tracking", monkeypatch)
    monkeypatch.setattr(module, "RESULTS", tmp_path)
    assert module.main(["--quick"]) == 0
    text = (tmp_path / "tracking.md").read_text()
    table, timing = text.split("## Controller time per step")
    rows = {
        (cells[0], cells[1]): cells
        for line in table.splitlines()
        if line.startswith("| ") and not line.startswith(("| condition", "|---"))
        for cells in [[c.strip() for c in line.strip("|").split("|")]]
    }
    labels = ["pseudo-inverse PID", "differential-IK QP", "joint PD"]
    assert list(rows) == [(c, label) for c in module.CONDITIONS for label in labels]
    # On the plan at the limits the pseudo-inverse asks for more than a limit, the QP never.
    over = {label: rows[("at the limits", label)] for label in labels}
    assert over["pseudo-inverse PID"][6] != "0/2" and float(over["pseudo-inverse PID"][7]) > 1.0
    assert over["differential-IK QP"][6] == "0/2"
    assert float(over["differential-IK QP"][7]) <= 1.0
    assert "| differential-IK QP |" in timing and "| 1.00 |" in timing
