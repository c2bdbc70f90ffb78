"""One TOPPRA retiming of a built problem: the solves, their retries and the trajectory.

:func:`solve` first refuses what no timing can do (gravity alone beyond a torque limit, an
end path velocity beyond the limits), then runs toppra and verifies its answer between the
gridpoints (:func:`~planners.time_optimal.toppra_verify.verify`). Three measures keep the
result within the limits: speed caps use bounds that also hold between gridpoints, every
rate limit is shrunk by :data:`~planners.time_optimal.toppra_problem.MARGIN` before solving,
and where a verified bound still exceeds ``1 - MARGIN / 2`` of its limit

* the grid is refined there and the problem solved again, when fixing the excess would
  otherwise slow the motion down by more than :data:`REFINE_ABOVE` (at most
  :data:`RETRIES` times);
* else a rest-to-rest motion is slowed down uniformly in time just enough (speeds scale by
  c, accelerations by c^2), and a motion with a moving start or end is solved again with
  the exceeded limits shrunk further (it cannot be slowed without changing its boundary
  velocities).

A rest-to-rest motion shorter than :data:`~optraj.validation.MIN_DURATION` is slowed down to
last that long. The result is the exact trajectory of toppra's answer
(:func:`~planners.time_optimal.toppra_time_law.compose`); ``metadata["limit_ratio"]`` holds
the verified bounds, ``metadata["slowdown"]`` the factor on the duration and
``metadata["native"]`` toppra's own output object.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from optraj.errors import SolverError
from optraj.planners.base import stamp
from optraj.planners.time_optimal.toppra_failures import (
    check_end_velocity,
    check_gravity,
    raise_failure,
)
from optraj.planners.time_optimal.toppra_grid import refined, stretch_factor
from optraj.planners.time_optimal.toppra_path import toppra_classes
from optraj.planners.time_optimal.toppra_problem import ToppraProblem, initial_scale
from optraj.planners.time_optimal.toppra_time_law import TimeLaw, compose_law
from optraj.planners.time_optimal.toppra_verify import TARGET, Verification, verify
from optraj.planners.trajectory import Phase, Trajectory
from optraj.validation import MIN_DURATION

__all__ = ["REFINE_ABOVE", "RETRIES", "solve"]

FloatArray = NDArray[np.float64]

#: Re-solves after the verification: with a finer grid where the limits are exceeded by
#: more than a small slow-down fixes, or (a motion with a moving start or end, which
#: cannot be slowed down) with the exceeded limits shrunk further.
RETRIES = 2
#: A slow-down by more than this fraction of the duration is avoided by refining the grid
#: where the limits are exceeded and solving again (at most :data:`RETRIES` times).
REFINE_ABOVE = 0.005


class _Solved(NamedTuple):
    """The last toppra solve: its problem (grid), time law, controllable sets and bounds."""

    problem: ToppraProblem
    law: TimeLaw
    controllable_sets: FloatArray
    check: Verification
    solves: int


class _Timing(NamedTuple):
    """The time law of the result, its bounds on the limit ratios and its slow-down c <= 1."""

    law: TimeLaw
    ratios: dict[str, float]
    slowdown: float


def solve(problem: ToppraProblem, planner: str, started: float) -> Trajectory:
    """Retime a built problem time-optimally, as an exact trajectory.

    Args:
        problem: The problem, from :meth:`Toppra.build
            <planners.time_optimal.toppra_planner.Toppra.build>`.
        planner: Name recorded in the trajectory's metadata.
        started: ``time.perf_counter()`` when planning started (for ``solve_time``).

    Raises:
        InfeasibleError, SolverError: As listed for :meth:`Toppra.solve
            <planners.time_optimal.toppra_planner.Toppra.solve>`.
    """
    if problem.torque:
        check_gravity(problem)
    scale = initial_scale(problem)
    if problem.sd_end > 0.0:
        check_end_velocity(problem, scale)
    solved = _solve_verified(problem, scale)
    return _trajectory(solved, _final_timing(solved), scale, planner, started)


def _solve_verified(problem: ToppraProblem, scale: dict[str, float]) -> _Solved:
    """Solve and verify, solving again up to :data:`RETRIES` times (see the module).

    ``scale`` (the factor on each rate limit) is shrunk in place where a motion with a
    moving start or end exceeds a limit.
    """
    path = problem.path
    # toppra solves on a path at least one path unit long (see stretch_factor)
    stretch = stretch_factor(path)
    native = path.native if stretch == 1.0 else path.stretched(stretch).native
    for attempt in range(RETRIES + 1):
        sd, controllable = _parametrize(problem, native, stretch, scale)
        law = TimeLaw(problem.grid, np.asarray(sd, dtype=float))
        check = verify(problem, law)
        solved = _Solved(problem, law, controllable, check, attempt + 1)
        if max(check.ratios.values()) <= TARGET:
            break
        if attempt < RETRIES and check.slowdown < 1.0 / (1.0 + REFINE_ABOVE):
            # a marked excess between gridpoints: refine the grid there and solve again
            problem = refined(problem, check.over)
            continue
        if not problem.moving:
            break  # slowed down by _final_timing
        if attempt == RETRIES:
            raise _still_exceeded(solved)
        _shrink(scale, check.ratios)
    return solved


def _parametrize(
    problem: ToppraProblem, native: Any, stretch: float, scale: dict[str, float]
) -> tuple[FloatArray, FloatArray]:
    """One toppra solve on the path stretched by ``stretch``, in the path's own units.

    Returns:
        (path velocities at the gridpoints [path units/s], shape (N + 1,); controllable
        sets of the squared path velocity, shape (N + 1, 2)).

    Raises:
        InfeasibleError, SolverError: As :func:`~planners.time_optimal.toppra_failures.
            raise_failure` says, when toppra finds no parametrisation.
    """
    lib = toppra_classes()
    instance = lib.TOPPRA(problem.constraints(scale), native, problem.grid * stretch)
    _, sd, _, K = instance.compute_parameterization(
        problem.sd_start * stretch, problem.sd_end * stretch, return_data=True
    )
    if sd is not None:  # back to the path's own units: sd / c, x = sd^2 / c^2
        sd = np.asarray(sd, dtype=float) / stretch
    if K is not None:
        K = np.asarray(K, dtype=float) / stretch**2
    if sd is None or instance.problem_data.return_code != lib.Ok:
        raise_failure(problem, instance, sd, K)
    if problem.sd_start**2 > float(K[0, 1]) * (1.0 + 1e-9):
        # toppra lets a start up to 1e-5 (in sd^2) beyond its controllable set pass
        raise_failure(problem, instance, None, K)
    return sd, K


def _shrink(scale: dict[str, float], ratios: dict[str, float]) -> None:
    """Shrink the factor of each limit whose bound exceeds TARGET by that excess."""
    for name, ratio in ratios.items():
        if ratio > TARGET:
            scale[name] *= TARGET / ratio


def _still_exceeded(solved: _Solved) -> SolverError:
    """The error for a moving motion still beyond a limit after every re-solve."""
    ratios = solved.check.ratios
    name = max(ratios, key=ratios.__getitem__)
    return SolverError(
        "toppra",
        "limit exceeded between gridpoints",
        iterations=solved.solves,
        detail=(
            f"after {solved.solves} solves the {name} still reaches "
            f"{ratios[name]:.6g} x its limit between gridpoints; use more "
            f"gridpoints (now {solved.problem.grid.size - 1})"
        ),
    )


def _final_timing(solved: _Solved) -> _Timing:
    """The last solve's time law, slowed down where a rest-to-rest motion needs it.

    A rest-to-rest motion is slowed down uniformly just enough to bring every bound to
    TARGET, and, if shorter, to last :data:`~optraj.validation.MIN_DURATION`.
    """
    problem, law, check = solved.problem, solved.law, solved.check
    ratios, slowdown = check.ratios, check.slowdown
    if slowdown < 1.0:  # rest to rest: slow the whole motion down just enough
        law = TimeLaw(problem.grid, law.sd * slowdown)
        ratios = check.after
    floor = float(law.t[-1]) / MIN_DURATION * (1.0 - 1e-12)  # not a rounding below
    if not problem.moving and floor < 1.0:
        # a tiny move lasts MIN_DURATION, the shortest duration any planner takes (a
        # slower rest-to-rest motion only lowers every speed and acceleration)
        law = TimeLaw(problem.grid, law.sd * floor)
        ratios = verify(problem, law).ratios
        slowdown = min(slowdown, 1.0) * floor
    return _Timing(law, ratios, slowdown)


def _trajectory(
    solved: _Solved, timing: _Timing, scale: dict[str, float], planner: str, started: float
) -> Trajectory:
    """The exact trajectory of the final time law, with its phases and metadata."""
    lib = toppra_classes()
    problem, law = solved.problem, timing.law
    path = problem.path
    breakpoints, coefficients = compose_law(path.knots, path.coefficients, law, problem.segment)
    phase_s = np.array([[p[1], p[2]] for p in problem.phases], dtype=float).reshape(-1, 2)
    phase_t = law.time_at(phase_s.ravel()).reshape(-1, 2)
    traj = Trajectory(
        breakpoints,
        coefficients,
        joint_names=problem.limits.names,
        phases=[
            Phase(p[0], t0, max(t0, t1))
            for p, (t0, t1) in zip(problem.phases, phase_t, strict=True)
        ],
        metadata={"native": lib.ConstAccelOutput(path.native, problem.grid, law.sd)},
    )
    return stamp(
        traj,
        planner,
        started,
        gridpoints=problem.grid.size - 1,
        path=path.kind,
        path_unit=path.unit,
        sd_start=problem.sd_start,
        sd_end=problem.sd_end,
        margin={name: 1.0 - factor for name, factor in scale.items()},
        limit_ratio=timing.ratios,
        slowdown=1.0 / timing.slowdown,
        solves=solved.solves,
        grid=problem.grid,
        grid_times=law.t,
        path_velocity=law.sd,
        controllable_sets=solved.controllable_sets,
    )
