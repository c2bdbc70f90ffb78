"""The search for pool contact configurations: evaluate a strike window, improve it.

A pool cue can meet the ball from a two-dimensional family of configurations (Sawyer has 7
joints for 5 task rows). :class:`PoolSearch` evaluates one of them as a :class:`PoolWindow`:
the configurations at contact and at the strike line's entry and exit (the whole line is run at
the strike speed), the largest twist ratio over the three
(:func:`planners.strike.twist_ratio.unit_ratio`), an estimate of the room the window leaves to
turn at the position limits, and a score that ranks candidates. :meth:`PoolSearch.improve`
lowers a window's score by a pattern search along the self-motion. With a scene
(``problem.scene``) a window also carries the arm's clearance from it (the nearest pair over
the three configurations); a window nearer than the scene's margin is *blocked*, and
:meth:`PoolSearch.improve` raises a blocked window's clearance until it is clear, then lowers
its score keeping it clear. The ranking of the candidates and the choice among them are
:mod:`planners.strike.pool_contact`'s. Usage::

    search = PoolSearch(problem)
    window = search.window(q)  # None when the line's ends are out of reach from q
    better = search.improve(window, trials=12)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.planners.strike.min_max_ratio import MinMaxRatio, idle_columns
from optraj.planners.strike.twist_ratio import binding_joints, task_rows, unit_ratio
from optraj.problems import PoolStrike
from optraj.problems.common import normal_pair
from optraj.problems.scene_distances import SceneCollision
from optraj.robots.ik import LocalIK

__all__ = ["PoolSearch", "PoolWindow"]

FloatArray = NDArray[np.float64]

#: A pattern-search trial succeeds only if it lowers the score by more than this fraction:
#: smaller changes are rounding and IK-tolerance noise (about 1e-12), and letting them decide
#: would make the search depend on the last bits of the LP solution.
_TIE = 1e-9
#: Pattern search steps along the self-motion [rad or m]: first, largest and smallest. The
#: search starts coarse: the ratio along the self-motion can rise before it falls, and a
#: start pinned at a joint limit may only improve a large step away.
_FIRST_STEP = 0.4
_LARGEST_STEP = 0.4
_SMALLEST_STEP = 0.0125
#: A blocked window's trial must be clearer by this much to count as a success [m]: less is
#: the geometry's rounding.
_CLEARER = 1e-6
#: A joint within this fraction of its range from a position limit is near it, and ...
_LIMIT_ZONE = 0.1
#: ... a candidate whose joint sits on a limit has its ratio raised by this fraction when
#: candidates are ranked (a tie-break that prefers room to brake after the strike).
_LIMIT_PENALTY = 0.02


@dataclass(frozen=True)
class PoolWindow:
    """A pool candidate: contact, entry and exit configurations and their unit-speed LPs.

    Attributes:
        q: Contact configuration [rad], shape (n,).
        q_entry: Configuration at the line's entry point, reached from q [rad], shape (n,).
        q_exit: Configuration at the line's exit point, reached from q [rad], shape (n,).
        r1: Largest unit-speed twist ratio of the three [s/m].
        qd1: Optimal contact joint velocity at unit speed [rad/m], shape (n,).
        binding: Binding joints where the largest ratio occurs.
        binding_qd1: The joint velocity at unit speed there [rad/m], shape (n,).
        turn: Unit-speed ratio of the room the window leaves to turn at a limit
            (:meth:`PoolSearch.turn`) [s/m].
        score: ``max(r1, turn)`` raised by the joint-limit penalty, for ranking [s/m].
        order: Places (0 contact, 1 entry, 2 exit): the largest ratio's, the one nearest a
            limit, then the rest; the order in which a trial near this window is evaluated.
        clearance: Smallest signed distance between two shapes of the arm and scene that may
            not touch, over the three configurations [m]; inf without a scene.
        nearest: That pair's names and the place where it is nearest ("contact", "entry" or
            "exit"); empty without a scene.
        clear: Whether ``clearance`` is at least the scene's margin (True without a scene).
    """

    q: FloatArray
    q_entry: FloatArray
    q_exit: FloatArray
    r1: float
    qd1: FloatArray
    binding: tuple[int, ...]
    binding_qd1: FloatArray
    turn: float
    score: float
    order: tuple[int, ...]
    clearance: float = math.inf
    nearest: tuple[str, ...] = ()
    clear: bool = True

    @property
    def rank(self) -> tuple[bool, float]:
        """Sort key, best first: clear windows by score, then blocked ones, clearest first."""
        return (not self.clear, self.score if self.clear else -self.clearance)


class PoolSearch:
    """Evaluates and improves pool contact configurations for one problem.

    Keep one for one search, and share none between threads: it keeps an LP
    (:class:`planners.strike.min_max_ratio.MinMaxRatio`) and counts the configurations it
    evaluates (``evaluated``).

    Args:
        problem: The pool strike.
    """

    def __init__(self, problem: PoolStrike) -> None:
        self.problem = problem
        self.robot = problem.robot
        self.limits = problem.limits
        self.direction = np.asarray(problem.direction, dtype=float)
        self.across = normal_pair(self.direction)
        self.velocity_limit = np.asarray(self.limits.velocity, dtype=float)
        self.twice_acceleration = 2.0 * np.asarray(self.limits.acceleration, dtype=float)
        self.run_up = float(problem.run_up)
        self.follow_through = float(problem.follow_through)
        self.lower = np.asarray(self.limits.lower, dtype=float)
        self.upper = np.asarray(self.limits.upper, dtype=float)
        self.zone = _LIMIT_ZONE * (self.upper - self.lower)
        self.lp = MinMaxRatio()
        self.evaluated = 0
        scene = problem.scene
        self.shapes = None if scene is None else SceneCollision(self.robot, scene)
        self.margin = 0.0 if scene is None else float(scene.margin)
        self._pairs = None if self.shapes is None else self.shapes.static_mask()
        # solve_ik(robot, point, axis=direction, q_near=q, restarts=0) for each point of the line
        self.to_contact, self.to_entry, self.to_exit = (
            LocalIK(self.robot, point, axis=self.direction)
            for point in (problem.contact_point, problem.entry_point, problem.exit_point)
        )

    def _inside(self, q: FloatArray) -> bool:
        """Whether q lies within the problem's position limits."""
        inside = np.count_nonzero(q >= self.lower) + np.count_nonzero(q <= self.upper)
        return inside == 2 * q.size

    def _closeness(self, q: FloatArray) -> float:
        """How deep the joint nearest a position limit is in the zone near it: 0 outside, 1 on.

        The zone of a joint is the last :data:`_LIMIT_ZONE` of its range at either end.
        """
        clearance = np.minimum(q - self.lower, self.upper - q)
        # The deepest joint is the one with the least clearance relative to its zone.
        return min(1.0, max(0.0, 1.0 - float((clearance / self.zone).min())))

    def near(self, ik: LocalIK, q: FloatArray) -> FloatArray | None:
        """The IK solution for one point of the line reached from q, if any (within limits)."""
        found = ik(q)
        return found if found is not None and self._inside(found) else None

    def turn(self, entry: FloatArray, contact: FloatArray, exit_: FloatArray) -> float:
        """How hard the window presses a joint against a position limit, per unit speed [s/m].

        A joint that enters the window moving away from a limit must have turned round
        before, in the room behind it; one that leaves it moving towards a limit must stop in
        the room ahead. Turning or stopping from speed u at acceleration a takes u^2 / (2 a).
        With the joint velocity along the window estimated from its configurations, u1 per
        metre of tool travel ((contact - entry) / run_up at the entry, (exit - contact) /
        follow_through at the exit), the strike at speed v has that room when
        ``v |u1| / sqrt(2 a room) <= 1``; the largest of these over the joints and both ends
        is returned (0 when no joint moves, inf when one moves off a limit it sits on). It is
        an estimate, not a bound (the arm may use its self-motion), so it ranks candidates
        and never refuses a strike.
        """
        worst = 0.0
        for near, far, length, ahead in (
            (entry, contact, self.run_up, False),
            (exit_, contact, self.follow_through, True),
        ):
            if length <= 0.0:
                continue
            rate = (near - far if ahead else far - near) / length  # [rad/m], along the window
            towards_upper = (rate > 0.0) == ahead  # the side whose room counts
            room = np.where(towards_upper, self.upper - near, near - self.lower)
            moving = rate != 0.0
            if not moving.any():
                continue
            with np.errstate(divide="ignore"):
                need = np.abs(rate[moving]) / np.sqrt(
                    self.twice_acceleration[moving] * np.maximum(room[moving], 0.0)
                )
            worst = max(worst, float(need.max()))
        return worst

    def _ratio(self, q: FloatArray) -> tuple[float, FloatArray]:
        """:func:`unit_ratio` at q for the strike direction, the cue held on the line."""
        return unit_ratio(
            self.lp, self.robot, q, self.direction, self.velocity_limit, 0.0, self.across
        )

    def clearance(self, configs: list[FloatArray]) -> tuple[float, tuple[str, ...]]:
        """The nearest pair over configurations (contact, entry, exit) [m], its names and place.

        ``(inf, ())`` without a scene. Pairs the scene allows at some time are left out.
        """
        if self.shapes is None:
            return math.inf, ()
        best: tuple[float, tuple[str, ...]] = (math.inf, ())
        self.shapes.set_active(self._pairs)
        for place, q in zip(("contact", "entry", "exit"), configs, strict=True):
            self.shapes.compute(q)
            index, distance = self.shapes.smallest(self._pairs)
            if distance < best[0]:
                best = (distance, (*self.shapes.pair_names(index), place))
        return best

    def window(
        self,
        q: FloatArray,
        bound: float = math.inf,
        order: tuple[int, ...] = (0, 1, 2),
        clear_only: bool = False,
    ) -> PoolWindow | None:
        """Evaluate contact configuration q (with the cue on the line at the contact point).

        Returns None when the line's entry or exit cannot be reached near q, or when the
        window's score cannot be below a finite ``bound``: checked as each configuration
        comes in against the largest ratio so far raised by the limit penalty of the
        configurations so far (a lower bound of the score), so a poor trial is dropped after
        one LP. ``order`` lists the places (0 contact, 1 entry, 2 exit) in the order they are
        evaluated: where the window that set the bound had its largest ratio and the joint
        nearest a limit prunes a poor trial soonest. The pruning and the order change nothing
        else. With ``clear_only`` a window that is not clear of the scene is None too.
        """
        self.evaluated += 1
        if not self._inside(q):
            return None
        prune = math.isfinite(bound)  # with no bound, a singular candidate is kept (r1 = inf)
        # Per place (contact, entry, exit), each filled in when the place is evaluated.
        configs: list[FloatArray] = [q, q, q]
        ratios = [0.0, 0.0, 0.0]
        velocities: list[FloatArray] = [q, q, q]
        near_limit = [self._closeness(q), 0.0, 0.0]
        for place in order:
            if place > 0:
                end = self.near(self.to_entry if place == 1 else self.to_exit, q)
                if end is None:
                    return None
                configs[place] = end
                near_limit[place] = self._closeness(end)
            closeness = max(near_limit)
            ratios[place], velocities[place] = self._ratio(configs[place])
            if prune and max(ratios) * (1.0 + _LIMIT_PENALTY * closeness) >= bound:
                return None
        clearance, nearest = self.clearance(configs)
        clear = clearance >= self.margin
        if clear_only and not clear:
            return None
        worst = max(range(3), key=ratios.__getitem__)  # the earliest place on a tie
        tightest = max(range(3), key=near_limit.__getitem__)
        turn = self.turn(configs[1], q, configs[2])
        return PoolWindow(
            q=q,
            q_entry=configs[1],
            q_exit=configs[2],
            r1=ratios[worst],
            qd1=velocities[0],
            binding=tuple(binding_joints(velocities[worst], self.velocity_limit)),
            binding_qd1=velocities[worst],
            turn=turn,
            score=max(ratios[worst], turn) * (1.0 + _LIMIT_PENALTY * near_limit[tightest]),
            order=tuple(dict.fromkeys((worst, tightest, 0, 1, 2))),
            clearance=clearance,
            nearest=nearest,
            clear=clear,
        )

    def improve(self, start: PoolWindow, trials: int) -> PoolWindow:
        """Pattern search along the self-motion: lower the score by moving the contact q.

        The self-motion keeps the cue tip on the contact point with the cue on the line; to
        first order it is the null space of the 5 task rows (the same rows as the LP's).
        Joints whose column of the rows vanishes (:func:`idle_columns`: Sawyer's last joint,
        which turns the cue about its own axis) are left out: moving them changes no ratio.
        Steps of size h along the remaining null-space directions and their opposites are
        tried, the last successful direction first; a success (a score lower by more than
        :data:`_TIE`, relative) moves there and doubles h, a failure halves it. Each trial is
        projected back with IK. A blocked window (:attr:`PoolWindow.clear` False) counts a
        trial a success when it is clear or its clearance is larger by more than
        :data:`_CLEARER`; once clear, only clear trials succeed.
        """
        current, step, last = start, _FIRST_STEP, None
        while step >= _SMALLEST_STEP and trials > 0:
            rows = task_rows(self.robot, current.q, 0.0, self.across)
            moving = ~idle_columns(rows)
            null = np.zeros((max(int(moving.sum()) - rows.shape[0], 0), rows.shape[1]))
            null[:, moving] = np.linalg.svd(rows[:, moving])[2][rows.shape[0] :]
            moves = [*null, *(-null)]
            if last is not None:
                moves.sort(key=lambda move: -float(move @ last))
            moved = False
            bound = current.score * (1.0 - _TIE) if current.clear else math.inf
            for move in moves:
                if trials == 0:
                    break
                trials -= 1
                guess = np.clip(current.q + step * move, self.lower, self.upper)
                q = self.near(self.to_contact, guess)
                trial = None if q is None else self.window(q, bound, current.order, current.clear)
                if trial is not None and _better(trial, current, bound):
                    last = (trial.q - current.q) / np.linalg.norm(trial.q - current.q)
                    current, moved = trial, True
                    break
            step = min(2.0 * step, _LARGEST_STEP) if moved else 0.5 * step
        return current


def _better(trial: PoolWindow, current: PoolWindow, bound: float) -> bool:
    """Whether a pattern-search trial improves on the current window (:meth:`improve`)."""
    if current.clear:
        return trial.clear and trial.score < bound
    return trial.clear or trial.clearance > current.clearance + _CLEARER
