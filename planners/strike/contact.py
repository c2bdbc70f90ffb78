r"""Where a strike meets the ball, and whether any configuration is fast enough.

At contact the tool must move at ``speed`` along a direction: in a pool shot the cue tip moves
along the shot direction with its z axis (the cue axis) held on the line, free to turn about it
(roll); in a paddle shot the ball point moves along the paddle normal. At a configuration q the
joint velocities giving this motion form an affine set :math:`\{\dot q : A(q) \dot q = v\, b\}`,
and the smallest velocity-limit ratio over it is a small linear programme (LP),

.. math::

    r(q, v) = \min_{\dot q,\, s} s \quad \text{s.t.} \quad A \dot q = v\, b, \quad
    -s\, \dot q_{\max} \le \dot q \le s\, \dot q_{\max},

solved by :func:`twist_ratio` over the null-space coordinates of A, so the equalities hold to
rounding: exactly in NumPy by enumerating the LP's vertices when the null space has one or two
dimensions (a cue on its line, a paddle), which returns the least-norm optimal joint velocity,
and by HiGHS through CasADi otherwise. A joint that moves nothing the rows hold (the cue's roll
about its own axis) stays still. The ratio is linear in the speed,
:math:`r(q, v) = v\, r_1(q)`, so the fastest strike the configuration allows within the
velocity limits is :math:`1 / r_1(q)`.

:func:`choose_contact` picks the contact configuration with the smallest ratio. A pool cue can
meet the ball from a two-dimensional family of configurations (Sawyer has 7 joints for 5 task
rows): the candidates are distinct inverse-kinematics (IK) solutions, the best few improved by
a pattern search along the self-motion, each ranked by the largest ratio over the strike window
(the configurations at contact and at the line's entry and exit, since the whole line is run at
the strike speed). A paddle4 contact is fixed by its closed-form IK. When even the best ratio
exceeds 1 (or 1 - margin) the strike is rejected at once, with an
:class:`optraj.errors.InfeasibleError` naming the binding joint and the fastest strike found: a
pre-check that answers in well under a second instead of letting a planner spend its iteration
budget on a strike no configuration can make. :func:`contact_near` re-plans without the search:
it follows a previous contact configuration's IK branch to a strike that changed a little.
"""

from __future__ import annotations

import functools
import itertools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import casadi as ca
import numpy as np
import pinocchio as pin
from numpy.typing import ArrayLike, NDArray

from optraj.errors import CONTACT_CHOICE, InfeasibleError, InvalidInputError, SolverError
from optraj.problems import PaddleStrike, PoolStrike
from optraj.problems.common import MAX_TOOL_SPEED, normal_pair, unit_vector
from optraj.robots import JointLimits, Robot, solve_ik
from optraj.robots.ik import LocalIK
from optraj.robots.paddle_ik import BALL_OFFSET
from optraj.validation import as_count, as_number, as_vector

__all__ = [
    "BRANCH_SPREAD",
    "HEADROOM",
    "ContactChoice",
    "choose_contact",
    "contact_choices",
    "contact_near",
    "stopping_speeds",
    "twist_ratio",
]

FloatArray = NDArray[np.float64]

_WORLD_ALIGNED = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED

#: Most contact configurations one search may collect or evaluate (each is an IK solve).
MAX_CANDIDATES = 1000
#: Longest lever :func:`twist_ratio` takes from the tool origin [m]: several times the length
#: of any arm here, so more is a unit mistake (and near 1e150 m the lever's products overflow).
MAX_OFFSET = 10.0

