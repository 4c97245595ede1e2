"""Executors for sweeps: the one place of murus that imports Dask.

A sweep hands independent chunks of cases to a :class:`concurrent.futures.Executor` (GUIDE §1:
"parallelism is a layer, not a property of kernels"). Three kinds:

- ``"serial"``: the chunks run one after the other in this process (numba still spreads each
  chunk over the cores with ``prange``);
- ``"process"`` (default): a local :class:`~concurrent.futures.ProcessPoolExecutor` of ``workers``
  processes started with ``spawn`` (never ``fork``: the parent may hold numba's thread pool),
  each limited to one numba thread by the initializer so that processes do not oversubscribe
  the cores;
- ``"dask"``: a Dask cluster through :meth:`distributed.Client.get_executor`, either an existing
  scheduler (``scheduler="tcp://HOST:PORT"``) or a :class:`distributed.LocalCluster` started here
  (``scheduler="local"``: ``workers`` processes of one thread each, on 127.0.0.1).

:func:`open_executor` returns an :class:`ExecutorHandle` (a context manager) whose ``executor``
is a plain ``concurrent.futures.Executor``; ``restart()`` replaces a process pool broken by the
death of a worker (Dask reschedules such tasks on its own); ``abort()`` stops at once the
tasks running (Ctrl-C: their workers are killed, nothing waits for them).

Workers never outlive this process: the pool's workers and those of a local Dask cluster watch
their parent (:func:`watch_parent`, a daemon thread polling ``os.getppid()`` every 0.5 s) and
exit when it is gone, even killed by SIGKILL, within a second. Pool workers ignore SIGINT: a
Ctrl-C at the terminal reaches the whole process group, and the main process decides (it
aborts the tasks running and keeps the finished ones).
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from concurrent.futures import Executor, Future

from murus.errors import MurusError

__all__ = ["SerialExecutor", "ExecutorHandle", "open_executor", "limit_threads",
           "fresh_pool_size",
           "watch_parent", "EXECUTOR_KINDS", "ExecutorError"]

EXECUTOR_KINDS = ("serial", "process", "dask")


class ExecutorError(MurusError, ValueError):
    """An executor that cannot be opened (one-line message)."""


def fresh_pool_size(n: int) -> None:
    """Set the size of numba's thread pool (``NUMBA_NUM_THREADS``, unless the user set it) to
    ``n`` in a process that has not imported numba yet (a fresh worker). Not in one that has:
    its pool may already run with another count, and numba refuses a changed
    ``NUMBA_NUM_THREADS`` at its next compilation, every later compilation of the process
    failing (the variable would stay behind in a process that goes on)."""
    if "numba" not in sys.modules:
        os.environ.setdefault("NUMBA_NUM_THREADS", str(int(n)))


def limit_threads(n: int | None = 1) -> None:
    """Limit numba's threads in this thread (``None``: leave them). Used as the process-pool
    initializer and at the start of every chunk (Dask runs tasks in worker threads and numba's
    thread count is per thread); the pool's size too in a fresh worker
    (:func:`fresh_pool_size`)."""
    if n is None:
        return
    fresh_pool_size(n)
    import numba

    numba.set_num_threads(max(1, min(int(n), numba.config.NUMBA_NUM_THREADS)))


_WATCHING: set[int] = set()


def watch_parent(parent: int | None = None, interval: float = 0.5) -> None:
    """Exit this process (``os._exit(1)``) as soon as its parent ``parent`` (default: the
    current parent) is gone, e.g. killed by SIGKILL: a daemon thread compares ``os.getppid()``
    with ``parent`` every ``interval`` seconds (a process whose parent dies is re-parented, so
    this works on every POSIX system without ``prctl``). Started once per process; a no-op
    when this process is not a child of ``parent``."""
    parent = os.getppid() if parent is None else int(parent)
    if parent in _WATCHING or os.getppid() != parent:
        return
    _WATCHING.add(parent)

    def loop():
        import time

        while True:
            time.sleep(interval)
            if os.getppid() != parent:
                os._exit(1)

    threading.Thread(target=loop, daemon=True, name="murus-watch-parent").start()


def _no_interrupt(signum, frame) -> None:
    """SIGINT handler of the pool's workers: nothing (a Python function rather than SIG_IGN, so
    that the DEM engine sees a handler of a caller and does not catch Ctrl-C itself)."""


def _pool_worker_init(threads: int | None, parent: int) -> None:
    """Initializer of the pool's workers: ignore SIGINT (the main process handles Ctrl-C),
    exit with the parent, limit numba's threads."""
    try:
        signal.signal(signal.SIGINT, _no_interrupt)
    except ValueError:  # not the main thread
        pass
    watch_parent(parent)
    limit_threads(threads)


def dask_setup(worker=None) -> None:
    """Preload of the workers of a local Dask cluster (``preload=["murus.studies.
    executors"]``): they exit when the process that started the cluster is gone (its pid in
    ``MURUS_PARENT_PID``)."""
    pid = os.environ.get("MURUS_PARENT_PID")
    if pid:
        watch_parent(int(pid))


class SerialExecutor(Executor):
    """Runs each submitted call at once, in the calling thread (a completed Future)."""

    def submit(self, fn, /, *args, **kwargs):
        f: Future = Future()
        try:
            f.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # noqa: BLE001 - handed to the caller through the future
            f.set_exception(exc)
        return f


