r"""The one trajectory type every planner returns: piecewise polynomials in time.

A :class:`Trajectory` holds breakpoints ``0 = t_0 < t_1 < ... < t_K = duration`` and, for each
segment ``k`` and joint ``j``, a polynomial in the local time ``tau = t - t_k``:

.. math:: q_j(t) = \sum_{i=0}^{d} c_{k,i,j} \, \tau^i, \qquad t_k \le t < t_{k+1}

Segments need not join smoothly: a jump at a breakpoint is kept as it is (the independent
checker reports it), so that a planner's real output is never smoothed over.
"""

from __future__ import annotations

import csv
import json
import math
import os
import pickle
import reprlib
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.validation import (
    MAX_COUNT,
    MAX_DURATION,
    as_array,
    as_choice,
    as_count,
    as_flag,
    as_number,
    as_positive,
    as_vector,
    ndim_of,
)

__all__ = ["Phase", "Trajectory", "TrajectorySample", "sampling_rate"]

FloatArray = NDArray[np.float64]

#: Times this far outside [0, duration] [s] are taken as the end point (round-off).
TIME_TOLERANCE = 1e-9
#: Most joints a trajectory may have (arrays are (samples, dof)).
MAX_DOF = 1000
#: Highest sampling rate [Hz]: one sample per microsecond, the shortest duration
#: :func:`optraj.validation.as_duration` accepts (the checker's bound too).
MAX_RATE = 1e6
#: Largest trajectory JSON read [bytes] (text or file): a 10,000-segment quintic of 7 joints
#: takes about 10 MB; beyond this a file is not one of ours.
MAX_JSON_BYTES = 64 * 2**20
#: Deepest nesting of lists and objects in a file's metadata: ours are two levels deep
#: (``problem_options`` with a list), and the exports recurse through them.
MAX_METADATA_DEPTH = 32
_FORMAT = "optraj.trajectory/1"


@dataclass(frozen=True)
class Phase:
    """A named time window of a trajectory, e.g. ``approach``, ``strike``, ``stop``.

    Attributes:
        name: Phase name.
        t_start: Start time [s].
        t_end: End time [s], >= t_start.
    """

    name: str
    t_start: float
    t_end: float

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise InvalidInputError(
                f"a phase name must be a str, got {type(self.name).__name__} {self.name!r}",
                name="phases",
            )
        for field in ("t_start", "t_end"):
            value = as_number(getattr(self, field), f"phase {self.name!r} {field}", "s")
            object.__setattr__(self, field, value)
        if self.t_end < self.t_start:
            raise InvalidInputError(
                f"phase {self.name!r} ends at {self.t_end:.6g} s before it starts at "
                f"{self.t_start:.6g} s",
                name="phases",
            )

    @property
    def duration(self) -> float:
        """Length of the phase [s]."""
        return self.t_end - self.t_start


def sampling_rate(rate: object, duration: float, dof: int) -> float:
    """``rate`` [Hz] checked for sampling ``dof`` joints over ``duration`` [s].

    All samples of every joint are held at once, so their number (instants times joints)
    is bounded by :data:`optraj.validation.MAX_COUNT`: q, qd, qdd and jerk are then at most
    320 MB.

    Raises:
        InvalidInputError: Not a number (bools refused), <= 0, above :data:`MAX_RATE`, or
            more sampled values than MAX_COUNT; the message names the rate that would fit.
    """
    hz = as_positive(rate, "rate", "Hz", maximum=MAX_RATE)
    samples = max(math.ceil(duration * hz), 1) + 1
    if samples * dof > MAX_COUNT:
        fits = (MAX_COUNT / dof - 1.0) / duration
        raise InvalidInputError(
            f"rate {hz:.6g} Hz over a {duration:.6g} s trajectory of {dof} joints needs "
            f"{samples * dof:.3g} sampled values, more than MAX_COUNT = {MAX_COUNT:.3g}; give "
            f"rate <= {fits:.6g} Hz",
            name="rate",
            value=rate,
        )
    return hz


