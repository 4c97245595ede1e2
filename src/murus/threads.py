"""Numba threads on a shared machine: the threading layer's wait policy, the thread count of a
run, and a governor that keeps a run on one thread while that is faster.

A parallel region of numba (``prange``) ends when its slowest thread ends. The distinct-element
engine runs two such regions per step, thousands of steps per second: when another process
holds a core, one of the engine's threads waits for the scheduler at every region, and a run on
two threads becomes slower than on one (1.6 times with one competing process on two cores,
issue 15 item 6). Two things made it much worse and are set here:

- **Wait policy.** Numba's default threading layer on Linux is OpenMP (GNU libgomp) when it is
  installed; libgomp's threads spin for about 300,000 iterations at the end of each region
  before they sleep, and on a busy machine that spinning takes the core from the thread that
  has the work left: 13 to 36 times slower than one thread on a 2-core machine shared with
  other jobs (``benchmarks/bench_threads.py``). :func:`configure_layer` sets
  ``OMP_WAIT_POLICY=passive`` (idle threads sleep at once) before the layer is loaded, unless
  the user set it. The price on an idle machine is a wake-up per parallel region: in a
  near-idle measurement, 300 steps of the disc case took 0.112 s on two sleeping threads,
  0.103 s on two spinning ones and 0.14 s on one. It has no effect when the
  OpenMP runtime was already loaded by another package, nor on the ``workqueue`` and ``tbb``
  layers (both already yield; numba takes ``tbb`` first where the ``tbb`` package is
  installed: measured once under background load, default / one thread 0.91 to 1.35 over two
  identical configurations, as noisy as that load); the governor below covers those cases.
- **Thread count.** :class:`Governor` decides the thread count of each part (at most 200
  steps) of a run. Its first guide is the load: :func:`choose_threads` gives the cores of this
  process's CPU affinity minus the other runnable threads of the machine, read from
  ``/proc/loadavg`` (at most every 20 ms, smoothed over two readings), so a run moves to one
  thread when another process starts spinning on the second core and back when it stops. Its
  second guide is time, for what the load does not show (a CPU quota, a core shared with the
  host): every part is timed, and now and then a part of 50 steps runs on the other choice
  (one thread against the many); two such probes in a row faster by 20 % override the load's
  choice until the load changes. The probe interval doubles (8 to 128 parts) while the choice
  holds and falls back to 8 when the current choice slows down by 30 %. The results do not
  depend on the thread count (the kernels sum in a fixed order) nor on the split into parts,
  so the choice changes only the speed.

Who decides (first match wins): a ``threads=`` argument (:func:`murus.dem.engine.run`,
``settle``, :func:`murus.rocking.simulate_batch`); the environment variable ``MURUS_THREADS``
(an integer, or ``auto``); an explicit ``NUMBA_NUM_THREADS`` in the environment (the count set
by ``numba.set_num_threads`` is then used as it is); otherwise ``auto``: the governor, never
above ``numba.get_num_threads()`` (so ``numba.set_num_threads(1)`` before a run still means one
thread).
"""

from __future__ import annotations

import contextlib
import os
import time

__all__ = ["choose_threads", "others_running", "usable_cores", "configure_layer", "resolve",
           "using", "Governor"]

ENV = "MURUS_THREADS"


