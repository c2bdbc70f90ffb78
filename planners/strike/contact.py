"""Where a strike meets the ball, and whether any configuration is fast enough.

:func:`choose_contact` picks the contact configuration of a pool or paddle strike whose
twist ratio (:func:`twist_ratio`: the least share of the velocity limits a joint velocity
giving the strike motion needs) is small enough, near the start. A pool cue can meet the ball
from a two-dimensional family of configurations (Sawyer has 7 joints for 5 task rows): the
candidates are distinct inverse-kinematics (IK) solutions, the best few improved by a pattern
search along the self-motion, each ranked by the largest ratio over the strike window (the
configurations at contact and at the line's entry and exit, since the whole line is run at the
strike speed). A paddle4 contact is fixed by its closed-form IK. When even the best ratio
exceeds 1 (or 1 - margin) the strike is rejected at once, with an
:class:`optraj.errors.InfeasibleError` naming the binding joint and the fastest strike found:
a pre-check instead of letting a planner spend its iteration budget on a strike no
configuration can make. :func:`contact_choices` returns the next IK branches too, for a planner
to fall back on, and :func:`contact_near` re-plans without the search: it follows a previous
contact configuration's IK branch to a strike that changed a little.

The pieces live in their own modules and are re-exported here:

- :mod:`planners.strike.twist_ratio` and :mod:`planners.strike.min_max_ratio`: the ratio and
  its linear programme;
- :mod:`planners.strike.contact_choice`: :class:`ContactChoice` and the refusal errors;
- :mod:`planners.strike.pool_search` and :mod:`planners.strike.pool_contact`: a pool strike's
  window evaluation, self-motion search and ranking, and :func:`contact_near`;
- :mod:`planners.strike.paddle_contact`: a paddle strike's contact and :func:`stopping_speeds`.
"""

from __future__ import annotations

import copy
import dataclasses
import threading
import weakref
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.strike.contact_choice import ContactChoice, as_margin
from optraj.planners.strike.paddle_contact import paddle_choice, stopping_speeds
from optraj.planners.strike.pool_contact import BRANCH_SPREAD, HEADROOM, contact_near, pool_choices
from optraj.planners.strike.twist_ratio import MAX_OFFSET, twist_ratio
from optraj.problems import PaddleStrike, PoolStrike
from optraj.validation import as_count, as_vector

__all__ = [
    "BRANCH_SPREAD",
    "HEADROOM",
    "MAX_CANDIDATES",
    "MAX_OFFSET",
    "ContactChoice",
    "choose_contact",
    "contact_choices",
    "contact_near",
    "stopping_speeds",
    "twist_ratio",
]

FloatArray = NDArray[np.float64]

#: Most contact configurations one search may collect or evaluate (each is an IK solve).
MAX_CANDIDATES = 1000

_Answer = ContactChoice | InfeasibleError
# choose_contact's answers (a choice, or the InfeasibleError it raised) per problem object and
# arguments: a sweep's row and the planner it calls ask the same question of one problem.
# Problems are frozen and hashed by identity, so an entry goes when its problem does.
_MEMO: weakref.WeakKeyDictionary[object, dict[tuple[object, ...], _Answer]] = (
    weakref.WeakKeyDictionary()
)
_MEMO_LOCK = threading.Lock()