class TrajectorySample(NamedTuple):
    """Joint states at some times.

    Attributes:
        t: Times [s], shape (m,) (or a float for one time).
        q: Positions [rad or m], shape (m, n) (or (n,)).
        qd: Velocities [rad/s or m/s], same shape as q.
        qdd: Accelerations [rad/s^2 or m/s^2], same shape as q.
        jerk: Jerks [rad/s^3 or m/s^3], same shape as q.
    """

    t: FloatArray | float
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    jerk: FloatArray


def _derivative(coefficients: FloatArray) -> FloatArray:
    """Coefficients of the time derivative, one degree lower (at least degree 0)."""
    degree = coefficients.shape[1] - 1
    if degree == 0:
        return np.zeros_like(coefficients)
    powers = np.arange(1, degree + 1, dtype=float)[None, :, None]
    return coefficients[:, 1:, :] * powers


def _derivatives(coefficients: FloatArray) -> list[FloatArray]:
    """Coefficients of a polynomial and of its first three time derivatives."""
    result = [coefficients]
    for _ in range(3):
        result.append(_derivative(result[-1]))
    return result


def _validated(breakpoints: ArrayLike, coefficients: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Breakpoints and coefficients checked against each other, as read-only arrays."""
    knots = as_vector(breakpoints, "breakpoints")
    coeffs = as_array(coefficients, "coefficients", (None, None, None))
    if knots.size < 2 or coeffs.shape[0] != knots.size - 1:
        raise InvalidInputError(
            f"coefficients must have one row per segment: {knots.size} breakpoints need "
            f"shape ({knots.size - 1}, degree + 1, n), got {coeffs.shape}",
            name="coefficients",
        )
    if coeffs.shape[1] < 1 or coeffs.shape[2] < 1:
        raise InvalidInputError(
            f"coefficients must have at least one term and one joint, got {coeffs.shape}",
            name="coefficients",
        )
    if knots[0] != 0.0 or np.any(np.diff(knots) <= 0.0):
        raise InvalidInputError(
            "breakpoints must start at 0 s and strictly increase, got "
            f"{np.array2string(knots, precision=6, threshold=8)}",
            name="breakpoints",
        )
    as_number(knots[-1], "duration (last breakpoint)", "s", maximum=MAX_DURATION)
    for array in (knots, coeffs):
        array.setflags(write=False)
    return knots, coeffs


def _short(value: object) -> str:
    """A value's type and a short repr, for error messages."""
    return f"{type(value).__name__} {reprlib.repr(value)}"


def _is_collection(value: object) -> bool:
    """Whether ``value`` holds items (a list, tuple, generator ...), not a str or a mapping."""
    return isinstance(value, Iterable) and not isinstance(value, (str, bytes, Mapping))


def _depth(value: object) -> int:
    """How deeply lists, tuples and mappings nest in ``value`` (0 for a scalar).

    Walked with a stack, not recursion, so that any depth is measured.
    """
    deepest = 0
    stack = [(value, 0)]
    while stack:
        item, level = stack.pop()
        if isinstance(item, Mapping):
            children: Iterable[object] = item.values()
        elif isinstance(item, (list, tuple)):
            children = item
        else:
            continue
        deepest = max(deepest, level + 1)
        stack.extend((child, level + 1) for child in children)
    return deepest


def _writable(path: object) -> Path:
    """``path`` as a Path, or a typed error for something that is not a file path."""
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidInputError(f"path must be a str or a Path, got {_short(path)}", name="path")
    return Path(path)


def _write_error(path: Path, exc: OSError) -> InvalidInputError:
    """A typed error for a file that cannot be written (a directory, no permission, ...)."""
    reason = exc.strerror or str(exc)
    return InvalidInputError(f"cannot write {str(path)!r}: {reason}", name="path", value=path)


def _jsonable(value: Any) -> Any:
    """Metadata value as plain JSON data, or ``None`` when it has no JSON form."""
    if isinstance(value, (str, bool, int)) or value is None:
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else str(value)
    if isinstance(value, np.generic):
        return _jsonable(value.item())
    if isinstance(value, np.ndarray):
        return [_jsonable(v) for v in value.tolist()] if value.dtype != object else None
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return None


class Trajectory:
    """A joint trajectory, continuous in time, stored as piecewise polynomials.

    Args:
        breakpoints: Segment boundaries [s], shape (K + 1,), strictly increasing from 0.
        coefficients: Polynomial coefficients, shape (K, d + 1, n): ``coefficients[k, i, j]``
            multiplies ``(t - t_k)^i`` for joint j on segment k [rad/s^i or m/s^i].
        joint_names: Names of the n joints; ``q0 .. q{n-1}`` when omitted.
        phases: Named time windows (approach, strike, ...), within [0, duration].
        metadata: How the trajectory was made: ``planner`` (name), ``solve_time`` [s],
            ``status``, ``iterations`` and anything a planner wants to keep (non-JSON values
            are kept in memory and left out of exports).

    Raises:
        InvalidInputError: Shapes disagree, breakpoints do not increase from 0, non-finite
            coefficients, or phases outside [0, duration].
    """

    def __init__(
        self,
        breakpoints: ArrayLike,
        coefficients: ArrayLike,
        *,
        joint_names: Sequence[str] | None = None,
        phases: Iterable[Phase] = (),
        metadata: Mapping[str, Any] | None = None,
    ) -> None:
        knots, coeffs = _validated(breakpoints, coefficients)
        self._build: Callable[[], tuple[ArrayLike, ArrayLike]] | None = None
        self._pieces: tuple[FloatArray, list[FloatArray]] | None = (knots, _derivatives(coeffs))
        self._duration = float(knots[-1])
        self._describe(coeffs.shape[2], joint_names, phases, metadata)

    @classmethod
    def deferred(
        cls,
        duration: float,
        dof: int,
        build: Callable[[], tuple[ArrayLike, ArrayLike]],
        *,
        joint_names: Sequence[str] | None = None,
        phases: Iterable[Phase] = (),
        metadata: Mapping[str, Any] | None = None,
    ) -> Trajectory:
        """A trajectory of known duration whose polynomials are computed on first use.

        For planners whose own result is exact but costly to expand into polynomials (Ruckig's
        phase lists): the duration, joint names, phases and metadata are there at once, and
        ``build`` runs once, the first time anything needs the polynomials (sampling,
        ``breakpoints``, ``coefficients``, export, pickling). Its result is checked as the
        constructor checks its arguments and must end at ``duration``.

        Args:
            duration: Total time [s], > 0.
            dof: Number of joints, >= 1.
            build: Returns ``(breakpoints, coefficients)`` as for the constructor. An error
                it raises reaches the caller of that first use.
            joint_names: As for the constructor.
            phases: As for the constructor.
            metadata: As for the constructor.

        Raises:
            InvalidInputError: A duration that is not in (0, MAX_DURATION] s, a dof outside
                [1, MAX_DOF], a ``build`` that is not callable, or names, phases or metadata
                that do not fit; later, a ``build`` result that does not fit.
        """
        length = as_positive(duration, "duration", "s", maximum=MAX_DURATION)
        if not callable(build):
            raise InvalidInputError(
                f"build must be a function returning (breakpoints, coefficients), got "
                f"{type(build).__name__}",
                name="build",
            )
        traj = cls.__new__(cls)
        traj._build = build
        traj._pieces = None
        traj._duration = length
        traj._describe(as_count(dof, "dof", 1, MAX_DOF), joint_names, phases, metadata)
        return traj

    def _describe(
        self,
        n: int,
        joint_names: Sequence[str] | None,
        phases: Iterable[Phase],
        metadata: Mapping[str, Any] | None,
    ) -> None:
        """Set the joint names, phases and metadata of a trajectory of n joints."""
        names: tuple[Any, ...] | None = None
        if joint_names is None:
            names = tuple(f"q{j}" for j in range(n))
        elif _is_collection(joint_names):
            names = tuple(joint_names)  # once: a generator is spent by one pass
        if names is None or not all(isinstance(name, str) for name in names):
            raise InvalidInputError(
                f"joint_names must be a sequence of {n} str, got {_short(joint_names)}",
                name="joint_names",
            )
        if len(names) != n:
            raise InvalidInputError(
                f"joint_names must name the {n} joints, got {len(names)} names", name="joint_names"
            )
        windows = tuple(phases) if _is_collection(phases) else None
        if windows is None or not all(isinstance(phase, Phase) for phase in windows):
            raise InvalidInputError(
                f"phases must be a sequence of planners.Phase, got {_short(phases)}",
                name="phases",
            )
        if metadata is not None and not isinstance(metadata, Mapping):
            raise InvalidInputError(
                f"metadata must be a mapping (dict) or None, got {_short(metadata)}",
                name="metadata",
            )
        self._dof = n
        self.joint_names: tuple[str, ...] = names
        self.phases: tuple[Phase, ...] = windows
        for phase in self.phases:
            if phase.t_start < -TIME_TOLERANCE or phase.t_end > self.duration + TIME_TOLERANCE:
                raise InvalidInputError(
                    f"phase {phase.name!r} [{phase.t_start:.6g}, {phase.t_end:.6g}] s lies "
                    f"outside the trajectory [0, {self.duration:.6g}] s",
                    name="phases",
                )
        self.metadata: dict[str, Any] = dict(metadata or {})

    def _expand(self) -> tuple[FloatArray, list[FloatArray]]:
        """Breakpoints and the coefficients of q and its three derivatives (built once)."""
        pieces = self._pieces
        if pieces is None:
            # Without polynomials a trajectory always has its builder.
            build = cast(Callable[[], tuple[ArrayLike, ArrayLike]], self._build)
            knots, coeffs = _validated(*build())
            if knots[-1] != self._duration or coeffs.shape[2] != self._dof:
                raise InvalidInputError(
                    f"a deferred trajectory of {self._duration!r} s and {self._dof} joints was "
                    f"built with {knots[-1]!r} s and {coeffs.shape[2]} joints",
                    name="build",
                )
            pieces = (knots, _derivatives(coeffs))
            self._pieces = pieces
            self._build = None
        return pieces

    @property
    def _knots(self) -> FloatArray:
        return self._expand()[0]

    @property
    def _coeffs(self) -> list[FloatArray]:
        return self._expand()[1]

    def __setstate__(self, state: dict[str, Any]) -> None:
        """Restore a pickled trajectory.

        Pickles made before deferred building existed stored ``_knots`` and ``_coeffs``.
        """
        if "_pieces" not in state:
            knots, coeffs = state.pop("_knots"), state.pop("_coeffs")
            state.update(
                _pieces=(knots, coeffs),
                _build=None,
                _duration=float(knots[-1]),
                _dof=int(coeffs[0].shape[2]),
            )
        self.__dict__.update(state)

    def __getstate__(self) -> dict[str, Any]:
        """Everything but the metadata values that cannot be pickled (Ruckig's own object).

        Plans can then be sent to worker processes; the dropped values stay in the original.
        A deferred trajectory is built first (its builder need not pickle).
        """
        self._expand()
        state = self.__dict__.copy()
        state["_build"] = None
        kept = {}
        for key, value in self.metadata.items():
            try:
                pickle.dumps(value)
            except Exception:
                continue
            kept[key] = value
        state["metadata"] = kept
        return state

    # ---------------------------------------------------------------------- properties

    @property
    def breakpoints(self) -> FloatArray:
        """Segment boundaries [s], shape (K + 1,) (read-only)."""
        return self._knots

    @property
    def coefficients(self) -> FloatArray:
        """Position polynomial coefficients, shape (K, d + 1, n) (read-only)."""
        return self._coeffs[0]

    @property
    def duration(self) -> float:
        """Total time [s]."""
        return self._duration

    @property
    def dof(self) -> int:
        """Number of joints."""
        return self._dof

    @property
    def degree(self) -> int:
        """Polynomial degree of the segments."""
        return int(self._coeffs[0].shape[1] - 1)

    def __repr__(self) -> str:
        planner = self.metadata.get("planner", "?")
        phases = ", ".join(p.name for p in self.phases) or "-"
        # A deferred trajectory is not built just to be shown.
        segments = "?" if self._pieces is None else str(len(self._pieces[0]) - 1)
        return (
            f"Trajectory(duration={self.duration:.4g} s, dof={self.dof}, "
            f"segments={segments}, planner={planner!r}, phases=[{phases}])"
        )

    def phase(self, name: str) -> Phase:
        """The phase called ``name``.

        Raises:
            UnknownNameError: No such phase; lists the phases.
        """
        as_choice(name, "phase", [p.name for p in self.phases])
        return next(phase for phase in self.phases if phase.name == name)

    # ------------------------------------------------------------------------ sampling

    def sample(self, t: ArrayLike) -> TrajectorySample:
        """Joint positions, velocities, accelerations and jerks at the given times.

        At a breakpoint the segment that starts there is used (values are right-continuous),
        except at the final time.

        Args:
            t: One time or an array of times [s], within [0, duration].

        Returns:
            The sample; arrays of shape (m, n) for m times, (n,) for one time.

        Raises:
            InvalidInputError: A time is not finite or lies outside [0, duration].
        """
        scalar = ndim_of(t) == 0
        times = as_array(t, "t", ()) if scalar else as_vector(t, "t")
        times = np.atleast_1d(times)
        if times.size and (
            times.min() < -TIME_TOLERANCE or times.max() > self.duration + TIME_TOLERANCE
        ):
            bad = times[(times < -TIME_TOLERANCE) | (times > self.duration + TIME_TOLERANCE)][0]
            raise InvalidInputError(
                f"time {bad:.6g} s is outside the trajectory [0, {self.duration:.6g}] s",
                name="t",
                value=bad,
            )
        times = np.clip(times, 0.0, self.duration)
        segment = np.clip(np.searchsorted(self._knots, times, side="right") - 1, 0, None)
        segment = np.minimum(segment, len(self._knots) - 2)
        tau = (times - self._knots[segment])[:, None]
        values = []
        for coeffs in self._coeffs:
            rows = coeffs[segment]  # (m, d + 1, n)
            result = rows[:, -1, :].copy()
            for i in range(rows.shape[1] - 2, -1, -1):
                result = result * tau + rows[:, i, :]
            values.append(result)
        if scalar:
            return TrajectorySample(float(times[0]), *(v[0] for v in values))
        return TrajectorySample(times, *values)

    def times(self, rate: float = 1000.0, *, include_breakpoints: bool = True) -> FloatArray:
        """Evenly spaced times at ``rate`` [Hz] from 0 to the end, plus every breakpoint.

        Args:
            rate: Sampling rate [Hz], in (0, MAX_RATE].
            include_breakpoints: Also include every breakpoint (and the times just before
                each, so that jumps are seen from both sides).

        Raises:
            InvalidInputError: A rate that is not a number in (0, MAX_RATE] Hz, or one whose
                samples of every joint (times x joints) would be more than
                :data:`optraj.validation.MAX_COUNT` values, the checker's rule too: the
                samples of q, qd, qdd and jerk are then at most 320 MB.
        """
        hz = sampling_rate(rate, self.duration, self.dof)
        with_breakpoints = as_flag(include_breakpoints, "include_breakpoints")
        count = max(math.ceil(self.duration * hz), 1)
        grid = np.linspace(0.0, self.duration, count + 1)
        if with_breakpoints:
            inner = self._knots[1:-1]
            before = np.maximum(inner - 1e-9 * max(self.duration, 1.0), 0.0)
            grid = np.unique(np.concatenate([grid, self._knots, before]))
        return grid

    # -------------------------------------------------------------------- construction

    @classmethod
    def from_hermite(
        cls,
        times: ArrayLike,
        q: ArrayLike,
        qd: ArrayLike,
        qdd: ArrayLike | None = None,
        **kwargs: Any,
    ) -> Trajectory:
        """Interpolate states: cubic Hermite from (q, qd), quintic Hermite with qdd too.

        Each segment matches the given position and velocity (and acceleration) at both ends,
        so the result is C1 (C2 with qdd) and passes through every sample.

        Args:
            times: Sample times [s], shape (m,), strictly increasing from 0.
            q: Positions [rad or m], shape (m, n).
            qd: Velocities [rad/s or m/s], shape (m, n).
            qdd: Accelerations [rad/s^2 or m/s^2], shape (m, n), or None for cubic segments.
            **kwargs: joint_names, phases, metadata, as for the constructor.
        """
        t = as_vector(times, "times")
        m = t.size
        pos = as_array(q, "q", (m, None))
        vel = as_array(qd, "qd", pos.shape)
        h = np.diff(t)[:, None]
        if np.any(h <= 0.0):
            raise InvalidInputError("times must strictly increase", name="times")
        p0, p1, v0, v1 = pos[:-1], pos[1:], vel[:-1], vel[1:]
        if qdd is None:
            c2 = (3 * (p1 - p0) - (2 * v0 + v1) * h) / h**2
            c3 = (2 * (p0 - p1) + (v0 + v1) * h) / h**3
            coeffs = np.stack([p0, v0, c2, c3], axis=1)
        else:
            acc = as_array(qdd, "qdd", pos.shape)
            a0, a1 = acc[:-1], acc[1:]
            # Solve the end conditions for c3, c4, c5 in closed form.
            dp = p1 - p0 - v0 * h - 0.5 * a0 * h**2
            dv = v1 - v0 - a0 * h
            da = a1 - a0
            c3 = (20 * dp - 8 * dv * h + da * h**2) / (2 * h**3)
            c4 = (-30 * dp + 14 * dv * h - 2 * da * h**2) / (2 * h**4)
            c5 = (12 * dp - 6 * dv * h + da * h**2) / (2 * h**5)
            coeffs = np.stack([p0, v0, 0.5 * a0, c3, c4, c5], axis=1)
        return cls(t - t[0], coeffs, **kwargs)

    @classmethod
    def constant(cls, q: ArrayLike, duration: float, **kwargs: Any) -> Trajectory:
        """Stand still at ``q`` [rad or m] for ``duration`` [s], in (0, MAX_DURATION].

        Not as_duration's microsecond floor: a hold has no derivatives to overflow, and
        planners hold for waits as short as their round-off allows.
        """
        value = as_vector(q, "q")
        length = as_positive(duration, "duration", "s", maximum=MAX_DURATION)
        return cls([0.0, length], value[None, None, :], **kwargs)

    @classmethod
    def sequence(
        cls,
        phases: Sequence[tuple[str, Sequence[Trajectory]]],
        *,
        joint_names: Sequence[str] | None = None,
        metadata: Mapping[str, Any] | None = None,
    ) -> Trajectory:
        """Pieces played one after another, one named phase spanning each group of them.

        Args:
            phases: ``(name, pieces)`` in order; a phase with no pieces lasts 0 s.
            joint_names: Joint names of the result; the first piece's when None.
            metadata: Metadata of the result (empty when None).

        Raises:
            InvalidInputError: Phases that are not ``(str, [Trajectory, ...])`` pairs, no
                pieces at all, or pieces of different joint counts.
        """
        if not isinstance(phases, (list, tuple)) or not all(
            isinstance(group, (list, tuple))
            and len(group) == 2
            and isinstance(group[0], str)
            and isinstance(group[1], (list, tuple))
            and all(isinstance(piece, Trajectory) for piece in group[1])
            for group in phases
        ):
            raise InvalidInputError(
                f"phases must be (name, [Trajectory, ...]) pairs, got {_short(phases)}",
                name="phases",
            )
        parts = [piece for _, pieces in phases for piece in pieces]
        if not parts:
            raise InvalidInputError("a sequence needs at least one piece", name="phases")
        windows: list[Phase] = []
        clock = 0.0
        for name, pieces in phases:
            start = clock
            clock += sum(piece.duration for piece in pieces)
            windows.append(Phase(name, start, clock))
        joined = parts[0].then(*parts[1:])
        return cls(
            joined.breakpoints,
            joined.coefficients,
            joint_names=joint_names if joint_names is not None else parts[0].joint_names,
            phases=windows,
            metadata=metadata or {},
        )

    def then(self, *others: Trajectory, metadata: Mapping[str, Any] | None = None) -> Trajectory:
        """This trajectory followed by others, each shifted to start where the previous ends.

        Degrees are raised to the highest one; phases are shifted along. Continuity between
        the pieces is not enforced: a mismatch stays visible to the checker.
        """
        pieces = (self, *others)
        for piece in others:
            if not isinstance(piece, Trajectory):
                raise InvalidInputError(
                    f"then() joins planners.Trajectory objects, got {_short(piece)}",
                    name="others",
                )
            if piece.dof != self.dof:
                raise InvalidInputError(
                    f"cannot join trajectories of {self.dof} and {piece.dof} joints",
                    name="others",
                )
        degree = max(piece.degree for piece in pieces)
        knots: list[FloatArray] = []
        rows: list[FloatArray] = []
        phases: list[Phase] = []
        offset = 0.0
        for piece in pieces:
            knots.append(piece.breakpoints[:-1] + offset)
            coeffs = piece.coefficients
            pad = np.zeros((coeffs.shape[0], degree + 1, coeffs.shape[2]))
            pad[:, : coeffs.shape[1], :] = coeffs
            rows.append(pad)
            phases.extend(Phase(p.name, p.t_start + offset, p.t_end + offset) for p in piece.phases)
            offset += piece.duration
        knots.append(np.array([offset]))
        merged = dict(metadata) if metadata is not None else dict(self.metadata)
        return Trajectory(
            np.concatenate(knots),
            np.concatenate(rows),
            joint_names=self.joint_names,
            phases=phases,
            metadata=merged,
        )

    # ------------------------------------------------------------------------- export

    def to_arrays(self, rate: float = 1000.0) -> dict[str, FloatArray]:
        """Samples at ``rate`` [Hz] (and every breakpoint) as NumPy arrays.

        Returns:
            ``{"t": (m,), "q": (m, n), "qd": (m, n), "qdd": (m, n), "jerk": (m, n)}``.
        """
        sample = self.sample(self.times(rate))
        return {
            "t": np.asarray(sample.t),
            "q": sample.q,
            "qd": sample.qd,
            "qdd": sample.qdd,
            "jerk": sample.jerk,
        }

    def to_dict(self) -> dict[str, Any]:
        """The exact trajectory as plain JSON-ready data (metadata without non-JSON values)."""
        metadata = {k: _jsonable(v) for k, v in self.metadata.items()}
        return {
            "format": _FORMAT,
            "joint_names": list(self.joint_names),
            "breakpoints": self._knots.tolist(),
            "coefficients": self.coefficients.tolist(),
            "phases": [
                {"name": p.name, "t_start": p.t_start, "t_end": p.t_end} for p in self.phases
            ],
            "metadata": {k: v for k, v in metadata.items() if v is not None},
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Trajectory:
        """Rebuild a trajectory from :meth:`to_dict` output.

        Raises:
            InvalidInputError: Another format, or a missing or malformed field (each field
                is checked as the constructor checks its argument).
        """
        if not isinstance(data, Mapping) or data.get("format") != _FORMAT:
            found = data.get("format") if isinstance(data, Mapping) else type(data).__name__
            raise InvalidInputError(
                f"not an optraj trajectory: expected format {_FORMAT!r}, got {found!r}",
                name="data",
            )
        missing = [key for key in ("breakpoints", "coefficients", "phases") if key not in data]
        if missing:
            raise InvalidInputError(
                f"trajectory data is missing or has a malformed field: no {', '.join(missing)}",
                name="data",
            )
        rows = data["phases"]
        if not isinstance(rows, list) or not all(
            isinstance(row, Mapping) and {"name", "t_start", "t_end"} <= row.keys() for row in rows
        ):
            raise InvalidInputError(
                "trajectory data is missing or has a malformed field: phases must be a list "
                f"of {{name, t_start, t_end}} objects, got {_short(rows)}",
                name="phases",
            )
        metadata = data.get("metadata", {})
        if not isinstance(metadata, Mapping) or _depth(metadata) > MAX_METADATA_DEPTH:
            raise InvalidInputError(
                "trajectory data is missing or has a malformed field: metadata must be an "
                f"object nested at most {MAX_METADATA_DEPTH} levels deep, got "
                f"{_short(metadata)}",
                name="metadata",
            )
        return cls(
            data["breakpoints"],
            data["coefficients"],
            joint_names=data.get("joint_names"),
            phases=[Phase(row["name"], row["t_start"], row["t_end"]) for row in rows],
            metadata=metadata,
        )

    def to_json(self, path: str | Path | None = None) -> str:
        """The exact trajectory as JSON text; also written to ``path`` when given.

        Raises:
            InvalidInputError: A path that is not a str or Path, or that cannot be written
                (a directory, a missing folder, no permission).
        """
        text = json.dumps(self.to_dict(), indent=1)
        if path is not None:
            target = _writable(path)
            try:
                target.write_text(text)
            except OSError as exc:
                raise _write_error(target, exc) from exc
        return text

    @classmethod
    def from_json(cls, source: str | Path) -> Trajectory:
        """Read a trajectory from JSON text or from a file path.

        Raises:
            InvalidInputError: No such file, one that cannot be read, text over
                MAX_JSON_BYTES, not valid JSON (nested too deeply, a number too long) or not
                an optraj trajectory.
        """
        if not isinstance(source, (str, os.PathLike)):
            raise InvalidInputError(
                f"source must be JSON text or a file path, got {_short(source)}", name="source"
            )
        text = str(source)
        where = ""  # the file, for the messages
        if not text.lstrip().startswith("{"):
            path = Path(source)
            where = f" in {str(path)!r}"
            if not path.is_file():
                raise InvalidInputError(f"no trajectory file at {str(path)!r}", name="source")
            try:
                size = path.stat().st_size
                if size > MAX_JSON_BYTES:
                    raise InvalidInputError(
                        f"{str(path)!r} has {size} bytes, more than the {MAX_JSON_BYTES} bytes "
                        "of any trajectory file",
                        name="source",
                    )
                text = path.read_text()
            except (OSError, UnicodeDecodeError) as exc:
                reason = exc.strerror if isinstance(exc, OSError) else "not UTF-8 text"
                raise InvalidInputError(
                    f"cannot read {str(path)!r}: {reason}", name="source"
                ) from exc
        elif len(text) > MAX_JSON_BYTES:
            raise InvalidInputError(
                f"trajectory JSON has {len(text)} characters, more than the {MAX_JSON_BYTES} "
                "of any trajectory file",
                name="source",
            )
        try:
            data = json.loads(text)
        except RecursionError as exc:
            raise InvalidInputError(
                f"trajectory JSON is malformed{where}: nested too deeply", name="source"
            ) from exc
        except ValueError as exc:  # JSONDecodeError, and integers of over 4300 digits
            raise InvalidInputError(
                f"trajectory JSON is malformed{where}: {exc}", name="source"
            ) from exc
        return cls.from_dict(data)

    def to_csv(self, path: str | Path, rate: float = 1000.0) -> None:
        """Write samples at ``rate`` [Hz]: columns t, q_<joint>, qd_<joint>, qdd_, jerk_.

        Raises:
            InvalidInputError: A bad rate (see :meth:`times`), or a path that is not a str
                or Path or cannot be written.
        """
        target = _writable(path)
        arrays = self.to_arrays(rate)
        header = ["t"] + [
            f"{prefix}_{name}" for prefix in ("q", "qd", "qdd", "jerk") for name in self.joint_names
        ]
        table = np.column_stack([arrays[key] for key in ("t", "q", "qd", "qdd", "jerk")])
        try:
            with target.open("w", newline="") as handle:
                writer = csv.writer(handle)
                writer.writerow(header)
                writer.writerows(table.tolist())
        except OSError as exc:
            raise _write_error(target, exc) from exc

    def to_ros(self, rate: float | None = None) -> dict[str, Any]:
        """A dict shaped like ROS ``trajectory_msgs/JointTrajectory`` (no ROS needed).

        Args:
            rate: Point rate [Hz]; the breakpoints only when ``None``.

        Returns:
            ``{"joint_names": [...], "points": [{"positions", "velocities", "accelerations",
            "time_from_start": {"sec", "nanosec"}}, ...]}``.
        """
        times = self._knots if rate is None else self.times(rate, include_breakpoints=False)
        sample = self.sample(times)
        points = []
        for k, t in enumerate(np.atleast_1d(sample.t)):
            sec, nanosec = divmod(round(float(t) * 1e9), 1_000_000_000)
            points.append(
                {
                    "positions": sample.q[k].tolist(),
                    "velocities": sample.qd[k].tolist(),
                    "accelerations": sample.qdd[k].tolist(),
                    "time_from_start": {"sec": sec, "nanosec": nanosec},
                }
            )
        return {"joint_names": list(self.joint_names), "points": points}
