import io

from optraj.sweeps.progress import Progress


def test_bar_counts_and_ends_its_line():
    stream = io.StringIO()
    bar = Progress(4, stream=stream)
    bar.advance()
    assert "1/4" in stream.getvalue() and "s left" in stream.getvalue()
    bar.advance(3)
    assert stream.getvalue().endswith("\n") and "4/4" in stream.getvalue()
    assert bar.done == 4


def test_disabled_bar_draws_nothing():
    stream = io.StringIO()
    bar = Progress(4, enabled=False, stream=stream)
    bar.advance()
    assert stream.getvalue() == "" and bar.done == 1
    Progress(0, stream=stream).advance(0)
    assert stream.getvalue() == ""