def choose_contact(
    problem: PoolStrike | PaddleStrike,
    *,
    candidates: int = 16,
    seed: int = 0,
    margin: float = 0.0,
) -> ContactChoice:
    """The contact configuration of a strike: fast enough, near the start.

    Pool strike: up to ``candidates`` distinct IK solutions with the cue tip on the contact
    point and the cue along the direction (from ``problem.q_start`` and seeded random starts),
    plus ``problem.q_contact``; each keeps the strike window reachable (the line's entry and
    exit solved from it) and is ranked by the largest ratio over contact, entry and exit
    (raised by at most 2 % near a joint position limit, a tie-break); the best three and the
    one nearest the start are improved by a short pattern search along the self-motion. Among
    the configurations that need at most 90 % (:data:`HEADROOM`) of the allowed ratio, the
    one the arm reaches soonest from the start (largest joint travel over velocity limit) is
    chosen; when none has that much room, the one with the smallest ratio. Paddle strike: the
    closed-form ``problem.q_contact``, the ball point moving along the normal and the normal
    held still (the joint velocity of :func:`planners.profiles.cartesian.paddle_contact_velocity`;
    letting the paddle turn at contact would lower paddle4's ratio by a few percent at the cost
    of spinning it, see :func:`twist_ratio` with ``align_axis=False``).

    Args:
        problem: A :class:`problems.PoolStrike` or :class:`problems.PaddleStrike`.
        candidates: IK solutions to collect for a pool strike (1 to :data:`MAX_CANDIDATES`);
            more search wider and take longer.
        seed: Seed of the IK's random restarts (the result is reproducible).
        margin: Fraction of the velocity limits kept in reserve, in [0, 1): the strike is
            accepted when its ratio is at most 1 - margin.

    The answer is remembered per problem object and arguments: asking again returns a copy
    at once, or raises the same refusal.

    Returns:
        The chosen configuration, its joint velocity at contact and its ratio.

    Raises:
        InfeasibleError: Even the best configuration needs a joint faster than its velocity
            limit (``limit="velocity"``, the binding ``joint``, ``required`` its speed and
            ``allowed`` its limit times 1 - margin [rad/s or m/s], ``max_speed`` the fastest
            strike speed that would pass [m/s], ``found_by``
            :data:`optraj.errors.CONTACT_CHOICE`). Also raised with ``limit="position"``:
            when no pool candidate keeps the line's entry and exit reachable within the
            position limits, and (``found_by`` the contact choice too, ``required`` and
            ``allowed`` the room [rad or m]) when a paddle contact leaves a joint too little
            room to start from and come back to rest around it (:func:`stopping_speeds`).
        InvalidInputError: Another problem type, or bad ``candidates``, ``seed`` or ``margin``.
        SolverError: HiGHS fails on an LP (not expected).
    """
    key = (
        as_count(candidates, "candidates", 1, MAX_CANDIDATES),
        as_count(seed, "seed", 0, maximum=None),
        as_margin(margin),
    )
    with _MEMO_LOCK:
        known: _Answer | None = _MEMO.get(problem, {}).get(key)
    if known is None:
        try:
            known = contact_choices(problem, 1, candidates=candidates, seed=seed, margin=margin)[0]
        except InfeasibleError as exc:
            known = _bare(exc)
            with _MEMO_LOCK:
                _MEMO.setdefault(problem, {})[key] = known
            raise
        with _MEMO_LOCK:
            _MEMO.setdefault(problem, {})[key] = known
    if isinstance(known, InfeasibleError):
        raise _bare(known)
    return dataclasses.replace(
        known,
        q=known.q.copy(),
        qd=known.qd.copy(),
        q_entry=None if known.q_entry is None else known.q_entry.copy(),
        q_exit=None if known.q_exit is None else known.q_exit.copy(),
    )


def _bare(error: InfeasibleError) -> InfeasibleError:
    """A copy of ``error`` without traceback or context.

    A remembered refusal must not keep the frames (and the problem in them) alive, or its
    problem would never be forgotten.
    """
    return copy.copy(error).with_traceback(None)


def contact_choices(
    problem: PoolStrike | PaddleStrike,
    count: int = 3,
    *,
    candidates: int = 16,
    seed: int = 0,
    margin: float = 0.0,
    exclude: Sequence[ArrayLike] | None = (),
) -> tuple[ContactChoice, ...]:
    """The best ``count`` distinct contact configurations, in :func:`choose_contact`'s order.

    The first is :func:`choose_contact`'s; the others are other IK branches (at least 0.1 rad
    apart on some joint), for a planner to fall back on when it cannot solve from the first.
    A paddle strike has one (closed-form) configuration.

    Args:
        problem: As :func:`choose_contact`.
        count: Most configurations to return (>= 1).
        candidates: As :func:`choose_contact`.
        seed: As :func:`choose_contact`.
        margin: As :func:`choose_contact`.
        exclude: Pool: configurations already tried [rad], each shape (n,); choices on their
            branches (within 0.1 rad on every joint) are left out, so the result may be
            empty. None excludes nothing.

    Raises:
        InfeasibleError, InvalidInputError, SolverError: As :func:`choose_contact`.
    """
    wanted = as_count(count, "count", 1, MAX_CANDIDATES)
    searched = as_count(candidates, "candidates", 1, MAX_CANDIDATES)
    as_count(seed, "seed", 0, maximum=None)
    reserve = as_margin(margin)
    if isinstance(problem, PoolStrike):
        tried = _configurations(exclude, "exclude", problem.limits.n)
        return tuple(pool_choices(problem, searched, int(seed), reserve, wanted, tried))
    if isinstance(problem, PaddleStrike):
        return (paddle_choice(problem, reserve),)
    raise InvalidInputError(
        f"choose_contact takes a problems.PoolStrike or a problems.PaddleStrike, got "
        f"{type(problem).__name__}",
        name="problem",
    )


def _configurations(value: Sequence[ArrayLike] | None, name: str, n: int) -> list[FloatArray]:
    """``value`` as a list of configurations of n joints; None is none."""
    if value is None:
        return []
    if isinstance(value, (str, bytes)) or not isinstance(value, (Sequence, np.ndarray)):
        raise InvalidInputError(
            f"{name} must be a sequence of configurations of {n} joints, got {value!r}",
            name=name,
        )
    if len(value) and np.ndim(value[0]) == 0:
        raise InvalidInputError(
            f"{name} must be a sequence of configurations of {n} joints, got one of numbers: "
            f"put a single configuration in a list",
            name=name,
        )
    return [as_vector(q, f"{name}[{k}]", n) for k, q in enumerate(value)]
