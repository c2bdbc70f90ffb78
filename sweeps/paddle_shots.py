"""Sets of paddle4 strikes: a grid or a seeded random set of ball points in its workspace.

A :class:`PaddleShotSet` describes paddle strikes (:class:`optraj.problems.PaddleStrike`)
over a box of ball centres inside the paddle4 workspace cuboid
(:data:`optraj.robots.PADDLE4_WORKSPACE`), for a few contact angles and paddle speeds.
Iterating over it gives :class:`optraj.sweeps.Shot` records of kind ``"paddle-strike"`` in a
fixed order, each with a stable id made from its inputs; ``shot.problem()`` builds the
strike (contact at the problem's default time, 2 s after the start).

>>> from optraj import sweeps
>>> shots = sweeps.PaddleShotSet(x=(0.6, 0.9), y=(0.0, 0.0), grid=(2, 1, 1), speeds=(0.5,))
>>> len(shots), shots[0].shot_id
(2, 'paddle4:paddle-strike:x=0.6000:y=0.0000:z=0.3000:h=0.000:v=0.5000')
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from optraj.problems.common import MAX_TOOL_SPEED
from optraj.robots import PADDLE4_WORKSPACE
from optraj.sweeps.shots import (
    MAX_SHOTS,
    Shot,
    ShotSequence,
    as_grid,
    as_range,
    as_values,
    check_total,
    make_shot,
)
from optraj.validation import as_count

__all__ = ["MAX_GRID", "PADDLE_KIND", "PADDLE_ROBOT", "PaddleShotSet"]

#: The registry kind of a paddle strike (:data:`optraj.planners.registry.KINDS`).
PADDLE_KIND = "paddle-strike"
#: The robot that strikes with a paddle.
PADDLE_ROBOT = "paddle4"
#: Most ball positions along one axis of the grid.
MAX_GRID = 1000


@dataclass(frozen=True)
class PaddleShotSet(ShotSequence):
    """Paddle4 strikes over a box of ball centres, for a few contact angles and speeds.

    On a grid (``samples=None``), the shots are every combination of ``grid[0]`` ball x
    positions evenly spread over ``x``, ``grid[1]`` y positions over ``y``, ``grid[2]`` z
    positions over ``z``, each heading and each speed, in that nesting order (x outermost).
    With ``samples=N``, they are N shots drawn with ``seed``: x, y and z uniform in their
    ranges, heading and speed uniform between the smallest and largest of ``headings`` and
    ``speeds``. A ball inside the workspace may still need a joint beyond its position
    limits at some contact angles: that shot's row is ``refused`` (``JointLimitError``).

    Attributes:
        x: First and last ball x [m], base frame, within the workspace's x, [0.3, 1.1].
        y: First and last ball y [m], within the workspace's y, [-0.8, 0.8].
        z: First and last ball z [m], within the workspace's z, [-0.1, 0.7].
        headings: Contact angles, the paddle normal at contact from +x about +z [deg],
            each in [-360, 360]; the ball is sent that way.
        speeds: Paddle speeds along its normal at contact [m/s], each in
            [0, MAX_TOOL_SPEED] (0: the paddle arrives at rest and sends no ball).
        grid: Ball positions along x, y and z, each in [1, :data:`MAX_GRID`].
        samples: Random shots instead of the grid, or None for the grid.
        seed: Seed of the random shots.

    Raises:
        InvalidInputError: A value out of its range (the message names it and the limit).
    """

    x: tuple[float, float] = (0.6, 0.9)
    y: tuple[float, float] = (-0.3, 0.3)
    z: tuple[float, float] = (0.3, 0.3)
    headings: tuple[float, ...] = (0.0,)
    speeds: tuple[float, ...] = (0.5,)
    grid: tuple[int, int, int] = (3, 3, 1)
    samples: int | None = None
    seed: int = 0

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        for axis in ("x", "y", "z"):
            low, high = PADDLE4_WORKSPACE[axis]
            set_(self, axis, as_range(getattr(self, axis), axis, "m", low, high))
        set_(self, "headings", as_values(self.headings, "headings", "deg", -360.0, 360.0))
        set_(self, "speeds", as_values(self.speeds, "speeds", "m/s", 0.0, MAX_TOOL_SPEED))
        set_(self, "seed", as_count(self.seed, "seed", maximum=None))
        if self.samples is not None:
            set_(self, "samples", as_count(self.samples, "samples", 1, MAX_SHOTS))
        self._check_grid()

    def _check_grid(self) -> None:
        ranges = {"x": self.x, "y": self.y, "z": self.z}
        object.__setattr__(self, "grid", as_grid(self.grid, ranges, self.samples, MAX_GRID))
        check_total(len(self))

    def __len__(self) -> int:
        if self.samples is not None:
            return self.samples
        nx, ny, nz = self.grid
        return nx * ny * nz * len(self.headings) * len(self.speeds)

    def __iter__(self) -> Iterator[Shot]:
        if self.samples is not None:
            yield from self._random()
            return
        ranges = (self.x, self.y, self.z)
        axes = [
            np.linspace(first, last, count)
            for (first, last), count in zip(ranges, self.grid, strict=True)
        ]
        for x, y, z, heading, speed in itertools.product(*axes, self.headings, self.speeds):
            yield self._shot((float(x), float(y), float(z)), heading, speed)

    def _random(self) -> Iterator[Shot]:
        rng = np.random.default_rng(self.seed)
        for _ in range(len(self)):
            x, y, z = rng.uniform(*self.x), rng.uniform(*self.y), rng.uniform(*self.z)
            heading = rng.uniform(min(self.headings), max(self.headings))
            speed = rng.uniform(min(self.speeds), max(self.speeds))
            yield self._shot((float(x), float(y), float(z)), float(heading), float(speed))

    @staticmethod
    def _shot(ball: tuple[float, float, float], heading: float, speed: float) -> Shot:
        return make_shot(PADDLE_ROBOT, ball, heading, speed, PADDLE_KIND)
