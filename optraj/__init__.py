"""optraj: optimization-based motion planning for arms that strike and carry.

The import packages are :mod:`robots`, :mod:`problems`, :mod:`planners` and
:mod:`controllers`; this package holds the shared base (errors) and the command-line tool, and
re-exports the errors only, so that ``import optraj`` stays cheap.
"""

from optraj.errors import (
    CompilerError,
    InfeasibleError,
    InvalidInputError,
    JointLimitError,
    MissingDependencyError,
    OptrajError,
    OptrajWarning,
    PathJumpError,
    PathJumpWarning,
    SolverError,
    UnknownNameError,
    UnreachableError,
    UnsupportedModelError,
    WorkspaceError,
)

__all__ = [
    "CompilerError",
    "InfeasibleError",
    "InvalidInputError",
    "JointLimitError",
    "MissingDependencyError",
    "OptrajError",
    "OptrajWarning",
    "PathJumpError",
    "PathJumpWarning",
    "SolverError",
    "UnknownNameError",
    "UnreachableError",
    "UnsupportedModelError",
    "WorkspaceError",
]
__version__ = "0.1.0"
