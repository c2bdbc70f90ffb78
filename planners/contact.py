r"""Where a strike meets the ball, and whether any configuration is fast enough.

At contact the tool must move at ``speed`` along a direction: in a pool shot the cue tip moves
along the shot direction with its z axis (the cue axis) held on the line, free to turn about it
(roll); in a paddle shot the ball point moves along the paddle normal. At a configuration q the
joint velocities giving this motion form an affine set :math:`\{\dot q : A(q) \dot q = v\, b\}`,
and the smallest velocity-limit ratio over it is a small linear programme (LP),

.. math::

    r(q, v) = \min_{\dot q,\, s} s \quad \text{s.t.} \quad A \dot q = v\, b, \quad
    -s\, \dot q_{\max} \le \dot q \le s\, \dot q_{\max},

solved by :func:`twist_ratio` (HiGHS through CasADi, over the null-space coordinates of A, so
the equalities hold to rounding). It is linear in the speed, :math:`r(q, v) = v\, r_1(q)`, so
the fastest strike the configuration allows within the velocity limits is :math:`1 / r_1(q)`.

:func:`choose_contact` picks the contact configuration with the smallest ratio. A pool cue can
meet the ball from a two-dimensional family of configurations (Sawyer has 7 joints for 5 task
rows): the candidates are distinct inverse-kinematics (IK) solutions, the best few improved by
a pattern search along the self-motion, each ranked by the largest ratio over the strike window
(the configurations at contact and at the line's entry and exit, since the whole line is run at
the strike speed). A paddle4 contact is fixed by its closed-form IK. When even the best ratio
exceeds 1 (or 1 - margin) the strike is rejected at once, with an
:class:`optraj.errors.InfeasibleError` naming the binding joint and the fastest strike found: a
pre-check that answers in well under a second instead of letting a planner spend its iteration
budget on a strike no configuration can make.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError, SolverError, UnreachableError
from optraj.validation import as_array, as_count, as_vector
from problems import PaddleStrike, PoolStrike
from problems.common import unit_vector
from robots import JointLimits, Robot, solve_ik
from robots.paddle_ik import BALL_OFFSET

__all__ = ["ContactChoice", "choose_contact", "contact_choices", "twist_ratio"]

FloatArray = NDArray[np.float64]

#: Singular values below this fraction of the largest count as zero in the task rows.
_RANK_TOLERANCE = 1e-10
#: Relative residual above which the task rows cannot give the motion (ratio = inf).
_RESIDUAL_TOLERANCE = 1e-9
#: HiGHS primal and dual feasibility tolerances (its defaults are 1e-7).
_LP_TOLERANCE = 1e-10
#: Random IK restarts allowed per candidate asked for: about 2/3 of Sawyer's random starts
#: converge with the cue on the line, so 3 per candidate rarely runs out.
_RESTARTS_PER_CANDIDATE = 3
#: Candidates (best first) improved by the self-motion pattern search ...
_REFINED = 3
#: ... at least this far apart (largest joint difference) [rad or m], ...
_SPREAD = 0.1
#: ... each with at most this many trial configurations.
_TRIALS_PER_REFINEMENT = 20
#: Pattern search steps along the self-motion [rad or m]: first, largest and smallest.
_FIRST_STEP = 0.2
_LARGEST_STEP = 0.4
_SMALLEST_STEP = 0.0125
#: A joint within this fraction of its range from a position limit is near it, and ...
_LIMIT_ZONE = 0.1
#: ... a candidate whose joint sits on a limit has its ratio raised by this fraction when
#: candidates are ranked (a tie-break that prefers room to brake after the strike).
_LIMIT_PENALTY = 0.02
#: Contacts whose ratio is at most this fraction of the allowed one count as fast enough
#: with room to spare; among them the one nearest the start (in joint travel time) is chosen,
#: since the contact with the very smallest ratio can lie far from the start.
_HEADROOM = 0.9


@dataclass(frozen=True)
class ContactChoice:
    """The configuration at which a strike meets the ball, and how fast it can strike.

    Attributes:
        q: Contact configuration [rad or m], shape (n,).
        qd: Joint velocity at contact that gives the strike motion at the requested speed with
            the smallest largest velocity-limit ratio [rad/s or m/s], shape (n,); zero for a
            paddle arriving at rest.
        ratio: Largest ``|qd_i| / qd_max_i`` the strike needs at the requested speed [-]: for
            a pool shot the largest over the contact, entry and exit configurations (so at
            least that of ``qd``), for a paddle shot at contact. At most 1 - margin.
        max_speed: Fastest strike this choice allows within the velocity limits [m/s]
            (1 / the ratio at unit speed; inf if no joint needs to move).
        binding_joint: The joint with the largest ratio, the first to reach its limit as the
            speed rises (at the optimum several joints usually bind together); empty if no
            joint velocity gives the motion (a singular paddle contact at rest).
        candidates: Contact configurations evaluated (IK solutions and pattern-search trials).
        q_entry: Pool: configuration at the line's entry point near ``q`` [rad], shape (n,);
            None for a paddle strike.
        q_exit: Pool: configuration at the line's exit point near ``q`` [rad], shape (n,);
            None for a paddle strike.
    """

    q: FloatArray
    qd: FloatArray
    ratio: float
    max_speed: float
    binding_joint: str
    candidates: int
    q_entry: FloatArray | None = None
    q_exit: FloatArray | None = None


# ----------------------------------------------------------------------------------- LP


class _MinMaxRatio:
    r"""Smallest :math:`\max_i |y_i|` over the solutions of :math:`M y = b`.

    With :math:`y = y_0 + N z` (:math:`y_0` the minimum-norm solution, N an orthonormal basis
    of the null space of M) the equalities hold by construction, and HiGHS solves the LP in
    (z, s): minimise s subject to :math:`-s \le y_0 + N z \le s`. The CasADi solvers are built
    once per problem size and kept by this object, which lives for one call of the public
    functions (nothing is shared between threads).
    """

    def __init__(self) -> None:
        self._solvers: dict[tuple[int, int], ca.Function] = {}

    def _solver(self, n: int, k: int) -> ca.Function:
        if (n, k) not in self._solvers:
            highs = {
                "output_flag": False,
                "presolve": "off",  # a 3-variable LP: presolve only costs time
                "primal_feasibility_tolerance": _LP_TOLERANCE,
                "dual_feasibility_tolerance": _LP_TOLERANCE,
            }
            self._solvers[n, k] = ca.conic(
                "min_max_ratio",
                "highs",
                {"a": ca.Sparsity.dense(2 * n, k + 1), "h": ca.Sparsity(k + 1, k + 1)},
                {"highs": highs, "error_on_fail": False},
            )
        return self._solvers[n, k]

    def __call__(self, M: FloatArray, b: FloatArray) -> FloatArray | None:
        """The minimiser y, shape (n,), or None when ``M y = b`` has no solution."""
        n = M.shape[1]
        U, S, Vt = np.linalg.svd(M)
        rank = int(np.sum(_RANK_TOLERANCE * S[0] < S)) if S.size and S[0] > 0.0 else 0
        y0 = Vt[:rank].T @ ((U[:, :rank].T @ b) / S[:rank])
        scale = float(np.linalg.norm(b)) + (float(S[0] * np.linalg.norm(y0)) if rank else 0.0)
        if float(np.linalg.norm(M @ y0 - b)) > _RESIDUAL_TOLERANCE * scale:
            return None
        null = Vt[rank:].T  # (n, k)
        k = null.shape[1]
        if k == 0 or not np.any(y0):
            return y0
        ones = np.ones((n, 1))
        solver = self._solver(n, k)
        out = solver(
            g=np.r_[np.zeros(k), 1.0],
            a=np.block([[null, -ones], [-null, -ones]]),
            lba=-np.inf,
            uba=np.r_[-y0, y0],
            lbx=np.r_[np.full(k, -np.inf), 0.0],
            ubx=np.inf,
        )
        stats = solver.stats()
        if not stats.get("success", False):
            raise SolverError("highs", str(stats.get("return_status", "unknown")))
        return y0 + null @ np.asarray(out["x"]).ravel()[:k]


def _across(direction: FloatArray) -> FloatArray:
    """Two unit vectors completing ``direction`` to an orthonormal basis, shape (2, 3)."""
    helper = np.eye(3)[int(np.argmin(np.abs(direction)))]
    first = np.cross(direction, helper)
    first /= np.linalg.norm(first)
    return np.array([first, np.cross(direction, first)])


def _task_rows(robot: Robot, q: FloatArray, offset: float, across: FloatArray | None) -> FloatArray:
    """Rows A with ``A qd`` = [point velocity; angular velocity along ``across``].

    Shape (3, n), or (5, n) with the two ``across`` rows.
    """
    jac = robot.jacobian(q)
    rows = jac[:3]
    if offset != 0.0:
        lever = offset * robot.tool_pose(q)[:3, 2]
        rows = rows - pin.skew(lever) @ jac[3:]  # v + w x lever
    if across is not None:
        rows = np.vstack([rows, across @ jac[3:]])
    return rows


def _unit_ratio(
    lp: _MinMaxRatio,
    robot: Robot,
    q: FloatArray,
    direction: FloatArray,
    velocity_limit: FloatArray,
    offset: float,
    across: FloatArray | None,
) -> tuple[float, FloatArray]:
    """r_1(q) [s/m] and an optimal joint velocity at unit speed (inf and NaNs if impossible)."""
    rows = _task_rows(robot, q, offset, across)
    target = np.zeros(rows.shape[0])
    target[:3] = direction
    y = lp(rows * velocity_limit, target)
    if y is None:
        return math.inf, np.full(q.size, np.nan)
    return float(np.abs(y).max()), y * velocity_limit


def _binding(qd: FloatArray, velocity_limit: FloatArray) -> list[int]:
    """Joints whose ratio is within 1e-9 (relative) of the largest, in joint order.

    Empty when a velocity is not finite (the motion is impossible).
    """
    ratios = np.abs(qd) / velocity_limit
    if not np.all(np.isfinite(ratios)):
        return []
    top = float(ratios.max(initial=0.0))
    return [int(i) for i in np.flatnonzero(ratios >= top * (1.0 - 1e-9))]


def twist_ratio(
    robot: Robot,
    q: ArrayLike,
    direction: ArrayLike,
    speed: float,
    *,
    offset: float = 0.0,
    align_axis: bool = True,
    limits: JointLimits | None = None,
) -> tuple[float, FloatArray, int]:
    r"""Smallest velocity-limit ratio of a joint velocity giving a strike motion at q.

    The motion: the tool point (the tool origin moved ``offset`` along the tool z axis) moves
    at ``speed`` along the unit ``direction`` d; with ``align_axis`` the tool turns about d
    only (the angular velocity across d is zero, the roll rate about d free), which keeps a
    tool z axis lying along d on it. With :math:`e_1, e_2` completing d to an orthonormal
    basis and :math:`J_p = J_v - [\ell]_\times J_\omega` the point's rows (lever
    :math:`\ell` = offset times the tool z axis), it solves the LP

    .. math::

        \min_{\dot q} \max_i \frac{|\dot q_i|}{\dot q_{\max,i}} \quad \text{s.t.} \quad
        J_p \dot q = v\, d, \quad e_1^T J_\omega \dot q = e_2^T J_\omega \dot q = 0

    exactly (HiGHS through CasADi). The ratio is linear in the speed.

    Args:
        robot: The robot.
        q: Configuration [rad or m], shape (n,).
        direction: Direction of the point's velocity, shape (3,) (normalised here).
        speed: Point speed [m/s], >= 0.
        offset: Distance of the point from the tool origin along the tool z axis [m].
        align_axis: Forbid turning across ``direction`` (pool cue); False leaves the angular
            velocity free (paddle).
        limits: Limits whose velocity limits [rad/s or m/s] are used; the robot's when None.

    Returns:
        ``(ratio, qd, joint)``: the smallest ``max_i |qd_i| / qd_max_i`` [-]; a joint velocity
        attaining it [rad/s or m/s], shape (n,); the index of the binding joint (the first of
        those whose ratio equals the largest). ``(0.0, zeros, 0)`` at speed 0, and
        ``(inf, NaNs, -1)`` at a singular configuration that cannot give the motion at all.

    Raises:
        InvalidInputError: Malformed robot, q, direction, speed, offset or limits.
        SolverError: HiGHS fails (not expected: the LP is always feasible and bounded).
    """
    if not isinstance(robot, Robot):
        raise InvalidInputError(
            f"robot must be a robots.Robot, got {type(robot).__name__}", name="robot"
        )
    config = as_vector(q, "q", robot.dof)
    unit = unit_vector(direction, "direction")
    speed_value = float(as_array(speed, "speed", ()))
    if speed_value < 0.0:
        raise InvalidInputError(f"speed must be >= 0 m/s, got {speed_value:.6g} m/s", name="speed")
    offset_value = float(as_array(offset, "offset", ()))
    used = robot.limits if limits is None else limits
    if not isinstance(used, JointLimits) or used.names != robot.joint_names:
        raise InvalidInputError(
            f"limits must be a robots.JointLimits for the joints {robot.joint_names}",
            name="limits",
        )
    if speed_value == 0.0:
        return 0.0, np.zeros(robot.dof), 0
    velocity_limit = np.asarray(used.velocity, dtype=float)
    across = _across(unit) if align_axis else None
    r1, qd1 = _unit_ratio(_MinMaxRatio(), robot, config, unit, velocity_limit, offset_value, across)
    qd = speed_value * qd1
    binding = _binding(qd, velocity_limit)
    return speed_value * r1, qd, binding[0] if binding else -1


# ------------------------------------------------------------------------- contact choice


@dataclass(frozen=True)
class _Window:
    """A pool candidate: contact, entry and exit configurations and their unit-speed LPs."""

    q: FloatArray
    q_entry: FloatArray
    q_exit: FloatArray
    r1: float  # largest unit-speed ratio of the three [s/m]
    qd1: FloatArray  # optimal contact joint velocity at unit speed [rad/m]
    binding: tuple[int, ...]  # binding joints where the largest ratio occurs
    binding_qd1: FloatArray  # the joint velocity at unit speed there [rad/m]
    score: float  # r1 raised by the joint-limit penalty, for ranking


def _closeness(limits: JointLimits, q: FloatArray) -> float:
    """How deep the joint nearest a position limit is in the zone near it: 0 outside, 1 on it."""
    span = limits.upper - limits.lower
    clearance = np.minimum(q - limits.lower, limits.upper - q)
    return float(np.max(np.clip(1.0 - clearance / (_LIMIT_ZONE * span), 0.0, 1.0)))


class _PoolSearch:
    """Evaluates and improves pool contact configurations for one problem (one call)."""

    def __init__(self, problem: PoolStrike) -> None:
        self.problem = problem
        self.robot = problem.robot
        self.limits = problem.limits
        self.direction = np.asarray(problem.direction, dtype=float)
        self.across = _across(self.direction)
        self.velocity_limit = np.asarray(self.limits.velocity, dtype=float)
        self.lp = _MinMaxRatio()
        self.evaluated = 0

    def _near(self, point: FloatArray, q: FloatArray) -> FloatArray | None:
        """The IK solution with the cue tip at ``point`` on the line reached from q, if any."""
        try:
            found = solve_ik(self.robot, point, axis=self.direction, q_near=q, restarts=0).q
        except UnreachableError:
            return None
        return found if self.limits.contains(found) else None

    def _ratio(self, q: FloatArray) -> tuple[float, FloatArray]:
        return _unit_ratio(
            self.lp, self.robot, q, self.direction, self.velocity_limit, 0.0, self.across
        )

    def window(self, q: FloatArray, bound: float = math.inf) -> _Window | None:
        """Evaluate contact configuration q (with the cue on the line at the contact point).

        Returns None when the line's entry or exit cannot be reached near q, or when the
        window's largest ratio cannot be below a finite ``bound`` (checked as each ratio
        comes in, so a poor trial is dropped after one LP).
        """
        self.evaluated += 1
        if not self.limits.contains(q):
            return None
        prune = math.isfinite(bound)  # with no bound, a singular candidate is kept (r1 = inf)
        r1, qd1 = self._ratio(q)
        if prune and r1 >= bound:
            return None
        configs = [q]
        worst = (r1, qd1)
        for point in (self.problem.entry_point, self.problem.exit_point):
            end = self._near(point, q)
            if end is None:
                return None
            ratio, qd = self._ratio(end)
            if prune and ratio >= bound:
                return None
            configs.append(end)
            if ratio > worst[0]:
                worst = (ratio, qd)
        closeness = max(_closeness(self.limits, c) for c in configs)
        return _Window(
            q=q,
            q_entry=configs[1],
            q_exit=configs[2],
            r1=worst[0],
            qd1=qd1,
            binding=tuple(_binding(worst[1], self.velocity_limit)),
            binding_qd1=worst[1],
            score=worst[0] * (1.0 + _LIMIT_PENALTY * closeness),
        )

    def improve(self, start: _Window, trials: int) -> _Window:
        """Pattern search along the self-motion: lower the score by moving the contact q.

        The self-motion keeps the cue tip on the contact point with the cue on the line; to
        first order it is the null space of the 5 task rows (the same rows as the LP's).
        Steps of size h along the two null-space directions and their opposites are tried,
        the last successful direction first; a success moves there and doubles h, a failure
        halves it. Each trial is projected back with IK.
        """
        current, step, last = start, _FIRST_STEP, None
        while step >= _SMALLEST_STEP and trials > 0:
            rows = _task_rows(self.robot, current.q, 0.0, self.across)
            null = np.linalg.svd(rows)[2][rows.shape[0] :]
            moves = [*null, *(-null)]
            if last is not None:
                moves.sort(key=lambda move: -float(move @ last))
            moved = False
            for move in moves:
                if trials == 0:
                    break
                trials -= 1
                guess = self.limits.clip(current.q + step * move)
                q = self._near(self.problem.contact_point, guess)
                trial = None if q is None else self.window(q, bound=current.score)
                if trial is not None and trial.score < current.score:
                    last = (trial.q - current.q) / np.linalg.norm(trial.q - current.q)
                    current, moved = trial, True
                    break
            step = min(2.0 * step, _LARGEST_STEP) if moved else 0.5 * step
        return current


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
    (raised by at most 2 % near a joint position limit, a tie-break); the best
    three and the one nearest the start are improved by a short pattern search along the
    self-motion. Among the configurations that need at most 90 % of the allowed ratio, the
    one the arm reaches soonest from the start (largest joint travel over velocity limit)
    is chosen; when none has that much room, the one with the smallest ratio. Paddle strike: the
    closed-form ``problem.q_contact``, the ball point moving along the normal and the normal held
    still (the joint velocity of :func:`planners.cartesian.paddle_contact_velocity`; letting
    the paddle turn at contact would lower paddle4's ratio by a few percent at the cost of
    spinning it, see :func:`twist_ratio` with ``align_axis=False``).

    Args:
        problem: A :class:`problems.PoolStrike` or :class:`problems.PaddleStrike`.
        candidates: IK solutions to collect for a pool strike (>= 1); more search wider and
            take longer (about 5 ms each on Sawyer, where the whole choice takes about 0.2 s
            with the defaults).
        seed: Seed of the IK's random restarts (the result is reproducible).
        margin: Fraction of the velocity limits kept in reserve, in [0, 1): the strike is
            accepted when its ratio is at most 1 - margin.

    Returns:
        The chosen configuration, its joint velocity at contact and its ratio.

    Raises:
        InfeasibleError: Even the best configuration needs a joint faster than its velocity
            limit (``limit="velocity"``, the binding ``joint``, ``required`` its speed and
            ``allowed`` its limit times 1 - margin [rad/s or m/s]); the exception also carries
            ``max_speed``, the fastest strike speed that would pass [m/s]. Also raised (with
            ``limit="position"``) when no pool candidate keeps the line's entry and exit
            reachable within the position limits.
        InvalidInputError: Another problem type, or bad ``candidates``, ``seed`` or ``margin``.
        SolverError: HiGHS fails on an LP (not expected).
    """
    return contact_choices(problem, 1, candidates=candidates, seed=seed, margin=margin)[0]


def contact_choices(
    problem: PoolStrike | PaddleStrike,
    count: int = 3,
    *,
    candidates: int = 16,
    seed: int = 0,
    margin: float = 0.0,
) -> tuple[ContactChoice, ...]:
    """The best ``count`` distinct contact configurations, in :func:`choose_contact`'s order.

    The first is :func:`choose_contact`'s; the others are other IK branches (at least 0.1 rad
    apart on some joint), for a planner to fall back on when it cannot solve from the first.
    A paddle strike has one (closed-form) configuration.

    Raises:
        InfeasibleError, InvalidInputError, SolverError: As :func:`choose_contact`.
    """
    wanted = as_count(count, "count", 1)
    searched = as_count(candidates, "candidates", 1)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InvalidInputError(f"seed must be an integer >= 0, got {seed!r}", name="seed")
    reserve = float(as_array(margin, "margin", ()))
    if not 0.0 <= reserve < 1.0:
        raise InvalidInputError(f"margin must be in [0, 1), got {reserve:.6g}", name="margin")
    if isinstance(problem, PoolStrike):
        return tuple(_rank_pool(problem, searched, int(seed), reserve, wanted))
    if isinstance(problem, PaddleStrike):
        return (_choose_paddle(problem, reserve),)
    raise InvalidInputError(
        f"choose_contact takes a problems.PoolStrike or a problems.PaddleStrike, got "
        f"{type(problem).__name__}",
        name="problem",
    )


def _reach(problem: PoolStrike, q: FloatArray) -> float:
    """Time the slowest joint needs from the start to q at its velocity limit [s]."""
    start = np.asarray(problem.q_start, dtype=float)
    return float(np.max(np.abs(q - start) / np.asarray(problem.limits.velocity, dtype=float)))


def _rank_pool(
    problem: PoolStrike, candidates: int, seed: int, margin: float, count: int
) -> list[ContactChoice]:
    """Up to ``count`` distinct contact configurations, best first (see choose_contact)."""
    search = _PoolSearch(problem)
    robot = problem.robot
    ik = solve_ik(
        robot,
        problem.contact_point,
        axis=problem.direction,
        q_near=problem.q_start,
        min_solutions=candidates,
        restarts=_RESTARTS_PER_CANDIDATE * candidates,
        seed=seed,
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
    found.sort(key=lambda w: w.score)
    seeds: list[_Window] = []
    for window in found:  # the best few, at least _SPREAD apart (not one optimum thrice)
        if len(seeds) < _REFINED and all(
            np.abs(window.q - other.q).max() > _SPREAD for other in seeds
        ):
            seeds.append(window)
    nearest = min(found, key=lambda w: _reach(problem, w.q))
    if all(nearest is not other for other in seeds):
        seeds.append(nearest)
    windows = found + [search.improve(w, _TRIALS_PER_REFINEMENT) for w in seeds]
    speed = float(problem.speed)
    fastest = min(windows, key=lambda w: w.r1)
    if speed * fastest.r1 > 1.0 - margin:
        raise _too_fast(
            problem.limits,
            speed,
            fastest.r1,
            fastest.binding,
            fastest.binding_qd1,
            margin,
            f"any contact configuration found ({search.evaluated} tried)",
        )
    room = _HEADROOM * (1.0 - margin)
    roomy = [w for w in windows if speed * w.r1 <= room]
    tight = [w for w in windows if speed * w.r1 > room]
    # Fast enough with room to spare: the one the arm reaches soonest first; then the rest
    # by whether they are fast enough and their ratio.
    ranked = sorted(roomy, key=lambda w: (_reach(problem, w.q), w.score)) + sorted(
        tight, key=lambda w: (speed * w.r1 > 1.0 - margin, w.score)
    )
    distinct: list[_Window] = []
    for window in ranked:  # alternatives must be other branches, not the same one refined
        if speed * window.r1 <= 1.0 - margin and all(
            np.abs(window.q - other.q).max() > _SPREAD for other in distinct
        ):
            distinct.append(window)
        if len(distinct) == count:
            break
    return [
        ContactChoice(
            q=w.q,
            qd=speed * w.qd1,
            ratio=speed * w.r1,
            max_speed=1.0 / w.r1 if w.r1 > 0.0 else math.inf,
            binding_joint=problem.limits.names[w.binding[0]],
            candidates=search.evaluated,
            q_entry=w.q_entry,
            q_exit=w.q_exit,
        )
        for w in distinct
    ]


def _choose_paddle(problem: PaddleStrike, margin: float) -> ContactChoice:
    limits = problem.limits
    velocity_limit = np.asarray(limits.velocity, dtype=float)
    q = np.asarray(problem.q_contact, dtype=float)
    normal = np.asarray(problem.normal, dtype=float)
    lp = _MinMaxRatio()
    # Hold the normal still at contact (as planners.cartesian.paddle_contact_velocity does);
    # paddle4 always can, but should a robot not, let the paddle turn.
    r1, qd1 = _unit_ratio(
        lp, problem.robot, q, normal, velocity_limit, BALL_OFFSET, _across(normal)
    )
    if math.isinf(r1):
        r1, qd1 = _unit_ratio(lp, problem.robot, q, normal, velocity_limit, BALL_OFFSET, None)
    binding = _binding(qd1, velocity_limit)
    speed = float(problem.speed)
    if speed > 0.0 and speed * r1 > 1.0 - margin:
        raise _too_fast(limits, speed, r1, tuple(binding), qd1, margin, "the contact configuration")
    return ContactChoice(
        q=q,
        qd=speed * qd1 if speed > 0.0 else np.zeros(q.size),
        ratio=speed * r1 if speed > 0.0 else 0.0,
        max_speed=1.0 / r1 if r1 > 0.0 else math.inf,
        binding_joint=limits.names[binding[0]] if binding else "",
        candidates=1,
    )


def _too_fast(
    limits: JointLimits,
    speed: float,
    r1: float,
    binding: tuple[int, ...] | list[int],
    qd1: FloatArray,
    margin: float,
    which: str,
) -> InfeasibleError:
    """The error for a strike faster than the velocity limits allow anywhere searched."""
    fastest = (1.0 - margin) / r1 if r1 > 0.0 else math.inf
    if not binding:  # singular everywhere: no joint velocity gives the motion
        error = InfeasibleError(
            f"strike speed {speed:.3g} m/s: {which} cannot move the tool along the strike "
            f"direction at all (singular)",
            limit="velocity",
        )
        error.max_speed = 0.0  # type: ignore[attr-defined]
        return error
    j = binding[0]
    unit = limits.unit("velocity", j)
    required = abs(float(qd1[j])) * speed
    limit = float(limits.velocity[j])
    allowed = (1.0 - margin) * limit
    others = [limits.names[i] for i in binding[1:]]
    also = (
        f"; {', '.join(others)} {'is' if len(others) == 1 else 'are'} as far over" if others else ""
    )
    kept = f" (with margin {margin:.3g}: {allowed:.4g} {unit})" if margin > 0.0 else ""
    error = InfeasibleError(
        f"strike speed {speed:.3g} m/s needs {limits.names[j]} at {required:.3g} {unit}, limit "
        f"{limit:.4g} {unit}{kept}{also}; the fastest strike {which} allows is "
        f"{fastest:.3g} m/s",
        limit="velocity",
        joint=limits.names[j],
        required=required,
        allowed=allowed,
    )
    error.max_speed = fastest  # type: ignore[attr-defined]
    return error
