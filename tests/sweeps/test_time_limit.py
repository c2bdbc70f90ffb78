import threading
import time

import pytest

from optraj.sweeps.time_limit import ShotTimeout, time_limit


def test_a_block_past_the_limit_is_interrupted():
    start = time.monotonic()
    with pytest.raises(ShotTimeout, match=r"time limit of 0\.2 s"), time_limit(0.2):
        time.sleep(5.0)
    assert time.monotonic() - start < 2.0


def test_a_quick_block_runs_and_leaves_no_alarm():
    with time_limit(0.2):
        pass
    time.sleep(0.3)  # a leftover alarm would raise here


def test_no_limit_and_off_the_main_thread_run_unlimited():
    with time_limit(None):
        time.sleep(0.01)
    failures = []

    def worker():
        try:
            with time_limit(0.01):
                time.sleep(0.05)
        except ShotTimeout as exc:  # pragma: no cover - the failure this test looks for
            failures.append(exc)

    thread = threading.Thread(target=worker)
    thread.start()
    thread.join()
    assert failures == []
