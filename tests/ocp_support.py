"""Shared pieces of the ocp tests: problems, a contact choice, a compiled youBot NLP, its rows."""

from __future__ import annotations

import dataclasses

import casadi as ca
import numpy as np
from conftest import get_robot

from optraj import problems
from optraj.errors import UnreachableError
from optraj.planners.ocp.transcription import (
    Structure,
    compile_nlp,
    structure_limits,
)
from optraj.planners.strike.contact import ContactChoice
from optraj.robots import SymbolicModel

#: Ranges of the strike benchmark's Sawyer shots: ball centre [m] and heading [deg].
SAWYER_SHOT = {"x": (0.65, 0.85), "y": (-0.05, 0.3), "z": (-0.1, 0.0), "heading": (-20.0, 20.0)}


def sawyer_shots(count: int, speed: float, seed: int = 7):
    """``count`` seeded Sawyer pool shots at ``speed`` [m/s] within :data:`SAWYER_SHOT`."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        ball = tuple(rng.uniform(*SAWYER_SHOT[axis]) for axis in "xyz")
        yield problems.sawyer_pool_shot(
            speed, ball, heading_deg=rng.uniform(*SAWYER_SHOT["heading"])
        )


def reachable_shots(
    count: int, seed: int = 7, with_table: bool = False
) -> list[problems.PoolStrike]:
    """``count`` seeded Sawyer shots at 1 m/s within :data:`SAWYER_SHOT`, out-of-reach ones
    skipped; ``with_table``: ``problems.sawyer_pool_shot(with_table=True)``."""
    rng = np.random.default_rng(seed)
    found: list[problems.PoolStrike] = []
    while len(found) < count:
        ball = tuple(rng.uniform(*SAWYER_SHOT[axis]) for axis in "xyz")
        heading = rng.uniform(*SAWYER_SHOT["heading"])
        try:
            found.append(problems.sawyer_pool_shot(1.0, ball, heading, with_table=with_table))
        except UnreachableError:
            continue
    return found


def table_shots(count: int, seed: int = 11) -> list[problems.PoolStrike]:
    """Seeded shots over the cloth and ball of a table (its cushions left out)."""
    found = []
    for shot in reachable_shots(count, seed, with_table=True):
        kept = tuple(o for o in shot.scene.objects if o.name in ("cloth", "ball"))
        found.append(dataclasses.replace(shot, scene=dataclasses.replace(shot.scene, objects=kept)))
    return found


def paddle_move() -> problems.PointToPoint:
    """A paddle4 move from the middle of the joint ranges, 0.2 of each range along."""
    robot = get_robot("paddle4")
    lower, upper = robot.limits.lower, robot.limits.upper
    middle = 0.5 * (lower + upper)
    return problems.PointToPoint(robot, middle, middle + 0.2 * (upper - lower))


def tight_choice(max_speed: float) -> ContactChoice:
    """A Sawyer contact choice at 0.97 of right_j1's velocity limit."""
    return ContactChoice(
        q=np.zeros(7),
        qd=np.zeros(7),
        ratio=0.97,
        max_speed=max_speed,
        binding_joint="right_j1",
        candidates=1,
    )


def youbot_nlp(intervals=(4, 3), **fields):
    robot = get_robot("youbot")
    structure = Structure(
        robot=robot.name,
        limits=structure_limits(robot.limits),
        tool_frame=robot.tool_frame,
        intervals=intervals,
        free=(True, False),
        **fields,
    )
    return robot, compile_nlp(structure, SymbolicModel(robot))


def nlp_rows(compiled, w, name):
    g = ca.Function("g", [compiled.w, compiled.p], [compiled.g])(w, compiled.parameters.vector())
    g = np.asarray(g).reshape(-1)
    return np.concatenate([g[a:b] for group, a, b in compiled.groups if group == name])


def exact_motion(compiled, rng):
    """A decision vector whose nodes follow the exact triple integrator (numpy, not CasADi)."""
    layout = compiled.layout
    mid, half, vel, acc, jerk = compiled.scale
    n = layout.n
    w = np.zeros(layout.size)
    h = rng.uniform(0.02, 0.08, layout.K)
    w[: layout.K] = h
    q, v, a = mid + 0.2 * half * rng.uniform(-1, 1, n), 0.1 * vel * rng.uniform(-1, 1, n), 0 * vel
    for k in range(layout.K + 1):
        w[layout.x_index(k, 0)] = (q - mid) / half
        w[layout.x_index(k, 1)] = v / vel
        w[layout.x_index(k, 2)] = a / acc
        if k == layout.K:
            break
        u = jerk * rng.uniform(-0.5, 0.5, n)
        w[layout.u_index(k)] = u / jerk
        q, v, a = (
            q + h[k] * v + h[k] ** 2 / 2 * a + h[k] ** 3 / 6 * u,
            v + h[k] * a + h[k] ** 2 / 2 * u,
            a + h[k] * u,
        )
    return w
