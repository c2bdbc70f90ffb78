"""Refinement rounds of a plan: solves repeated with tighter bounds and rows until they hold."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from optraj.errors import (
    InfeasibleError,
    OptrajError,
    SolverError,
)
from optraj.planners.ocp.formulation import keep_switch_grid
from optraj.planners.ocp.options import (
    ANCHOR_WEIGHT,
    GRID_WEIGHT,
    MAX_STRIKE_INTERVALS,
    POSITION_SHRINKS,
    ROUNDS,
    STRIKE_GRID_WEIGHT,
    TORQUE_POINTS,
    TORQUE_WATCH,
)
from optraj.planners.ocp.problem import (
    OptimalControlProblem,
    Spec,
    WarmStart,
)
from optraj.planners.ocp.refinement import (
    fixed_ratios,
    position_excess,
    shrunk,
    tightened,
)
from optraj.planners.ocp.solution import (
    dense_times,
    with_totals,
)
from optraj.planners.trajectory import Trajectory
from optraj.robots import JointLimits

if TYPE_CHECKING:
    from optraj.planners.ocp.optimal_control import OptimalControl

FloatArray = NDArray[np.float64]


def round_weights(
    planner: OptimalControl, spec: Spec, *, time_only: bool = False
) -> dict[str, float]:
    """The objective weights of a round, with the regularization terms added."""
    weights = {"time": 1.0} if time_only else dict(planner.weights)
    robot = spec.robot
    if set(weights) == {"time"} and all(d is not None for d in spec.durations):
        weights = {"jerk": 1.0}  # nothing to shorten: the smoothest motion in the time
    if planner.regularization > 0.0:
        weights["jerk"] = weights.get("jerk", 0.0) + planner.regularization
        if spec.switch_joint is not None:  # first nodes on the jerk switches: keep them near
            weights["anchor"] = ANCHOR_WEIGHT
        else:
            weights["grid"] = GRID_WEIGHT if spec.strike is None else STRIKE_GRID_WEIGHT
        if robot.dof >= 7:
            weights["posture"] = planner.regularization
    return weights


@dataclass
class RoundSettings:
    """What a round is built with; each round's findings change it for the next.

    Attributes:
        torque_nodes: Nodes with torque rows.
        position_rows: Whether positions are bounded between nodes by rows.
        shrink: Node position bounds moved in, shape (nodes, 2, n) [rad or m], or None.
        shrinks: Rounds that moved them so far.
        strike_scale: Factor on the strike window's intervals.
        torque_margin: Fraction of the torque limits RNEA rows keep free [-].
        row_margins: Linear rows' margins per row node and joint [-], or None for
            ``torque_margin`` everywhere.
        expansions: Rounds in a row solved with linear torque rows.
    """

    torque_nodes: tuple[int, ...] = ()
    position_rows: bool = False
    shrink: FloatArray | None = None
    shrinks: int = 0
    strike_scale: int = 1
    torque_margin: float = 0.0
    row_margins: FloatArray | None = None
    expansions: int = 0

    @classmethod
    def first(
        cls, planner: OptimalControl, spec: Spec, warm_start: Trajectory | None
    ) -> RoundSettings:
        """The first round's: the planner's, or a previous solution's grid and rows.

        A warm start of the same phases lends its grid and its torque rows (so that its
        multipliers apply too) to ``spec`` and to the first round.
        """
        settings = cls(
            position_rows=planner.position_rows is True, torque_margin=planner.torque_margin
        )
        saved = None if warm_start is None else warm_start.metadata.get("warm_start")
        if isinstance(saved, WarmStart) and len(saved.structure.intervals) == len(spec.names):
            spec.intervals = saved.structure.intervals
            settings.torque_nodes = saved.structure.torque_nodes
            settings.position_rows = settings.position_rows or saved.structure.position_rows
        return settings

    def finer_strike(self) -> None:
        """Twice the strike intervals: the nodes are renumbered, so rows and moves start over."""
        self.strike_scale *= 2
        self.torque_nodes, self.row_margins, self.expansions = (), None, 0
        self.shrink, self.shrinks = None, 0

    def fitted_positions(self, excess: FloatArray, limits: JointLimits) -> None:
        """After a piece passed a position limit between nodes (``excess``, (K, 2, n)).

        Its nodes' bounds move in (the same NLP, warm) up to :data:`POSITION_SHRINKS`
        times; when that does not settle, rows bound positions between nodes from then on.
        """
        if self.shrinks < POSITION_SHRINKS:
            self.shrink = shrunk(self.shrink, excess, limits)
            self.shrinks += 1
        else:
            self.position_rows, self.shrink = True, None

    def more_torque_rows(
        self,
        planner: OptimalControl,
        found: RoundFindings,
        rows: tuple[int, ...],
        spec: Spec,
    ) -> None:
        """Torque rows at the ``found`` nodes too, with more room where rows did not hold.

        ``rows`` are the round's torque nodes. Linear rows are at every node: the next round
        expands about this solution. From the second expansion about a solution with rows
        on, rows whose torques still break the limit (at or between their nodes) keep more
        room, so that rounds which swap the binding nodes back and forth settle. RNEA rows
        needed everywhere already keep more room, all of them.
        """
        if found.ratios is None:  # pragma: no cover - torque nodes come from ratios
            return
        if planner.torque_rows == "linear":
            self.expansions = self.expansions + 1 if rows else 0
            if self.expansions >= 2:
                if self.row_margins is None:
                    self.row_margins = np.full((len(rows), spec.limits.n), self.torque_margin)
                self.row_margins = tightened(
                    self.row_margins, found.ratios[2] / spec.limits.effort, fixed_ratios(spec)
                )
        elif set(found.more) <= set(rows):
            self.torque_margin = min(0.2, 2.0 * self.torque_margin + 0.01)
        self.torque_nodes = tuple(sorted(set(self.torque_nodes) | set(found.more)))


@dataclass
class RoundFindings:
    """What the checks after a solve found.

    Attributes:
        ratios: :func:`torque_ratios` of the solution, or None.
        more: Nodes that need torque rows (:func:`torque_nodes`); empty when none.
        misses: The strike line's misses between nodes (:func:`strike_misses`).
        excess: :func:`position_excess` of the solution, or None when rows bound positions.
        plain: Whether the round had neither torque rows nor moved bounds (nothing but the
            grid that a new round could change).
    """

    ratios: tuple[FloatArray, FloatArray, FloatArray] | None
    more: list[int]
    misses: list[tuple[str, float, float, str]]
    excess: FloatArray | None
    plain: bool

    @property
    def positions_ok(self) -> bool:
        """Whether the positions kept their limits between nodes."""
        return self.excess is None or not self.excess.any()

    @property
    def settled(self) -> bool:
        """Whether nothing calls for another round."""
        return not self.more and not self.misses and self.positions_ok


def _round_findings(
    planner: OptimalControl,
    traj: Trajectory,
    built: OptimalControlProblem,
    spec: Spec,
    settings: RoundSettings,
) -> RoundFindings:
    """Check a round's solution: torques, the strike line and positions between nodes."""
    ratios = planner._torque_ratios(traj, spec)
    return RoundFindings(
        ratios=ratios,
        more=[] if planner.torque is False else planner._torque_nodes(traj, ratios, built, spec),
        misses=planner._strike_misses(traj, spec),
        excess=None if settings.position_rows else position_excess(traj, spec.limits),
        plain=not built.compiled.structure.torque_nodes and settings.shrink is None,
    )


