"""The rows of ``peers.py``: the protocol's moves and, per row, the optraj and peer calls.

Every builder returns :class:`peer_timing.Spec` objects whose calls close over problems
built beforehand, so that the clock sees only the planning.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import peer_calls as peer
from peer_timing import Row, Spec, measure_steps

from benchmarking import pool_shots
from optraj import controllers, planners, problems, robots
from optraj.controllers.simulation import simulate
from optraj.planners import registry
from optraj.planners.ocp.building import forget_compiled
from optraj.planners.time_optimal.lower_bound import lower_bound_va

SEED = 35
MOVES = 16  # moves the protocol draws
FIXED = 2.0  # duration of the fixed-duration time scalings [s]
TOPPRA_INTERVALS = 100
STRIKE_SHIFT = (0.0, 0.02, 0.0)  # the re-planned ball is moved this much [m]


class Moves:
    """The seeded moves of the protocol and their problems, built before any timing.

    The protocol draws 16 moves (more when more are asked for); ``indices`` picks the ones
    timed.
    """

    def __init__(self, robot: robots.Robot, indices: Sequence[int]) -> None:
        limits = robot.limits
        n = limits.n
        drawn = max(MOVES, max(indices) + 1)
        rng = np.random.default_rng(SEED)
        span = limits.upper - limits.lower
        pick = list(indices)
        self.starts = (limits.lower + span * rng.uniform(0.1, 0.9, (drawn, n)))[pick]
        self.goals = (limits.lower + span * rng.uniform(0.1, 0.9, (drawn, n)))[pick]
        self.v_start = (0.2 * limits.velocity * rng.uniform(-1, 1, (drawn, n)))[pick]
        self.v_goal = (0.2 * limits.velocity * rng.uniform(-1, 1, (drawn, n)))[pick]
        vias = (limits.lower + span * rng.uniform(0.1, 0.9, (drawn, 2, n)))[pick]
        count = len(pick)
        self.points = [np.vstack([self.starts[k], vias[k], self.goals[k]]) for k in range(count)]
        self.rest = [
            problems.PointToPoint(robot, self.starts[k], self.goals[k]) for k in range(count)
        ]
        self.moving = [
            problems.PointToPoint(
                robot,
                self.starts[k],
                self.goals[k],
                qd_start=self.v_start[k],
                qd_goal=self.v_goal[k],
            )
            for k in range(count)
        ]
        self.waypoints = [problems.Waypoints(robot, points) for points in self.points]
        self.count = count
        self.zero = np.zeros(n)

    def velocities(self, k: int, moving: bool) -> tuple[np.ndarray, np.ndarray]:
        """The start and goal velocities of move k [rad/s]: the drawn ones, or rest."""
        return (self.v_start[k], self.v_goal[k]) if moving else (self.zero, self.zero)


def scaling_rows(moves: Moves) -> list[Spec]:
    """Quintic and cubic against ``jtraj``: fixed 2 s and shortest, rest and boundary."""
    rtb = peer.missing("Robotics Toolbox")
    specs = []
    for shortest in (False, True):
        for name, kind in (("quintic", planners.Quintic), ("cubic", planners.Cubic)):
            for moving in (False, True):
                planner = kind() if shortest else kind(duration=FIXED)
                chosen = moves.moving if moving else moves.rest

                def ours(k: int, plan: Any = planner.plan, chosen: Any = chosen) -> Any:
                    return lambda: plan(chosen[k])

                def other(k: int, traj: Any, moving: bool = moving) -> Any:
                    qd0, qd1 = moves.velocities(k, moving)
                    q0, q1, duration = moves.starts[k], moves.goals[k], traj.duration
                    return lambda: peer.jtraj(q0, q1, duration, qd0, qd1)

                timing = "shortest" if shortest else f"{FIXED:g} s"
                label = f"{name} {timing}, {'boundary' if moving else 'rest'}"
                specs.append(Spec(label, ours, other, rtb))
    return specs


def profile_rows(robot: robots.Robot, moves: Moves) -> list[Spec]:
    """LSPB against ``mtraj(trapezoidal)``, ViaPoints against ``mstraj``, problem building."""
    rtb = peer.missing("Robotics Toolbox")
    lspb = planners.LSPB()

    def trapezoid(k: int, traj: Any) -> Any:
        q0, q1, duration = moves.starts[k], moves.goals[k], traj.duration
        return lambda: peer.trapezoidal(q0, q1, duration)

    def multi(k: int, _: Any) -> Any:
        points, velocity = moves.points[k], robot.limits.velocity
        return lambda: peer.mstraj(points, velocity)

    specs = [Spec("LSPB, rest", lambda k: lambda: lspb.plan(moves.rest[k]), trapezoid, rtb)]
    for profile in ("lspb", "quintic"):
        via = planners.ViaPoints(profile)
        specs.append(
            Spec(
                f"ViaPoints {profile}",
                lambda k, via=via: lambda: via.plan(moves.waypoints[k]),
                multi,
                rtb,
                goal=1.5,
            )
        )

    def build(k: int) -> Any:
        q0, q1 = moves.starts[k], moves.goals[k]
        return lambda: problems.PointToPoint(robot, q0, q1)

    specs.append(Spec("PointToPoint construction", build, None, None, kind="absolute", goal=10.0))
    return specs


def time_optimal_rows(robot: robots.Robot, moves: Moves) -> list[Spec]:
    """Ruckig against raw ruckig (rest and boundary); Toppra against raw toppra."""
    limits = robot.limits
    ruckig = planners.Ruckig()
    specs = []
    for moving in (False, True):
        chosen = moves.moving if moving else moves.rest

        def raw(k: int, _: Any, moving: bool = moving) -> Any:
            qd0, qd1 = moves.velocities(k, moving)
            q0, q1 = moves.starts[k], moves.goals[k]
            return lambda: peer.ruckig_move(q0, q1, qd0, qd1, limits)

        specs.append(
            Spec(
                f"Ruckig, {'boundary' if moving else 'rest'}",
                lambda k, chosen=chosen: lambda: ruckig.plan(chosen[k]),
                raw,
                peer.missing("ruckig"),
                goal=0.5,
            )
        )
    toppra = planners.Toppra(gridpoints=TOPPRA_INTERVALS)

    def raw_toppra(k: int, traj: Any) -> Any:
        built = toppra.build(moves.points[k], limits)  # the same knots and grid
        pchip = str(traj.metadata["path"]).startswith("pchip")  # the spline left the limits
        points = moves.points[k]
        return peer.toppra_path(built.path.knots, points, built.grid, limits, pchip=pchip)

    specs.append(
        Spec(
            f"Toppra, {TOPPRA_INTERVALS} intervals",
            lambda k: lambda: toppra.plan(moves.waypoints[k]),
            raw_toppra,
            peer.missing("toppra"),
            goal=0.95,
        )
    )
    return specs


class OcpRows:
    """OptimalControl (minimum time) against the bare OCP and Drake, and its first plan.

    Keeps each solver's IPOPT iterations and motion time over the lower bound of the limits
    it was given, from the untimed solve of each move.
    """

    def __init__(self, robot: robots.Robot, moves: Moves) -> None:
        self.moves = moves
        self.limits = robot.limits
        self.reused = planners.OptimalControl("time")
        self.bare_missing = peer.missing("bare CasADi OCP")
        self.drake_missing = peer.missing("Drake")
        self.bare = None if self.bare_missing else peer.bare_ocp(self.limits)
        self.drake = None if self.drake_missing else peer.DrakeMinTime(self.limits)
        self.iterations: dict[str, list[float]] = {"optraj": [], "bare": []}
        self.over_bound: dict[str, list[float]] = {"optraj": [], "bare": [], "drake": []}

    def specs(self) -> list[Spec]:
        """The rows: NLP reused against the bare OCP and Drake; first plan against reused."""
        label = "OptimalControl min time, NLP reused"
        return [
            Spec(
                f"{label}, vs bare CasADi",
                self.ours,
                self.bare_call,
                self.bare_missing,
                observe=self.observe_bare,
            ),
            Spec(
                f"{label}, vs Drake",
                self.ours,
                self.drake_call,
                self.drake_missing,
                goal=1.5,
                observe=self.observe_drake,
            ),
            Spec(
                "OptimalControl first plan vs reused",
                self.first,
                self.reused_call,
                None,
                kind="first / reused",
                goal=1.5,
            ),
            Spec(
                "OptimalControl new planner object vs reused",
                self.new_object,
                self.reused_call,
                None,
                kind="first / reused",
                goal=1.5,
            ),
        ]

    def ours(self, k: int) -> Callable[[], Any]:
        """The reused planner's plan of move k."""
        problem = self.moves.rest[k]
        return lambda: self.reused.plan(problem)

    def reused_call(self, k: int, _: Any) -> Callable[[], Any]:
        """The same, as the reference of the first-plan row."""
        return self.ours(k)

    def first(self, k: int) -> Callable[[], Any]:
        """A new planner's plan of move k in a process that keeps no NLP: its NLP built."""
        problem = self.moves.rest[k]

        def plan() -> Any:
            forget_compiled()
            return planners.OptimalControl("time").plan(problem)

        return plan

    def new_object(self, k: int) -> Callable[[], Any]:
        """A new planner's plan of move k, the NLP of its shape already built in the process."""
        problem = self.moves.rest[k]
        return lambda: planners.OptimalControl("time").plan(problem)

    def bare_call(self, k: int, _: Any) -> Callable[[], Any]:
        """The bare OCP's solve of move k; raises PeerError when IPOPT fails."""
        q0, q1, bare = self.moves.starts[k], self.moves.goals[k], self.bare

        def solve() -> Any:
            solution = bare.solve(q0, q1)  # type: ignore[union-attr]
            if not solution.success:
                raise peer.PeerError("bare OCP: IPOPT did not succeed")
            return solution

        return solve

    def drake_call(self, k: int, _: Any) -> Callable[[], Any]:
        """Drake's solve of move k."""
        q0, q1, drake = self.moves.starts[k], self.moves.goals[k], self.drake
        return lambda: drake.solve(q0, q1)  # type: ignore[union-attr]

    def va_bound(self, k: int) -> float:
        """Move k's lower bound under the velocity and acceleration limits alone [s]."""
        delta = self.moves.goals[k] - self.moves.starts[k]
        return lower_bound_va(delta, self.limits.velocity, self.limits.acceleration)

    def observe_bare(self, k: int, traj: Any, solution: Any) -> None:
        """Record optraj's and the bare OCP's iterations and motion over the bound."""
        self.iterations["optraj"].append(float(traj.metadata["iterations"]))
        bound = planners.lower_bound(self.moves.rest[k])
        self.over_bound["optraj"].append(traj.duration / bound)
        if solution is not None:
            self.iterations["bare"].append(float(solution.iterations))
            self.over_bound["bare"].append(solution.duration / self.va_bound(k))

    def observe_drake(self, k: int, _: Any, duration: float | None) -> None:
        """Record Drake's motion over the bound."""
        if duration is not None:
            self.over_bound["drake"].append(duration / self.va_bound(k))

    def table(self) -> list[str]:
        """Median IPOPT iterations and motion time / lower bound of each solver."""
        iterations, over = self.iterations, self.over_bound
        met_iterations = bool(iterations["optraj"]) and _median(iterations["optraj"]) <= 20.0
        met_bound = bool(over["optraj"]) and _median(over["optraj"]) <= 1.003
        return [
            "| solver | moves solved | median IPOPT iterations | median motion / lower bound "
            "| bound of | target |",
            "|---|---|---|---|---|---|",
            f"| optraj OptimalControl('time') | {len(over['optraj'])} "
            f"| {_cell(iterations['optraj'], 0)} | {_cell(over['optraj'], 4)} "
            "| velocity, acceleration, jerk | iterations <= 20 "
            f"({'met' if met_iterations else 'missed'}), motion / bound <= 1.003 "
            f"({'met' if met_bound else 'missed'}) |",
            f"| bare CasADi + IPOPT | {len(over['bare'])} | {_cell(iterations['bare'], 0)} "
            f"| {_cell(over['bare'], 4)} | velocity, acceleration | - |",
            f"| Drake KinematicTrajectoryOptimization + IPOPT | {len(over['drake'])} | - "
            f"| {_cell(over['drake'], 4)} | velocity, acceleration | - |",
        ]


