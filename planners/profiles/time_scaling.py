"""Cubic and quintic polynomial time scalings, joint by joint, all joints synchronised.

A cubic meets positions and velocities at both ends (the ECE486 paddle task uses the rest-to-rest
form s(t) = 3 (t/T)^2 - 2 (t/T)^3); a quintic also meets accelerations (Coursework 3 Q1a solves
its 6x6 system; here it is solved in closed form). Without a fixed duration, the shortest one
whose velocity, acceleration (and, for the quintic, jerk) peaks fit the limits is found. Rest
to rest, the peaks have closed forms; with moving ends they are exact at the roots of the
derivative polynomials (:mod:`optraj.planners.profiles.peaks`), sought only for the joints
whose cheap bounds (:mod:`optraj.planners.profiles.peak_bounds`) may reach a limit, so every
answer is the one exact peaks give.
"""

from __future__ import annotations

import time

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InfeasibleError, InvalidInputError, UnknownNameError
from optraj.planners.base import (
    JointProfile,
    refuse_prescribed_accelerations,
    rest_to_rest_inputs,
    stamp,
)
from optraj.planners.profiles.contact_velocity import paddle_contact_velocity
from optraj.planners.profiles.duration_search import bisect, shortest_in
from optraj.planners.profiles.lspb import LSPB
from optraj.planners.profiles.peak_bounds import position_range, rate_bounds
from optraj.planners.profiles.peaks import (
    REST_PEAKS,
    peak_of,
    polynomial_peaks,
    rest_to_rest_peaks,
)
from optraj.planners.profiles.polynomial_coefficients import (
    cubic_coefficients,
    quintic_coefficients,
)
from optraj.planners.trajectory import Phase, Trajectory
from optraj.problems import PaddleStrike, PointToPoint
from optraj.problems.point_to_point import STILL_TOLERANCE
from optraj.robots import JointLimits
from optraj.validation import MIN_DURATION, as_duration

__all__ = [
    "Cubic",
    "Quintic",
    "cubic_coefficients",
    "polynomial_peaks",
    "quintic_coefficients",
    "rate_limit_error",
    "worst_rate_limit",
]

FloatArray = NDArray[np.float64]

#: Relative slack on limits when searching for the shortest duration (round-off only).
_SLACK = 1e-9


def worst_rate_limit(
    peaks: dict[str, FloatArray],
    limits: JointLimits,
    quantities: tuple[str, ...],
    slack: float = _SLACK,
) -> tuple[str, int, float, float] | None:
    """The worst rate limit that peaks break, as (quantity, joint, needed, allowed), or None.

    Args:
        peaks: Peaks per quantity, as returned by :func:`polynomial_peaks`.
        limits: The limits.
        quantities: Quantities to compare, e.g. ``("velocity", "acceleration")``.
        slack: Relative excess tolerated (round-off).
    """
    worst: tuple[str, int, float, float] | None = None
    worst_ratio = 1.0 + slack
    for quantity in quantities:
        allowed = getattr(limits, quantity)
        ratio = peaks[quantity] / allowed
        j = int(ratio.argmax())
        if ratio[j] > worst_ratio:
            worst = (quantity, j, float(peaks[quantity][j]), float(allowed[j]))
            worst_ratio = float(ratio[j])
    return worst


def rate_limit_error(
    worst: tuple[str, int, float, float], limits: JointLimits, subject: str, context: str = ""
) -> InfeasibleError:
    """The error for a broken rate limit, :func:`worst_rate_limit`'s ``worst``.

    Reads "<subject> needs joint 'j' at <needed> <unit> (<quantity>), limit <allowed>
    <unit><context>".
    """
    quantity, j, needed, allowed = worst
    unit = limits.unit(quantity, j)
    return _limit_error(
        worst,
        limits,
        f"{subject} needs joint {limits.names[j]!r} at {needed:.4g} {unit} ({quantity}), "
        f"limit {allowed:.4g} {unit}{context}",
    )


def _limit_error(
    worst: tuple[str, int, float, float], limits: JointLimits, message: str
) -> InfeasibleError:
    """An InfeasibleError with ``message`` and the fields of ``worst``: quantity, joint, etc."""
    quantity, j, needed, allowed = worst
    return InfeasibleError(
        message, limit=quantity, joint=limits.names[j], required=needed, allowed=allowed
    )


#: Row of each rate in :func:`~optraj.planners.profiles.peak_bounds.rate_bounds`.
_ROWS = {"velocity": 0, "acceleration": 1, "jerk": 2}


