"""Error lines of the ``optraj`` command that name the option at fault.

The library names its arguments (``speed must be > 0 m/s``, ``x must be <= 0.85 m``); on the
command line the user typed ``--speed`` or ``--x``. :func:`error_line` finds the option an
error is about, from the error's own fields (an :class:`~optraj.errors.InvalidInputError`'s
``name``, an :class:`~optraj.errors.UnknownNameError`'s ``kind``, a file name) or from what
kind of error it is (an unreachable or out-of-workspace ball, a strike too fast), and puts it
first the way argparse does: ``argument --speed: speed must be > 0 m/s, got -1 m/s``.
"""

from __future__ import annotations

import argparse
from collections.abc import Mapping

from optraj.errors import (
    InfeasibleError,
    InvalidInputError,
    JointLimitError,
    UnknownNameError,
    UnreachableError,
    WorkspaceError,
)

__all__ = ["error_line", "option_flags"]

#: Library argument names that differ from the option's destination.
_ALIASES = {"heading_deg": "heading", "factor": "limit_scale", "path": "out"}


def option_flags(parser: argparse.ArgumentParser) -> dict[str, str]:
    """The options of ``parser`` by destination: ``{"limit_scale": "--limit-scale", ...}``.

    Positional arguments are left out: their words are in the messages already.
    """
    return {
        action.dest: max(action.option_strings, key=len)
        for action in parser._actions
        if action.option_strings and action.dest not in ("help", "version")
    }


def _key(name: object) -> str:
    """An argument name as an option destination: ``--q-goal`` and ``q_goal`` are ``q_goal``."""
    key = str(name).lstrip("-").replace("-", "_")
    return _ALIASES.get(key, key)


def _candidates(exc: BaseException, values: Mapping[str, object]) -> list[str]:
    """The destinations an error may be about, the most likely first."""
    keys: list[str] = []
    name = getattr(exc, "name", None)
    if isinstance(exc, UnknownNameError):
        keys.append(_key(exc.kind.split()[0]))
    elif isinstance(exc, InvalidInputError) and name is not None:
        keys.append(_key(name))
    elif isinstance(exc, JointLimitError):
        keys.append(_key(str(exc).split(":")[0]))  # "q_goal: joint 'j1' position ..."
    elif isinstance(exc, (WorkspaceError, UnreachableError)):
        keys += ["ball", "heading"]  # a ball out of reach, or a shot the cue cannot make
    elif isinstance(exc, InfeasibleError):
        # A strike too fast for the limits, or a move too short for them.
        strike = exc.max_speed is not None or "strike" in str(exc)
        keys += ["speed"] if strike else ["duration", "limit_scale"]
    elif isinstance(exc, OSError) and exc.filename is not None:
        keys += [key for key, value in values.items() if _same_file(value, exc.filename)]
    return keys


def _same_file(value: object, filename: object) -> bool:
    """Whether the file an OSError names is (or grows from) an option's value."""
    return isinstance(value, str) and bool(value) and str(filename).startswith(value)


def error_line(
    exc: BaseException,
    message: str,
    flags: Mapping[str, str],
    values: Mapping[str, object],
) -> str:
    """``message``, led by ``argument --option:`` when the error is about an option.

    Args:
        exc: The error.
        message: Its text, on one line.
        flags: The command's options by destination (:func:`option_flags`).
        values: The parsed arguments by destination (to tell which options were given).

    Returns:
        The message unchanged when it names the option already or no option is at fault.
    """
    keys = [key for key in _candidates(exc, values) if key in flags]
    given = [key for key in keys if values.get(key) is not None]
    named = (given or keys)[:2]
    if not named or any(flags[key] in message for key in named):
        return message
    message = message.removeprefix(f"{named[0]}: ")  # "q_goal: joint ..." says it again
    return f"argument {'/'.join(flags[key] for key in named)}: {message}"
