"""What the plan plots share before drawing: labelled plans, checked inputs, samples, bands.

>>> plans = named({"cubic": cubic, "LSPB": lspb})      # {label: Trajectory}
>>> samples = samples_of(plans, rate=1000.0)           # {label: TrajectorySample}
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from optraj.errors import InvalidInputError
from optraj.planners.plot_style import BAR_HEIGHT, LineStyle, shade_phase
from optraj.planners.trajectory import Trajectory, TrajectorySample
from optraj.validation import as_choice

__all__ = [
    "FIELD",
    "QUANTITIES",
    "check_dof",
    "named",
    "quantities_of",
    "samples_of",
    "shade_strikes",
]

#: The joint quantities a trajectory has, in order.
QUANTITIES = ("position", "velocity", "acceleration", "jerk")
#: The :class:`TrajectorySample` field of each quantity.
FIELD = {"position": "q", "velocity": "qd", "acceleration": "qdd", "jerk": "jerk"}
#: The phase shaded in its plan's colour.
STRIKE_PHASE = "strike"


def named(trajectories: Trajectory | Mapping[str, Trajectory]) -> dict[str, Trajectory]:
    """``{label: Trajectory}``: a mapping as given, one trajectory under its planner's name.

    Raises:
        InvalidInputError: Neither a Trajectory nor a non-empty mapping of them.
    """
    if isinstance(trajectories, Trajectory):
        label = str(trajectories.metadata.get("planner", "trajectory"))
        return {label: trajectories}
    if isinstance(trajectories, Mapping) and trajectories:
        plans = dict(trajectories)
        if all(isinstance(t, Trajectory) for t in plans.values()):
            return {str(k): v for k, v in plans.items()}
    raise InvalidInputError(
        "trajectories must be a planners.Trajectory or a non-empty {label: Trajectory} mapping",
        name="trajectories",
    )


def check_dof(plans: Mapping[str, Trajectory], dof: int, what: str) -> None:
    """Raise unless every plan has ``dof`` joints (``what`` names whose count that is).

    Raises:
        InvalidInputError: A plan with another joint count; names it and both counts.
    """
    for label, trajectory in plans.items():
        if trajectory.dof != dof:
            raise InvalidInputError(
                f"trajectory {label!r} has {trajectory.dof} joints, {what} {dof}",
                name="trajectories",
            )


def quantities_of(quantities: Sequence[str], known: Sequence[str]) -> list[str]:
    """The panels asked for, each one of ``known``, in order.

    Raises:
        InvalidInputError: A single string (it would be read letter by letter), or none.
        UnknownNameError: An unknown quantity; lists the known ones.
    """
    if isinstance(quantities, str):
        raise InvalidInputError(
            f"quantities must be a sequence of names, got {quantities!r}; "
            f"write ({quantities!r},) for one",
            name="quantities",
        )
    wanted = list(quantities)
    if not wanted:
        raise InvalidInputError(
            f"quantities must name at least one of {tuple(known)}", name="quantities"
        )
    for quantity in wanted:
        as_choice(quantity, "plotted quantity", known)
    return wanted


def samples_of(plans: Mapping[str, Trajectory], rate: float) -> dict[str, TrajectorySample]:
    """Each plan sampled at ``rate`` [Hz], with every breakpoint and the instant before it."""
    return {label: t.sample(t.times(rate)) for label, t in plans.items()}


def shade_strikes(
    ax: Any, plans: Mapping[str, Trajectory], styles: Mapping[str, LineStyle]
) -> None:
    """Each plan's strike phase as a band and a bar in the plan's colour.

    The bars go in rows along the bottom, one per plan with a strike; the y-range is
    stretched downwards so that they lie under the data, never on it. Call after drawing.
    """
    row = 0
    for label, trajectory in plans.items():
        windows = [p for p in trajectory.phases if p.name == STRIKE_PHASE]
        for phase in windows:
            shade_phase(ax, phase.t_start, phase.t_end, styles[label], row)
        row += bool(windows)
    if row:
        low, high = ax.get_ylim()
        ticks = [tick for tick in ax.get_yticks() if low <= tick <= high]
        share = BAR_HEIGHT * row + 0.01  # of the stretched range, under the old bottom
        ax.set_ylim(low - share * (high - low) / (1.0 - share), high)
        ax.set_yticks(ticks)  # none in the bars' room: no value is drawn there