def _at_rest(boundary: dict[str, FloatArray]) -> bool:
    """Whether every end velocity and acceleration of ``boundary`` is zero."""
    return not any(value.any() for value in boundary.values())


class _Polynomial(JointProfile):
    """Shared machinery of the cubic and quintic scalings."""

    degree = 3
    #: Which limits the profile keeps (a cubic's jerk is not bounded at its ends).
    limited: tuple[str, ...] = ("velocity", "acceleration")
    #: The rest-to-rest shape s(x) on [0, 1], ascending powers of x.
    shape: tuple[float, ...] = (0.0, 0.0, 3.0, -2.0)

    def __init__(self, duration: float | None = None) -> None:
        """Args: duration: Fixed duration [s] for every move, or None (shortest in limits)."""
        self.duration = None if duration is None else as_duration(duration, "duration")

    # -- to be provided by the subclasses
    def _coefficients(
        self, q0: FloatArray, q1: FloatArray, duration: float, boundary: dict[str, FloatArray]
    ) -> FloatArray:
        raise NotImplementedError

    def _rest_coefficients(self, q0: FloatArray, q1: FloatArray, duration: float) -> FloatArray:
        """Coefficients of q0 + (q1 - q0) s(t / T), shape (degree + 1, n).

        The rest-to-rest move: :meth:`_coefficients` with zero end rates, up to round-off.
        """
        shape = np.array(self.shape)
        scale = shape / duration ** np.arange(shape.size, dtype=float)
        coeffs = np.multiply.outer(scale, q1 - q0)
        coeffs[0] = q0
        return coeffs

    def _check(
        self,
        coeffs: FloatArray,
        duration: float,
        limits: JointLimits,
        slack: float = _SLACK,
        ends: tuple[FloatArray, FloatArray] | None = None,
        bounds: tuple[FloatArray, FloatArray] | None = None,
        rates: bool = True,
    ) -> tuple[str, int, float, float] | None:
        """The worst limit broken as (quantity, joint, needed, allowed), or None.

        ``ends`` (q0, q1) says the move is the rest-to-rest one between them: its peaks then
        have closed forms. ``bounds`` are the rate bounds of ``coeffs`` if already known.
        ``rates=False`` checks the positions alone (for a move whose rates fit by
        construction).
        """
        if ends is not None:
            lowest, highest = np.minimum(*ends), np.maximum(*ends)  # a monotone move
        else:
            lowest, highest = position_range(coeffs, duration, limits.lower, limits.upper, 1e-9)
        below = limits.lower - lowest
        above = highest - limits.upper
        for excess, values, bound in (
            (below, lowest, limits.lower),
            (above, highest, limits.upper),
        ):
            j = int(excess.argmax())
            if excess[j] > 1e-9:
                return "position", j, float(values[j]), float(bound[j])
        if not rates:
            return None
        if ends is not None:
            peaks = rest_to_rest_peaks(ends[0], ends[1], duration, self.degree)
        else:
            screened = self._screened_peaks(coeffs, duration, limits, slack, bounds)
            if screened is None:
                return None
            peaks = screened
        return worst_rate_limit(peaks, limits, self.limited, slack)

    def _screened_peaks(
        self,
        coeffs: FloatArray,
        duration: float,
        limits: JointLimits,
        slack: float,
        bounds: tuple[FloatArray, FloatArray] | None = None,
    ) -> dict[str, FloatArray] | None:
        """Rate peaks, exact for every joint that may break a limit; None if none may.

        A joint whose upper bound (:func:`~optraj.planners.profiles.peak_bounds.rate_bounds`) keeps
        within a limit carries that bound: it is below the threshold :func:`worst_rate_limit`
        applies, so its answer is the one exact peaks give.
        """
        _, upper = bounds if bounds is not None else rate_bounds(coeffs, duration)
        unsure = {q: upper[_ROWS[q]] / getattr(limits, q) > 1.0 + slack for q in self.limited}
        if not any(mask.any() for mask in unsure.values()):
            return None
        peaks = {}
        for quantity, mask in unsure.items():
            values = upper[_ROWS[quantity]].copy()
            if mask.any():
                values[mask] = peak_of(quantity, coeffs[:, mask], duration)
            peaks[quantity] = values
        return peaks

    def _failure(
        self, coeffs: FloatArray, duration: float, limits: JointLimits
    ) -> tuple[str, int, float, float]:
        """The limit broken by a move that :meth:`_fits` refuses, as :meth:`_check` gives it.

        Should round-off make the check pass where a grid value broke a rate limit, that
        grid value names the limit.
        """
        failure = self._check(coeffs, duration, limits)
        if failure is not None:
            return failure
        lower = rate_bounds(coeffs, duration)[0]
        ratios = {q: lower[_ROWS[q]] / getattr(limits, q) for q in self.limited}
        quantity = max(ratios, key=lambda q: float(ratios[q].max()))
        j = int(ratios[quantity].argmax())
        return quantity, j, float(lower[_ROWS[quantity], j]), float(getattr(limits, quantity)[j])

    def _fits(self, coeffs: FloatArray, duration: float, limits: JointLimits) -> bool:
        """Whether the move keeps every limit; a grid value beyond a rate limit says no at once."""
        bounds = rate_bounds(coeffs, duration)
        lower = bounds[0]
        for quantity in self.limited:
            if (lower[_ROWS[quantity]] / getattr(limits, quantity)).max() > 1.0 + _SLACK:
                return False
        return self._check(coeffs, duration, limits, bounds=bounds) is None

    def _shortest(
        self,
        q0: FloatArray,
        q1: FloatArray,
        limits: JointLimits,
        boundary: dict[str, FloatArray],
        rest: bool,
    ) -> float:
        """Shortest duration whose peaks fit the limits.

        Rest to rest, q(t) = q0 + (q1 - q0) s(t / T) for a fixed shape s, so the k-th
        derivative peaks scale exactly as 1 / T^k: the closed-form peaks at T = 1 give T.
        With moving ends the shape changes with T: doubling, then the bisection of
        :mod:`~optraj.planners.profiles.duration_search`. A rest-to-rest move lasts at least
        MIN_DURATION [s].
        """
        if rest:
            distance = np.abs(q1 - q0)
            needs = [
                ((distance * peak) / getattr(limits, quantity)).max() ** (1.0 / order)
                for order, (quantity, peak) in enumerate(
                    zip(self.limited, REST_PEAKS[self.degree], strict=False), start=1
                )
            ]
            shortest = float(max(needs))
            if shortest > 0.0:
                # a tiny move lasts MIN_DURATION, the shortest duration any planner takes
                return max(shortest * (1.0 + 1e-12), MIN_DURATION)
        # Below |q1 - q0| / vmax the mean velocity, so the peak, is beyond a limit: those
        # durations of the doubling fail without a check.
        floor = float((np.abs(q1 - q0) / limits.velocity).max()) / (1.0 + _SLACK) * (1.0 - 1e-12)
        high = 1e-3
        while high < floor and high * 2.0 <= 1e4:
            high *= 2.0
        while not self._fits(self._coefficients(q0, q1, high, boundary), high, limits):
            high *= 2.0
            if high > 1e4:
                last = high / 2.0
                failure = self._failure(self._coefficients(q0, q1, last, boundary), last, limits)
                quantity, j, needed, allowed = failure
                raise _limit_error(
                    failure,
                    limits,
                    f"no {self.name} of any duration keeps joint {limits.names[j]!r} within its "
                    f"{quantity} limit ({needed:.4g} needed, {allowed:.4g} allowed)",
                )

        def fits(duration: float) -> bool:
            return self._fits(self._coefficients(q0, q1, duration, boundary), duration, limits)

        if high == 1e-3:  # the first try fits: halve down from it
            return bisect(fits, 0.0, high)
        return shortest_in(
            fits, lambda duration: self._margin(q0, q1, duration, limits, boundary), high / 2, high
        )

    def _worst_ratio(self, coeffs: FloatArray, duration: float, limits: JointLimits) -> float:
        """The largest rate peak over its limit, of any joint and limited quantity [-].

        Exact; only the quantities whose grid bounds may reach the largest grid value over its
        limit are solved for.
        """
        lower, upper = rate_bounds(coeffs, duration)
        allowed = {q: getattr(limits, q) for q in self.limited}
        floor = max(float((lower[_ROWS[q]] / allowed[q]).max()) for q in self.limited)
        worst = floor
        for quantity in self.limited:
            row = _ROWS[quantity]
            if float((upper[row] / allowed[quantity]).max()) >= floor:
                peak = peak_of(quantity, coeffs, duration)
                worst = max(worst, float((peak / allowed[quantity]).max()))
        return worst

    def _margin(
        self,
        q0: FloatArray,
        q1: FloatArray,
        duration: float,
        limits: JointLimits,
        boundary: dict[str, FloatArray],
    ) -> float:
        """How far the move of this duration [s] is from fitting, continuous in the duration.

        > 0 exactly where :meth:`_check` finds a limit broken: the larger of the worst position
        excess beyond 1e-9 [rad or m] and the logarithm of the worst rate peak over its limit
        and 1 + slack (rate peaks go nearly as powers of T).
        """
        coeffs = self._coefficients(q0, q1, duration, boundary)
        lowest, highest = position_range(coeffs, duration, limits.lower, limits.upper, 1e-9)
        position = max(float((limits.lower - lowest).max()), float((highest - limits.upper).max()))
        rate = self._worst_ratio(coeffs, duration, limits)
        with np.errstate(divide="ignore"):  # no motion at all: log 0 = -inf, it fits
            return max(position - 1e-9, float(np.log(rate / (1.0 + _SLACK))))

    def _timed(
        self,
        q0: FloatArray,
        q1: FloatArray,
        limits: JointLimits,
        duration: float | None,
        boundary: dict[str, FloatArray],
        rest: bool | None = None,
    ) -> tuple[float, FloatArray]:
        """Duration [s] and coefficients (degree + 1, n) of one move within the limits.

        ``rest`` says whether every value of ``boundary`` is zero (the rest-to-rest closed
        forms then apply); None leaves that to be found out.

        Raises:
            InfeasibleError: A fixed duration that breaks a limit, or no duration that fits.
        """
        if rest is None:
            rest = _at_rest(boundary)
        shortest = duration is None
        if duration is None:
            duration = self._shortest(q0, q1, limits, boundary, rest)
        if rest:
            coeffs = self._rest_coefficients(q0, q1, duration)
            # The shortest rest-to-rest duration puts each rate peak at most 1 / (1 + 1e-12)
            # of its limit (or was found by checking them): only the positions remain.
            failure = self._check(coeffs, duration, limits, ends=(q0, q1), rates=not shortest)
        else:
            coeffs = self._coefficients(q0, q1, duration, boundary)
            # a duration the search returns has passed this very check
            failure = None if shortest else self._check(coeffs, duration, limits)
        if failure is not None:
            raise rate_limit_error(failure, limits, f"{self.name} in {duration:.4g} s")
        return duration, coeffs

    def move(
        self,
        q_start: ArrayLike,
        q_goal: ArrayLike,
        limits: JointLimits,
        duration: float | None = None,
    ) -> Trajectory:
        """Rest-to-rest move (see :meth:`JointProfile.move`).

        Raises:
            InfeasibleError: A fixed duration that breaks a limit (names joint, needed and
                allowed values).
            InvalidInputError: Bad inputs, or q_goal equals q_start and neither the call nor
                the planner gives a duration.
        """
        if duration is None:
            duration = self.duration
        q0, q1, duration = rest_to_rest_inputs(q_start, q_goal, limits, duration, self.name)
        zeros = np.zeros(limits.n)
        boundary = {"v0": zeros, "v1": zeros, "a0": zeros, "a1": zeros}
        length, coeffs = self._timed(q0, q1, limits, duration, boundary, rest=True)
        return Trajectory(np.array([0.0, length]), coeffs[None], joint_names=limits.names)

    def plan(self, problem: PointToPoint | PaddleStrike) -> Trajectory:
        """Plan a PointToPoint, or a paddle4 strike (the ECE486 task's: arrive at rest).

        A PointToPoint may start and end moving (a cubic meets velocities, a quintic also
        accelerations). A paddle strike at speed approaches the ball in contact_time and then
        stops within the limits.

        Raises:
            InfeasibleError: No motion of this kind fits the limits.
            InvalidInputError: A problem this profile cannot plan, or a rest-to-rest
                PointToPoint whose goal equals its start without a duration (from the
                problem or the planner).
        """
        started = time.perf_counter()
        if isinstance(problem, PaddleStrike):
            traj = self._paddle(problem)
            return stamp(traj, self.name, started)
        if not isinstance(problem, PointToPoint):
            raise InvalidInputError(
                f"{type(self).__name__} plans a PointToPoint or a PaddleStrike, got "
                f"{type(problem).__name__}",
                name="problem",
            )
        q0, q1 = problem.q_start, problem.q_goal
        if self.duration is None and not (np.abs(q1 - q0) > STILL_TOLERANCE).any():
            problem.require_motion(self.name)  # a goal that equals the start: refused at rest
        boundary = self._boundary(problem)
        duration = problem.duration if problem.duration is not None else self.duration
        rest = (
            problem.qdd_start is None
            and problem.qdd_goal is None
            and not (boundary["v0"].any() or boundary["v1"].any())
        )
        length, coeffs = self._timed(q0, q1, problem.limits, duration, boundary, rest=rest)
        traj = Trajectory(
            np.array([0.0, length]),
            coeffs[None],
            joint_names=problem.limits.names,
            phases=[Phase("move", 0.0, length)],
        )
        return stamp(traj, self.name, started)

    def _boundary(self, problem: PointToPoint) -> dict[str, FloatArray]:
        zeros = np.zeros(problem.limits.n)
        boundary = {
            "v0": np.asarray(problem.qd_start),
            "v1": np.asarray(problem.qd_goal),
            "a0": zeros if problem.qdd_start is None else np.asarray(problem.qdd_start),
            "a1": zeros if problem.qdd_goal is None else np.asarray(problem.qdd_goal),
        }
        if self.degree < 5:  # a rest-to-rest cubic starts at 6 delta / T^2
            refuse_prescribed_accelerations(problem, f"a {self.name}")
        return boundary

    def _paddle(self, problem: PaddleStrike) -> Trajectory:
        """Approach the ball in contact_time; at speed, then stop as fast as the limits allow."""
        limits = problem.limits
        q0, qc = np.asarray(problem.q_start), np.asarray(problem.q_contact)
        zeros = np.zeros(limits.n)
        contact_time = float(problem.contact_time)
        if float(problem.speed) == 0.0:
            boundary = {"v0": zeros, "v1": zeros, "a0": zeros, "a1": zeros}
            length, coeffs = self._timed(q0, qc, limits, contact_time, boundary)
            return Trajectory(
                np.array([0.0, length]),
                coeffs[None],
                joint_names=limits.names,
                phases=[Phase("approach", 0.0, length)],
            )
        qd_contact = paddle_contact_velocity(problem)
        boundary = {"v0": zeros, "v1": qd_contact, "a0": zeros, "a1": zeros}
        length, coeffs = self._timed(q0, qc, limits, contact_time, boundary)
        approach = Trajectory(np.array([0.0, length]), coeffs[None], joint_names=limits.names)
        stop_boundary = {"v0": qd_contact, "v1": zeros, "a0": zeros, "a1": zeros}
        # Coast to a stop: for the stop time T, end where the velocity would carry it in T/2.
        stop = None
        for stop_time in np.geomspace(0.05, 5.0, 60):
            q_end = qc + 0.5 * stop_time * qd_contact
            if not limits.contains(q_end):
                continue
            coeffs = self._coefficients(qc, q_end, stop_time, stop_boundary)
            if self._check(coeffs, stop_time, limits) is None:
                stop = Trajectory([0.0, stop_time], coeffs[None], joint_names=limits.names)
                break
        if stop is None:
            raise InfeasibleError(
                f"the paddle cannot stop within its limits after meeting the ball at "
                f"{float(problem.speed):.3g} m/s",
                limit="position",
            )
        return Trajectory.sequence(
            [("approach", [approach]), ("stop", [stop])], joint_names=limits.names
        )