def configure_layer() -> None:
    """Make OpenMP's idle threads sleep at once (``OMP_WAIT_POLICY=passive``) unless the user
    set a wait policy (``OMP_WAIT_POLICY``, ``GOMP_SPINCOUNT`` or ``KMP_BLOCKTIME``). Call it
    before the first parallel kernel runs: OpenMP reads the variable when it is loaded."""
    if not any(k in os.environ for k in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT", "KMP_BLOCKTIME")):
        os.environ["OMP_WAIT_POLICY"] = "passive"


def choose_threads(cap: int, cores: int, others: float) -> int:
    """Thread count for a parallel run on a shared machine.

    Parameters
    ----------
    cap : int
        Largest count allowed (``numba.get_num_threads()``), >= 1.
    cores : int
        Cores this process may run on (its CPU affinity).
    others : float
        Runnable threads of other processes (not counting this process's own).

    Returns
    -------
    int
        ``cap`` limited to the cores left free by the others, at least 1: a parallel region
        waits for its slowest thread, so a thread that has to share a core slows all of them.
    """
    free = int(cores) - int(round(max(0.0, float(others))))
    return max(1, min(int(cap), free))


def usable_cores() -> int:
    """Number of cores this process may run on (its CPU affinity; ``os.cpu_count()`` where
    affinity is not available)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        return os.cpu_count() or 1


def _own_running() -> int:
    n = 0
    try:
        for tid in os.listdir("/proc/self/task"):
            with open(f"/proc/self/task/{tid}/stat", "rb") as f:
                s = f.read()
            if s[s.rfind(b")") + 2:s.rfind(b")") + 3] == b"R":
                n += 1
    except OSError:  # pragma: no cover - thread ended while reading, or no /proc
        return max(n, 1)
    return max(n, 1)


def others_running(samples: int = 3) -> float:
    """Runnable threads of other processes on the machine: the median over ``samples`` reads of
    the running count of ``/proc/loadavg`` minus this process's running threads (Linux); where
    ``/proc`` is missing, the 1-minute load average minus one (which then counts this process's
    threads as others too)."""
    vals = []
    for _ in range(samples):
        try:
            with open("/proc/loadavg") as f:
                running = int(f.read().split()[3].split("/")[0])
        except (OSError, ValueError, IndexError):  # pragma: no cover - not Linux
            return max(0.0, os.getloadavg()[0] - 1.0) if hasattr(os, "getloadavg") else 0.0
        vals.append(max(0, running - _own_running()))
    vals.sort()
    return float(vals[len(vals) // 2])


def resolve(threads: int | None = None) -> int | None:
    """The fixed thread count of a run, or ``None`` for ``auto`` (module doc: who decides).

    Parameters
    ----------
    threads : int, optional
        Thread count asked for by the caller (>= 1); limited to ``NUMBA_NUM_THREADS``.
    """
    import numba

    top = numba.config.NUMBA_NUM_THREADS
    if threads is not None:
        if int(threads) != threads or threads < 1:
            raise ValueError(f"threads must be an integer >= 1, got {threads!r}")
        return min(int(threads), top)
    env = os.environ.get(ENV, "").strip().lower()
    if env and env != "auto":
        try:
            n = int(env)
        except ValueError:
            raise ValueError(f"{ENV} must be an integer >= 1 or 'auto', got {env!r}") from None
        if n < 1:
            raise ValueError(f"{ENV} must be an integer >= 1 or 'auto', got {env!r}")
        return min(n, top)
    if not env and "NUMBA_NUM_THREADS" in os.environ:
        return numba.get_num_threads()
    return None


@contextlib.contextmanager
def using(n: int | None):
    """Run the block on ``n`` numba threads (``None``: leave the count), then restore it."""
    import numba

    old = numba.get_num_threads()
    if n is not None:
        numba.set_num_threads(n)
    try:
        yield
    finally:
        numba.set_num_threads(old)


class Governor:
    """Thread count of each part of the chunks of steps of one run (module doc).

    Parameters
    ----------
    cap : int
        Largest thread count (>= 1).
    start : int, optional
        Count of the first part (default: the load's choice).
    base, longest : int
        Shortest and longest interval between timing probes [parts].
    margin : float
        Fraction by which the other choice must be faster, in two probes in a row, to be taken
        against the load's choice (the time of a part varies by some 10 % with its content:
        contact rebuilds, the number of active contacts).
    fixed : bool
        Always ``cap`` threads, no probes (a count fixed by the user).
    part : int
        Largest part of a chunk timed on its own [steps] (a step of a model with enough pairs
        for the parallel loop takes 0.05 ms or more: a part lasts 10 ms or more, and the
        kernel call costs some 0.03 ms).
    load : callable, optional
        ``load() -> others`` (default :func:`others_running`), read at most every
        ``load_every`` seconds and smoothed over two readings.
    cores : int, optional
        Cores of the run (default :func:`usable_cores`).
    """

    def __init__(self, cap: int, start: int | None = None, base: int = 8, longest: int = 128,
                 margin: float = 0.2, fixed: bool = False, part: int = 200,
                 load=None, cores: int | None = None, load_every: float = 0.02):
        self.cap = max(1, int(cap))
        self.fixed = bool(fixed)
        self.base = base
        self.longest = longest
        self.margin = margin
        self.part = max(1, int(part))
        self.load = others_running if load is None else load
        self.cores = usable_cores() if cores is None else int(cores)
        self.load_every = load_every
        self.switches = 0
        self.probes = 0
        self.steps: dict[int, int] = {}  # steps run on each thread count
        self.others = 0.0
        self.t_load = -1e300
        self.target = self.cap
        if not self.fixed and self.cap > 1:
            self.others = float(self.load())
            self.t_load = time.monotonic()
            self.target = choose_threads(self.cap, self.cores, self.others)
        self.cur = self.cap if self.fixed else (self.target if start is None
                                                else max(1, min(self.cap, int(start))))
        self._reset()

    def _reset(self) -> None:
        self.interval = self.base
        self.since = max(0, self.base - 2)  # the first probe after two timed parts
        self.cost: float | None = None  # EMA of the current choice [s per step]
        self.ref: float | None = None  # its value at the last decision
        self.warm = False  # the first part after a change may wake threads: not timed
        self.pending = False  # one probe in favour of the other choice

    def _alt(self) -> int:
        if self.cur > 1:
            return 1
        return max(2, choose_threads(self.cap, self.cores, 0.0) if self.target == 1
                   else self.target)

    def _follow_load(self) -> None:
        now = time.monotonic()
        if now - self.t_load < self.load_every:
            return
        self.t_load = now
        self.others = 0.5 * self.others + 0.5 * float(self.load())
        t = choose_threads(self.cap, self.cores, self.others)
        if t != self.target:
            self.target = t
            if t != self.cur:
                self.cur = t
                self.switches += 1
                self._reset()

    def next(self, n: int) -> tuple[int, int]:
        """The next part of the ``n`` steps left in a chunk: ``(steps, threads)``, at most
        ``part`` steps on the current count, or a timing probe of ``part // 4`` steps on the
        other choice (one thread against the many). The load is read first: when its choice
        changes, the count follows it."""
        if self.fixed:
            return n, self.cur
        if self.cap > 1:
            self._follow_load()
            if self.warm and self.cost is not None and self.since >= self.interval:
                return min(n, max(1, self.part // 4)), self._alt()
        return min(n, self.part), self.cur

    def record(self, threads: int, steps: int, seconds: float) -> None:
        """Time of a part of ``steps`` steps run on ``threads`` threads [s]."""
        if steps <= 0:
            return
        self.steps[threads] = self.steps.get(threads, 0) + steps
        if self.fixed:
            return
        x = seconds / steps
        if threads == self.cur:
            if not self.warm:
                self.warm = True
                return
            self.cost = x if self.cost is None else 0.7 * self.cost + 0.3 * x
            if self.ref is None:
                self.ref = self.cost
            self.since += 1
            if self.cost > 1.3 * self.ref and self.interval > self.base:
                self.interval = self.base  # slowed down: look at the other choice soon
            return
        # a probe of the other choice
        self.probes += 1
        self.since = 0
        if self.cost is not None and x < (1.0 - self.margin) * self.cost:
            if self.pending:  # the second probe in a row: take it
                self.cur = threads
                self.switches += 1
                self._reset()
                self.warm = True
                self.cost = self.ref = x
                return
            self.pending = True
            self.interval = 0  # confirm at the next part
            return
        self.pending = False
        self.ref = self.cost
        self.interval = min(2 * max(self.interval, self.base // 2), self.longest)

    @classmethod
    def for_run(cls, threads: int | None = None) -> Governor:
        """The governor of a run: a fixed count (``threads``, ``MURUS_THREADS``, an explicit
        ``NUMBA_NUM_THREADS``) or ``auto`` up to ``numba.get_num_threads()``."""
        import numba

        global last
        fixed = resolve(threads)
        last = cls(fixed, fixed=True) if fixed is not None else cls(numba.get_num_threads())
        return last


last: Governor | None = None  # the governor of the latest run (benchmarks read its counts)


configure_layer()
