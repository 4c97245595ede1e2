"""murus.progress: a line at the start and end (and periodically) when the stream is not a
terminal, nothing when quiet, a rich bar in a terminal, updates forwarded to a reporter."""

import io
import threading

from murus.progress import format_seconds, progress, set_reporter


def test_plain_lines_counts_and_end_state():
    buf = io.StringIO()
    with progress(40, "study", unit="chunks", stream=buf, terminal=False) as p:
        p.update(10)
        p.advance(2, info="1 failed")
        assert p.line().startswith("study: 12/40 chunks (30 %), 1 failed, ")
        assert "ETA" in p.line()
    lines = buf.getvalue().splitlines()
    assert lines[0].startswith("study: 0/40 chunks (0 %)")
    assert lines[-1].startswith("study: 12/40 chunks (30 %), 1 failed") \
        and lines[-1].endswith("(done)")


def test_plain_periodic_line_while_nothing_advances():
    buf = io.StringIO()
    with progress(None, "loading", stream=buf, terminal=False, interval=0.01) as p:
        threading.Event().wait(0.2)  # the ticker prints even when nothing advances
        p.stage("drawing")
    lines = buf.getvalue().splitlines()
    assert lines[0] == "loading ..." and len(lines) >= 3
    assert lines[-1].startswith("loading: drawing, ") and lines[-1].endswith("(done)")


def test_interrupted_block_says_so():
    buf = io.StringIO()
    try:
        with progress(3, "x", stream=buf, terminal=False) as p:
            p.advance()
            raise KeyboardInterrupt
    except KeyboardInterrupt:
        pass
    assert buf.getvalue().splitlines()[-1].endswith("(interrupted)")


def test_quiet_prints_nothing(monkeypatch):
    buf = io.StringIO()
    with progress(3, "x", stream=buf, terminal=False, quiet=True) as p:
        p.advance(3)
    monkeypatch.setenv("MURUS_PROGRESS", "0")
    with progress(3, "y", stream=buf, terminal=False) as p:
        p.advance(3)
    assert buf.getvalue() == ""


def test_terminal_bar_and_nested_blocks():
    buf = io.StringIO()
    with progress(3, "outer", unit="cases", stream=buf, terminal=True) as p:
        with progress(10, "inner", stream=buf, terminal=True) as q:
            q.update(5)
        p.advance()
    out = buf.getvalue()
    assert "outer" in out and "1/3 cases" in out


def test_reporter_takes_the_blocks_opened_after_it():
    got = []
    buf = io.StringIO()
    with progress(2, "shown", stream=buf, terminal=False) as outer:
        set_reporter(lambda *a: got.append(a))
        try:
            with progress(5, "DEM run", quiet=True) as q:  # quiet: still reported
                q.update(2.5, info="t = 1 s")
            outer.advance()  # opened before the reporter: shown, not reported
        finally:
            set_reporter(None)
    assert got == [("DEM run", 2.5, 5, "t = 1 s")]
    assert buf.getvalue().splitlines()[-1].startswith("shown: 1/2")


def test_format_seconds():
    assert format_seconds(8.44) == "8.4s"
    assert format_seconds(75.2) == "1m15s"
    assert format_seconds(3725) == "1h02m05s"
