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


def test_no_limit_runs_unlimited():
    with time_limit(None):
        time.sleep(0.01)


def _in_a_thread(block):
    """Run ``block`` in a new thread; the exception it raised, or None."""
    raised = []

    def target():
        try:
            block()
        except BaseException as exc:
            raised.append(exc)

    thread = threading.Thread(target=target)
    thread.start()
    thread.join(10.0)
    assert not thread.is_alive()
    return raised[0] if raised else None


def test_python_code_off_the_main_thread_is_interrupted():
    def loop():
        with time_limit(0.2):
            while True:
                sum(range(100))

    start = time.monotonic()
    raised = _in_a_thread(loop)
    assert isinstance(raised, ShotTimeout) and raised.seconds == 0.2
    assert "time limit of 0.2 s" in str(raised)
    assert time.monotonic() - start < 2.0


def test_a_quick_block_off_the_main_thread_leaves_nothing_pending():
    def quick():
        with time_limit(0.05):
            pass
        deadline = time.monotonic() + 0.3
        while time.monotonic() < deadline:  # a leftover exception would be raised here
            sum(range(100))

    assert _in_a_thread(quick) is None
