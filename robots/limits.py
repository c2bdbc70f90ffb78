"""Joint limits of a robot: position, velocity, acceleration, jerk and effort."""

from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, replace
from types import MappingProxyType

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, JointLimitError, UnknownNameError
from optraj.validation import as_batch, as_choice, as_count, as_fraction, as_number, as_vector

__all__ = ["JointLimits"]

FloatArray = NDArray[np.float64]

_ARRAY_FIELDS = ("lower", "upper", "velocity", "acceleration", "jerk", "effort")

#: Units of each limited quantity, by joint kind ("rad" for revolute, "m" for prismatic).
_UNITS = {
    "position": {"rad": "rad", "m": "m"},
    "velocity": {"rad": "rad/s", "m": "m/s"},
    "acceleration": {"rad": "rad/s^2", "m": "m/s^2"},
    "jerk": {"rad": "rad/s^3", "m": "m/s^3"},
    "effort": {"rad": "N m", "m": "N"},
}


@dataclass(frozen=True, eq=False)
class JointLimits:
    """Box limits of every joint, validated when built.

    Velocity, acceleration, jerk and effort limits are symmetric: the joint may move in
    ``[-limit, +limit]``.

    Attributes:
        names: Joint names, length n.
        kinds: ``"rad"`` for a revolute joint, ``"m"`` for a prismatic one, length n.
        lower: Lower position limits [rad or m], shape (n,).
        upper: Upper position limits [rad or m], shape (n,).
        velocity: Speed limits [rad/s or m/s], shape (n,).
        acceleration: Acceleration limits [rad/s^2 or m/s^2], shape (n,).
        jerk: Jerk limits [rad/s^3 or m/s^3], shape (n,).
        effort: Torque or force limits [N m or N], shape (n,).
    """

    names: tuple[str, ...]
    kinds: tuple[str, ...]
    lower: FloatArray
    upper: FloatArray
    velocity: FloatArray
    acceleration: FloatArray
    jerk: FloatArray
    effort: FloatArray

    def __post_init__(self) -> None:
        if not isinstance(self.names, (list, tuple)) or not all(
            isinstance(name, str) for name in self.names
        ):
            raise InvalidInputError(
                f"names must be a sequence of joint names, got {self.names!r}", name="names"
            )
        n = len(self.names)
        object.__setattr__(self, "names", tuple(self.names))
        object.__setattr__(self, "kinds", tuple(self.kinds))
        if len(self.kinds) != n or any(kind not in ("rad", "m") for kind in self.kinds):
            raise InvalidInputError(
                f"kinds must hold 'rad' or 'm' for each of the {n} joints, got {self.kinds}",
                name="kinds",
            )
        for name in _ARRAY_FIELDS:
            array = as_vector(getattr(self, name), name, n).copy()
            array.setflags(write=False)
            object.__setattr__(self, name, array)
        for i, joint in enumerate(self.names):
            if not self.lower[i] < self.upper[i]:
                raise InvalidInputError(
                    f"joint {joint!r}: lower position limit {self.lower[i]:.6g} must be below "
                    f"the upper limit {self.upper[i]:.6g}",
                    name="lower",
                )
        for name in ("velocity", "acceleration", "jerk", "effort"):
            values = getattr(self, name)
            bad = np.flatnonzero(values <= 0.0)
            if bad.size:
                i = int(bad[0])
                raise InvalidInputError(
                    f"joint {self.names[i]!r}: {name} limit must be > 0, got {values[i]:.6g}",
                    name=name,
                )

    def __getstate__(self) -> dict[str, object]:
        """The fields only, for pickling: cached views (``floats``) are rebuilt on demand."""
        state = self.__dict__.copy()
        state.pop("floats", None)
        return state

    @functools.cached_property
    def floats(self) -> Mapping[str, tuple[float, ...]]:
        """Each limit array as a tuple of Python floats, keyed by field name.

        Keys are ``lower``, ``upper``, ``velocity``, ``acceleration``, ``jerk`` and
        ``effort`` (units as the arrays). For libraries that take lists, and for per-joint
        loops where NumPy scalars cost more than the work; computed once (limits are frozen).
        """
        return MappingProxyType(
            {name: tuple(getattr(self, name).tolist()) for name in _ARRAY_FIELDS}
        )

    @property
    def n(self) -> int:
        """Number of joints."""
        return len(self.names)

    def unit(self, quantity: str, joint: int) -> str:
        """Unit of ``quantity`` (position, velocity, ...) for joint index ``joint``."""
        as_choice(quantity, "limited quantity", _UNITS)
        if not 0 <= joint < self.n:
            raise InvalidInputError(
                f"joint index {joint} is out of range for {self.n} joints", name="joint"
            )
        return _UNITS[quantity][self.kinds[joint]]

    def contains(self, q: ArrayLike, tolerance: float = 0.0) -> bool | NDArray[np.bool_]:
        """Whether configurations lie within the position limits.

        Args:
            q: Joint positions [rad or m], shape (n,) or (m, n).
            tolerance: Allowed excess beyond each limit [rad or m].

        Returns:
            One bool for a single configuration, or a bool array of shape (m,).
        """
        batch, single = as_batch(q, "q", self.n)
        tolerance = _tolerance(tolerance)
        inside = np.all(
            (batch >= self.lower - tolerance) & (batch <= self.upper + tolerance), axis=1
        )
        return bool(inside[0]) if single else inside

    def check_position(self, q: ArrayLike, tolerance: float = 0.0, context: str = "") -> None:
        """Raise if a configuration is outside the position limits.

        Args:
            q: Joint positions [rad or m], shape (n,).
            tolerance: Allowed excess beyond each limit [rad or m].
            context: Prefix for the error message, e.g. ``"IK solution"``.

        Raises:
            JointLimitError: For the joint that exceeds its limit by the most.
            InvalidInputError: Wrong shape or non-finite values.
        """
        values = as_vector(q, "q", self.n)
        tolerance = _tolerance(tolerance)
        if self.within_positions(values.tolist(), tolerance):
            return
        excess = np.maximum(self.lower - values, values - self.upper)
        worst = int(np.argmax(excess))
        if excess[worst] > tolerance:
            raise JointLimitError(
                self.names[worst],
                values[worst],
                self.lower[worst],
                self.upper[worst],
                unit=self.unit("position", worst),
                context=context,
            )

    def within_positions(self, values: list[float], tolerance: float) -> bool:
        """Whether no joint exceeds a position limit by more than ``tolerance`` [rad or m].

        The arithmetic of :meth:`check_position` on Python floats (for a few joints cheaper
        than NumPy's): ``lower - q`` and ``q - upper`` against the tolerance. A NaN or an
        infinity is never within. The caller has checked the length and the tolerance.

        Args:
            values: Joint positions [rad or m], n floats.
            tolerance: Allowed excess beyond each limit [rad or m], >= 0.
        """
        floats = self.floats
        for x, low, high in zip(values, floats["lower"], floats["upper"], strict=True):
            if not (low - x <= tolerance and x - high <= tolerance):
                return False
        return True

    def within_symmetric(self, quantity: str, values: list[float], tolerance: float) -> bool:
        """Whether no ``|value|`` exceeds its limit of ``quantity`` by more than ``tolerance``.

        Computes ``|value| - limit`` on Python floats; a NaN or an infinity is never within.

        Args:
            quantity: ``velocity``, ``acceleration``, ``jerk`` or ``effort``.
            values: One value per joint (units of the quantity), n floats.
            tolerance: Allowed excess (units of the quantity), >= 0.
        """
        for x, bound in zip(values, self.floats[quantity], strict=True):
            if not abs(x) - bound <= tolerance:
                return False
        return True

    def clip(self, q: ArrayLike) -> FloatArray:
        """Return ``q`` moved onto the nearest point of the position box (for internal seeds)."""
        return np.clip(as_vector(q, "q", self.n), self.lower, self.upper)

    def sample(self, rng: np.random.Generator, count: int) -> FloatArray:
        """Draw configurations uniformly within the position limits.

        Args:
            rng: Random generator; pass a seeded one for reproducible draws.
            count: Number of configurations, >= 0.

        Returns:
            Joint positions [rad or m], shape (count, n).
        """
        if not isinstance(rng, np.random.Generator):
            raise InvalidInputError(
                f"rng must be a numpy.random.Generator (np.random.default_rng(seed)), got "
                f"{type(rng).__name__}",
                name="rng",
            )
        return rng.uniform(self.lower, self.upper, size=(as_count(count, "count"), self.n))

    def scaled(
        self,
        factor: float,
        quantities: tuple[str, ...] = ("velocity", "acceleration", "jerk"),
    ) -> JointLimits:
        """The same limits with some symmetric ones scaled, e.g. to plan with room to spare.

        Planning within ``0.8`` of the velocity, acceleration and jerk limits leaves a tracking
        controller 20 % to correct errors with (as a velocity scaling factor does in MoveIt).

        Args:
            factor: Scale, in [1e-6, 1] [-].
            quantities: Which of ``velocity``, ``acceleration``, ``jerk``, ``effort``.

        Raises:
            InvalidInputError: A factor outside [1e-6, 1], or quantities that are not a
                tuple or list of names.
            UnknownNameError: A quantity that is not one of the four.
        """
        number = as_fraction(factor, "factor")
        symmetric = ("velocity", "acceleration", "jerk", "effort")
        if not isinstance(quantities, (list, tuple)):
            raise InvalidInputError(
                f"quantities must be a tuple of names from {', '.join(symmetric)}, e.g. "
                f"('velocity',), got {type(quantities).__name__} {quantities!r}",
                name="quantities",
            )
        for name in quantities:
            if name not in symmetric:
                raise UnknownNameError("scalable limit", str(name), symmetric)
        return replace(self, **{name: getattr(self, name) * number for name in quantities})

    def table(self) -> list[dict[str, object]]:
        """One dict per joint with its name, unit and every limit, for printing."""
        return [
            {
                "joint": self.names[i],
                "unit": self.kinds[i],
                "lower": float(self.lower[i]),
                "upper": float(self.upper[i]),
                "velocity": float(self.velocity[i]),
                "acceleration": float(self.acceleration[i]),
                "jerk": float(self.jerk[i]),
                "effort": float(self.effort[i]),
            }
            for i in range(self.n)
        ]


def _tolerance(value: float) -> float:
    """A tolerance as a finite float >= 0."""
    return as_number(value, "tolerance", minimum=0.0)
