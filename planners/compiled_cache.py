"""Compiled solvers kept for reuse: per object (dropped on pickling) and per process.

A planner that compiles solvers on demand (CasADi functions, NLP solvers) and guards them with a
lock subclasses :class:`CompiledCache`; a pickled copy, e.g. sent to a worker process, arrives
with empty caches and a fresh lock and compiles again when it needs to.

>>> class Solver(CompiledCache):
...     def __init__(self):
...         self._compiled = {}
...         self._lock = threading.Lock()
>>> copy = pickle.loads(pickle.dumps(Solver()))

Building a solver can take longer than solving with it, so a :class:`ProcessCache` shares the
solvers of equal keys (everything that shapes them) between every object of a process: a new
planner object plans at once with the solvers an earlier one built.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from typing import Any, Generic, TypeVar

from optraj.errors import InvalidInputError

__all__ = ["CompiledCache", "ProcessCache"]

T = TypeVar("T")


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


class ProcessCache(Generic[T]):
    """Values built once per key and shared by every user in the process, the newest kept.

    Thread-safe: a value is built outside the lock (two threads may build the same key at
    once; the first stored wins and both get it), so one slow build does not hold up the
    others. Past ``size`` entries the least recently used one is dropped.

    Args:
        size: Most entries kept, an integer >= 1.

    Raises:
        InvalidInputError: size is not an integer >= 1.
    """

    def __init__(self, size: int) -> None:
        if int(size) != size or size < 1:
            raise InvalidInputError(
                f"cache size must be an integer >= 1, got {size!r}", name="size"
            )
        self.size = int(size)
        self._entries: OrderedDict[Hashable, T] = OrderedDict()
        self._lock = threading.Lock()

    def __len__(self) -> int:
        """Entries kept."""
        return len(self._entries)

    def get(self, key: Hashable) -> T | None:
        """The value of ``key``, or None when none is kept."""
        with self._lock:
            value = self._entries.get(key)
            if value is not None:
                self._entries.move_to_end(key)
            return value

    def get_or_build(self, key: Hashable, build: Callable[[], T]) -> T:
        """The value of ``key``, built by ``build()`` and kept when there is none yet."""
        value = self.get(key)
        if value is not None:
            return value
        built = build()
        with self._lock:
            value = self._entries.setdefault(key, built)
            self._entries.move_to_end(key)
            while len(self._entries) > self.size:
                self._entries.popitem(last=False)
            return value

    def clear(self) -> None:
        """Drop every entry."""
        with self._lock:
            self._entries.clear()
