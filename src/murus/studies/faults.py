"""Fault injection for the tests of the sweep runner (``run_plan(..., hook=...)``).

The hooks are picklable objects of an importable module, so that worker processes (a process
pool started with ``spawn``, Dask workers) can run them. They coordinate across processes through
marker files in a folder that the test owns.
"""

from __future__ import annotations

import os
import signal
from dataclasses import dataclass
from pathlib import Path

__all__ = ["KillOnce", "FailTimes", "Touch", "Interrupt", "Sleep"]


@dataclass(frozen=True)
class KillOnce:
    """Kill the worker process that runs chunk ``chunk`` (SIGKILL), the first time only: the
    marker file ``folder/killed-<chunk>`` records that it happened."""

    folder: str
    chunk: int = 0

    def __call__(self, index: int) -> None:
        if index != self.chunk:
            return
        marker = Path(self.folder) / f"killed-{index}"
        try:
            fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
        except FileExistsError:
            return
        os.write(fd, str(os.getpid()).encode())
        os.close(fd)
        os.kill(os.getpid(), signal.SIGKILL)


@dataclass(frozen=True)
class FailTimes:
    """Raise ``RuntimeError`` the first ``times`` times chunk ``chunk`` runs (``times < 0``:
    always); the attempts are counted by marker files in ``folder``."""

    folder: str
    chunk: int = 0
    times: int = 1

    def __call__(self, index: int) -> None:
        if index != self.chunk:
            return
        folder = Path(self.folder)
        n = len(list(folder.glob(f"fail-{index}-*")))
        (folder / f"fail-{index}-{n}").write_text(str(os.getpid()))
        if self.times < 0 or n < self.times:
            raise RuntimeError(f"injected failure {n + 1} of chunk {index}")


@dataclass(frozen=True)
class Touch:
    """Record that a chunk ran: creates ``folder/ran-<chunk>-<pid>`` (which chunks a resumed
    run computes)."""

    folder: str

    def __call__(self, index: int) -> None:
        (Path(self.folder) / f"ran-{index}-{os.getpid()}").write_text("")


@dataclass(frozen=True)
class Interrupt:
    """Raise ``KeyboardInterrupt`` (as Ctrl-C) when task or chunk ``chunk`` starts."""

    chunk: int = 0

    def __call__(self, index: int) -> None:
        if index == self.chunk:
            raise KeyboardInterrupt


@dataclass(frozen=True)
class Sleep:
    """Sleep ``seconds`` before every task or chunk (a slow study, for interruption tests)."""

    seconds: float = 0.5

    def __call__(self, index: int) -> None:
        import time

        time.sleep(self.seconds)