class Cubic(_Polynomial):
    """Cubic time scaling: meets positions and velocities at both ends.

    Rest to rest, every joint follows q0 + (q1 - q0) s(t/T) with s = 3 x^2 - 2 x^3 (peak
    velocity 1.5 delta/T, peak acceleration 6 delta/T^2). Keeps velocity and acceleration
    limits; its acceleration jumps at the ends.
    """

    name = "cubic"
    degree = 3
    limited = ("velocity", "acceleration")

    def _coefficients(
        self, q0: FloatArray, q1: FloatArray, duration: float, boundary: dict[str, FloatArray]
    ) -> FloatArray:
        return cubic_coefficients(q0, q1, duration, boundary["v0"], boundary["v1"])


class Quintic(_Polynomial):
    """Quintic time scaling: meets positions, velocities and accelerations at both ends.

    Rest to rest, s = 10 x^3 - 15 x^4 + 6 x^5 (peak velocity 1.875 delta/T, acceleration
    5.774 delta/T^2, jerk 60 delta/T^3). Keeps velocity, acceleration and jerk limits.
    """

    name = "quintic"
    degree = 5
    limited = ("velocity", "acceleration", "jerk")
    shape = (0.0, 0.0, 0.0, 10.0, -15.0, 6.0)

    def _coefficients(
        self, q0: FloatArray, q1: FloatArray, duration: float, boundary: dict[str, FloatArray]
    ) -> FloatArray:
        return quintic_coefficients(
            q0, q1, duration, boundary["v0"], boundary["v1"], boundary["a0"], boundary["a1"]
        )


def profile_by_name(name: str) -> JointProfile:
    """A default-constructed profile by name: ``"cubic"``, ``"quintic"`` or ``"lspb"``."""
    if name == "cubic":
        return Cubic()
    if name == "quintic":
        return Quintic()
    if name == "lspb":
        return LSPB()
    raise UnknownNameError("profile", name, ["cubic", "quintic", "lspb"])