class ExecutorHandle:
    """An open executor: ``.executor`` (a ``concurrent.futures.Executor``), ``.kind``,
    ``.workers`` (parallel slots), ``.threads`` (numba threads per chunk, ``None``: all),
    ``.describe()``, ``.restart()``, ``.close()``; a context manager.

    Parameters
    ----------
    kind : str
        ``"serial"``, ``"process"`` or ``"dask"``.
    workers : int, optional
        Parallel workers.
    scheduler : str, optional
        Address of a Dask scheduler, or ``"local"``.
    timeout : float
        Time to reach the scheduler [s].
    """

    def __init__(self, kind: str, workers: int | None = None, scheduler: str | None = None,
                 timeout: float = 20.0):
        self.kind = kind
        self.timeout = float(timeout)
        self.scheduler = scheduler
        self._client = None
        self._cluster = None
        self._worker_pids: list[int] = []
        self.executor: Executor
        if kind == "serial":
            self.workers = 1
            self.threads = None
            self.executor = SerialExecutor()
        elif kind == "process":
            self.workers = int(workers or os.cpu_count() or 1)
            if self.workers < 1:
                raise ExecutorError(f"workers must be >= 1, got {workers!r}")
            self.threads = 1
            self.executor = self._pool()
        elif kind == "dask":
            self.threads = 1
            self._open_dask(workers, scheduler)
        else:
            raise ExecutorError(f"unknown executor {kind!r}; expected one of {EXECUTOR_KINDS}")

    # ------------------------------------------------------------------ process pool
    def _pool(self):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        return ProcessPoolExecutor(self.workers, mp_context=multiprocessing.get_context("spawn"),
                                   initializer=_pool_worker_init, initargs=(1, os.getpid()))

    # ------------------------------------------------------------------ dask
    def _open_dask(self, workers, scheduler):
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            raise ExecutorError("the Dask executor needs dask[distributed]: "
                                "pip install murus[dask]") from None
        if scheduler in (None, "local"):
            n = int(workers or os.cpu_count() or 1)
            if n < 1:
                raise ExecutorError(f"workers must be >= 1, got {workers!r}")
            self._cluster = LocalCluster(
                n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                dashboard_address=None, preload=["murus.studies.executors"],
                env={"NUMBA_NUM_THREADS": "1", "MURUS_PARENT_PID": str(os.getpid())})
            self._client = Client(self._cluster)
            self.scheduler = "local"
            self._worker_pids = list(self._client.run(os.getpid).values())
        else:
            try:
                self._client = Client(scheduler, timeout=f"{self.timeout}s")
            except (OSError, TimeoutError, ValueError) as exc:
                raise ExecutorError(f"cannot reach the Dask scheduler {scheduler}: "
                                    f"{str(exc).splitlines()[0] if str(exc) else exc!r}") from None
        info = self._client.scheduler_info()
        self.workers = max(1, sum(int(w.get("nthreads", 1))
                                  for w in info.get("workers", {}).values()))
        self.executor = self._client.get_executor(pure=False)

    # ------------------------------------------------------------------ common
    def restart(self) -> None:
        """Replace a broken process pool (a worker died); a no-op for the other kinds."""
        if self.kind == "process":
            self.executor.shutdown(wait=False, cancel_futures=True)
            self.executor = self._pool()

    def abort(self) -> None:
        """Stop now: cancel the queued tasks and kill the workers of a process pool (the tasks
        running are lost); close a Dask client and the local cluster started here (its workers
        are killed with it). The serial executor has nothing running."""
        if self.kind == "process":
            procs = list(getattr(self.executor, "_processes", {}).values())
            for p in procs:
                try:
                    p.kill()
                except (OSError, AttributeError, ValueError):
                    pass
            self.executor.shutdown(wait=False, cancel_futures=True)
            for p in procs:
                p.join(timeout=1.0)
            self._aborted = True
        elif self.kind == "dask":
            if self._cluster is not None:  # our workers: killed, not waited for
                for pid in self._worker_pids:
                    try:
                        os.kill(pid, signal.SIGKILL)
                    except OSError:
                        pass
            try:
                self.executor.shutdown(wait=False)
            except Exception:  # noqa: BLE001 - closing anyway
                pass
        self.close()

    def describe(self) -> dict:
        d = {"kind": self.kind, "workers": self.workers}
        if self.kind == "dask":
            d["scheduler"] = self.scheduler
        return d

    def close(self) -> None:
        try:
            if self.kind == "process" and not getattr(self, "_aborted", False):
                self.executor.shutdown(wait=True, cancel_futures=True)
        finally:
            if self._client is not None:
                self._client.close()
                self._client = None
            if self._cluster is not None:
                self._cluster.close()
                self._cluster = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def open_executor(kind: str = "process", workers: int | None = None,
                  scheduler: str | None = None, timeout: float = 20.0) -> ExecutorHandle:
    """Open an executor: ``"serial"``, ``"process"`` (``workers`` processes, default the number
    of cores) or ``"dask"`` (``scheduler="tcp://HOST:PORT"``, or ``"local"``/``None`` to start
    a LocalCluster of ``workers`` single-threaded processes on 127.0.0.1); ``timeout`` [s] to
    reach a scheduler.

    Parameters
    ----------
    kind : str
        ``"serial"``, ``"process"`` or ``"dask"``.
    workers : int, optional
        Parallel workers.
    scheduler : str, optional
        Address of a Dask scheduler, or ``"local"``.
    timeout : float
        Time to reach the scheduler [s].

    Returns
    -------
    ExecutorHandle
    """
    return ExecutorHandle(kind, workers, scheduler, timeout)


def is_broken_pool(exc: BaseException) -> bool:
    """Whether ``exc`` says that the process pool lost a worker (the pool must be restarted)."""
    from concurrent.futures.process import BrokenProcessPool

    return isinstance(exc, BrokenProcessPool)
