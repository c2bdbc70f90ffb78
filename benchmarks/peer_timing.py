"""Interleaved timing of optraj against a peer, and the rows of ``peers.py``'s table.

A row times two calls per move, optraj's and the other side's (a peer, or optraj itself in
another setting), alternating their order from one repeat to the next so that a slow spell
of a shared machine hits both. A move's time is the median of its repeats, a row's the
median over its moves; the cyclic garbage collector is off while a row is timed.
"""

from __future__ import annotations

import contextlib
import gc
import statistics
import time
import warnings
from collections import Counter
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from optraj.errors import OptrajError

#: The default quotient of a row: peer time over optraj time (>= goal: optraj is faster).
PEER = "peer / optraj"
#: A row with no other side: optraj's time itself [us] must stay <= goal.
ABSOLUTE = "absolute"


class Spec:
    """What a row times.

    Attributes:
        label: The row's name in the table.
        ours: Move index -> the optraj call.
        other: (move index, what optraj's call returned) -> the other side's call; None for
            an :data:`ABSOLUTE` row.
        missing: Why the peer cannot run ("<module> not installed"), or None.
        kind: :data:`PEER` (ratio other / ours, target ``>= goal``), :data:`ABSOLUTE`
            (optraj's time <= goal [us]) or the name of the quotient ours / other (target
            ``<= goal``), e.g. ``"first / reused"``.
        goal: The target.
        observe: Called with (move index, optraj's result, the other's result or None)
            after the untimed calls of each move.
    """

    def __init__(
        self,
        label: str,
        ours: Callable[[int], Callable[[], Any]] | None,
        other: Callable[[int, Any], Callable[[], Any]] | None,
        missing: str | None,
        *,
        kind: str = PEER,
        goal: float = 1.0,
        observe: Callable[[int, Any, Any], None] | None = None,
    ) -> None:
        self.label = label
        self.ours = ours
        self.other = other
        self.missing = missing
        self.kind = kind
        self.goal = goal
        self.observe = observe

    def target(self) -> str:
        """The target as the table states it."""
        if self.kind == PEER:
            return f"{PEER} >= {self.goal:g}"
        if self.kind == ABSOLUTE:
            return f"optraj <= {self.goal:g} us"
        return f"{self.kind} <= {self.goal:g}"


class Row:
    """What a row measured: per-move medians [s] and what went wrong on which moves."""

    def __init__(self, spec: Spec, count: int) -> None:
        self.spec = spec
        self.count = count
        self.ours: list[float] = []
        self.other: list[float] = []
        self.refused: Counter[str] = Counter()  # optraj's errors, by class
        self.failed: Counter[str] = Counter()  # the other side's errors, by class

    def ratio(self) -> float | None:
        """The row's quotient, or None without both sides."""
        if not self.ours or not self.other:
            return None
        ours, other = statistics.median(self.ours), statistics.median(self.other)
        return other / ours if self.spec.kind == PEER else ours / other

    def met(self) -> str:
        """``met``, ``missed``, or ``-`` when the row cannot say."""
        if self.spec.kind == ABSOLUTE:
            if not self.ours:
                return "-"
            return "met" if 1e6 * statistics.median(self.ours) <= self.spec.goal else "missed"
        ratio = self.ratio()
        if ratio is None:
            return "-"
        meets = ratio >= self.spec.goal if self.spec.kind == PEER else ratio <= self.spec.goal
        return "met" if meets else "missed"

    def cells(self) -> list[str]:
        """The table cells after the label."""
        ratio = self.ratio()
        if self.spec.kind == ABSOLUTE:
            other = "-"
        elif self.spec.missing is not None:
            other = f"peer not installed ({self.spec.missing})"
        else:
            other = _us(self.other)
        moves = f"{len(self.ours)}/{self.count}"
        if self.refused:
            moves += f"; optraj refused {_counts(self.refused)}"
        if self.failed:
            moves += f"; other side failed on {_counts(self.failed)}"
        return [
            _us(self.ours),
            other,
            "-" if ratio is None else f"{ratio:.3g}",
            self.spec.target(),
            self.met(),
            moves,
        ]


def _us(times: list[float]) -> str:
    if not times:
        return "-"
    value = 1e6 * statistics.median(times)
    return f"{value:.2f}" if value < 100.0 else f"{value:.0f}"


