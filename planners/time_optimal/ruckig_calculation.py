"""Ruckig's input parameters for one move, and its offline calculation with typed errors.

:func:`ruckig_input` fills a ``ruckig.InputParameter`` field by field (``current_position``,
``target_velocity``, ``max_jerk``, ...) from validated states and :class:`robots.JointLimits`;
:func:`calculate` runs Ruckig on it with a calculator kept per thread and turns every failure
into :class:`InfeasibleError` (a state out of reach, its joint named) or :class:`SolverError`
(with Ruckig's status)::

    inp = ruckig_input(limits, q0, q1, None, synchronization=..., minimum_duration=None)
    native = calculate(inp, limits)   # a ruckig.Trajectory
"""

from __future__ import annotations

import re
import threading

import numpy as np
import ruckig
from numpy.typing import NDArray

from optraj.errors import InfeasibleError, SolverError
from optraj.robots import JointLimits

__all__ = ["USABLE_RESULTS", "calculate", "reused_input", "ruckig_error", "ruckig_input"]

FloatArray = NDArray[np.float64]

#: Results that carry a usable trajectory.
USABLE_RESULTS = (ruckig.Result.Working, ruckig.Result.Finished)


def ruckig_input(
    limits: JointLimits,
    q0: FloatArray,
    q1: FloatArray,
    states: tuple[list[float], list[float], list[float], list[float]] | None,
    *,
    synchronization: ruckig.Synchronization,
    minimum_duration: float | None,
    interface: ruckig.ControlInterface = ruckig.ControlInterface.Position,
) -> ruckig.InputParameter:
    """Ruckig's input for one move (states in the joint units, limits from ``limits``).

    Args:
        limits: Velocity, acceleration and jerk limits.
        q0: Start positions, shape (n,).
        q1: Target positions, shape (n,).
        states: Start velocities and accelerations, target velocities and accelerations,
            or None for rest at both ends (Ruckig's default).
        synchronization: Ruckig's synchronisation option.
        minimum_duration: Shortest duration [s], or None.
        interface: Ruckig's control interface.
    """
    inp = ruckig.InputParameter(limits.n)
    # Identity, cheaper than the binding's equality: an equal option that is another object
    # is set, to the value it already has.
    if interface is not ruckig.ControlInterface.Position:
        inp.control_interface = interface
    if synchronization is not ruckig.Synchronization.Time:
        inp.synchronization = synchronization
    inp.current_position = q0.tolist()
    inp.target_position = q1.tolist()
    if states is not None:
        (
            inp.current_velocity,
            inp.current_acceleration,
            inp.target_velocity,
            inp.target_acceleration,
        ) = states
    _set_limits(inp, limits)
    if minimum_duration is not None:
        inp.minimum_duration = minimum_duration
    return inp


def _set_limits(inp: ruckig.InputParameter, limits: JointLimits) -> None:
    """Set ``inp``'s velocity, acceleration and jerk limits from ``limits``."""
    floats = limits.floats
    inp.max_velocity = floats["velocity"]
    inp.max_acceleration = floats["acceleration"]
    inp.max_jerk = floats["jerk"]


#: Ruckig's defaults of the options a move sets (see reused_input).
_POSITION = ruckig.ControlInterface.Position
_TIME = ruckig.Synchronization.Time


class _Reused:
    """One thread's reused InputParameter for n joints, set up for one limits object.

    Attributes:
        limits: The limits its velocity, acceleration and jerk limits were set from.
        inp: The input.
        changed: Fields the last move set away from their defaults: ``states`` (the
            boundary velocities and accelerations), ``control_interface``,
            ``synchronization``, ``minimum_duration``.
    """

    def __init__(self, limits: JointLimits) -> None:
        self.limits = limits
        self.inp = ruckig.InputParameter(limits.n)
        _set_limits(self.inp, limits)
        self.changed: set[str] = set()


