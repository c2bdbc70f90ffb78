"""optraj: optimization-based motion planning for arms that strike and carry.

The packages are :mod:`optraj.robots`, :mod:`optraj.problems`, :mod:`optraj.planners`,
:mod:`optraj.controllers` and :mod:`optraj.physics` (``from optraj import planners``); this
package holds the shared base (errors, input checks) and the command-line tool, and
re-exports the errors only (every name of :mod:`optraj.errors`), so that ``import optraj``
stays cheap. ``optraj.__version__`` is the installed distribution's version (from its
metadata, read on first use; pyproject.toml is the one place it is written).
"""

import optraj.errors as errors
from optraj.errors import *  # noqa: F403  # the errors are the package's public face

__all__ = list(errors.__all__)

#: The version when optraj runs from a folder that was never installed.
UNINSTALLED_VERSION = "0+unknown"


def __getattr__(name: str) -> str:
    """``__version__``, read from the installed metadata when first asked for."""
    if name != "__version__":
        raise AttributeError(f"module 'optraj' has no attribute {name!r}")
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("optraj")
    except PackageNotFoundError:
        return UNINSTALLED_VERSION
