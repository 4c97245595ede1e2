"""Progress of long commands: one helper for every command that can run more than a few seconds.

Usage::

    from murus.progress import progress

    with progress(total=40, desc="study", unit="chunks") as p:
        for chunk in chunks:
            run(chunk)
            p.advance()             # or p.update(done), p.update(done, info="2 failed")

    with progress(None, "loading the result") as p:   # no total: elapsed time only
        ds = load()

What it shows (on standard error, never on standard output):

- in a terminal: a rich bar (description, bar, done/total, unit, info, elapsed, ETA); nested
  ``progress`` blocks (a study whose tasks run DEM runs in this process) share one display, a
  line each;
- when standard error is not a terminal (a log file, CI, a pipe): one line when the block
  starts, one line every ``interval`` seconds (default 10 s) while it runs, whether or not it
  advanced, and one line when it ends, e.g.
  ``study: 12/40 chunks (30 %), 1m02s elapsed, ETA 2m25s``;
- nothing with ``quiet=True`` (the ``--quiet`` of the commands), nor when the environment
  variable ``MURUS_PROGRESS`` is ``0``.

A process can forward the updates of the blocks it opens from then on elsewhere instead of
showing them (:func:`set_reporter`: a worker of a study reports the progress of its DEM run to
the process that shows the study's bar, which reads it with ``poll``); a reporter receives the
updates even of quiet blocks, so a long computation should open a block (quiet when its caller
asked for no progress) rather than none.
The helper never raises because of its display, and costs a few microseconds per update
(rich refreshes at 10 Hz in its own thread; the plain mode prints from a daemon thread).
"""

from __future__ import annotations

import os
import sys
import threading
import time
from collections.abc import Callable

__all__ = ["progress", "Progress", "LazyProgress", "set_reporter", "format_seconds"]

_REPORTER: Callable[[str, float, float | None, str], None] | None = None
_LOCK = threading.RLock()
_RICH = {"progress": None, "users": 0}


def set_reporter(fn: Callable[[str, float, float | None, str], None] | None) -> None:
    """Forward every update of the :func:`progress` blocks opened from now on in this process
    to ``fn(desc, done, total, info)`` instead of showing them (``None``: show again)."""
    global _REPORTER
    _REPORTER = fn


def format_seconds(s: float) -> str:
    """``75.2`` -> ``"1m15s"``, ``3725`` -> ``"1h02m05s"``, ``8.44`` -> ``"8.4s"``."""
    if s != s or s < 0:
        return "?"
    if s < 60:
        return f"{s:.1f}s"
    s = int(round(s))
    h, r = divmod(s, 3600)
    m, sec = divmod(r, 60)
    return f"{h}h{m:02d}m{sec:02d}s" if h else f"{m}m{sec:02d}s"


