"""What the benchmark scripts share: the progress bar and the seeded pool shots.

The scripts import this module by name; they run from the repository root
(``python benchmarks/<name>.py``), which puts this directory on ``sys.path``.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from optraj import problems
from optraj.errors import UnreachableError

#: Cue speed of the pool shots [m/s].
SPEED = 1.0
#: Seed of the pool shots.
SEED = 7


class _Bars:
    """The one progress bar the scripts draw at a time (tqdm, on stderr)."""

    current: Any = None
    done = 0


def progress(done: int, total: int, label: str) -> None:
    """Show ``done`` of ``total`` with ``label`` on stderr: a tqdm bar with the time left.

    Drawn only on a terminal (nothing, not even a carriage return, when stderr is piped). A
    call with a new ``total`` or a smaller ``done`` starts a new bar; ``done == total`` ends it.
    """
    from tqdm import tqdm

    bar = _Bars.current
    if bar is None or bar.total != total or done < _Bars.done:
        if bar is not None:
            bar.close()
        bar = _Bars.current = tqdm(total=total, disable=None, dynamic_ncols=True, leave=True)
        _Bars.done = 0
    bar.set_description_str(label, refresh=False)
    bar.update(done - _Bars.done)
    _Bars.done = done
    if done >= total:
        bar.close()
        _Bars.current = None


def pool_shots(count: int, seed: int = SEED) -> tuple[list[problems.PoolStrike], int]:
    """``count`` seeded random Sawyer shots and how many draws were redrawn (out of reach).

    Ball centre x in [0.65, 0.85] m, y in [-0.05, 0.3] m, z in [-0.1, 0] m, heading in
    [-20, 20] deg, cue speed :data:`SPEED`.
    """
    rng = np.random.default_rng(seed)
    found: list[problems.PoolStrike] = []
    redrawn = 0
    while len(found) < count:
        ball = (rng.uniform(0.65, 0.85), rng.uniform(-0.05, 0.3), rng.uniform(-0.1, 0.0))
        heading = rng.uniform(-20.0, 20.0)
        try:
            found.append(problems.sawyer_pool_shot(SPEED, ball, heading_deg=heading))
        except UnreachableError:
            redrawn += 1
    return found, redrawn


def shot_arguments(
    argv: list[str] | None,
    doc: str | None,
    default: int,
    quick: int,
    out: Path,
    extra: Callable[[argparse.ArgumentParser], None] | None = None,
) -> argparse.Namespace:
    """Parse ``--shots N``, ``--quick`` (``quick`` shots, for CI) and ``--out PATH``.

    Args:
        argv: The arguments; ``sys.argv[1:]`` when None.
        doc: The script's docstring; its first paragraph is the description.
        default: Shots without ``--shots``.
        quick: Shots with ``--quick``.
        out: The Markdown file written without ``--out``.
        extra: Adds the script's own arguments to the parser; none when None.
    """
    parser = argparse.ArgumentParser(description=(doc or "").split("\n\n")[0])
    parser.add_argument("--shots", type=int, default=default, help="random shots")
    parser.add_argument("--quick", action="store_true", help=f"{quick} shots only (for CI)")
    parser.add_argument("--out", type=Path, default=out, help="Markdown file to write")
    if extra is not None:
        extra(parser)
    args = parser.parse_args(argv)
    if args.quick:
        args.shots = quick
    if args.shots < 1:
        parser.error(f"--shots must be >= 1, got {args.shots}")
    return args


def write_report(lines: list[str], out: Path) -> None:
    """Write the Markdown lines to ``out`` (creating its folder) and print them."""
    text = "\n".join(lines) + "\n"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(text)
    print(text)
