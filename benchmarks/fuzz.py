"""The fuzz run of ``make fuzz``: the suite of tests/fuzz in its ``fuzz`` profile, and a report.

Runs every property of ``tests/fuzz`` with hypothesis's ``fuzz`` profile: ``--cases`` cases
in all (100,000 by default, shared over the properties by ``tests/fuzz/budget.py``), random
from one fixed ``--seed``, a per-case deadline of ``--deadline`` seconds (a refusal slower
than that fails its property), in ``--jobs`` pytest processes at once. Then writes
``fuzz.md`` into ``--out``: the seed, the duration, the cases, time and outcomes of each
property, and each failure with hypothesis's falsifying example (a reproducer: robot,
planner, inputs) and its reproduce blob.

Usage: ``python benchmarks/fuzz.py [--cases N] [--seed S] [--jobs J] [--out DIR]``
(``FUZZ_SEED`` and ``FUZZ_CASES`` give the defaults). Exits 1 when a property fails.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_SEED = 20261202

#: The tests of the suite (file, function, property shown), each run as one pytest process,
#: the costliest first (so that the jobs end together).
TESTS: list[tuple[str, str, str]] = [
    (
        "test_planners.py",
        "test_a_plan_passes_the_checker_or_is_refused",
        "1, 2: planned and checked, or refused",
    ),
    (
        "test_inputs.py",
        "test_a_malformed_input_gives_a_typed_error",
        "malformed input: a typed error",
    ),
    (
        "test_cli.py",
        "test_any_argv_exits_0_1_or_2_with_one_error_line",
        "5: CLI argv, exit 0/1/2, one error line",
    ),
    (
        "test_cli.py",
        "test_checking_a_broken_file_exits_0_1_or_2_with_one_error_line",
        "5: CLI broken file, exit 0/1/2, one error line",
    ),
    (
        "test_planners.py",
        "test_a_hard_problem_is_refused_with_a_typed_error_or_planned_within_limits",
        "4: a hard problem refused in time",
    ),
    (
        "test_planners.py",
        "test_two_plans_of_one_problem_are_identical",
        "3: two plans identical",
    ),
    (
        "test_trajectories.py",
        "test_the_checker_sees_every_breach_that_dense_sampling_sees",
        "checker: sees every sampled breach, no NaN",
    ),
    (
        "test_trajectories.py",
        "test_a_trajectory_survives_export_and_import",
        "trajectory: export and import unchanged",
    ),
    (
        "test_controllers.py",
        "test_a_closed_loop_run_finishes_without_nan_or_is_refused",
        "controllers: closed loop without NaN",
    ),
    (
        "test_planners.py",
        "test_a_cartesian_line_passes_the_checker_or_is_refused",
        "1, 2: Cartesian line checked or refused",
    ),
    (
        "test_planners.py",
        "test_a_paddle_strike_passes_the_checker_or_is_refused",
        "1, 2: paddle strike checked or refused",
    ),
    (
        "test_planners.py",
        "test_optimal_control_plans_pass_the_checker_or_are_refused",
        "1, 2: optimal control checked or refused",
    ),
    (
        "test_planners.py",
        "test_optimal_control_strikes_and_hard_moves_are_planned_or_refused",
        "4: optimal control hard cases refused in time",
    ),
    (
        "test_planners.py",
        "test_known_cases",
        "known cases (reproducers of past findings)",
    ),
]


def run_test(test: str, raw: Path, env: dict[str, str], seed: int) -> tuple[str, int, float]:
    """Run one test of the suite in its own pytest process; ``(test, status, seconds)``."""
    record = raw / (test.replace("/", "_").replace(":", "_") + ".json")
    started = time.perf_counter()
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            f"tests/fuzz/{test}",
            "-q",
            "-p",
            "no:cacheprovider",
            f"--hypothesis-seed={seed}",
        ],
        cwd=ROOT,
        env={**env, "FUZZ_REPORT": str(record)},
        capture_output=True,
        text=True,
        check=False,
    )
    (raw / (record.stem + ".log")).write_text(done.stdout + done.stderr)
    return test, done.returncode, time.perf_counter() - started


def _rate(cases: int, seconds: float) -> str:
    return f"{cases / seconds:,.0f}" if seconds > 0 else "-"


def report(
    args: argparse.Namespace, raw: Path, runs: list[tuple[str, int, float]], wall: float
) -> tuple[str, int]:
    """The Markdown report and the number of failing tests."""
    label = {f"{file}::{test}": text for file, test, text in TESTS}
    rows = []
    failures: list[tuple[str, str]] = []
    known: list[tuple[str, str]] = []
    total = 0
    for test, status, seconds in runs:
        record_path = raw / (test.replace("/", "_").replace(":", "_") + ".json")
        records = json.loads(record_path.read_text()) if record_path.exists() else {}
        cases = sum(r.get("cases", 0) for r in records.values())
        spent = sum(r.get("seconds", 0.0) for r in records.values())
        outcomes: Counter[str] = Counter()
        for r in records.values():
            outcomes.update(r.get("outcomes", {}))
        slowest = max((r.get("slowest", 0.0) for r in records.values()), default=0.0)
        refusal = max((r.get("slowest_refusal", 0.0) for r in records.values()), default=0.0)
        bad = [(node, r["failure"]) for node, r in records.items() if r.get("failure")]
        expected = [(node, r["known"]) for node, r in records.items() if r.get("known")]
        known.extend(expected)
        if status not in (0, 5) and not bad:  # 5: nothing collected (e.g. no known cases)
            log = (raw / (record_path.stem + ".log")).read_text()
            bad = [(test, log[-4000:])]
        failures.extend(bad)
        total += cases
        top = ", ".join(f"{name} {count}" for name, count in outcomes.most_common(4))
        rows.append(
            f"| {label.get(test, test)} | {cases:,} | {len(bad)} | {len(expected)} | "
            f"{seconds:.0f} | {_rate(cases, spent)} | {slowest:.2f} | {refusal:.2f} | {top} |"
        )
    lines = [
        "# Fuzz run",
        "",
        f"Command: `make fuzz` (`python benchmarks/fuzz.py --cases {args.cases} --seed "
        f"{args.seed} --jobs {args.jobs} --deadline {args.deadline:g}`), hypothesis profile "
        "`fuzz` of tests/fuzz/conftest.py.",
        "",
        f"Seed {args.seed}; {total:,} cases run of {args.cases:,} asked; {wall:.0f} s wall "
        f"time on {args.jobs} jobs ({os.cpu_count()} CPUs, Python "
        f"{platform.python_version()}); a case slower than {args.deadline:g} s fails.",
        "",
        f"**{len(failures)} failing test{'s' if len(failures) != 1 else ''}**; "
        f"{len(known)} known defect{'s' if len(known) != 1 else ''} (tests marked xfail "
        "until the library fix) failed as expected.",
        "",
        "Cases/s is per process (the case time without hypothesis's own time); slowest and "
        "slowest refusal in s; the outcomes are the most common ones (`planned`, a refusal "
        "by error class, `problem ...` for a problem the library refused to build, ...).",
        "",
        "| property | cases | failures | known | process time [s] | cases/s | slowest [s] | "
        "slowest refusal [s] | outcomes |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---|",
        *rows,
        "",
    ]
    if failures:
        lines += ["## Failures", ""]
        for node, text in failures:
            lines += [f"### `{node}`", "", "```", text.strip()[-6000:], "```", ""]
    if known:
        lines += ["## Known defects (xfail)", ""]
        for node, text in known:
            lines += [f"### `{node}`", "", "```", text.strip()[-3000:], "```", ""]
    return "\n".join(lines), len(failures)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--cases", type=int, default=int(os.environ.get("FUZZ_CASES", "100000")), help="in all"
    )
    parser.add_argument(
        "--seed", type=int, default=int(os.environ.get("FUZZ_SEED", DEFAULT_SEED)), help="seed"
    )
    parser.add_argument("--jobs", type=int, default=2, help="pytest processes at once")
    parser.add_argument("--deadline", type=float, default=30.0, help="per case [s]")
    parser.add_argument(
        "--out", type=Path, default=ROOT / "build" / "fuzz", help="folder for fuzz.md"
    )
    parser.add_argument("--only", nargs="*", help="run only these tests (names of TESTS)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    raw = Path(tempfile.mkdtemp(prefix="optraj-fuzz-"))
    env = {
        **os.environ,
        "FUZZ_PROFILE": "fuzz",
        "FUZZ_CASES": str(args.cases),
        "FUZZ_DEADLINE": str(args.deadline),
        "PYTHONHASHSEED": "0",
    }
    tests = [
        f"{file}::{test}"
        for file, test, _ in TESTS
        if not args.only or any(o in test for o in args.only)
    ]
    started = time.perf_counter()
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futures = [pool.submit(run_test, test, raw, env, args.seed) for test in tests]
        runs = []
        for future in futures:
            runs.append(future.result())
            test, status, seconds = runs[-1]
            print(f"fuzz: {test} exit {status} in {seconds:.0f} s", flush=True)
    text, failed = report(args, raw, runs, time.perf_counter() - started)
    target = args.out / "fuzz.md"
    target.write_text(text)
    print(f"fuzz: wrote {target} ({failed} failing); raw records in {raw}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
