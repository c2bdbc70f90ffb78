"""Tests of planners.compiled_cache: copies drop their compiled solvers and lock."""

from __future__ import annotations

import pickle
import threading

import pytest

from optraj.errors import InvalidInputError
from optraj.planners.base import CompiledCache as ReExported
from optraj.planners.compiled_cache import CompiledCache, ProcessCache


class Cached(CompiledCache):
    """Two caches, a lock and a plain setting, as a planner keeps them."""

    caches = ("_compiled", "_other")

    def __init__(self) -> None:
        self.setting = 3.0
        self._compiled = {"solver": object()}
        self._other = {"x": 1}
        self._lock = threading.Lock()


def test_a_copy_has_empty_caches_a_fresh_lock_and_the_same_settings():
    original = Cached()
    copy = pickle.loads(pickle.dumps(original))
    assert copy.setting == 3.0
    assert copy._compiled == {} and copy._other == {}
    assert isinstance(copy._lock, type(threading.Lock()))
    assert copy._lock is not original._lock
    assert copy._lock.acquire(blocking=False)
    assert original._compiled and original._other == {"x": 1}  # the original keeps them


def test_the_default_cache_is_compiled_and_the_base_module_re_exports_it():
    assert CompiledCache.caches == ("_compiled",)
    assert ReExported is CompiledCache


@pytest.mark.parametrize("size", [0, -3, 2.5])
def test_a_process_cache_refuses_a_size_that_is_not_a_whole_number_above_zero(size):
    with pytest.raises(InvalidInputError, match=rf"cache size must be an integer >= 1, got {size}"):
        ProcessCache(size)
