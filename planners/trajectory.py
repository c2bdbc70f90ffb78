r"""The one trajectory type every planner returns: piecewise polynomials in time.

A :class:`Trajectory` holds breakpoints ``0 = t_0 < t_1 < ... < t_K = duration`` and, for each
segment ``k`` and joint ``j``, a polynomial in the local time ``tau = t - t_k``:

.. math:: q_j(t) = \sum_{i=0}^{d} c_{k,i,j} \, \tau^i, \qquad t_k \le t < t_{k+1}

Segments need not join smoothly: a jump at a breakpoint is kept as it is (the independent
checker reports it), so that a planner's real output is never smoothed over.

The class is the face; the work is done in modules of their own: :mod:`.phase` (``Phase``),
:mod:`.piecewise` (checks, derivatives, Hermite interpolation, joining), :mod:`.sampling`
(``TrajectorySample``, times and rates), :mod:`.description` (joint names, phases, metadata),
:mod:`.serialization` (exact JSON; its schema in :mod:`.trajectory_schema`), :mod:`.export_csv`
(fixed-rate CSV) and :mod:`.ros_message` (ROS 2 ``JointTrajectory``). Their public names used
with trajectories are importable from here too.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError
from optraj.planners import export_csv, ros_message, serialization
from optraj.planners.description import (
    as_joint_names,
    as_metadata,
    as_phases,
    check_phases_within,
    picklable,
    short_repr,
)
from optraj.planners.phase import Phase, back_to_back
from optraj.planners.piecewise import (
    built_pieces,
    hermite_pieces,
    joined,
    validated_pieces,
    with_derivatives,
)
from optraj.planners.sampling import (
    MAX_RATE,
    TIME_TOLERANCE,
    TrajectorySample,
    evaluate,
    hold_after_end,
    sampling_rate,
    time_grid,
    times_within,
)
from optraj.planners.serialization import MAX_METADATA_DEPTH
from optraj.validation import (
    MAX_DURATION,
    as_choice,
    as_count,
    as_flag,
    as_positive,
    as_vector,
    ndim_of,
)

__all__ = [
    "MAX_DOF",
    "MAX_JSON_BYTES",
    "MAX_METADATA_DEPTH",
    "MAX_RATE",
    "TIME_TOLERANCE",
    "Phase",
    "Trajectory",
    "TrajectorySample",
    "fitted_to",
    "sampling_rate",
]

if TYPE_CHECKING:
    from optraj.robots import Robot

FloatArray = NDArray[np.float64]

#: Most joints a trajectory may have (arrays are (samples, dof)).
MAX_DOF = 1000
#: Largest trajectory JSON read [bytes] (text or file): a 10,000-segment quintic of 7 joints
#: takes about 10 MB; beyond this a file is not one of ours.
MAX_JSON_BYTES = 64 * 2**20


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
        knots, coeffs = validated_pieces(breakpoints, coefficients)
        self._build: Callable[[], tuple[ArrayLike, ArrayLike]] | None = None
        self._pieces: tuple[FloatArray, list[FloatArray]] | None = (knots, [coeffs])
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
        names = as_joint_names(joint_names, n)
        windows = as_phases(phases)
        data = as_metadata(metadata)
        self._dof = n
        self.joint_names: tuple[str, ...] = names
        self.phases: tuple[Phase, ...] = windows
        check_phases_within(self.phases, self.duration)
        self.metadata: dict[str, Any] = data

    def _expand(self) -> tuple[FloatArray, list[FloatArray]]:
        """Breakpoints and coefficients of q (of its derivatives too once sampled), built once."""
        pieces = self._pieces
        if pieces is None:
            # Without polynomials a trajectory always has its builder.
            build = cast(Callable[[], tuple[ArrayLike, ArrayLike]], self._build)
            knots, coeffs = built_pieces(build, self._duration, self._dof)
            pieces = (knots, [coeffs])
            self._pieces = pieces
            self._build = None
        return pieces

    @property
    def _knots(self) -> FloatArray:
        return self._expand()[0]

    @property
    def _coeffs(self) -> list[FloatArray]:
        """Coefficients of q and of its first three time derivatives (derived once)."""
        polynomials = self._expand()[1]
        if len(polynomials) < 4:
            polynomials[:] = with_derivatives(polynomials[0])
        return polynomials

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
        state["metadata"] = picklable(self.metadata)
        return state

    # ---------------------------------------------------------------------- properties

    @property
    def breakpoints(self) -> FloatArray:
        """Segment boundaries [s], shape (K + 1,) (read-only)."""
        return self._knots

    @property
    def coefficients(self) -> FloatArray:
        """Position polynomial coefficients, shape (K, d + 1, n) (read-only)."""
        return self._expand()[1][0]

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
        return int(self._expand()[1][0].shape[1] - 1)

    def __repr__(self) -> str:
        planner = self.metadata.get("planner", "?")
        phases = ", ".join(p.name for p in self.phases) or "-"
        # A deferred trajectory is not built just to be shown.
        segments = "deferred" if self._pieces is None else str(len(self._pieces[0]) - 1)
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

    def sample(self, t: ArrayLike, *, hold: bool = False) -> TrajectorySample:
        """Joint positions, velocities, accelerations and jerks at the given times.

        At a breakpoint the segment that starts there is used (values are right-continuous),
        except at the final time.

        Args:
            t: One time or an array of times [s], within [0, duration].
            hold: Accept times past the end and hold the final state there, as the Robotics
                Toolbox and MoveIt do: the final position with zero velocity, acceleration
                and jerk (also when the trajectory ends in motion, as a strike's follow-through
                may: its velocity then drops to 0 after the end, a controller holding its last
                set point). At the end itself the trajectory's own values are kept.

        Returns:
            The sample; arrays of shape (m, n) for m times, (n,) for one time.

        Raises:
            InvalidInputError: A time is not finite, lies before 0, or (without ``hold``) lies
                after the duration; the message names the time and the duration.
        """
        scalar = ndim_of(t) == 0
        times = times_within(t, self.duration, hold=as_flag(hold, "hold"))
        values = evaluate(self._knots, self._coeffs, np.minimum(times, self.duration))
        values = hold_after_end(values, times > self.duration)
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
        return time_grid(self.duration, hz, self._knots if with_breakpoints else None)

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
        return cls(*hermite_pieces(times, q, qd, qdd), **kwargs)

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
        _check_groups(phases)
        parts = [piece for _, pieces in phases for piece in pieces]
        if not parts:
            raise InvalidInputError("a sequence needs at least one piece", name="phases")
        windows = back_to_back(
            [(name, sum(piece.duration for piece in pieces)) for name, pieces in phases]
        )
        whole = parts[0].then(*parts[1:])
        return cls(
            whole.breakpoints,
            whole.coefficients,
            joint_names=joint_names if joint_names is not None else parts[0].joint_names,
            phases=windows,
            metadata=metadata or {},
        )

    def then(self, *others: Trajectory, metadata: Mapping[str, Any] | None = None) -> Trajectory:
        """This trajectory followed by others, each shifted to start where the previous ends.

        Degrees are raised to the highest one; phases are shifted along. Continuity between
        the pieces is not enforced: a mismatch stays visible to the checker.
        """
        _check_joinable(self, others)
        knots, coeffs, phases = joined((self, *others))
        merged = dict(metadata) if metadata is not None else dict(self.metadata)
        return Trajectory(
            knots,
            coeffs,
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

    # The exact JSON form, each a function of serialization taking the trajectory first.
    to_dict = serialization.trajectory_dict
    from_dict = classmethod(serialization.from_dict)
    to_json = serialization.to_json

    @classmethod
    def from_json(cls, source: str | Path) -> Trajectory:
        """Read a trajectory from JSON text or from a file path.

        Raises:
            InvalidInputError: No such file, one that cannot be read, text over
                MAX_JSON_BYTES, not valid JSON (nested too deeply, a number too long) or not
                an optraj trajectory; an error in a file names it.
        """
        data = serialization.read_json(source, MAX_JSON_BYTES)
        try:
            return cls.from_dict(data)
        except InvalidInputError as exc:
            if serialization.is_json_text(source):
                raise
            named = f"{str(source)!r}: {exc}"
            raise InvalidInputError(named, name=exc.name, value=exc.value) from exc

    # The sampled formats, functions of their modules taking the trajectory first.
    to_csv = export_csv.to_csv
    from_csv = classmethod(export_csv.from_csv)
    to_ros = ros_message.to_ros
    to_ros_yaml = ros_message.to_ros_yaml
    from_ros = classmethod(ros_message.from_ros)

    def plot(self, **kwargs: Any) -> Any:
        """Plot this trajectory: ``planners.plot.plot_trajectory(self, **kwargs)``.

        matplotlib is imported on this first call only, so that the trajectory type stays
        headless.

        Args:
            **kwargs: Passed on to :func:`optraj.planners.plot.plot_trajectory`.

        Returns:
            What ``plot_trajectory`` returns (its matplotlib figure).
        """
        from optraj.planners.plot_trajectory import plot_trajectory

        return plot_trajectory(self, **kwargs)


def _check_groups(phases: object) -> None:
    """Refuse anything but ``(name, [Trajectory, ...])`` pairs for :meth:`Trajectory.sequence`."""
    if not isinstance(phases, (list, tuple)) or not all(
        isinstance(group, (list, tuple))
        and len(group) == 2
        and isinstance(group[0], str)
        and isinstance(group[1], (list, tuple))
        and all(isinstance(piece, Trajectory) for piece in group[1])
        for group in phases
    ):
        raise InvalidInputError(
            f"phases must be (name, [Trajectory, ...]) pairs, got {short_repr(phases)}",
            name="phases",
        )


def _check_joinable(first: Trajectory, others: Sequence[object]) -> None:
    """Refuse what :meth:`Trajectory.then` cannot join to ``first``: no trajectory, other dof."""
    for piece in others:
        if not isinstance(piece, Trajectory):
            raise InvalidInputError(
                f"then() joins planners.Trajectory objects, got {short_repr(piece)}",
                name="others",
            )
        if piece.dof != first.dof:
            raise InvalidInputError(
                f"cannot join trajectories of {first.dof} and {piece.dof} joints",
                name="others",
            )


def fitted_to(trajectory: object, robot: Robot) -> Trajectory:
    """``trajectory``, checked to be a :class:`Trajectory` of ``robot``'s joint count.

    Raises:
        InvalidInputError: Not a Trajectory, or another joint count than the robot's.
    """
    if not isinstance(trajectory, Trajectory):
        raise InvalidInputError(
            f"trajectory must be a planners.Trajectory, got {type(trajectory).__name__}",
            name="trajectory",
        )
    if trajectory.dof != robot.dof:
        raise InvalidInputError(
            f"the trajectory has {trajectory.dof} joints, robot {robot.name!r} has {robot.dof}",
            name="trajectory",
        )
    return trajectory
