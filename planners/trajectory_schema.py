"""The JSON Schema (draft 2020-12) of the ``optraj.trajectory/1`` files that ``to_json`` writes.

The schema ships with the package as ``schema/optraj.trajectory-1.schema.json``, so that other
programs can check a file without optraj's reader:

>>> from optraj.planners.trajectory_schema import load_schema
>>> load_schema()["properties"]["format"]["const"]
'optraj.trajectory/1'

:func:`validate_trajectory_data` checks data against it with the ``jsonschema`` package (in
optraj's ``test`` extra). ``Trajectory.from_dict`` does not need it: it checks every field
itself, including what a schema cannot say (breakpoints increasing, shapes agreeing).
"""

from __future__ import annotations

import functools
import json
from importlib import resources
from typing import Any

from optraj.errors import InvalidInputError, MissingDependencyError
from optraj.planners.serialization import FORMAT

__all__ = ["SCHEMA_FILE", "load_schema", "validate_trajectory_data"]

#: Where the schema lies in the ``optraj.planners`` package.
SCHEMA_FILE = "schema/optraj.trajectory-1.schema.json"


@functools.cache
def _schema_text() -> str:
    """The schema file's text, read once."""
    return resources.files("optraj.planners").joinpath(SCHEMA_FILE).read_text(encoding="utf-8")


def load_schema() -> dict[str, Any]:
    """The JSON Schema of the ``optraj.trajectory/1`` format, as a new dict on each call."""
    schema: dict[str, Any] = json.loads(_schema_text())
    return schema


def validate_trajectory_data(data: object) -> None:
    """Check trajectory data (``Trajectory.to_dict`` output, a loaded JSON file) on the schema.

    Raises:
        MissingDependencyError: The ``jsonschema`` package is not installed.
        InvalidInputError: The data breaks the schema; the message names the field (as a
            path such as ``phases/0/t_end``) and the rule.
    """
    try:
        import jsonschema
    except ImportError as exc:
        raise MissingDependencyError(
            "jsonschema", "test", f"validating {FORMAT} data against its schema"
        ) from exc
    validator = jsonschema.Draft202012Validator(load_schema())
    error = jsonschema.exceptions.best_match(validator.iter_errors(data))
    if error is not None:
        field = "/".join(str(part) for part in error.absolute_path) or "(top level)"
        raise InvalidInputError(
            f"trajectory data breaks the {FORMAT} schema at {field}: {error.message}",
            name=field,
        )
