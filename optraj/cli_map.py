"""``optraj map``: sweep a robot's shots, or draw a sweep's heat maps.

``optraj map sawyer --speeds 0.5,1.0 --grid 20x20 --headings 0,45,90 --out map.parquet``
plans every shot of the :class:`optraj.sweeps.ShotSet` (for paddle4, the strikes of a
:class:`optraj.sweeps.PaddleShotSet`) with :func:`optraj.sweeps.run`
(resuming a table that is already there) and prints the count of each status;
``optraj map --plot map.parquet`` draws the fastest reachable speed and the motion time over
the table to PNG files. The sweep packages are imported when the command runs.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, TextIO

from optraj.errors import InvalidInputError

__all__ = ["IMAGE_SUFFIXES", "add_map_parser", "cmd_map", "parse_grid", "parse_numbers"]

#: The image files ``--image`` may name.
IMAGE_SUFFIXES = (".png", ".pdf", ".svg")
#: The planner of a sweep when ``--planner`` is not given: fast, and it says the fastest
#: speed a refused shot could have had.
DEFAULT_PLANNER = "ruckig"
#: The robot whose shots are paddle strikes (:class:`optraj.sweeps.PaddleShotSet`).
PADDLE_ROBOT = "paddle4"


def parse_numbers(text: str, option: str, unit: str) -> tuple[float, ...]:
    """The comma-separated numbers of ``option`` (``"0.5,1.0"``), in the order given.

    Raises:
        InvalidInputError: A word that is not a number, or no number (names the value).
    """
    words = [word.strip() for word in text.split(",")]
    try:
        return tuple(float(word) for word in words)
    except ValueError:
        raise InvalidInputError(
            f"{option} takes numbers [{unit}] separated by commas, e.g. 0.5,1.0; got {text!r}",
            name=option,
            value=text,
        ) from None


def _pair(text: str | None, option: str) -> tuple[float, float] | None:
    if text is None:
        return None
    numbers = parse_numbers(text, option, "m")
    if len(numbers) != 2:
        raise InvalidInputError(
            f"{option} takes two numbers FIRST,LAST [m], e.g. 0.65,0.85; got {text!r}",
            name=option,
            value=text,
        )
    return numbers[0], numbers[1]


def parse_grid(text: str, axes: int = 2) -> tuple[int, ...]:
    """``"20x20"`` as (positions along x, along y); with ``axes=3``, ``"8x8x2"`` (and z).

    Raises:
        InvalidInputError: Not ``axes`` whole numbers joined by ``x`` (names the value).
    """
    words = text.lower().split("x")
    if len(words) != axes or not all(word.strip().isdigit() for word in words):
        form, example = ("NXxNYxNZ", "8x8x2") if axes == 3 else ("NXxNY", "20x20")
        raise InvalidInputError(
            f"--grid takes {form}, ball positions along {'x, y and z' if axes == 3 else 'x and y'}"
            f", e.g. {example}; got {text!r}",
            name="--grid",
            value=text,
        )
    return tuple(int(word) for word in words)


def _shot_set(args: argparse.Namespace) -> Any:
    """The shot set the options describe: paddle4 strikes, or another robot's pool shots."""
    from optraj import sweeps

    if args.samples is not None and args.grid is not None:
        raise InvalidInputError(
            f"give --grid ({args.grid}) or --samples ({args.samples}), not both", name="--grid"
        )
    paddle = args.robot.lower() == PADDLE_ROBOT
    if args.z is not None and not paddle:
        raise InvalidInputError(
            f"--z is for {PADDLE_ROBOT}'s ball points; a pool ball lies on the table "
            f"(got --z {args.z} for {args.robot})",
            name="--z",
            value=args.z,
        )
    given: dict[str, Any] = {
        "speeds": parse_numbers(args.speeds, "--speeds", "m/s"),
        "headings": parse_numbers(args.headings, "--headings", "deg"),
        "seed": args.seed,
    }
    for option in ("x", "y", "z"):
        pair = _pair(getattr(args, option), f"--{option}")
        if pair is not None:
            given[option] = pair
    if args.samples is not None:
        given["samples"] = args.samples
    elif args.grid is not None:
        given["grid"] = parse_grid(args.grid, 3 if paddle else 2)
    if paddle:
        return sweeps.PaddleShotSet(**given)
    return sweeps.ShotSet(robot=args.robot.lower(), **given)