#: Singular values below this fraction of the largest count as zero in the task rows.
_RANK_TOLERANCE = 1e-10
#: A joint whose column of the task rows is shorter than this fraction of the longest one
#: moves nothing the rows hold, up to rounding and the IK tolerance (a cue's roll about its own
#: axis): it is left still and the LP solved for the other joints. Otherwise the minimiser
#: would spin it at the limit ratio for a gain of about 1e-9 in the ratio.
_IDLE_COLUMN = 1e-7
#: Relative residual above which the task rows cannot give the motion (ratio = inf).
_RESIDUAL_TOLERANCE = 1e-9
#: HiGHS primal and dual feasibility tolerances (its defaults are 1e-7).
_LP_TOLERANCE = 1e-10
#: Random IK restarts allowed per candidate asked for: about 2/3 of Sawyer's random starts
#: converge with the cue on the line, so 3 per candidate rarely runs out.
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
#: A joint within this fraction of its range from a position limit is near it, and ...
_LIMIT_ZONE = 0.1
#: ... a candidate whose joint sits on a limit has its ratio raised by this fraction when
#: candidates are ranked (a tie-break that prefers room to brake after the strike).
_LIMIT_PENALTY = 0.02
#: Contacts whose ratio is at most this fraction of the allowed one count as fast enough
#: with room to spare; among them the one nearest the start (in joint travel time) is chosen,
#: since the contact with the very smallest ratio can lie far from the start.
HEADROOM = 0.9


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
    of the null space of M, k columns) the equalities hold by construction, and what is left is
    the LP in (z, s): minimise s subject to :math:`-s \le y_0 + N z \le s`. For k <= 2 it is
    solved exactly in NumPy by enumerating its vertices (:func:`_min_max_on_line`,
    :func:`_min_max_on_plane`; a Sawyer cue on its line has k = 1 once its idle roll joint is
    set aside, paddle4 k = 1, Sawyer elsewhere k = 2); otherwise HiGHS solves it through
    CasADi, with solvers built once per problem size and kept by this object, which lives for
    one call of the public functions (nothing is shared between threads). Among several
    minimisers the one of least norm is returned.
    """

    def __init__(self) -> None:
        self._solvers: dict[tuple[int, int], ca.Function] = {}

    def _solver(self, n: int, k: int) -> ca.Function:
        if (n, k) not in self._solvers:
            highs = {
                "output_flag": False,
                "presolve": "off",  # a small LP: presolve only costs time
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
        idle = _idle_columns(M)
        if not np.count_nonzero(idle):
            return self._solve(M, b)
        # Idle joints stay still (see _IDLE_COLUMN): solve for the others.
        moving = ~idle
        y = np.zeros(M.shape[1])
        if not np.count_nonzero(moving):  # nothing moves: only b = 0 has a solution
            return None if np.count_nonzero(b) else y
        inner = self._solve(M[:, moving], b)
        if inner is None:
            return None
        y[moving] = inner
        return y

    def _solve(self, M: FloatArray, b: FloatArray) -> FloatArray | None:
        U, S, Vt = np.linalg.svd(M)
        singular_values = S.tolist()
        largest = singular_values[0] if singular_values else 0.0
        rank = sum(value > _RANK_TOLERANCE * largest for value in singular_values)
        y0 = Vt[:rank].T @ ((U[:, :rank].T @ b) / S[:rank])
        if rank < M.shape[0]:  # with full row rank every b has a solution
            scale = math.sqrt(b @ b) + (largest * math.sqrt(y0 @ y0) if rank else 0.0)
            residual = M @ y0 - b
            if math.sqrt(residual @ residual) > _RESIDUAL_TOLERANCE * scale:
                return None
        null = Vt[rank:].T  # (n, k)
        k = null.shape[1]
        if k == 0 or not np.count_nonzero(y0):
            return y0
        if k == 1:
            return _min_max_on_line(y0, null[:, 0])
        if k == 2:
            return _min_max_on_plane(y0, null)
        return self.highs(y0, null)

    def highs(self, y0: FloatArray, null: FloatArray) -> FloatArray:
        r"""The minimiser of :math:`\max_i |y_0 + N z|_i` by HiGHS, shape (n,).

        Args:
            y0: Offset, shape (n,).
            null: N, shape (n, k), orthonormal columns, k >= 1.

        Raises:
            SolverError: HiGHS fails (not expected: the LP is always feasible and bounded).
        """
        n, k = null.shape
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


# The LP in (z, s) behind _MinMaxRatio: minimise s subject to -s <= y0 + N z <= s, N of full
# column rank k. Its feasible set contains no line, so the optimum s* is attained at a vertex,
# where k + 1 constraints are active, on distinct rows r_0..r_k with signs sigma_j: two on one
# row would force s = 0, hence y0 = 0, which the caller handles. The sign of r_0 can be taken
# +1 (the opposite signs give the same z with -s), and eliminating s leaves the k equations
# (e_r0 - sigma_j e_rj)^T (y0 + N z) = 0. Every such candidate is solved for in closed form
# and max_i |y0 + N z|_i evaluated there; the smallest value is s*, since the optimal vertex is
# a candidate and any z gives an upper bound. Candidates with singular equations are skipped.
#
# The minimisers can be more than one point (paddle4 moving its paddle straight up leaves
# three joints free within the ratio of the fourth). Of them the one nearest z = 0 is
# returned, which is the joint velocity of least norm (y0 is orthogonal to N).


@functools.cache
def _line_candidates(n: int) -> FloatArray:
    r"""Equations of the 2 C(n, 2) candidate vertices for k = 1, shape (c, n).

    Row i is :math:`e_{r_0} - \sigma e_{r_1}` of candidate i, which therefore solves
    :math:`(P_i d) z = -P_i y_0`.
    """
    pairs = list(itertools.combinations(range(n), 2))
    operator = np.zeros((2 * len(pairs), n))
    for i, (first, second) in enumerate(pairs):
        operator[2 * i : 2 * i + 2, first] = 1.0
        operator[2 * i, second] = -1.0
        operator[2 * i + 1, second] = 1.0
    operator.setflags(write=False)
    return operator


def _min_max_on_line(y0: FloatArray, direction: FloatArray) -> FloatArray:
    r"""The least-norm minimiser of :math:`\max_i |y_0 + z d|_i` over the scalar z.

    Args:
        y0: Offset, nonzero, orthogonal to d, shape (n,).
        direction: d, a unit vector, shape (n,).

    Returns:
        The minimiser :math:`y_0 + z d`, shape (n,).
    """
    operator = _line_candidates(y0.size)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        z = -(operator @ y0) / (operator @ direction)
        worst = np.abs(direction[:, None] * z + y0[:, None]).max(axis=0)
    worst[~(worst < math.inf)] = math.inf  # singular candidates (and their NaNs)
    optimal = z[worst <= float(worst.min()) * (1.0 + 1e-12)]
    # The minimisers form an interval whose ends are optimal vertices: take 0 if it is inside.
    return y0 + min(max(0.0, float(optimal.min())), float(optimal.max())) * direction


@functools.cache
def _plane_candidates(n: int) -> FloatArray:
    r"""Equations of the 4 C(n, 3) candidate vertices for k = 2, shape (2 c, n).

    Row j c + i is :math:`e_{r_0} - \sigma_j e_{r_j}` of candidate i, which therefore solves
    :math:`(P_i N) z = -P_i y_0` (P_i its two rows).
    """
    triples = list(itertools.combinations(range(n), 3))
    signs = list(itertools.product((1.0, -1.0), repeat=2))
    count = len(triples) * len(signs)
    operator = np.zeros((2, count, n))
    for i, (rows, sign) in enumerate(itertools.product(triples, signs)):
        for j in range(2):
            operator[j, i, rows[0]] += 1.0
            operator[j, i, rows[j + 1]] -= sign[j]
    flat = operator.reshape(2 * count, n)
    flat.setflags(write=False)
    return flat


def _min_max_on_plane(y0: FloatArray, null: FloatArray) -> FloatArray:
    r"""The least-norm minimiser of :math:`\max_i |y_0 + N z|_i` over z in the plane.

    The minimisers form a convex polygon (usually a single vertex). Its point nearest z = 0
    is z = 0, the foot of z = 0 on a line where one constraint is active at s*, or one of
    its vertices: of those feasible (within 1e-12 of s*, relative), the nearest is taken.

    Args:
        y0: Offset, nonzero, orthogonal to the columns of N, shape (n,).
        null: N, shape (n, 2), orthonormal columns.

    Returns:
        The minimiser :math:`y_0 + N z`, shape (n,).
    """
    operator = _plane_candidates(y0.size)
    rows = operator @ np.column_stack([null, y0])  # [P_ij N | P_ij y0] in row j c + i
    count = rows.shape[0] // 2
    (a, b, e0), (c, d, e1) = rows[:count].T, rows[count:].T
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        det = a * d - b * c
        z = np.column_stack([(b * e1 - d * e0) / det, (c * e0 - a * e1) / det])
        worst = np.abs(null @ z.T + y0[:, None]).max(axis=0)
    worst[~(worst < math.inf)] = math.inf  # singular candidates (and their NaNs)
    index = int(np.argmin(worst))
    best = float(worst[index])
    allowed = best * (1.0 + 1e-12)
    optimal = z[worst <= allowed]
    if np.abs(optimal - z[index]).max() <= 1e-12 * (1.0 + np.abs(z[index]).max()):
        return y0 + null @ z[index]  # a single minimiser (all its candidates coincide)
    length2 = (null * null).sum(axis=1)
    usable = length2 > 0.0
    feet = [
        ((level - y0[usable]) / length2[usable])[:, None] * null[usable] for level in (best, -best)
    ]
    points = np.concatenate([np.zeros((1, 2)), *feet, optimal])
    values = np.abs(null @ points.T + y0[:, None]).max(axis=0)
    norms = (points * points).sum(axis=1)
    norms[~(values <= allowed)] = math.inf
    return y0 + null @ points[int(np.argmin(norms))]


def _idle_columns(rows: FloatArray) -> NDArray[np.bool_]:
    """Columns shorter than :data:`_IDLE_COLUMN` times the longest (all if every one is 0)."""
    lengths = (rows * rows).sum(axis=0)
    return lengths <= _IDLE_COLUMN**2 * lengths.max()


def _task_rows(robot: Robot, q: FloatArray, offset: float, across: FloatArray | None) -> FloatArray:
    """Rows A with ``A qd`` = [point velocity; angular velocity along ``across``].

    Shape (3, n), or (5, n) with the two ``across`` rows.
    """
    jac = pin.computeFrameJacobian(robot.model, robot.data, q, robot.tool_frame_id, _WORLD_ALIGNED)
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

    exactly: in NumPy, returning the least-norm optimal joint velocity, when A has a null space
    of one or two dimensions; else by HiGHS through CasADi. The ratio is linear in the speed.

    Args:
        robot: The robot.
        q: Configuration [rad or m], shape (n,).
        direction: Direction of the point's velocity, shape (3,) (normalised here).
        speed: Point speed [m/s], in [0, MAX_TOOL_SPEED].
        offset: Distance of the point from the tool origin along the tool z axis [m], at most
            :data:`MAX_OFFSET` either way.
        align_axis: Forbid turning across ``direction`` (pool cue); False leaves the angular
            velocity free (paddle).
        limits: Limits whose velocity limits [rad/s or m/s] are used; the robot's when None.

    Returns:
        ``(ratio, qd, joint)``: the smallest ``max_i |qd_i| / qd_max_i`` [-]; a joint velocity
        attaining it [rad/s or m/s], shape (n,); the index of the binding joint (the first of
        those whose ratio equals the largest). ``(0.0, zeros, 0)`` at speed 0, and
        ``(inf, NaNs, -1)`` at a singular configuration that cannot give the motion at all.

    Raises:
        InvalidInputError: Malformed robot, q, direction, speed, offset or limits. q need not
            lie within the position limits: the ratio is a property of the kinematics.
        SolverError: HiGHS fails (not expected: the LP is always feasible and bounded).
    """
    if not isinstance(robot, Robot):
        raise InvalidInputError(
            f"robot must be a robots.Robot, got {type(robot).__name__}", name="robot"
        )
    config = as_vector(q, "q", robot.dof)
    unit = unit_vector(direction, "direction")
    speed_value = as_number(speed, "speed", "m/s", minimum=0.0, maximum=MAX_TOOL_SPEED)
    offset_value = as_number(offset, "offset", "m", minimum=-MAX_OFFSET, maximum=MAX_OFFSET)
    used = robot.limits if limits is None else limits
    if not isinstance(used, JointLimits) or used.names != robot.joint_names:
        raise InvalidInputError(
            f"limits must be a robots.JointLimits for the joints {robot.joint_names}",
            name="limits",
        )
    if speed_value == 0.0:
        return 0.0, np.zeros(robot.dof), 0
    velocity_limit = np.asarray(used.velocity, dtype=float)
    across = normal_pair(unit) if align_axis else None
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
    turn: float  # unit-speed ratio of the room the window leaves to turn at a limit [s/m]
    score: float  # max(r1, turn) raised by the joint-limit penalty, for ranking
    order: tuple[int, ...]  # places (0 contact, 1 entry, 2 exit): largest ratio, nearest limit