def reused_input(
    limits: JointLimits,
    q0: FloatArray,
    q1: FloatArray,
    states: tuple[list[float], list[float], list[float], list[float]] | None,
    *,
    synchronization: ruckig.Synchronization,
    minimum_duration: float | None,
    interface: ruckig.ControlInterface = ruckig.ControlInterface.Position,
) -> ruckig.InputParameter:
    """:func:`ruckig_input`'s input, in an InputParameter this thread reuses.

    Building an InputParameter and setting its limits is a sizeable part of a move's cost;
    the reused one keeps the limits while ``limits`` is the same object (limits are frozen)
    and has every other field set as a new one would have it. It is only valid
    until this thread's next call: pass it straight to :func:`calculate`, never keep it.

    Args:
        limits: Velocity, acceleration and jerk limits.
        q0: Start positions, shape (n,).
        q1: Target positions, shape (n,).
        states: Start velocities and accelerations, target velocities and accelerations,
            or None for rest at both ends.
        synchronization: Ruckig's synchronisation option.
        minimum_duration: Shortest duration [s], or None.
        interface: Ruckig's control interface.
    """
    n = limits.n
    reused = _CALCULATORS.inputs.get(n)
    if reused is None or reused.limits is not limits:
        reused = _CALCULATORS.inputs[n] = _Reused(limits)
    inp, changed = reused.inp, reused.changed
    inp.current_position = q0.tolist()
    inp.target_position = q1.tolist()
    if states is not None:
        (
            inp.current_velocity,
            inp.current_acceleration,
            inp.target_velocity,
            inp.target_acceleration,
        ) = states
        changed.add("states")
    elif "states" in changed:
        rest = [0.0] * n
        inp.current_velocity = inp.current_acceleration = rest
        inp.target_velocity = inp.target_acceleration = rest
        changed.discard("states")
    if changed or interface is not _POSITION or synchronization is not _TIME:
        # Identity, cheaper than the binding's equality (see ruckig_input).
        for name, value, default in (
            ("control_interface", interface, _POSITION),
            ("synchronization", synchronization, _TIME),
        ):
            if value is not default:
                setattr(inp, name, value)
                changed.add(name)
            elif name in changed:
                setattr(inp, name, default)
                changed.discard(name)
    if minimum_duration is not None:
        inp.minimum_duration = minimum_duration
        changed.add("minimum_duration")
    elif "minimum_duration" in changed:
        inp.minimum_duration = None
        changed.discard("minimum_duration")
    return inp


def ruckig_error(exc: Exception, limits: JointLimits) -> Exception:
    """A typed error for an exception raised inside Ruckig, its DoF index named as a joint."""
    text = str(exc).strip().removeprefix("[ruckig]").strip()
    found = re.search(r"DoF (\d+)", text)
    joint = None
    if found and int(found.group(1)) < limits.n:
        joint = limits.names[int(found.group(1))]
        text = text.replace(found.group(0), f"joint {joint!r}")
    if "exceed" in text or "undercut" in text:
        limit = "acceleration" if "acceleration limit" in text else "velocity"
        return InfeasibleError(f"ruckig: {text}", limit=limit, joint=joint)
    return SolverError("ruckig", type(exc).__name__, detail=text)


class _Calculators(threading.local):
    """Ruckig calculators (and reused inputs) by joint count, one set per thread.

    Building a calculator costs about as much as an offline calculation, which starts
    afresh from its input every time (results do not depend on earlier calls); a
    calculator holds scratch space, so threads do not share one.
    """

    def __init__(self) -> None:
        self.by_dof: dict[int, ruckig.Ruckig] = {}
        self.inputs: dict[int, _Reused] = {}


_CALCULATORS = _Calculators()


def _calculator(n: int) -> ruckig.Ruckig:
    """This thread's Ruckig calculator for n joints (offline use only)."""
    calculators = _CALCULATORS.by_dof
    calculator = calculators.get(n)
    if calculator is None:
        calculator = calculators[n] = ruckig.Ruckig(n)
    return calculator


def calculate(inp: ruckig.InputParameter, limits: JointLimits) -> ruckig.Trajectory:
    """Run Ruckig's offline calculation.

    Raises:
        InfeasibleError: Ruckig finds the input out of reach within the limits.
        SolverError: Any other Ruckig failure, with Ruckig's status.
    """
    native = ruckig.Trajectory(limits.n)
    try:
        result = _calculator(limits.n).calculate(inp, native)
    except (ruckig.RuckigError, RuntimeError) as exc:  # RuckigError is a bare Exception
        raise ruckig_error(exc, limits) from exc
    except ValueError as exc:  # a status the binding's Result enum lacks, e.g. -101
        raise SolverError(
            "ruckig",
            str(exc).split()[0],
            detail="Ruckig returned a status its Python binding does not name (-101: the "
            "duration exceeds Ruckig's numerical range, about 7.6e3 s)",
        ) from exc
    if result not in USABLE_RESULTS:
        raise SolverError(
            "ruckig",
            result.name,
            detail="no trajectory within the velocity, acceleration and jerk limits was found",
        )
    return native