class Progress:
    """A progress block (see the module docstring); made by :func:`progress`.

    ``done`` and ``total`` are counts of ``unit`` (or any float, e.g. seconds of simulated
    time); ``info`` a short text shown after the counts ("2 failed", "t = 3.1 s")."""

    def __init__(self, total: float | None, desc: str, *, unit: str = "", quiet: bool = False,
                 interval: float = 10.0, stream=None, terminal: bool | None = None,
                 poll: Callable[[], str] | None = None):
        self.total = total
        self.desc = str(desc)
        self.unit = unit
        self.done = 0.0
        self.info = ""
        self.poll = poll
        self.extra = ""
        self._reporter = _REPORTER  # a reporter set later does not take this block
        self.interval = float(interval)
        self.stream = stream if stream is not None else sys.stderr
        self.quiet = bool(quiet) or os.environ.get("MURUS_PROGRESS", "1") == "0"
        if terminal is None:
            try:
                terminal = bool(self.stream.isatty())
            except (AttributeError, ValueError):
                terminal = False
        self.terminal = terminal
        self._t0 = time.monotonic()
        self._task = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._open = False
        self._outer = True

    # ------------------------------------------------------------------ public
    def advance(self, n: float = 1, info: str | None = None) -> None:
        """Add ``n`` to ``done``."""
        self.update(self.done + n, info=info)

    def update(self, done: float, total: float | None = None, info: str | None = None) -> None:
        """Set ``done`` (and ``total``, ``info`` when given)."""
        self.done = done
        if total is not None:
            self.total = total
        if info is not None:
            self.info = info
        if self._reporter is not None:
            try:
                self._reporter(self.desc, self.done, self.total, self.info)
            except Exception:  # noqa: BLE001 - progress must never break the work
                pass
            return
        if self.quiet or not self._open:
            return
        if self._task is not None:
            try:
                _RICH["progress"].update(self._task, completed=self.done, total=self.total,
                                         info=self._info(), counts=self._counts())
            except Exception:  # noqa: BLE001
                pass

    def stage(self, info: str, total: float | None = None) -> None:
        """Start a new stage of the work: ``done`` back to 0, a new ``total`` (``None``:
        unknown) and ``info`` saying what is being done."""
        self.total = total
        self.update(0, info=info)
        if self._task is not None and total is None:
            try:
                _RICH["progress"].update(self._task, total=None)
            except Exception:  # noqa: BLE001
                pass

    @property
    def elapsed(self) -> float:
        """Seconds since the block started."""
        return time.monotonic() - self._t0

    def line(self) -> str:
        """The one-line state: ``desc: done/total unit (pct), elapsed, ETA``."""
        el = self.elapsed
        parts = []
        if self.total:
            frac = min(1.0, max(0.0, self.done / self.total))
            parts.append(f"{self._counts()} ({100 * frac:.0f} %)")
        elif self.done:
            parts.append(self._counts())
        if self._info():
            parts.append(self._info())
        parts.append(f"{format_seconds(el)} elapsed")
        if self.total and 0 < self.done < self.total:
            parts.append(f"ETA {format_seconds(el * (self.total - self.done) / self.done)}")
        return f"{self.desc}: " + ", ".join(parts)

    # ------------------------------------------------------------------ context
    def __enter__(self):
        self._t0 = time.monotonic()
        self._open = True
        if self.quiet or self._reporter is not None:
            return self
        if self.terminal:
            self._start_rich()
            if self.poll is not None and self._task is not None:
                self._thread = threading.Thread(target=self._poll_rich, daemon=True,
                                                name="murus-progress")
                self._thread.start()
        else:
            self._print(self.line() if self.total or self.done else f"{self.desc} ...")
            self._thread = threading.Thread(target=self._tick, daemon=True,
                                            name="murus-progress")
            self._thread.start()
        return self

    def __exit__(self, exc_type, exc, tb):
        self._open = False
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=1.0)
        if self.quiet or self._reporter is not None:
            return False
        if self._task is not None:
            self._stop_rich()
        elif not self.terminal:
            end = "interrupted" if exc_type is KeyboardInterrupt else (
                "failed" if exc_type is not None else "done")
            self._print(f"{self.line()} ({end})")
        return False

    # ------------------------------------------------------------------ internals
    def _print(self, text: str) -> None:
        try:
            print(text, file=self.stream, flush=True)
        except (OSError, ValueError):
            pass

    def _info(self) -> str:
        return ", ".join(x for x in (self.info, self.extra) if x)

    def _refresh_extra(self) -> None:
        if self.poll is not None:
            try:
                self.extra = str(self.poll() or "")
            except Exception:  # noqa: BLE001 - progress must never break the work
                self.extra = ""

    def _tick(self) -> None:
        while not self._stop.wait(self.interval):
            self._refresh_extra()
            self._print(self.line())

    def _poll_rich(self) -> None:
        while not self._stop.wait(1.0):
            self._refresh_extra()
            try:
                _RICH["progress"].update(self._task, info=self._info())
            except Exception:  # noqa: BLE001
                pass

    def _start_rich(self) -> None:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            SpinnerColumn,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )
        from rich.progress import Progress as RichProgress

        with _LOCK:
            if _RICH["progress"] is None:
                prog = RichProgress(
                    SpinnerColumn(), TextColumn("[bold]{task.description}"), BarColumn(),
                    TextColumn("{task.fields[counts]}"), TextColumn("{task.fields[info]}"),
                    TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(),
                    console=Console(file=self.stream), transient=False)
                try:
                    prog.start()
                except Exception:  # noqa: BLE001 - another live display: plain lines
                    self.terminal = False
                    return
                _RICH["progress"] = prog
            _RICH["users"] += 1
            self._outer = _RICH["users"] == 1
            self._task = _RICH["progress"].add_task(self.desc, total=self.total,
                                                    completed=self.done, info=self._info(),
                                                    counts=self._counts())

    def _counts(self) -> str:
        u = f" {self.unit}" if self.unit else ""
        if self.total:
            return f"{_num(self.done)}/{_num(self.total)}{u}"
        return f"{_num(self.done)}{u}" if self.done else ""

    def _stop_rich(self) -> None:
        with _LOCK:
            prog = _RICH["progress"]
            if prog is None:
                return
            try:
                if self._outer:
                    prog.update(self._task, counts=self._counts())
                    prog.refresh()
                else:  # a nested block leaves no line behind
                    prog.remove_task(self._task)
            except Exception:  # noqa: BLE001
                pass
            _RICH["users"] -= 1
            if _RICH["users"] <= 0:
                try:
                    prog.stop()
                except Exception:  # noqa: BLE001
                    pass
                _RICH["progress"] = None
                _RICH["users"] = 0
            self._task = None


