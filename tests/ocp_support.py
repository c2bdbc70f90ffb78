"""NLPs of the ocp tests: a compiled youBot transcription, its rows and an exact motion."""

from __future__ import annotations

import casadi as ca
import numpy as np
from conftest import get_robot

from optraj.planners.ocp.transcription import (
    Structure,
    compile_nlp,
    structure_limits,
)
from optraj.robots import SymbolicModel


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
