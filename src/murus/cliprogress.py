"""A :func:`murus.progress.progress` block that shows only once the work has started.

Commands check their input inside the library call that then does the work (a DEM case is
validated by its build, a collapse run by :func:`~murus.retaining.collapse.collapse_run`): a
progress block opened before the call would print its first line, and its "(failed)" line,
around the one-line error of a bad input. :class:`LazyProgress` opens the block at the first
update instead, so that a bad input gives the error line alone::

    with LazyProgress("collapse DSRW1 5 Hz", unit="s") as bar:
        res = collapse_run(..., progress=bar.update)
"""

from __future__ import annotations

__all__ = ["LazyProgress"]


class LazyProgress:
    """Context manager with the ``update`` and ``advance`` of :class:`murus.progress.Progress`;
    the display (a bar in a terminal, a line every 10 s on stderr otherwise, nothing with
    ``quiet``) opens at the first call. Arguments: those of :func:`murus.progress.progress`."""

    def __init__(self, desc: str, total: float | None = None, **kw):
        self.desc = desc
        self.total = total
        self.kw = kw
        self.bar = None

    def _open(self):
        if self.bar is None:
            from murus.progress import progress

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
