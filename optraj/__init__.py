"""optraj: optimization-based motion planning for arms that strike and carry.

The packages are :mod:`optraj.robots`, :mod:`optraj.problems`, :mod:`optraj.planners`,
:mod:`optraj.controllers` and :mod:`optraj.physics` (``from optraj import planners``); this
package holds the shared base (errors, input checks) and the command-line tool, and
re-exports the errors only (every name of :mod:`optraj.errors`), so that ``import optraj``
stays cheap.
"""

import optraj.errors as errors
from optraj.errors import *  # noqa: F403  # the errors are the package's public face

__all__ = list(errors.__all__)
__version__ = "0.1.0"