def _num(x: float) -> str:
    if float(x).is_integer():
        return f"{int(x)}"
    return f"{x:.3g}"


def progress(total: float | None = None, desc: str = "", *, unit: str = "",
             quiet: bool = False, interval: float = 10.0, stream=None,
             terminal: bool | None = None, poll: Callable[[], str] | None = None) -> Progress:
    """A progress block, used as a context manager (module docstring).

    Parameters
    ----------
    total : float or None
        Amount of work (tasks, steps, simulated seconds); ``None``: unknown (elapsed time
        only).
    desc : str
        What is being done, shown first ("study spectrum_block2", "DEM run", "loading numba
        kernels").
    unit : str
        Name of the counted things ("chunks", "cases", "steps"), for the display.
    quiet : bool
        No output at all.
    interval : float
        Seconds between two lines when the stream is not a terminal [s].
    stream : file, optional
        Where to show it (default ``sys.stderr``).
    terminal : bool, optional
        Force the terminal (rich bar) or the plain line mode (default: ``stream.isatty()``).
    poll : callable, optional
        ``poll() -> str``: more text shown after ``info``, asked every second in a terminal
        and at each line otherwise (the runs in progress of a study in other processes).
    """
    return Progress(total, desc, unit=unit, quiet=quiet, interval=interval, stream=stream,
                    terminal=terminal, poll=poll)


class LazyProgress:
    """Context manager with the ``update`` and ``advance`` of :class:`murus.progress.Progress`;
    the display (a bar in a terminal, a line every 10 s on stderr otherwise, nothing with
    ``quiet``) opens at the first call. Arguments: those of :func:`progress`.

    Commands check their input inside the library call that then does the work: a block opened
    before the call would print its first line, and its "(failed)" line, around the one-line
    error of a bad input; this one opens at the first update, so a bad input gives the error
    line alone.
    """

    def __init__(self, desc: str, total: float | None = None, **kw):
        self.desc = desc
        self.total = total
        self.kw = kw
        self.bar = None

    def _open(self):
        if self.bar is None:
            self.bar = progress(self.total, self.desc, **self.kw)
            self.bar.__enter__()
        return self.bar

    def update(self, done: float, total: float | None = None, info: str | None = None) -> None:
        """Set the work done (and its total, a short text); opens the display."""
        self._open().update(done, total, info)

    def advance(self, n: float = 1, info: str | None = None) -> None:
        """Add ``n`` to the work done; opens the display."""
        self._open().advance(n, info)

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if self.bar is not None:
            self.bar.__exit__(exc_type, exc, tb)
        return False
