"""What the array functions return: samples of a profile, shaped like the Robotics Toolbox's.

The Robotics Toolbox for Python returns a ``Trajectory`` with ``t``, ``q``, ``qd`` and ``qdd``
(also named ``s``, ``sd``, ``sdd``) and ``istime``; :class:`SampledProfile` has the same names,
plus ``trajectory``: the same motion as an optraj :class:`~optraj.planners.Trajectory`,
continuous in time, for the checker, the controllers and the exports.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError
from optraj.planners.arrays.inputs import TimeBase
from optraj.planners.trajectory import Trajectory

__all__ = ["SampledProfile", "sample_fields"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class SampledProfile:
    """Positions, velocities and accelerations of a profile at given times.

    The unit of time is the unit of ``t``: seconds when a time vector was given
    (``istime``), else one step (``quintic``, ``trapezoidal``, ``mtraj``) or the normalised
    time of [0, 1] (``jtraj``); velocities and accelerations are per that unit and its square.

    Attributes:
        name: The function that made it: ``"quintic"``, ``"trapezoidal"``, ``"mtraj"``,
            ``"jtraj"`` or ``"mstraj"``.
        t: Sample times, shape (m,), in the unit of time above.
        q: Positions [rad or m, the unit of q0], shape (m,) for a scalar profile, (m, n) for
            n joints.
        qd: Velocities [unit of q per unit of t], shape of q.
        qdd: Accelerations [unit of q per unit of t squared], shape of q.
        istime: Whether ``t`` is time in seconds (a time vector or ``dt`` was given).
        trajectory: The profile as an optraj Trajectory over [0, t[-1]] in the unit of t
            (one joint for a scalar profile); ``trajectory.sample(t)`` gives the samples.
    """

    name: str
    t: FloatArray
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    istime: bool
    trajectory: Trajectory

    def __post_init__(self) -> None:
        for field in ("t", "q", "qd", "qdd"):
            getattr(self, field).setflags(write=False)

    @property
    def s(self) -> FloatArray:
        """Positions: the Robotics Toolbox's other name for ``q``."""
        return self.q

    @property
    def sd(self) -> FloatArray:
        """Velocities: the Robotics Toolbox's other name for ``qd``."""
        return self.qd

    @property
    def sdd(self) -> FloatArray:
        """Accelerations: the Robotics Toolbox's other name for ``qdd``."""
        return self.qdd

    @property
    def naxes(self) -> int:
        """Number of axes (joints): 1 for a scalar profile."""
        return 1 if self.q.ndim == 1 else int(self.q.shape[1])

    def __len__(self) -> int:
        """Number of samples m."""
        return int(self.q.shape[0])

    def __repr__(self) -> str:
        unit = "s" if self.istime else "steps"
        return (
            f"{type(self).__name__}({self.name!r}: {len(self)} samples x {self.naxes} axes, "
            f"t in [{self.t[0]:.6g}, {self.t[-1]:.6g}] {unit})"
        )


def sample_fields(
    trajectory: Trajectory, base: TimeBase, *, scalar: bool
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """``(t, q, qd, qdd)`` of ``trajectory`` at the times of ``base``.

    Args:
        trajectory: The profile, over [0, base.end].
        base: The sample times.
        scalar: Return q, qd, qdd of shape (m,) (a one-joint trajectory) instead of (m, n).

    Raises:
        InvalidInputError: A sample is not finite (the values overflow double precision).
    """
    with np.errstate(over="ignore", invalid="ignore"):  # overflow is reported below
        sample = trajectory.sample(base.times)
    q, qd, qdd = (
        np.array(v[:, 0] if scalar else v, dtype=float) for v in (sample.q, sample.qd, sample.qdd)
    )
    if not all(np.isfinite(v).all() for v in (q, qd, qdd)):
        raise InvalidInputError(
            "the samples overflow double precision: positions or velocities too large for "
            f"the time span {base.end:.6g}; scale q0 and qf (or the via points) down",
            name="q0",
        )
    return base.times.copy(), q, qd, qdd
