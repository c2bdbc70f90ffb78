"""Sets of pool shots for a robot: a grid or a seeded random set over the table.

A :class:`ShotSet` describes the shots; iterating over it gives :class:`Shot` records in a
fixed order, each with a stable id made from its inputs, and ``shot.problem()`` builds the
:class:`optraj.problems.PoolStrike` to plan. A shot's ``kind`` is the registry kind of its
problem (:data:`KINDS`): ``"pool-shot"`` here, ``"paddle-strike"`` for the paddle shots of
:mod:`optraj.sweeps.paddle_shots`.

>>> from optraj import sweeps
>>> shots = sweeps.ShotSet(x=(0.7, 0.8), y=(0.0, 0.2), grid=(2, 3), speeds=(0.3, 0.6))
>>> len(shots), shots[0].shot_id
(12, 'sawyer:x=0.7000:y=0.0000:z=-0.0500:h=0.000:v=0.3000')
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from optraj import robots
from optraj.errors import InvalidInputError, UnknownNameError
from optraj.problems import PaddleStrike, PoolStrike
from optraj.problems.common import MAX_TOOL_SPEED
from optraj.validation import as_choice, as_count, as_number

__all__ = [
    "KINDS",
    "MAX_REACH",
    "MAX_SHOTS",
    "Shot",
    "ShotSequence",
    "ShotSet",
    "as_grid",
    "as_range",
    "as_values",
    "check_total",
    "make_shot",
]

#: Largest |x|, |y| or |z| of a ball position accepted [m]: no arm we ship reaches further.
MAX_REACH = 5.0
#: Most shots one set may hold: a map beyond this is a job for many sets.
MAX_SHOTS = 1_000_000
#: The registry kinds (:data:`optraj.planners.registry.KINDS`) a shot may be of.
KINDS = ("pool-shot", "paddle-strike")


@dataclass(frozen=True)
class Shot:
    """One strike: where the ball is, which way and how fast the tool strikes it.

    Attributes:
        shot_id: Stable id made from the inputs (the same shot always has the same id).
        robot: The robot's name (:func:`optraj.robots.load`).
        ball: Ball centre in the robot's base frame [m].
        heading: Shot direction from +x about +z [deg]: the cue's direction (pool) or the
            paddle normal at contact, the strike's contact angle (paddle).
        speed: Tool speed at the strike [m/s]: the cue tip's (pool) or the paddle's along
            its normal (paddle; 0 arrives at rest).
        kind: The registry kind of the problem (:data:`KINDS`): ``"pool-shot"`` or
            ``"paddle-strike"``.

    Raises:
        UnknownNameError: A kind not in :data:`KINDS`.
    """

    shot_id: str
    robot: str
    ball: tuple[float, float, float]
    heading: float
    speed: float
    kind: str = "pool-shot"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise UnknownNameError("shot kind", self.kind, KINDS)

    def problem(self) -> PoolStrike | PaddleStrike:
        """The problem to plan (loads the robot; raises what the problem raises).

        A :class:`optraj.problems.PoolStrike` for a pool shot; a
        :class:`optraj.problems.PaddleStrike` (contact at its default time, 2 s) for a
        paddle strike.
        """
        angle = float(np.radians(self.heading))
        if self.kind == "paddle-strike":
            return PaddleStrike(
                robots.load(self.robot),
                ball=np.array(self.ball),
                contact_angle=angle,
                speed=self.speed,
            )
        return PoolStrike(
            robots.load(self.robot),
            ball=np.array(self.ball),
            direction=np.array((np.cos(angle), np.sin(angle), 0.0)),
            speed=self.speed,
        )


def as_grid(
    value: object, ranges: dict[str, tuple[float, float]], samples: int | None, maximum: int
) -> tuple[int, ...]:
    """A grid of positions, one count in [1, maximum] per axis of ``ranges``, checked.

    Raises:
        InvalidInputError: Not one count per axis, a count out of range, or (for a grid,
            ``samples`` None) several positions along an axis whose range is one value:
            every shot there would be repeated.
    """
    axes = list(ranges)
    if not isinstance(value, (tuple, list)) or len(value) != len(axes):
        size = {2: "a pair", 3: "a triple"}.get(len(axes), f"{len(axes)} counts")
        along = ", ".join(f"along {axis}" for axis in axes)
        raise InvalidInputError(f"grid must be {size} ({along}), got {value!r}", name="grid")
    grid = tuple(as_count(count, "grid", 1, maximum) for count in value)
    for count, axis in zip(grid, axes, strict=True):
        first, last = ranges[axis]
        if samples is None and count > 1 and first == last:
            raise InvalidInputError(
                f"grid has {count} positions along {axis}, but {axis} is the single value "
                f"{first:.6g} m: give a range or 1 position",
                name="grid",
                value=grid,
            )
    return grid


def check_total(total: int) -> None:
    """Refuse a set of more than :data:`MAX_SHOTS` shots."""
    if total > MAX_SHOTS:
        raise InvalidInputError(
            f"a shot set holds at most {MAX_SHOTS} shots, got {total}", name="grid", value=total
        )


def make_shot(
    robot: str,
    ball: tuple[float, float, float],
    heading: float,
    speed: float,
    kind: str = "pool-shot",
) -> Shot:
    """A :class:`Shot` with its id made from the inputs, rounded to 0.1 mm, 1e-3 deg, 0.1 mm/s.

    A pool shot's id is ``robot:x=..:y=..:z=..:h=..:v=..``; another kind's has the kind
    after the robot (``paddle4:paddle-strike:x=..``).
    """
    x, y, z = ball
    prefix = robot if kind == "pool-shot" else f"{robot}:{kind}"
    shot_id = f"{prefix}:x={x:.4f}:y={y:.4f}:z={z:.4f}:h={heading:.3f}:v={speed:.4f}"
    return Shot(shot_id, robot, (float(x), float(y), float(z)), float(heading), float(speed), kind)


def as_range(value: object, name: str, unit: str, low: float, high: float) -> tuple[float, float]:
    """``value`` as a (first, last) pair within [low, high] with first <= last.

    Raises:
        InvalidInputError: Not a pair of numbers, a number outside [low, high] [unit], or
            first > last (the message names the value and the limit).
    """
    if not isinstance(value, (tuple, list)) or len(value) != 2:
        raise InvalidInputError(
            f"{name} must be a (first, last) pair [{unit}], got {value!r}", name=name, value=value
        )
    first, last = (as_number(v, name, unit, minimum=low, maximum=high) for v in value)
    if first > last:
        raise InvalidInputError(
            f"{name} must have first <= last, got ({first:.6g}, {last:.6g}) {unit}",
            name=name,
            value=value,
        )
    return first, last


def as_values(
    value: object, name: str, unit: str, low: float, high: float, *, open_low: bool = False
) -> tuple[float, ...]:
    """``value`` as a non-empty tuple of numbers within [low, high] (or (low, high]).

    Raises:
        InvalidInputError: Not a non-empty tuple or list, or a number outside the interval
            [unit] (the message names the value and the limit).
    """
    if not isinstance(value, (tuple, list)) or not value:
        raise InvalidInputError(
            f"{name} must be a non-empty tuple of numbers [{unit}], got {value!r}",
            name=name,
            value=value,
        )
    return tuple(
        as_number(v, name, unit, minimum=low, maximum=high, open_minimum=open_low) for v in value
    )


class ShotSequence:
    """A set of shots in a fixed order: a subclass gives ``__len__`` and ``__iter__``."""

    def __len__(self) -> int:
        """How many shots the set holds."""
        raise NotImplementedError

    def __iter__(self) -> Iterator[Shot]:
        """The shots, in the set's order."""
        raise NotImplementedError

    def __getitem__(self, index: int) -> Shot:
        """The shot at ``index`` in the set's order (negative counts from the end).

        Raises:
            IndexError: ``index`` is outside the set.
        """
        position = index + len(self) if index < 0 else index
        if not 0 <= position < len(self):
            raise IndexError(f"shot index {index} is outside a set of {len(self)} shots")
        return next(itertools.islice(iter(self), position, None))

    def shots(self) -> tuple[Shot, ...]:
        """Every shot, in the set's order."""
        return tuple(self)


