"""Pickling for objects that cache compiled solvers: the caches stay behind.

A planner that compiles solvers on demand (CasADi functions, NLP solvers) and guards them with a
lock subclasses :class:`CompiledCache`; a pickled copy, e.g. sent to a worker process, arrives
with empty caches and a fresh lock and compiles again when it needs to.

>>> class Solver(CompiledCache):
...     def __init__(self):
...         self._compiled = {}
...         self._lock = threading.Lock()
>>> copy = pickle.loads(pickle.dumps(Solver()))
"""

from __future__ import annotations

import threading
from typing import Any

__all__ = ["CompiledCache"]


class CompiledCache:
    """Pickles without its compiled solvers and its lock; the solvers are rebuilt on demand.

    A subclass keeps its caches (dicts) in the attributes :attr:`caches` names and a
    ``threading.Lock`` in ``_lock``; a copy, e.g. in a worker process, starts them empty.
    """

    caches: tuple[str, ...] = ("_compiled",)
    _lock: threading.Lock

    def __getstate__(self) -> dict[str, Any]:
        """State without the compiled solvers and the lock."""
        state = self.__dict__.copy()
        for name in self.caches:
            state[name] = {}
        del state["_lock"]
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        """Restore from :meth:`__getstate__`."""
        self.__dict__.update(state)
        self._lock = threading.Lock()
