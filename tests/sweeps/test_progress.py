import io
import time

from optraj.sweeps.progress import Progress


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_bar_counts_shows_the_time_left_and_ends_its_line():
    stream = _Terminal()
    bar = Progress(4, stream=stream)
    time.sleep(0.15)  # tqdm redraws at most every 0.1 s
    bar.advance()
    assert "1/4" in stream.getvalue() and "<" in stream.getvalue()  # elapsed<left
    bar.advance(3)
    assert stream.getvalue().endswith("\n") and "4/4" in stream.getvalue()
    assert bar.done == 4


def test_no_bar_when_piped_or_disabled():
    piped = io.StringIO()
    bar = Progress(4, stream=piped)
    bar.advance(4)
    assert piped.getvalue() == "" and bar.done == 4  # not even a carriage return
    stream = _Terminal()
    bar = Progress(4, enabled=False, stream=stream)
    bar.advance()
    assert stream.getvalue() == "" and bar.done == 1
    Progress(0, stream=stream).advance(0)
    assert stream.getvalue() == ""
