"""Named NLP parameters: the values a compiled NLP reads, and where they sit in its ``p``.

A :class:`ParameterLayout` lists one NLP's parameters by name and size: the objective's
``time_scale`` first, then those of its task rows (:mod:`planners.ocp.task_rows`), then the
coefficients of linear torque rows (``torque``). The NLP's expressions take each parameter by
name (:meth:`ParameterLayout.symbols`) and a problem's values go in by name
(:meth:`ParameterLayout.vector`), so nothing depends on a parameter's position.

Example::

    layout = ParameterLayout((("time_scale", 1), ("speed", 1)))
    p = layout.vector(speed=1.2)        # time_scale 1 when not given
    layout.value(p, "speed")            # array([1.2])
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.validation import as_vector, ndim_of

FloatArray = NDArray[np.float64]

#: Values of parameters a vector is given none for: ``time_scale`` 1 [s], any other 0.
DEFAULTS = {"time_scale": 1.0}


class ParameterLayout:
    """Where each named parameter sits in an NLP's parameter vector ``p``.

    Args:
        entries: ``(name, size)`` of each parameter, in order.

    Raises:
        InvalidInputError: A name given twice.
    """

    def __init__(self, entries: Sequence[tuple[str, int]]) -> None:
        self.entries = tuple((str(name), int(size)) for name, size in entries)
        names = [name for name, _ in self.entries]
        twice = sorted({name for name in names if names.count(name) > 1})
        if twice:
            raise InvalidInputError(f"NLP parameter {twice[0]!r} is given twice", name=twice[0])
        self.slices: dict[str, slice] = {}
        start = 0
        for name, size in self.entries:
            self.slices[name] = slice(start, start + size)
            start += size
        #: Length of the parameter vector.
        self.size = start

    def __repr__(self) -> str:
        """The entries."""
        return f"ParameterLayout({self.entries!r})"

    @property
    def names(self) -> tuple[str, ...]:
        """The parameters' names, in order."""
        return tuple(name for name, _ in self.entries)

    def symbols(self, p: Any) -> dict[str, Any]:
        """Each parameter's part of the symbolic vector ``p`` (CasADi SX), by name."""
        return {name: p[index] for name, index in self.slices.items()}

    def value(self, p: FloatArray, name: str) -> FloatArray:
        """The value of parameter ``name`` in the vector ``p``.

        Raises:
            UnknownNameError: A name that is not one of the layout's.
        """
        if name not in self.slices:
            raise UnknownNameError("NLP parameter", name, list(self.names))
        return np.asarray(p, dtype=float)[self.slices[name]]

    def vector(self, **values: Any) -> FloatArray:
        """The parameter vector of these values; missing entries are :data:`DEFAULTS` or 0.

        Raises:
            UnknownNameError: A name that is not one of the layout's.
            InvalidInputError: A value that is not a finite number or vector of its size.
        """
        unknown = sorted(set(values) - set(self.slices))
        if unknown:
            raise UnknownNameError("NLP parameter", unknown[0], list(self.names))
        parts = [np.zeros(0)]
        for name, size in self.entries:
            value = values.get(name, np.full(size, DEFAULTS.get(name, 0.0)))
            scalar = ndim_of(value) == 0
            parts.append(as_vector(np.reshape(value, -1) if scalar else value, name, size))
        return np.concatenate(parts)
