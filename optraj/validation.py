"""Checks of user input shared by every package: shapes, finiteness, ranges.

Each function converts its argument to a float NumPy array and raises
:class:`optraj.errors.InvalidInputError` naming the argument, the value and what was expected.
Imports nothing from the project but :mod:`optraj.errors`.
"""

from __future__ import annotations

import math
import reprlib
from collections.abc import Iterable
from typing import cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from optraj.errors import InvalidInputError, UnknownNameError

__all__ = [
    "as_array",
    "as_batch",
    "as_choice",
    "as_count",
    "as_duration",
    "as_flag",
    "as_fraction",
    "as_number",
    "as_positive",
    "as_transform",
    "as_vector",
    "ndim_of",
]

FloatArray = NDArray[np.float64]


def _describe(value: object) -> str:
    text = np.array2string(np.asarray(value), precision=4, threshold=12)
    return text if len(text) < 120 else text[:117] + "..."


def _holds_a_bool(value: list[object] | tuple[object, ...]) -> bool:
    """Whether a nested list or tuple holds a bool anywhere."""
    return any(
        isinstance(item, (bool, np.bool_))
        or (isinstance(item, (list, tuple)) and _holds_a_bool(item))
        for item in value
    )


def as_array(value: ArrayLike, name: str, shape: tuple[int | None, ...]) -> FloatArray:
    """Return ``value`` as a finite float array of the given shape.

    Args:
        value: Anything NumPy can turn into an array.
        name: Argument name used in the error message.
        shape: Expected shape; ``None`` in a position accepts any length there.

    Raises:
        InvalidInputError: Not numeric, wrong shape, or NaN/inf entries.
    """
    try:
        raw = np.asarray(value)
        if raw.dtype.kind not in "iuf":  # no bools, strings or objects posing as numbers
            raise TypeError(raw.dtype)
        if isinstance(value, (list, tuple)) and _holds_a_bool(value):
            raise TypeError("bool")  # NumPy reads [0.5, True] as [0.5, 1.0]
        array = np.array(raw, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise InvalidInputError(
            f"{name} must be a numeric array of shape {_wanted(shape)}, got {reprlib.repr(value)}",
            name=name,
            value=value,
        ) from exc
    if array.ndim != len(shape) or any(
        want is not None and got != want for got, want in zip(array.shape, shape, strict=True)
    ):
        raise InvalidInputError(
            f"{name} must have shape {_wanted(shape)}, got shape {array.shape}",
            name=name,
            value=value,
        )
    if not np.all(np.isfinite(array)):
        raise InvalidInputError(
            f"{name} must be finite, got {_describe(array)}", name=name, value=value
        )
    return array


def _wanted(shape: tuple[int | None, ...]) -> str:
    """A shape as error messages write it: ``(3,)``, ``(any, 7)``."""
    sizes = ["any" if s is None else str(s) for s in shape]
    return "(" + ", ".join(sizes) + ("," if len(sizes) == 1 else "") + ")"


#: NumPy's float64 type, compared by identity on the fast path of :func:`as_vector`.
_FLOAT64 = np.dtype(np.float64)


def as_vector(value: ArrayLike, name: str, size: int | None = None) -> FloatArray:
    """Return ``value`` as a finite 1-D float array, of length ``size`` if given.

    A float64 array or a list of Python floats of the right length is checked element by
    element in Python, which for a few joints costs less than NumPy's reductions; anything
    else (or anything that fails) takes :func:`as_array`, which gives the same result or
    error.
    """
    if type(value) is np.ndarray:
        if (
            value.dtype is _FLOAT64
            and value.ndim == 1
            and (size is None or len(value) == size)
            and all(map(math.isfinite, value.tolist()))
        ):
            return value.copy()
    elif type(value) is list:
        items = cast(list[float], value)  # each item is checked to be a float below
        if (
            (size is None or len(items) == size)
            and all(type(x) is float for x in items)
            and all(map(math.isfinite, items))
        ):
            return np.array(items, dtype=float)
    return as_array(value, name, (size,))


def ndim_of(value: object) -> int:
    """The number of dimensions of ``value`` as NumPy reads it, -1 for ragged lists.

    :func:`as_array` refuses ragged lists with a typed error; this lets a caller choose a
    shape before that without NumPy's own ValueError.
    """
    try:
        return int(np.ndim(value))  # type: ignore[arg-type]  # any object: NumPy decides
    except ValueError:
        return -1


def as_batch(value: ArrayLike, name: str, size: int) -> tuple[FloatArray, bool]:
    """Accept one vector of length ``size`` or a stack of them.

    Returns:
        The values as shape (m, size), and whether a single vector was given.

    Raises:
        InvalidInputError: Wrong shape or non-finite entries.
    """
    if ndim_of(value) == 1:
        return as_array(value, name, (size,))[None, :], True
    return as_array(value, name, (None, size)), False


#: Largest count any argument may give unless its own bound is tighter: a count is a loop
#: or an allocation, and beyond this one ends in memory exhaustion, not in a result.
MAX_COUNT = 10_000_000


def as_count(value: object, name: str, minimum: int = 0, maximum: int | None = MAX_COUNT) -> int:
    """Return ``value`` as an int in [``minimum``, ``maximum``] (no bools, no fractions).

    ``maximum=None`` leaves it unbounded (a seed).
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InvalidInputError(
            f"{name} must be an integer >= {minimum}, got {value!r}", name=name, value=value
        )
    if maximum is not None and value > maximum:
        raise InvalidInputError(
            f"{name} must be an integer <= {maximum}, got {value!r}", name=name, value=value
        )
    return int(value)


def as_flag(value: object, name: str) -> bool:
    """Return ``value`` as a bool: a True/False switch (an int or a string is refused)."""
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidInputError(f"{name} must be True or False, got {value!r}", name=name)
    return bool(value)


def _with_unit(number: float, unit: str) -> str:
    return f"{number:.6g} {unit}" if unit else f"{number:.6g}"


def as_number(
    value: object,
    name: str,
    unit: str = "",
    *,
    minimum: float | None = None,
    maximum: float | None = None,
    open_minimum: bool = False,
) -> float:
    """Return ``value`` as a finite float in [``minimum``, ``maximum``].

    Args:
        value: An int or float (a NumPy scalar or 0-d array too); bools and strings are refused.
        name: Argument name used in the error message.
        unit: Unit named in the error message, e.g. ``"s"`` or ``"m/s"``.
        minimum: Smallest value accepted, or None for no lower bound.
        maximum: Largest value accepted, or None for no upper bound.
        open_minimum: Refuse ``minimum`` itself (the range is (minimum, maximum]).

    Raises:
        InvalidInputError: Not a finite number, or outside the range; the message names the
            value, the bound and the unit.
    """
    if (type(value) is float or type(value) is np.float64) and math.isfinite(value):
        number = float(value)  # the common case, without NumPy
    else:
        number = float(as_array(value, name, ()))  # type: ignore[arg-type]
    if minimum is not None and (number <= minimum if open_minimum else number < minimum):
        sign = ">" if open_minimum else ">="
        raise InvalidInputError(
            f"{name} must be {sign} {_with_unit(minimum, unit)}, got {_with_unit(number, unit)}",
            name=name,
            value=value,
        )
    if maximum is not None and number > maximum:
        raise InvalidInputError(
            f"{name} must be <= {_with_unit(maximum, unit)}, got {_with_unit(number, unit)}",
            name=name,
            value=value,
        )
    return number


def as_positive(value: float, name: str, unit: str = "", maximum: float | None = None) -> float:
    """Return ``value`` as a float that is finite, > 0 and, if given, <= ``maximum``."""
    return as_number(value, name, unit, minimum=0.0, maximum=maximum, open_minimum=True)


#: Shortest and longest duration a move, a hold or a simulation may have [s]. Below a
#: microsecond the derivatives of a finite move overflow double precision (a 1 rad cubic in
#: 1e-200 s needs 1e400 rad/s^2); above a day no arm's move is meant, and sample counts at
#: any control rate run into MAX_COUNT.
MIN_DURATION = 1e-6
MAX_DURATION = 86_400.0


def as_duration(value: object, name: str = "duration") -> float:
    """Return ``value`` as a duration in [MIN_DURATION, MAX_DURATION] seconds."""
    return as_number(value, name, "s", minimum=MIN_DURATION, maximum=MAX_DURATION)


#: Smallest scale or share of a limit accepted: below it a scaled limit is numerically zero
#: for every solver we use (a 1e-300 scale makes matrices singular).
MIN_FRACTION = 1e-6


def as_fraction(value: float, name: str, smallest: float = MIN_FRACTION) -> float:
    """Return ``value`` as a float in [``smallest``, 1] (a scale or a share of a limit)."""
    number = float(as_array(value, name, ()))
    if not smallest <= number <= 1.0:
        raise InvalidInputError(
            f"{name} must be in [{smallest:.6g}, 1], got {number:.6g}", name=name, value=value
        )
    return number


def as_transform(value: ArrayLike, name: str, tolerance: float = 1e-6) -> FloatArray:
    """Return ``value`` as a 4x4 homogeneous transform with a proper rotation.

    Args:
        value: Homogeneous matrix, shape (4, 4).
        name: Argument name used in the error message.
        tolerance: Allowed deviation of R^T R from identity and of the last row.

    Raises:
        InvalidInputError: Wrong shape, non-finite, or not a rigid transform.
    """
    transform = as_array(value, name, (4, 4))
    rotation = transform[:3, :3]
    orthogonality = float(np.max(np.abs(rotation.T @ rotation - np.eye(3))))
    if orthogonality > tolerance or np.linalg.det(rotation) < 0.0:
        raise InvalidInputError(
            f"{name}[:3, :3] must be a rotation matrix (R^T R = I, det R = +1); "
            f"max |R^T R - I| = {orthogonality:.3g}, det R = {np.linalg.det(rotation):.6g}",
            name=name,
            value=value,
        )
    if np.max(np.abs(transform[3] - [0.0, 0.0, 0.0, 1.0])) > tolerance:
        raise InvalidInputError(
            f"{name}[3] must be [0, 0, 0, 1], got {_describe(transform[3])}", name=name, value=value
        )
    return transform


def as_choice(value: object, kind: str, known: Iterable[str]) -> str:
    """Return ``value`` if it is one of the names ``known`` (a str; no arrays or numbers).

    Args:
        value: The name given.
        kind: What is named, for the message, e.g. ``"solver"``.
        known: The valid names.

    Raises:
        InvalidInputError: ``value`` is not a str.
        UnknownNameError: A str that is not one of ``known`` (the closest is suggested).
    """
    names = tuple(known)
    if not isinstance(value, str):
        raise InvalidInputError(
            f"{kind} must be a name, one of {', '.join(map(repr, names))}; got "
            f"{reprlib.repr(value)}",
            name=kind,
            value=value,
        )
    if value not in names:
        raise UnknownNameError(kind, value, names)
    return value