def _counts(counter: Counter[str]) -> str:
    return ", ".join(f"{count} ({name})" for name, count in counter.most_common())


def interleaved(calls: Sequence[Callable[[], Any]], repeats: int) -> list[float]:
    """Median wall time [s] of each call over ``repeats``, the order reversed every repeat."""
    times: list[list[float]] = [[] for _ in calls]
    for repeat in range(repeats):
        order = range(len(calls)) if repeat % 2 == 0 else range(len(calls) - 1, -1, -1)
        for index in order:
            started = time.perf_counter()
            calls[index]()
            times[index].append(time.perf_counter() - started)
    return [statistics.median(t) for t in times]


@contextlib.contextmanager
def collector_paused() -> Iterator[None]:
    """Collect garbage once, then keep the cyclic collector off (a row's timing)."""
    gc.collect()
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def measure(spec: Spec, count: int, repeats: int) -> Row:
    """Time a row's two sides on ``count`` moves (one untimed call of each first).

    A move optraj refuses (an ``OptrajError``) or the other side fails on (any exception:
    a peer's own) is counted and left out of both sides.
    """
    row = Row(spec, count)
    if spec.ours is None:
        raise ValueError(f"row {spec.label!r} has no optraj call")
    with collector_paused():
        _measure_moves(spec.ours, row, count, repeats)
    return row


def _measure_moves(
    ours_for: Callable[[int], Callable[[], Any]], row: Row, count: int, repeats: int
) -> None:
    """Fill ``row`` with each move's medians (see :func:`measure`)."""
    spec = row.spec
    for k in range(count):
        try:
            ours = ours_for(k)
            result = ours()
        except OptrajError as exc:
            row.refused[type(exc).__name__] += 1
            continue
        calls = [ours]
        other_result = None
        if spec.other is not None and spec.missing is None:
            try:
                other = spec.other(k, result)
                other_result = other()
            except Exception as exc:  # a peer raises its own types
                row.failed[type(exc).__name__] += 1
                continue
            calls.append(other)
        if spec.observe is not None:
            spec.observe(k, result, other_result)
        medians = interleaved(calls, repeats)
        row.ours.append(medians[0])
        if len(medians) > 1:
            row.other.append(medians[1])


def measure_steps(
    spec: Spec,
    controller: Any,
    other: Callable[[Any, Any], Any] | None,
    steps: Sequence[tuple[Any, Any]],
    repeats: int,
    dt: float,
) -> Row:
    """Time a controller's step against ``other`` on recorded (state, reference) pairs.

    The recorded run is replayed in order ``repeats`` times after an untimed replay, the
    controller reset at its start (its warm start follows the run as in closed loop); each
    step is one "move" of the row; ``dt`` is the control period [s].
    """
    row = Row(spec, len(steps))
    ours: list[list[float]] = [[] for _ in steps]
    theirs: list[list[float]] = [[] for _ in steps]
    with warnings.catch_warnings(), collector_paused():
        # through pink, qpsolvers warns on every call that it converts dense matrices
        warnings.filterwarnings("ignore", module="qpsolvers")
        for repeat in range(repeats + 1):
            controller.reset(steps[0][0])
            for index, (state, reference) in enumerate(steps):
                sides: list[tuple[list[float], Callable[[], Any]]] = [
                    (ours[index], lambda s=state, r=reference: controller.step(s, r, dt))
                ]
                if other is not None:
                    sides.append((theirs[index], lambda s=state, r=reference: other(s, r)))
                if repeat % 2:
                    sides.reverse()
                for times, call in sides:
                    started = time.perf_counter()
                    call()
                    if repeat:  # the first replay is untimed
                        times.append(time.perf_counter() - started)
    row.ours = [statistics.median(t) for t in ours]
    row.other = [statistics.median(t) for t in theirs] if other is not None else []
    return row


def table(rows: list[Row]) -> list[str]:
    """The Markdown table of the rows."""
    lines = [
        "| row | optraj [us] | peer or reference [us] | ratio | target | met | moves |",
        "|---|---|---|---|---|---|---|",
    ]
    lines += [f"| {row.spec.label} | {' | '.join(row.cells())} |" for row in rows]
    return lines
