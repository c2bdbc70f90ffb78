"""The planners by name, per kind of problem: the one list the CLI and the benchmarks read.

A kind is the command-line name of a problem (``pool-shot``, ``paddle-strike``,
``pick-and-place``, ``point-to-point``); each kind lists, in order, the names of the planners
that plan it and how to make each one with its default options.

>>> from optraj.planners import registry
>>> registry.planner_names("paddle-strike")
('cubic', 'quintic', 'toppra', 'ruckig', 'optimal-control', 'optimal-control-jerk')
>>> planner = registry.make_planner("pool-shot", "ruckig")   # TimeOptimalStrike("ruckig")
>>> registry.options("pool-shot", "ruckig")
('samples', 'contact')
>>> planner = registry.make_planner("pool-shot", "ruckig", contact="choose")

A new planner joins every list with :func:`register_planner` (see the README's "Adding a
planner").
"""

from __future__ import annotations

import inspect
import re
from collections.abc import Callable
from functools import partial

from optraj.errors import InvalidInputError, UnknownNameError
from optraj.planners.base import Planner
from optraj.planners.ocp.optimal_control import OptimalControl
from optraj.planners.profiles.lspb import LSPB
from optraj.planners.profiles.sequencer import PickAndPlacePlanner
from optraj.planners.profiles.time_scaling import Cubic, Quintic
from optraj.planners.strike.classic_strike import ClassicStrike
from optraj.planners.strike.pull_back_strike import PullBackStrike
from optraj.planners.strike.time_optimal_strike import TimeOptimalStrike
from optraj.planners.time_optimal.ruckig_planner import Ruckig
from optraj.planners.time_optimal.toppra_planner import Toppra

__all__ = ["KINDS", "make_planner", "options", "planner_names", "register_planner"]

#: Makes a planner: with no arguments its defaults, with keywords the planner's own options.
Factory = Callable[..., Planner]

#: The kinds of problem, in the order the CLI lists them.
KINDS = ("pool-shot", "paddle-strike", "pick-and-place", "point-to-point")


def _optimal_control() -> dict[str, Factory]:
    return {
        "optimal-control": partial(OptimalControl, objective="time"),
        "optimal-control-jerk": partial(OptimalControl, objective="jerk"),
    }


_REGISTRY: dict[str, dict[str, Factory]] = {
    "pool-shot": {
        "pull-back": PullBackStrike,
        "cubic": partial(ClassicStrike, "cubic"),
        "quintic": partial(ClassicStrike, "quintic"),
        "lspb": partial(ClassicStrike, "lspb"),
        "toppra": partial(TimeOptimalStrike, "toppra"),
        "ruckig": partial(TimeOptimalStrike, "ruckig"),
        **_optimal_control(),
    },
    "paddle-strike": {
        "cubic": Cubic,
        "quintic": Quintic,
        "toppra": partial(TimeOptimalStrike, "toppra"),
        "ruckig": partial(TimeOptimalStrike, "ruckig"),
        **_optimal_control(),
    },
    "pick-and-place": {
        "cubic": lambda: PickAndPlacePlanner(Cubic()),
        "quintic": lambda: PickAndPlacePlanner(Quintic()),
        "lspb": lambda: PickAndPlacePlanner(LSPB()),
        "ruckig": lambda: PickAndPlacePlanner(Ruckig()),
    },
    "point-to-point": {
        "cubic": Cubic,
        "quintic": Quintic,
        "lspb": LSPB,
        "toppra": Toppra,
        "ruckig": Ruckig,
        **_optimal_control(),
    },
}


def _kind(kind: str) -> dict[str, Factory]:
    if kind not in _REGISTRY:
        raise UnknownNameError("problem", kind, KINDS)
    return _REGISTRY[kind]


def planner_names(kind: str) -> tuple[str, ...]:
    """The names of the planners of a kind of problem, in registration order.

    Raises:
        UnknownNameError: An unknown kind (lists :data:`KINDS`).
    """
    return tuple(_kind(kind))


def _factory(kind: str, name: str) -> Factory:
    factories = _kind(kind)
    if name not in factories:
        raise UnknownNameError(f"planner for {kind}", name, tuple(factories))
    return factories[name]


def options(kind: str, name: str) -> tuple[str, ...]:
    """The keyword options that :func:`make_planner` passes to the planner ``name`` of ``kind``.

    Raises:
        UnknownNameError: An unknown kind or planner.
    """
    try:
        parameters = inspect.signature(_factory(kind, name)).parameters.values()
    except (TypeError, ValueError):  # a factory whose signature Python cannot read
        return ()
    return tuple(
        p.name
        for p in parameters
        if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD) and p.default is not p.empty
    )


def make_planner(kind: str, name: str, **settings: object) -> Planner:
    """A new planner called ``name`` for problems of ``kind``.

    Args:
        kind: One of :data:`KINDS`.
        name: One of :func:`planner_names` of that kind.
        **settings: The planner's own options (:func:`options` lists them), e.g.
            ``contact="choose"`` for a strike planner; its defaults otherwise.

    Raises:
        UnknownNameError: An unknown kind, or a planner that does not plan it (lists the
            ones that do).
        InvalidInputError: A setting the planner does not take (lists the ones it does).
    """
    factory = _factory(kind, name)
    unknown = sorted(set(settings) - set(options(kind, name)))
    if unknown:
        raise InvalidInputError(
            f"planner {name!r} for {kind} takes no option {unknown[0]!r}; its options are "
            f"{list(options(kind, name))}",
            name=unknown[0],
        )
    return factory(**settings)


def register_planner(kind: str, name: str, factory: Factory) -> None:
    """Add a planner to a kind's list (at its end): the CLI and the benchmarks then offer it.

    Args:
        kind: One of :data:`KINDS`.
        name: Its command-line name: lower case, words joined by ``-``.
        factory: Makes the planner with its default options when called with no arguments
            (once per use), and with the planner's own options as keywords
            (``functools.partial(MyPlanner, ...)`` or the class itself does both).

    Raises:
        UnknownNameError: An unknown kind.
        InvalidInputError: A name already taken for that kind, a name that is not lower case
            words joined by ``-``, or a factory that is not callable.
    """
    factories = _kind(kind)
    if not isinstance(name, str) or not re.fullmatch(r"[a-z0-9]+(-[a-z0-9]+)*", name):
        raise InvalidInputError(
            f"a planner name is lower-case words joined by '-', got {name!r}", name="name"
        )
    if name in factories:
        raise InvalidInputError(f"planner {name!r} is already registered for {kind}", name="name")
    if not callable(factory):
        raise InvalidInputError(
            f"factory must be callable, got {type(factory).__name__}", name="factory"
        )
    factories[name] = factory