@dataclass(frozen=True)
class ShotSet(ShotSequence):
    """Pool shots over a rectangle of the table, for a few headings and speeds.

    On a grid (``samples=None``), the shots are every combination of ``grid[0]`` ball x
    positions evenly spread over ``x``, ``grid[1]`` y positions over ``y``, each heading and
    each speed, in that nesting order (x outermost). With ``samples=N``, they are N shots
    drawn with ``seed``: x and y uniform in their ranges, heading and speed uniform between
    the smallest and largest of ``headings`` and ``speeds``.

    Attributes:
        x: First and last ball x [m], base frame.
        y: First and last ball y [m], base frame.
        headings: Shot directions from +x about +z [deg], each in [-360, 360].
        speeds: Cue speeds [m/s], each in (0, MAX_TOOL_SPEED].
        grid: Ball positions along x and along y, each in [1, 1000].
        samples: Random shots instead of the grid, or None for the grid.
        seed: Seed of the random shots.
        z: Ball centre height [m] (the table height plus the ball's radius).
        robot: The robot's name (:func:`optraj.robots.known_robots`).

    Raises:
        InvalidInputError: A value out of its range (the message names it and the limit).
        UnknownNameError: An unknown robot.
    """

    x: tuple[float, float] = (0.65, 0.85)
    y: tuple[float, float] = (-0.05, 0.3)
    headings: tuple[float, ...] = (0.0,)
    speeds: tuple[float, ...] = (0.5,)
    grid: tuple[int, int] = (3, 3)
    samples: int | None = None
    seed: int = 0
    z: float = -0.05
    robot: str = "sawyer"

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "x", as_range(self.x, "x", "m", -MAX_REACH, MAX_REACH))
        set_(self, "y", as_range(self.y, "y", "m", -MAX_REACH, MAX_REACH))
        set_(self, "headings", as_values(self.headings, "headings", "deg", -360.0, 360.0))
        set_(
            self,
            "speeds",
            as_values(self.speeds, "speeds", "m/s", 0.0, MAX_TOOL_SPEED, open_low=True),
        )
        set_(self, "z", as_number(self.z, "z", "m", minimum=-MAX_REACH, maximum=MAX_REACH))
        set_(self, "robot", as_choice(self.robot, "robot", robots.known_robots()))
        set_(self, "seed", as_count(self.seed, "seed", maximum=None))
        if self.samples is not None:
            set_(self, "samples", as_count(self.samples, "samples", 1, MAX_SHOTS))
        self._check_grid()

    def _check_grid(self) -> None:
        ranges = {"x": self.x, "y": self.y}
        object.__setattr__(self, "grid", as_grid(self.grid, ranges, self.samples, 1000))
        check_total(len(self))

    def __len__(self) -> int:
        if self.samples is not None:
            return self.samples
        return self.grid[0] * self.grid[1] * len(self.headings) * len(self.speeds)

    def __iter__(self) -> Iterator[Shot]:
        if self.samples is not None:
            yield from self._random()
            return
        xs = np.linspace(*self.x, self.grid[0])
        ys = np.linspace(*self.y, self.grid[1])
        for x, y, heading, speed in itertools.product(xs, ys, self.headings, self.speeds):
            yield make_shot(self.robot, (float(x), float(y), self.z), heading, speed)

    def _random(self) -> Iterator[Shot]:
        rng = np.random.default_rng(self.seed)
        for _ in range(len(self)):
            x, y = rng.uniform(*self.x), rng.uniform(*self.y)
            heading = rng.uniform(min(self.headings), max(self.headings))
            speed = rng.uniform(min(self.speeds), max(self.speeds))
            yield make_shot(self.robot, (float(x), float(y), self.z), float(heading), float(speed))