def _sweep(args: argparse.Namespace, out: TextIO) -> int:
    from optraj import sweeps

    if args.image is not None or args.speed is not None:
        raise InvalidInputError(
            "--image and --speed are for drawing a table: optraj map --plot TABLE", name="--image"
        )
    shots = _shot_set(args)
    planner = args.planner or DEFAULT_PLANNER
    rows = sweeps.run(
        shots,
        planner,
        workers=args.workers,
        scheduler=args.scheduler,
        out=args.out,
        time_limit=args.time_limit,
        max_shots=args.max_shots,
        outcome=args.outcome,
        progress=sys.stderr.isatty(),
    )
    counts = {status: 0 for status in sweeps.STATUSES}
    for row in rows:
        counts[str(row["status"])] = counts.get(str(row["status"]), 0) + 1
    spread = shots.samples is not None
    layout = f"{shots.samples} random" if spread else "x".join(map(str, shots.grid))
    out.write(
        f"map of {args.robot.lower()} with {planner}: {len(shots)} shots ({layout} positions, "
        f"headings {_listed(shots.headings, spread)} deg, speeds "
        f"{_listed(shots.speeds, spread)} m/s)\n"
        f"  {', '.join(f'{status} {count}' for status, count in counts.items())}\n"
    )
    left = len(shots) - len(rows)
    if left:
        out.write(f"  {left} shots left: run the same command again to plan them\n")
    out.write(f"table: {args.out} ({len(rows)} rows); draw it with: optraj map --plot {args.out}\n")
    return 0


def _listed(values: Sequence[float], spread: bool = False) -> str:
    """The values, or with ``spread`` (a random set) the range they are drawn from."""
    if spread and len(values) > 1:
        return f"{min(values):g} to {max(values):g}"
    return ", ".join(f"{value:g}" for value in values)


def _image(args: argparse.Namespace) -> tuple[Path, Path]:
    """Where the max-speed map and the motion-time map go."""
    image = Path(args.image) if args.image is not None else Path(args.plot).with_suffix(".png")
    if image.suffix.lower() not in IMAGE_SUFFIXES:
        raise InvalidInputError(
            f"--image must end in {', '.join(IMAGE_SUFFIXES)}, got {str(image)!r}",
            name="--image",
            value=str(image),
        )
    return image, image.with_name(f"{image.stem}-motion-time{image.suffix}")


def _plot(args: argparse.Namespace, out: TextIO) -> int:
    from optraj import sweeps
    from optraj.sweeps.maps import speeds_of

    if args.robot is not None:
        raise InvalidInputError(
            f"--plot draws a table already made: give no robot (got {args.robot!r})",
            name="robot",
        )
    speed_map, time_map = _image(args)
    table = Path(args.plot)
    rows = list(sweeps.read_rows(table).values())
    if not rows:
        raise InvalidInputError(
            f"no sweep rows in {str(table)!r}: make one with optraj map ROBOT --out {table}",
            name="--plot",
            value=str(table),
        )
    speed = args.speed if args.speed is not None else speeds_of(rows)[0]
    sweeps.plot_max_speed(rows).savefig(speed_map, dpi=120)
    sweeps.plot_motion_time(rows, speed=speed).savefig(time_map, dpi=120)
    out.write(
        f"{table}: {len(rows)} rows; wrote {speed_map} (fastest reachable speed [m/s]) and "
        f"{time_map} (motion time [s] at {speed:g} m/s)\n"
    )
    return 0