def _median(values: list[float]) -> float:
    return float(np.median(values))


def _cell(values: list[float], digits: int) -> str:
    return f"{_median(values):.{digits}f}" if values else "-"


def strike_rows(count: int) -> list[Spec]:
    """Strike OCP: warm re-plan against cold plan; cold plan against the Ruckig strike."""
    shots, _ = pool_shots(count)
    plain = planners.OptimalControl("time")
    ruckig = registry.make_planner("pool-shot", "ruckig", contact="choose")
    prepared: dict[int, tuple[problems.PoolStrike, Any]] = {}

    def prepare(k: int) -> tuple[problems.PoolStrike, Any]:
        """The moved shot and the unmoved one's plan, its warm-start solver compiled."""
        if k not in prepared:
            shot = shots[k]
            previous = plain.plan(shot)
            plain.plan(shot, warm_start=previous)
            heading = float(np.degrees(np.arctan2(shot.direction[1], shot.direction[0])))
            ball = tuple(np.asarray(shot.ball) + STRIKE_SHIFT)
            moved = problems.sawyer_pool_shot(float(shot.speed), ball, heading_deg=heading)
            prepared[k] = (moved, previous)
        return prepared[k]

    # Each timed plan gets a fresh copy of the shot, as a new shot would come: choose_contact
    # remembers its answer per problem object, so the same object would skip the search.
    def warm(k: int) -> Any:
        moved, previous = prepare(k)
        return lambda: plain.plan(copy.copy(moved), warm_start=previous)

    def cold(k: int) -> Any:
        moved, _ = prepare(k)
        return lambda: plain.plan(copy.copy(moved))

    def cold_other(k: int, _: Any) -> Any:
        return cold(k)

    def ruckig_other(k: int, _: Any) -> Any:
        moved, _ = prepare(k)
        return lambda: ruckig.plan(copy.copy(moved))

    return [
        Spec(
            "strike OCP warm re-plan vs cold", warm, cold_other, None, kind="warm / cold", goal=0.2
        ),
        Spec(
            "strike OCP cold vs Ruckig strike",
            cold,
            ruckig_other,
            None,
            kind="cold / Ruckig strike",
            goal=1.5,
        ),
    ]


def diffik_row(robot: robots.Robot, moves: Moves, repeats: int, steps: int | None) -> Row:
    """One DiffIKQP step against pink's ``solve_ik`` with daqp, on the states of one run.

    The run: the DiffIKQP following the Ruckig plan of the first move (dynamic plant); its
    first ``steps`` states, or all when None.
    """
    traj = planners.Ruckig().plan(moves.rest[0])
    recorded = simulate(robot, traj, controllers.DiffIKQP(robot), peer.DT, plant="dynamic")
    recorded_steps = [
        (
            controllers.State(float(recorded.t[k]), recorded.q[k], recorded.qd[k]),
            recorded.references[k],
        )
        for k in range(len(recorded.t) - 1)
    ]
    missing = peer.missing("pink + daqp")
    pink = None if missing else peer.pink_daqp(robot)
    spec = Spec("DiffIKQP step vs pink + daqp", None, None, missing, goal=4.0)
    chosen = recorded_steps[:steps]
    return measure_steps(spec, controllers.DiffIKQP(robot), pink, chosen, repeats, peer.DT)
