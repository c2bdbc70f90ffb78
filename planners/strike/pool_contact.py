"""The contact choice of a pool strike: rank the candidates, follow a previous branch.

:func:`pool_choices` collects distinct inverse-kinematics (IK) solutions with the cue tip on
the contact point and the cue along the shot, evaluates each one's strike window
(:class:`planners.strike.pool_search.PoolSearch`), improves the best few by a pattern search
along the self-motion (with a scene, first until the arm clears it), keeps those clear of the
scene, refuses the strike when even the fastest needs more than the velocity
limits, and ranks the rest: among those with room to spare the one the arm reaches soonest,
then the others by ratio. :func:`contact_near` re-plans without the search, following a previous
contact configuration's IK branch to a strike that changed a little.
:func:`planners.strike.contact.choose_contact` is the entry point for both strike kinds.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import CollisionError, InfeasibleError, InvalidInputError
from optraj.planners.strike.contact_choice import ContactChoice, as_margin, too_fast_error
from optraj.planners.strike.pool_search import PoolSearch, PoolWindow
from optraj.problems import PoolStrike
from optraj.robots import solve_ik
from optraj.validation import as_vector

__all__ = ["BRANCH_SPREAD", "HEADROOM", "contact_near", "pool_choices"]

FloatArray = NDArray[np.float64]

#: Random IK restarts allowed per candidate asked for: most random starts converge with the
#: cue on the line, so three per candidate rarely run out.
_RESTARTS_PER_CANDIDATE = 3
#: Candidates (best first) improved by the self-motion pattern search ...
_REFINED = 3
#: ... at least this far apart (largest joint difference) [rad or m]: configurations closer
#: than this on every joint count as one IK branch (here, and for a planner deciding whether a
#: previous solution through one contact can seed a plan through another), ...
BRANCH_SPREAD = 0.1
#: ... each with at most this many trial configurations (along the self-motion of the
#: joints that move the cue: turning the cue about its own axis changes no ratio), enough to
#: halve the step from the first to the smallest with both directions tried at each.
_TRIALS_PER_REFINEMENT = 12
#: Contacts whose ratio is at most this fraction of the allowed one count as fast enough
#: with room to spare; among them the one nearest the start (in joint travel time) is chosen,
#: since the contact with the very smallest ratio can lie far from the start.
HEADROOM = 0.9


def _reach(problem: PoolStrike, q: FloatArray) -> float:
    """Time the slowest joint needs from the start to q at its velocity limit [s]."""
    start = np.asarray(problem.q_start, dtype=float)
    return float(np.max(np.abs(q - start) / np.asarray(problem.limits.velocity, dtype=float)))


def pool_choices(
    problem: PoolStrike,
    candidates: int,
    seed: int,
    margin: float,
    count: int,
    exclude: Sequence[FloatArray] = (),
) -> list[ContactChoice]:
    """Up to ``count`` distinct contact configurations of a pool strike, best first.

    The search and the order of :func:`planners.strike.contact.choose_contact` (its docstring
    says them in words), with its arguments checked by the caller.

    Args:
        problem: The pool strike.
        candidates: IK solutions to collect, >= 1.
        seed: Seed of the IK's random restarts, >= 0.
        margin: Share of the velocity limits kept in reserve, in [0, 1).
        count: Most configurations to return, >= 1.
        exclude: Configurations already tried [rad], each shape (n,): choices on their
            branches (within :data:`BRANCH_SPREAD` on every joint) are left out.

    Raises:
        InfeasibleError: No candidate reaches the line's ends within the position limits, or
            even the fastest window needs more than the velocity limits.
        CollisionError: With a scene, no candidate keeps the arm its margin clear of it at
            contact, entry and exit (the pair of the clearest one).
    """
    search = PoolSearch(problem)
    found = _windows(problem, search, candidates, seed)
    seeds = _seeds(problem, found)
    windows = found + [search.improve(w, _TRIALS_PER_REFINEMENT) for w in seeds]
    clear = [w for w in windows if w.clear]
    if not clear:
        raise _blocked_error(problem, min(windows, key=lambda w: w.rank), search)
    windows = clear
    speed = float(problem.speed)
    fastest = min(windows, key=lambda w: w.r1)
    if speed * fastest.r1 > 1.0 - margin:
        raise too_fast_error(
            problem.limits,
            speed,
            fastest.r1,
            fastest.binding,
            fastest.binding_qd1,
            margin,
            f"any contact configuration found ({search.evaluated} tried)",
        )
    distinct = _distinct(_ranked(problem, windows, margin), speed, margin, count, exclude)
    return [_pool_choice(problem, w, search.evaluated) for w in distinct]


def _windows(
    problem: PoolStrike, search: PoolSearch, candidates: int, seed: int
) -> list[PoolWindow]:
    """The windows of ``problem.q_contact`` and of distinct IK solutions, lowest score first."""
    ik = solve_ik(
        problem.robot,
        problem.contact_point,
        axis=problem.direction,
        q_near=problem.q_start,
        min_solutions=candidates,
        restarts=_RESTARTS_PER_CANDIDATE * candidates,
        seed=seed,
        abandon_stalled=True,
    )
    starts = [np.asarray(problem.q_contact, dtype=float)]
    starts += [q for q in ik.solutions if min(np.linalg.norm(q - s) for s in starts) > 1e-9]
    found = [w for w in (search.window(q) for q in starts) if w is not None]
    if not found:
        raise InfeasibleError(
            f"none of the {len(starts)} contact configurations found reaches the strike "
            f"line's entry and exit nearby within the position limits",
            limit="position",
        )
    found.sort(key=lambda w: w.rank)
    return found


def _blocked_error(problem: PoolStrike, window: PoolWindow, search: PoolSearch) -> CollisionError:
    """The refusal of a strike none of whose contact configurations clears the scene."""
    first, second, place = window.nearest
    scene = problem.scene
    return CollisionError(
        first,
        second,
        window.clearance,
        what=f"the strike {place} of every contact configuration found ({search.evaluated} tried)",
        required=0.0 if scene is None else float(scene.margin),
    )


def _seeds(problem: PoolStrike, found: list[PoolWindow]) -> list[PoolWindow]:
    """The windows to improve: the best few on distinct branches, and the one nearest the start.

    With a scene, the nearest clear one when there is one.
    """
    seeds: list[PoolWindow] = []
    for window in found:  # the best few, at least BRANCH_SPREAD apart (not one optimum thrice)
        if len(seeds) < _REFINED and all(
            np.abs(window.q - other.q).max() > BRANCH_SPREAD for other in seeds
        ):
            seeds.append(window)
    pool = [w for w in found if w.clear] or found
    nearest = min(pool, key=lambda w: _reach(problem, w.q))
    if all(nearest is not other for other in seeds):
        seeds.append(nearest)
    return seeds


def _ranked(problem: PoolStrike, windows: list[PoolWindow], margin: float) -> list[PoolWindow]:
    """The windows in the order of choice.

    Fast enough with room to spare: the one the arm reaches soonest first; then the rest by
    whether they are fast enough and their ratio.
    """
    speed = float(problem.speed)
    room = HEADROOM * (1.0 - margin)
    # Room to spare: in the velocity ratio, and (estimated) to turn at the position limits.
    roomy = [w for w in windows if speed * max(w.r1, w.turn) <= room]
    tight = [w for w in windows if speed * max(w.r1, w.turn) > room]
    return sorted(roomy, key=lambda w: (_reach(problem, w.q), w.score)) + sorted(
        tight, key=lambda w: (speed * w.r1 > 1.0 - margin, w.score)
    )


def _distinct(
    ranked: list[PoolWindow],
    speed: float,
    margin: float,
    count: int,
    exclude: Sequence[FloatArray],
) -> list[PoolWindow]:
    """The first ``count`` fast enough windows on branches apart from each other and ``exclude``."""
    distinct: list[PoolWindow] = []
    taken = list(exclude)
    for window in ranked:  # alternatives must be other branches, not the same one refined
        if speed * window.r1 <= 1.0 - margin and all(
            np.abs(window.q - other).max() > BRANCH_SPREAD for other in taken
        ):
            distinct.append(window)
            taken.append(window.q)
        if len(distinct) == count:
            break
    return distinct


def _pool_choice(problem: PoolStrike, window: PoolWindow, evaluated: int) -> ContactChoice:
    """The :class:`ContactChoice` of a pool window at the problem's speed."""
    speed = float(problem.speed)
    return ContactChoice(
        q=window.q,
        qd=speed * window.qd1,
        ratio=speed * window.r1,
        max_speed=1.0 / window.r1 if window.r1 > 0.0 else math.inf,
        binding_joint=problem.limits.names[window.binding[0]],
        candidates=evaluated,
        q_entry=window.q_entry,
        q_exit=window.q_exit,
    )