def cmd_map(args: argparse.Namespace, out: TextIO) -> int:
    """Run ``optraj map``: a sweep, or with ``--plot`` the heat maps of a table; exit 0."""
    if args.plot is not None:
        return _plot(args, out)
    if args.robot is None:
        raise InvalidInputError(
            "optraj map needs a robot to sweep (see optraj robots), or --plot TABLE",
            name="robot",
        )
    return _sweep(args, out)


#: option -> (default, metavar, help) of the options given as text.
_TEXT_OPTIONS: Mapping[str, tuple[str | None, str, str]] = {
    "--speeds": ("0.5", "V,...", "cue speeds [m/s], comma-separated (default 0.5)"),
    "--headings": ("0", "DEG,...", "shot directions from +x about +z [deg], comma-separated "
                   "(default 0; a list that starts with a minus goes after '=': "
                   "--headings=-45,45)"),
    "--grid": (None, "NXxNY", "ball positions along x and y (default 3x3); for paddle4 "
               "NXxNYxNZ, along z too (default 3x3x1)"),
    "--x": (None, "FIRST,LAST", "first and last ball x [m], base frame (default 0.65,0.85)"),
    "--y": (None, "FIRST,LAST", "first and last ball y [m], base frame (default -0.05,0.3; "
            "a negative FIRST goes after '=': --y=-0.1,0.2)"),
    "--z": (None, "FIRST,LAST", "paddle4 only: first and last ball z [m] (default 0.3,0.3)"),
    "--planner": (None, "NAME", f"pool-shot planner (default {DEFAULT_PLANNER})"),
    "--out": ("map.parquet", "PATH", "the table: .parquet, or JSON lines for any other name "
              "(default map.parquet); a table already there is resumed"),
    "--scheduler": (None, "ADDRESS", "Dask scheduler tcp://HOST:PORT to plan on a cluster"),
    "--plot": (None, "TABLE", "draw the heat maps of this table (.parquet or JSON lines)"),
    "--image": (None, "PATH", "max-speed map file (.png, .pdf, .svg; default: the table's "
                "name with .png); the motion-time map goes beside it as NAME-motion-time.png"),
}  # fmt: skip


def add_map_parser(sub: Any) -> None:
    """Add the ``map`` command to the subparsers ``sub`` of the ``optraj`` parser."""
    parser = sub.add_parser(
        "map",
        help="sweep pool shots or paddle strikes (Parquet table), or draw its heat maps",
        description=(
            "Plan every pool shot (paddle4: every paddle strike) of a grid (or a seeded random "
            "set) of ball positions [m], "
            "headings [deg] and cue speeds [m/s], appending one row per shot to --out (a "
            "table already there is resumed), and print the count of each status. With "
            "--plot TABLE, draw the fastest reachable speed [m/s] and the motion time [s] over "
            "the table instead. Exit status 0 when done, 2 on bad input."
        ),
    )
    parser.add_argument("robot", nargs="?", metavar="ROBOT", help="robot name (optraj robots)")
    for option, (default, metavar, text) in _TEXT_OPTIONS.items():
        parser.add_argument(option, default=default, metavar=metavar, help=text)
    parser.add_argument("--samples", type=int, metavar="N", help="N random shots, not a grid")
    parser.add_argument("--seed", type=int, default=0, help="seed of --samples (default 0)")
    parser.add_argument(
        "--workers", type=int, metavar="N", help="processes, 0: serial (default: cores)"
    )
    parser.add_argument("--time-limit", type=float, metavar="S", help="per shot [s]")
    parser.add_argument(
        "--outcome",
        action="store_true",
        help="track each planned shot in MuJoCo and record where the ball went (~1 s a shot)",
    )
    parser.add_argument("--max-shots", type=int, metavar="N", help="plan at most N new shots")
    parser.add_argument(
        "--speed", type=float, metavar="M/S", help="motion-time map speed [m/s] (default lowest)"
    )
    parser.set_defaults(run=cmd_map)