class _PoolSearch:
    """Evaluates and improves pool contact configurations for one problem (one call)."""

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
        self.lp = _MinMaxRatio()
        self.evaluated = 0
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

    def _near(self, ik: LocalIK, q: FloatArray) -> FloatArray | None:
        """The IK solution for one point of the line reached from q, if any (within limits)."""
        found = ik(q)
        return found if found is not None and self._inside(found) else None

    def _turn(self, entry: FloatArray, contact: FloatArray, exit_: FloatArray) -> float:
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
        """:func:`_unit_ratio` at q for the strike direction, the cue held on the line."""
        return _unit_ratio(
            self.lp, self.robot, q, self.direction, self.velocity_limit, 0.0, self.across
        )

    def window(
        self, q: FloatArray, bound: float = math.inf, order: tuple[int, ...] = (0, 1, 2)
    ) -> _Window | None:
        """Evaluate contact configuration q (with the cue on the line at the contact point).

        Returns None when the line's entry or exit cannot be reached near q, or when the
        window's score cannot be below a finite ``bound``: checked as each configuration
        comes in against the largest ratio so far raised by the limit penalty of the
        configurations so far (a lower bound of the score), so a poor trial is dropped after
        one LP. ``order`` lists the places (0 contact, 1 entry, 2 exit) in the order they are
        evaluated: where the window that set the bound had its largest ratio and the joint
        nearest a limit prunes a poor trial soonest. The pruning and the order change nothing
        else.
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
                end = self._near(self.to_entry if place == 1 else self.to_exit, q)
                if end is None:
                    return None
                configs[place] = end
                near_limit[place] = self._closeness(end)
            closeness = max(near_limit)
            ratios[place], velocities[place] = self._ratio(configs[place])
            if prune and max(ratios) * (1.0 + _LIMIT_PENALTY * closeness) >= bound:
                return None
        worst = max(range(3), key=ratios.__getitem__)  # the earliest place on a tie
        tightest = max(range(3), key=near_limit.__getitem__)
        turn = self._turn(configs[1], q, configs[2])
        return _Window(
            q=q,
            q_entry=configs[1],
            q_exit=configs[2],
            r1=ratios[worst],
            qd1=velocities[0],
            binding=tuple(_binding(velocities[worst], self.velocity_limit)),
            binding_qd1=velocities[worst],
            turn=turn,
            score=max(ratios[worst], turn) * (1.0 + _LIMIT_PENALTY * near_limit[tightest]),
            order=tuple(dict.fromkeys((worst, tightest, 0, 1, 2))),
        )

    def improve(self, start: _Window, trials: int) -> _Window:
        """Pattern search along the self-motion: lower the score by moving the contact q.

        The self-motion keeps the cue tip on the contact point with the cue on the line; to
        first order it is the null space of the 5 task rows (the same rows as the LP's).
        Joints whose column of the rows vanishes (:func:`_idle_columns`: Sawyer's last joint,
        which turns the cue about its own axis) are left out: moving them changes no ratio.
        Steps of size h along the remaining null-space directions and their opposites are
        tried, the last successful direction first; a success (a score lower by more than
        :data:`_TIE`, relative) moves there and doubles h, a failure halves it. Each trial is
        projected back with IK.
        """
        current, step, last = start, _FIRST_STEP, None
        while step >= _SMALLEST_STEP and trials > 0:
            rows = _task_rows(self.robot, current.q, 0.0, self.across)
            moving = ~_idle_columns(rows)
            null = np.zeros((max(int(moving.sum()) - rows.shape[0], 0), rows.shape[1]))
            null[:, moving] = np.linalg.svd(rows[:, moving])[2][rows.shape[0] :]
            moves = [*null, *(-null)]
            if last is not None:
                moves.sort(key=lambda move: -float(move @ last))
            moved = False
            bound = current.score * (1.0 - _TIE)
            for move in moves:
                if trials == 0:
                    break
                trials -= 1
                guess = np.clip(current.q + step * move, self.lower, self.upper)
                q = self._near(self.to_contact, guess)
                trial = None if q is None else self.window(q, bound, current.order)
                if trial is not None and trial.score < bound:
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
    still (the joint velocity of
    :func:`planners.profiles.cartesian.paddle_contact_velocity`; letting
    the paddle turn at contact would lower paddle4's ratio by a few percent at the cost of
    spinning it, see :func:`twist_ratio` with ``align_axis=False``).

    Args:
        problem: A :class:`problems.PoolStrike` or :class:`problems.PaddleStrike`.
        candidates: IK solutions to collect for a pool strike (1 to :data:`MAX_CANDIDATES`);
            more search wider and
            take longer (on Sawyer the whole choice takes about 45 ms with the defaults, median
            over the strike benchmark's shots).
        seed: Seed of the IK's random restarts (the result is reproducible).
        margin: Fraction of the velocity limits kept in reserve, in [0, 1): the strike is
            accepted when its ratio is at most 1 - margin.

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
    return contact_choices(problem, 1, candidates=candidates, seed=seed, margin=margin)[0]


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
    reserve = _margin(margin)
    if isinstance(problem, PoolStrike):
        tried = _configurations(exclude, "exclude", problem.limits.n)
        return tuple(_rank_pool(problem, searched, int(seed), reserve, wanted, tried))
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
    problem: PoolStrike,
    candidates: int,
    seed: int,
    margin: float,
    count: int,
    exclude: Sequence[FloatArray] = (),
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
    found.sort(key=lambda w: w.score)
    seeds: list[_Window] = []
    for window in found:  # the best few, at least BRANCH_SPREAD apart (not one optimum thrice)
        if len(seeds) < _REFINED and all(
            np.abs(window.q - other.q).max() > BRANCH_SPREAD for other in seeds
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
    room = HEADROOM * (1.0 - margin)
    # Room to spare: in the velocity ratio, and (estimated) to turn at the position limits.
    roomy = [w for w in windows if speed * max(w.r1, w.turn) <= room]
    tight = [w for w in windows if speed * max(w.r1, w.turn) > room]
    # Fast enough with room to spare: the one the arm reaches soonest first; then the rest
    # by whether they are fast enough and their ratio.
    ranked = sorted(roomy, key=lambda w: (_reach(problem, w.q), w.score)) + sorted(
        tight, key=lambda w: (speed * w.r1 > 1.0 - margin, w.score)
    )
    distinct: list[_Window] = []
    taken = list(exclude)
    for window in ranked:  # alternatives must be other branches, not the same one refined
        if speed * window.r1 <= 1.0 - margin and all(
            np.abs(window.q - other).max() > BRANCH_SPREAD for other in taken
        ):
            distinct.append(window)
            taken.append(window.q)
        if len(distinct) == count:
            break
    return [_pool_choice(problem, w, search.evaluated) for w in distinct]


def _pool_choice(problem: PoolStrike, window: _Window, evaluated: int) -> ContactChoice:
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


def _margin(value: float) -> float:
    """A share of the velocity limits kept in reserve, in [0, 1) (no bool, no string)."""
    reserve = as_number(value, "margin", minimum=0.0)
    if not reserve < 1.0:
        raise InvalidInputError(f"margin must be in [0, 1), got {reserve:.6g}", name="margin")
    return reserve


def contact_near(problem: PoolStrike, q: ArrayLike, *, margin: float = 0.0) -> ContactChoice | None:
    """The pool contact configuration on the IK branch of q, if it has room to spare.

    For re-planning a strike that changed a little (the ball moved, another heading or
    speed) from a previous contact configuration q: one local IK from q and one evaluation
    of its strike window (about 1 ms on Sawyer), instead of :func:`choose_contact`'s search
    (about 45 ms). It is returned only when :func:`choose_contact` would count it fast enough
    with room to spare: the speed times the larger of its velocity ratio and its
    room-to-turn estimate at most 90 % of ``1 - margin``. Otherwise None: run the search.

    Args:
        problem: The pool strike.
        q: A previous contact configuration [rad], shape (n,), within the position limits.
        margin: As :func:`choose_contact`.

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
    reserve = _margin(margin)
    search = _PoolSearch(problem)
    found = search._near(search.to_contact, seed)
    window = None if found is None else search.window(found)
    if window is None:
        return None
    if float(problem.speed) * max(window.r1, window.turn) > HEADROOM * (1.0 - reserve):
        return None
    return _pool_choice(problem, window, search.evaluated)


def _choose_paddle(problem: PaddleStrike, margin: float) -> ContactChoice:
    limits = problem.limits
    velocity_limit = np.asarray(limits.velocity, dtype=float)
    q = np.asarray(problem.q_contact, dtype=float)
    normal = np.asarray(problem.normal, dtype=float)
    lp = _MinMaxRatio()
    # Hold the normal still at contact (as
    # planners.profiles.cartesian.paddle_contact_velocity does);
    # paddle4 always can, but should a robot not, let the paddle turn.
    r1, qd1 = _unit_ratio(
        lp, problem.robot, q, normal, velocity_limit, BALL_OFFSET, normal_pair(normal)
    )
    if math.isinf(r1):
        r1, qd1 = _unit_ratio(lp, problem.robot, q, normal, velocity_limit, BALL_OFFSET, None)
    binding = _binding(qd1, velocity_limit)
    speed = float(problem.speed)
    if speed > 0.0 and speed * r1 > 1.0 - margin:
        raise _too_fast(limits, speed, r1, tuple(binding), qd1, margin, "the contact configuration")
    if speed > 0.0:
        _check_room(problem, lp, q, normal, speed, margin)
    return ContactChoice(
        q=q,
        qd=speed * qd1 if speed > 0.0 else np.zeros(q.size),
        ratio=speed * r1 if speed > 0.0 else 0.0,
        max_speed=1.0 / r1 if r1 > 0.0 else math.inf,
        binding_joint=limits.names[binding[0]] if binding else "",
        candidates=1,
    )


def stopping_speeds(limits: JointLimits, q: ArrayLike) -> FloatArray:
    r"""Fastest speed at which each joint can pass q on a motion from rest to rest.

    A joint that passes q at speed v within its position limits, with
    :math:`|\ddot q| \le a`, on a motion that starts and ends at rest, reached v from rest
    behind q and comes to rest ahead of it: it needs :math:`v^2 / (2 a)` of room on both sides
    of q, so

    .. math::

        v \le \sqrt{2 a \min(q - q_{lower}, q_{upper} - q)}.

    The jerk limit asks for more room still, so this is a bound, not a speed that can always
    be reached.

    Args:
        limits: The joint limits.
        q: Configuration within the position limits [rad or m], shape (n,).

    Returns:
        The speeds [rad/s or m/s], shape (n,).
    """
    here = as_vector(q, "q", limits.n)
    room = np.maximum(np.minimum(here - limits.lower, limits.upper - here), 0.0)
    return np.sqrt(2.0 * np.asarray(limits.acceleration, dtype=float) * room)


def _check_room(
    problem: PaddleStrike,
    lp: _MinMaxRatio,
    q: FloatArray,
    normal: FloatArray,
    speed: float,
    margin: float,
) -> None:
    """Refuse a paddle strike whose contact leaves a joint too little room to pass it.

    The contact configuration is the paddle's only one, and the contact fixes the ball
    point's velocity but not the paddle's turning: a joint velocity that gives the strike
    within the velocity limits and :func:`stopping_speeds` exists, or no motion from rest to
    rest makes the strike within the position and acceleration limits.
    """
    limits = problem.limits
    kept = (1.0 - margin) * np.asarray(limits.velocity, dtype=float)
    allowed = np.minimum(kept, stopping_speeds(limits, q))
    r1, qd1 = _unit_ratio(lp, problem.robot, q, normal, allowed, BALL_OFFSET, None)
    if speed * r1 <= 1.0:
        return
    binding = _binding(qd1, allowed) or list(range(limits.n))
    tight = [j for j in binding if allowed[j] < kept[j]]
    j = (tight or binding)[0]
    unit = limits.unit("position", j)
    room = float(min(q[j] - limits.lower[j], limits.upper[j] - q[j]))
    side = "lower" if q[j] - limits.lower[j] <= limits.upper[j] - q[j] else "upper"
    need = abs(float(qd1[j])) * speed if math.isfinite(r1) else math.inf
    acceleration = float(limits.acceleration[j])
    required = need * need / (2.0 * acceleration)
    fastest = 1.0 / r1 if r1 > 0.0 else 0.0
    raise InfeasibleError(
        f"paddle strike at {speed:.3g} m/s: at the contact configuration {limits.names[j]} is "
        f"{room:.4g} {unit} from its {side} limit; the joint velocity that gives the strike "
        f"with the least excess over the joints' rooms still moves it at {need:.3g} "
        f"{limits.unit('velocity', j)}, which needs {required:.4g} {unit} on both sides to "
        f"start from and come back to rest at {acceleration:.4g} "
        f"{limits.unit('acceleration', j)}; the fastest strike this contact allows is at "
        f"most {fastest:.3g} m/s (the jerk limit asks for more room still)",
        limit="position",
        joint=limits.names[j],
        required=required,
        allowed=room,
        max_speed=fastest,
        found_by=CONTACT_CHOICE,
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
        return InfeasibleError(
            f"strike speed {speed:.3g} m/s: {which} cannot move the tool along the strike "
            f"direction at all (singular)",
            limit="velocity",
            max_speed=0.0,
            found_by=CONTACT_CHOICE,
        )
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
    return InfeasibleError(
        f"strike speed {speed:.3g} m/s needs {limits.names[j]} at {required:.3g} {unit}, limit "
        f"{limit:.4g} {unit}{kept}{also}; the fastest strike {which} allows is "
        f"{fastest:.3g} m/s",
        limit="velocity",
        joint=limits.names[j],
        required=required,
        allowed=allowed,
        max_speed=fastest,
        found_by=CONTACT_CHOICE,
    )
