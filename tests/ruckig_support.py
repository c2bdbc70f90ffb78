"""Limits and configurations shared by the Ruckig tests (tests/planners/time_optimal)."""

from __future__ import annotations

import dataclasses

#: Every quantity the checker judges a Ruckig move on.
QUANTITIES = ("position", "velocity", "acceleration", "jerk")


def scaled_limits(robot, scale):
    """The robot's limits with velocity, acceleration and jerk times the rows of ``scale``."""
    base = robot.limits
    return dataclasses.replace(
        base,
        velocity=base.velocity * scale[0],
        acceleration=base.acceleration * scale[1],
        jerk=base.jerk * scale[2],
    )


def random_limits(robot, rng, low=0.3, high=2.0):
    """The robot's limits, each quantity of each joint scaled by a factor in [low, high)."""
    return scaled_limits(robot, rng.uniform(low, high, size=(3, robot.dof)))


def inner(limits, rng, fraction=0.8):
    """A configuration in the middle ``fraction`` of every joint's range."""
    middle = 0.5 * (limits.lower + limits.upper)
    half = 0.5 * (limits.upper - limits.lower)
    return middle + fraction * half * rng.uniform(-1.0, 1.0, limits.n)