def refined(
    planner: OptimalControl,
    settings: RoundSettings,
    found: RoundFindings,
    built: OptimalControlProblem,
    spec: Spec,
) -> bool:
    """Change ``settings`` by a round's findings; False when no new round could help.

    Positions first (moved bounds or rows); then a finer strike grid for a strike line
    missed between nodes (it renumbers the nodes, so torque rows wait), else torque rows.
    """
    if found.excess is not None and found.excess.any():
        settings.fitted_positions(found.excess, spec.limits)
    if found.misses:
        intervals = _strike_intervals(built, spec)
        if intervals >= MAX_STRIKE_INTERVALS and found.plain and found.positions_ok:
            return False  # no finer grid, and nothing else that a new round would drop
        settings.finer_strike()
    elif found.more and found.ratios is not None:
        settings.more_torque_rows(planner, found, built.compiled.structure.torque_nodes, spec)
    return True


def solve_rounds(
    planner: OptimalControl,
    problem: Any,
    spec: Spec,
    weights: dict[str, float],
    warm_start: Trajectory | None,
) -> Trajectory:
    """Solve ``spec`` in rounds, adding torque and position rows and finer grids until they hold.

    Raises:
        InfeasibleError: Torques that stay past their limits with rows.
        SolverError: Rounds that do not settle, or a strike line missed between nodes on
            the finest grid.
    """
    settings = RoundSettings.first(planner, spec, warm_start)
    keep_switch_grid(spec, warm_start)
    solves: list[Trajectory] = []
    for round_ in range(1, ROUNDS + 1):
        built = planner._build(
            problem,
            spec,
            weights,
            settings.torque_nodes,
            settings.strike_scale,
            warm_start,
            settings.torque_margin,
            settings.row_margins,
            settings.position_rows,
            settings.shrink,
        )
        traj = planner._solve(built)
        solves.append(traj)
        found = _round_findings(planner, traj, built, spec, settings)
        if found.settled:
            with_totals(traj, solves)
            traj.metadata["rounds"] = round_
            traj.metadata["torque_rows"] = len(built.compiled.structure.torque_nodes)
            traj.metadata["position_rows"] = settings.position_rows
            return traj
        if not refined(planner, settings, found, built, spec):
            break
        warm_start = traj
    raise _unsettled(planner, found, built, spec, round_)


