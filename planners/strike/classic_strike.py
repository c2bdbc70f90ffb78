r"""Pool strikes with the classic profiles: a cubic, quintic or LSPB approach, the line, a stop.

The strike window is the same as :class:`planners.TimeOptimalStrike`'s
(:func:`planners.strike.time_optimal_strike.strike_line`: the cue tip at the commanded speed
along the direction,
through the contact point, cue axis on the line, turned into joints by IK sample by sample),
from the problem's contact configuration or, with ``contact="choose"``, from the one
:class:`planners.OptimalControl` chooses
(:func:`planners.strike.time_optimal_strike.contact_configuration`).
Its first state (q, qd, qdd) is the entry state, its last the exit state. The three phases are
``approach``, ``strike`` and ``stop``.

Cubic
    The approach is one cubic Hermite per joint from rest at ``q_start`` to the entry
    (q, qd); its acceleration jumps at the entry (the cubic cannot match the line's). The
    stop is a cubic from the exit (q, qd) to rest at the free end position
    ``q_exit + qd_exit T / 2``, which makes it a constant deceleration (its cubic term
    vanishes).
Quintic
    The approach also matches the entry acceleration (and starts at zero acceleration); the
    stop matches the exit (q, qd, qdd) and ends at rest with zero acceleration at
    ``q_exit + qd_exit T / 2 + qdd_exit T^2 / 12``, which makes its quintic term vanish
    (from zero exit acceleration the velocity falls as ``qd_exit (1 - 3 s^2 + 2 s^3)``).
LSPB
    A trapezoidal velocity profile cannot enter the line at speed, so this profile plays the
    pull-back shot's role (:class:`planners.PullBackStrike`): a rest-to-rest LSPB from
    ``q_start`` to the entry configuration, then the line starting at full speed, then holding
    still. The velocity jumps at the entry and at the exit; the checker reports the unbounded
    accelerations this needs.

With moving ends, the shape of a polynomial changes with its duration T, so its peaks do not
scale as :math:`1/T^k`. The shortest T is bracketed by doubling and then bisected, judging each
T by the exact peaks of velocity and acceleration (and jerk for the quintic) from
:func:`planners.profiles.time_scaling.polynomial_peaks`:

.. math:: T^\star = \min \{ T : \max_{t \in [0, T]} |q_j^{(k)}(t)| \le \bar q_j^{(k)}
          \ \forall j, k \}

The position limits are checked at T*; a profile that leaves them raises.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InfeasibleError, InvalidInputError
from optraj.planners.base import stamp
from optraj.planners.profiles.cartesian import MAX_IK_SAMPLES
from optraj.planners.profiles.lspb import LSPB
from optraj.planners.profiles.time_scaling import (
    cubic_coefficients,
    polynomial_peaks,
    quintic_coefficients,
    rate_limit_error,
    worst_rate_limit,
)
from optraj.planners.strike.time_optimal_strike import (
    check_contact,
    check_line,
    contact_configuration,
    strike_line,
)
from optraj.planners.trajectory import Trajectory, TrajectorySample
from optraj.problems import PoolStrike
from optraj.problems.point_to_point import is_still
from optraj.robots import JointLimits
from optraj.validation import as_choice, as_count

__all__ = ["PROFILES", "ClassicStrike", "shortest_duration"]

FloatArray = NDArray[np.float64]

#: The approach profiles :class:`ClassicStrike` knows.
PROFILES: tuple[str, ...] = ("cubic", "quintic", "lspb")
#: How long the LSPB profile holds still after the line [s] (as :class:`planners.PullBackStrike`).
HOLD_TIME = 0.2
#: Bounds of the duration search [s] and the points of its geometric grid (5 % apart).
_SHORTEST, _LONGEST, _GRID = 1e-2, 1e2, 190
#: Samples per polynomial when the grid is scanned.
_SCAN_SAMPLES = 48
#: Relative width at which the bisection stops [-].
_BISECTION_TOLERANCE = 1e-6
_BISECTION_STEPS = 100
#: Relative slack on the limits (round-off only) [-].
_SLACK = 1e-9
#: The limited quantities of each polynomial profile (a cubic's jerk is unbounded at its ends).
_LIMITED: dict[str, tuple[str, ...]] = {
    "cubic": ("velocity", "acceleration"),
    "quintic": ("velocity", "acceleration", "jerk"),
    "lspb": ("velocity", "acceleration"),
}


class ClassicStrike:
    """Plan a :class:`problems.PoolStrike` with a classic profile: approach, line, stop.

    Args:
        profile: ``"cubic"``, ``"quintic"`` or ``"lspb"`` (see the module docstring).
        samples: IK samples along the strike line.
        contact: ``"problem"`` (the problem's contact configuration) or ``"choose"``
            (:func:`planners.strike.time_optimal_strike.contact_configuration`).

    Raises:
        InvalidInputError: An unknown profile (lists the valid ones) or fewer than 4 samples.
        UnknownNameError: An unknown ``contact``.
    """

    def __init__(
        self,
        profile: Literal["cubic", "quintic", "lspb"] = "cubic",
        samples: int = 60,
        contact: Literal["problem", "choose"] = "problem",
    ) -> None:
        as_choice(profile, "profile", PROFILES)
        self.profile: Literal["cubic", "quintic", "lspb"] = profile
        self.samples = as_count(samples, "samples", 4, maximum=MAX_IK_SAMPLES)
        self.contact = check_contact(contact)

    def __repr__(self) -> str:
        return (
            f"ClassicStrike(profile={self.profile!r}, samples={self.samples}, "
            f"contact={self.contact!r})"
        )

    @property
    def name(self) -> str:
        """Name recorded in trajectory metadata, e.g. ``"cubic strike"``."""
        return f"{self.profile} strike"

    def plan(self, problem: PoolStrike) -> Trajectory:
        """Approach, strike, stop; phases ``approach``, ``strike`` and ``stop``.

        Args:
            problem: The pool strike.

        Returns:
            The trajectory; metadata holds ``planner``, ``solve_time`` [s], ``status``,
            ``profile``, ``contact_configuration`` (and with ``contact="choose"``
            ``contact_speed_ratio``) and, for LSPB, ``entry_velocity_jump`` and
            ``exit_velocity_jump`` (largest joint velocity step [rad/s or m/s]).

        Raises:
            InvalidInputError: The problem is not a PoolStrike.
            InfeasibleError: The strike line itself breaks a velocity or acceleration (quintic:
                or jerk) limit, no approach or stop of this profile keeps within the limits,
                or the stop runs past a position limit; names the limit, the joint, the
                required and the allowed value. With ``contact="choose"``, also when no
                contact configuration can make the strike.
            UnreachableError: A pose on the strike line cannot be reached.
        """
        if not isinstance(problem, PoolStrike):
            raise InvalidInputError(
                f"ClassicStrike plans a problems.PoolStrike, got {type(problem).__name__}",
                name="problem",
            )
        started = time.perf_counter()
        limits = problem.limits
        q_contact, contact = contact_configuration(problem, self.contact)
        line = strike_line(problem, self.samples, q_contact=q_contact)
        check_line(line, problem.robot, limits, _LIMITED[self.profile], float(problem.speed))
        entry = line.sample(0.0)
        exit_state = line.sample(line.duration)
        extra: dict[str, object] = {"profile": self.profile, **contact}
        if self.profile == "lspb":
            # already at the entry pose (the goal equals the start): no approach move
            still = is_still(problem.q_start, entry.q)
            approach = [] if still else [LSPB().move(problem.q_start, entry.q, limits)]
            brake = Trajectory.constant(exit_state.q, HOLD_TIME)
            extra["entry_velocity_jump"] = float(np.max(np.abs(entry.qd)))
            extra["exit_velocity_jump"] = float(np.max(np.abs(exit_state.qd)))
        else:
            approach = [self._approach(np.asarray(problem.q_start, dtype=float), entry, limits)]
            brake = self._stop(exit_state, limits)
        traj = Trajectory.sequence(
            [("approach", approach), ("strike", [line]), ("stop", [brake])],
            joint_names=limits.names,
        )
        return stamp(traj, self.name, started, **extra)

    # ---------------------------------------------------------------------- pieces

    def _approach(
        self, q_start: FloatArray, entry: TrajectorySample, limits: JointLimits
    ) -> Trajectory:
        """From rest at q_start to the entry state, as fast as the limits allow."""
        zeros = np.zeros(limits.n)
        if self.profile == "cubic":

            def coefficients(duration: float) -> FloatArray:
                return cubic_coefficients(q_start, entry.q, duration, zeros, entry.qd)

        else:

            def coefficients(duration: float) -> FloatArray:
                return quintic_coefficients(
                    q_start, entry.q, duration, zeros, entry.qd, zeros, entry.qdd
                )

        return self._piece(coefficients, limits, "approach")

    def _stop(self, exit_state: TrajectorySample, limits: JointLimits) -> Trajectory:
        """From the exit state to rest at the free end that makes the stop a smooth brake."""
        q, qd, qdd = exit_state.q, exit_state.qd, exit_state.qdd
        zeros = np.zeros(limits.n)
        if self.profile == "cubic":

            def coefficients(duration: float) -> FloatArray:
                q_end = q + 0.5 * duration * qd  # the cubic term vanishes
                return cubic_coefficients(q, q_end, duration, qd, zeros)

        else:

            def coefficients(duration: float) -> FloatArray:
                q_end = q + 0.5 * duration * qd + duration**2 / 12.0 * qdd  # no quintic term
                return quintic_coefficients(q, q_end, duration, qd, zeros, qdd, zeros)

        return self._piece(coefficients, limits, "stop")

    def _piece(
        self, coefficients: Callable[[float], FloatArray], limits: JointLimits, label: str
    ) -> Trajectory:
        """The shortest polynomial within the limits, checked against the position limits."""
        what = f"{self.profile} {label}"
        duration = shortest_duration(coefficients, limits, _LIMITED[self.profile], what)
        coeffs = coefficients(duration)
        peaks = polynomial_peaks(coeffs, duration)
        for values, bound, side in (
            (peaks["position_min"], limits.lower, "lower"),
            (peaks["position_max"], limits.upper, "upper"),
        ):
            excess = (bound - values) if side == "lower" else (values - bound)
            j = int(np.argmax(excess))
            if excess[j] > 1e-9:
                unit = limits.unit("position", j)
                raise InfeasibleError(
                    f"the shortest {what} ({duration:.4g} s) takes joint {limits.names[j]!r} to "
                    f"{values[j]:.4g} {unit}, beyond its {side} limit {bound[j]:.4g} {unit}",
                    limit="position",
                    joint=limits.names[j],
                    required=float(values[j]),
                    allowed=float(bound[j]),
                )
        return Trajectory([0.0, duration], coeffs[None], joint_names=limits.names)


def shortest_duration(
    coefficients: Callable[[float], FloatArray],
    limits: JointLimits,
    quantities: tuple[str, ...] = ("velocity", "acceleration"),
    what: str = "polynomial",
) -> float:
    """Shortest duration T whose exact peaks of ``quantities`` fit the limits.

    With fixed boundary velocities (and accelerations) the polynomial changes shape with T and
    its peaks need not fall as T grows: a prescribed end acceleration, for one, adds a velocity
    that grows like T. So the durations on a geometric grid (5 % apart, 10 ms to 100 s) are
    first judged by sampled peaks (cheap, never too strict); from the shortest one that fits,
    in order, the first whose exact peaks fit is bisected against its grid neighbour below to
    a relative width of 1e-6. The returned T is the upper end of the bracket: it keeps the
    limits. A feasible window narrower than the grid spacing can be missed.

    Args:
        coefficients: T [s] -> coefficients, shape (d + 1, n), row i multiplying t^i.
        limits: The joint limits.
        quantities: Limited derivatives among ``velocity``, ``acceleration``, ``jerk``.
        what: Name of the polynomial in error messages.

    Returns:
        T [s].

    Raises:
        InfeasibleError: No duration on the grid keeps the limits; names the binding limit
            and joint at the best duration, the needed and the allowed value.
    """
    grid = np.geomspace(_SHORTEST, _LONGEST, _GRID)
    stacked = np.stack([coefficients(float(duration)) for duration in grid])
    ratios = _sampled_ratios(stacked, grid, limits, quantities)
    low, high = 0.0, math.nan
    for k in np.flatnonzero(ratios <= 1.0 + _SLACK):
        if _worst(coefficients(float(grid[k])), float(grid[k]), limits, quantities) is None:
            low, high = (float(grid[k - 1]) if k > 0 else 0.0), float(grid[k])
            break
    if math.isnan(high):
        best = float(grid[int(np.argmin(ratios))])
        # Sampled peaks never exceed the exact ones, so the best grid point fails exactly too.
        failure = _worst(coefficients(best), best, limits, quantities)
        raise rate_limit_error(
            failure or ("velocity", 0, math.nan, math.nan),
            limits,
            f"no {what} between {_SHORTEST:g} s and {_LONGEST:g} s keeps the limits: the best, "
            f"{best:.4g} s long,",
        )
    for _ in range(_BISECTION_STEPS):
        if high - low <= _BISECTION_TOLERANCE * high:
            break
        middle = 0.5 * (low + high)
        if _worst(coefficients(middle), middle, limits, quantities) is None:
            high = middle
        else:
            low = middle
    return high


def _sampled_ratios(
    coefficients: FloatArray,
    durations: FloatArray,
    limits: JointLimits,
    quantities: tuple[str, ...],
) -> FloatArray:
    """Largest sampled |derivative| / limit of polynomials over their durations.

    Args:
        coefficients: Shape (m, d + 1, n), row i multiplying t^i.
        durations: Shape (m,) [s].
        limits: The joint limits.
        quantities: Among ``velocity``, ``acceleration``, ``jerk``.

    Returns:
        Shape (m,): the worst ratio over joints, quantities and the samples.
    """
    order = {"velocity": 1, "acceleration": 2, "jerk": 3}
    fractions = np.linspace(0.0, 1.0, _SCAN_SAMPLES)
    tau = durations[:, None] * fractions[None, :]  # (m, S)
    worst = np.zeros(durations.size)
    degree = coefficients.shape[1] - 1
    for quantity in quantities:
        k = order[quantity]
        if k > degree:
            continue
        # d^k/dt^k of sum c_i t^i = sum c_i i! / (i - k)! t^(i - k)
        powers = np.arange(k, degree + 1)
        factors = np.array([np.prod(np.arange(i - k + 1, i + 1)) for i in powers], dtype=float)
        terms = coefficients[:, k:, :] * factors[None, :, None]  # (m, d + 1 - k, n)
        basis = tau[:, :, None] ** (powers - k)[None, None, :]  # (m, S, d + 1 - k)
        values = np.einsum("msi,min->msn", basis, terms)
        bound = np.asarray(getattr(limits, quantity))
        worst = np.maximum(worst, np.max(np.abs(values) / bound, axis=(1, 2)))
    return worst


def _worst(
    coeffs: FloatArray, duration: float, limits: JointLimits, quantities: tuple[str, ...]
) -> tuple[str, int, float, float] | None:
    """The worst limit broken as (quantity, joint, needed, allowed), or None."""
    return worst_rate_limit(polynomial_peaks(coeffs, duration), limits, quantities, _SLACK)