def contact_near(problem: PoolStrike, q: ArrayLike, *, margin: float = 0.0) -> ContactChoice | None:
    """The pool contact configuration on the IK branch of q, if it has room to spare.

    For re-planning a strike that changed a little (the ball moved, another heading or
    speed) from a previous contact configuration q: one local IK from q and one evaluation
    of its strike window, instead of the search of
    :func:`planners.strike.contact.choose_contact`. It is returned only when that search
    would count it fast enough with room to spare: the speed times the larger of its velocity
    ratio and its room-to-turn estimate at most :data:`HEADROOM` (90 %) of ``1 - margin``.
    With a scene it must also keep the arm the scene's margin clear at contact, entry and
    exit. Otherwise None: run the search.

    Args:
        problem: The pool strike.
        q: A previous contact configuration [rad], shape (n,), within the position limits.
        margin: As :func:`planners.strike.contact.choose_contact`.

    Raises:
        InvalidInputError: Not a pool strike, or bad ``q`` or ``margin``.
        JointLimitError: A joint of ``q`` outside its position limits.
    """
    if not isinstance(problem, PoolStrike):
        raise InvalidInputError(
            f"contact_near takes a problems.PoolStrike, got {type(problem).__name__}",
            name="problem",
        )
    seed = as_vector(q, "q", problem.limits.n)
    problem.limits.check_position(seed, context="contact_near q")
    reserve = as_margin(margin)
    search = PoolSearch(problem)
    found = search.near(search.to_contact, seed)
    window = None if found is None else search.window(found, clear_only=True)
    if window is None:
        return None
    if float(problem.speed) * max(window.r1, window.turn) > HEADROOM * (1.0 - reserve):
        return None
    return _pool_choice(problem, window, search.evaluated)