def _unsettled(
    planner: OptimalControl,
    found: RoundFindings,
    built: OptimalControlProblem,
    spec: Spec,
    rounds: int,
) -> OptrajError:
    """The error of a plan whose last round (``found``, of ``built``) still did not settle."""
    torque_rows = built.compiled.structure.torque_nodes
    ratios = found.ratios
    if torque_rows and ratios is not None and ratios[1].max() > 1.0:
        tau = ratios[2]
        i, j = np.unravel_index(int(np.argmax(np.abs(tau) / spec.limits.effort)), tau.shape)
        joint, value = spec.limits.names[j], float(tau[i, j])
        limit = float(spec.limits.effort[j])
        return InfeasibleError(
            f"torque of {joint} stays at {value:.4g} N m (limit {limit:.4g}) after "
            f"{rounds} rounds, the last with torque rows at {len(torque_rows)} nodes",
            limit="effort",
            joint=joint,
            required=value,
            allowed=limit,
        )
    if not found.misses:
        what = "position limits" if not found.positions_ok else "torque rows"
        return SolverError(planner.solver, f"{what} not settled", detail=f"after {rounds} rounds")
    what = "; ".join(
        f"{name} {value:.3g} {unit} (plans keep it within {allowed:.3g} {unit}, half the tolerance)"
        for name, value, allowed, unit in found.misses
    )
    if ratios is not None and ratios[1].max() > 1.0:
        what += f"; torques up to {ratios[1].max():.3g} of their limits"
    return SolverError(
        planner.solver,
        "strike line not met between nodes",
        detail=f"with {_strike_intervals(built, spec)} strike intervals after {rounds} rounds: "
        f"{what}; a looser tolerance or a faster strike (a shorter window) may pass",
    )


def _strike_intervals(built: OptimalControlProblem, spec: Spec) -> int:
    """The strike window's intervals in ``built`` (0 without a strike line)."""
    if spec.strike is None:
        return 0
    return built.compiled.structure.intervals[spec.strike.phase]


def torque_ratios(traj: Trajectory, spec: Spec) -> tuple[FloatArray, FloatArray, FloatArray] | None:
    """Torques at TORQUE_POINTS per interval: (times, worst |tau| / effort, tau).

    None when the effort limits are not all finite (nothing to watch).
    """
    effort = spec.limits.effort
    if not np.all(np.isfinite(effort)):
        return None
    times = dense_times(traj, TORQUE_POINTS)
    s = traj.sample(times)
    tau = spec.robot.inverse_dynamics(s.q, s.qd, s.qdd)
    return times, np.max(np.abs(tau) / effort, axis=1), tau


def torque_nodes(
    planner: OptimalControl,
    traj: Trajectory,
    ratios: tuple[FloatArray, FloatArray, FloatArray] | None,
    built: OptimalControlProblem,
    spec: Spec,
) -> list[int]:
    """Nodes to add torque rows at: around intervals where a torque nears its limit.

    Empty once every torque keeps within ``1 - torque_margin / 2`` of its limit, or within
    what a fixed state of the problem itself needs of that joint's limit, if more (a
    start holding 99 % of a limit against gravity: :func:`fixed_room`).
    """
    if ratios is None:
        return []
    times, ratio, tau = ratios
    settled = np.maximum(1.0 - 0.5 * planner.torque_margin, fixed_ratios(spec))
    if np.all(np.abs(tau) / spec.limits.effort <= settled):
        return []
    knots = traj.breakpoints
    hot = np.unique(
        np.clip(np.searchsorted(knots, times[ratio > TORQUE_WATCH], "right") - 1, 0, len(knots) - 2)
    )
    nodes: set[int] = set()
    for k in hot.tolist():
        nodes.update((k, k + 1))
    existing = set(built.compiled.structure.torque_nodes)
    return sorted(nodes - existing) or sorted(nodes)


def strike_misses(
    planner: OptimalControl, traj: Trajectory, spec: Spec
) -> list[tuple[str, float, float, str]]:
    """Where the cue tip leaves its schedule between the strike nodes (none without a line).

    :meth:`planners.ocp.task_rows.strike_line.StrikeLineRows.misses` of the spec's line.
    """
    return [] if spec.strike is None else spec.strike.misses(traj, spec.robot)
