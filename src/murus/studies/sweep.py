"""The sweep runner: a grid of rocking models x a set of ground motions, run in chunks on any
``concurrent.futures.Executor``, stored chunk by chunk, assembled into an xarray Dataset.

A :class:`Plan` is the resolved study: named dimensions (the swept parameters, in order), one
:class:`Point` per grid node (a :class:`~murus.rocking.RockingModel` and the scale of each record,
or an excitation of its own for generated motions), a :class:`~murus.studies.records.RecordSet`,
and the solver options of :func:`murus.rocking.simulate_batch` (event-driven kernel).

The grid nodes are numbered in C order and cut into chunks of consecutive nodes times all the
records (``chunk_size`` histories, a few hundred: one :func:`simulate_batch` call per chunk, so
the cost of a task dwarfs its scheduling). A chunk is a pure function of the plan: whichever
executor runs it, and however the chunks are spread, the numbers are the same, bit for bit.

Study folder (``out``)::

    out/
      study.json        the resolved study: spec, digest, chunk layout (written first)
      chunks/c00000.npz one file per finished chunk: raw summaries (n_nodes, n_records, 16),
      chunks/c00000.npz.sha256   written atomically (temporary file, fsync, os.replace) as
      ...               chunks finish, then its SHA-256 (``sha256sum -c`` reads it)
      failures.json     chunks that failed after their retries: error and attempts
      result.nc         the Dataset (NetCDF4 via h5netcdf), written when the run ends

Re-running the same study with the same ``out`` computes only the chunks that have no intact
file (missing, failed, or truncated or corrupt: their bytes do not match their checksum); a
folder that holds another study (different digest) is refused.

The engine underneath is generic: :func:`run_tasks` runs any picklable function over
``(index, payload)`` tasks with the same retries, window, progress and interruption rules, and
lets a finished task queue the tasks that need its result; :func:`prepare_folder`,
:func:`write_json` and :func:`study_status` (with the ``task_files`` of ``study.json``) give any
study the same folder, refusal of another study and ``murus study status``
(:mod:`murus.retaining.study`, the behaviour factor of dry-stone walls, is one).
"""

from __future__ import annotations

import hashlib
import json
import math
from collections import deque
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import FIRST_COMPLETED, wait
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from murus.errors import MurusError
from murus.outputs import atomic_write, process_tmp_name
from murus.rocking.defaults import RTOL
from murus.rocking.summary import LIMIT_STATES, SUMMARY
from murus.studies.records import RecordSet

__all__ = ["Dim", "Point", "Plan", "ChunkTask", "run_chunk", "run_plan", "run_tasks",
           "study_status", "prepare_folder", "check_folder", "write_json", "write_checksum",
           "check_file", "file_sha256", "task_file_state", "is_interrupt",
           "StudyError", "write_netcdf", "open_result", "SUMMARY_VARS"]

FORMAT_VERSION = 1


class StudyError(MurusError, ValueError):
    """An invalid study or results folder (one-line message)."""


# (name, index in the kernel summary, units, long name): the Dataset variables of the summary,
# read from the one declared table (murus.rocking.summary.SUMMARY)
SUMMARY_VARS = tuple((q.name, i, q.units, q.description) for i, q in enumerate(SUMMARY)
                     if q.dataset)

#: Earlier names of Dataset variables, still written (and added on reading an older file):
#: earlier name -> name.
RENAMED_VARS = {a: q.name for q in SUMMARY if q.dataset for a in q.aliases
                if a == "uplift_time"}


@dataclass(frozen=True)
class Dim:
    """A swept parameter, one dimension of the grid of a :class:`Plan`.

    Attributes
    ----------
    name : str
        Name of the parameter and of the dimension of the Dataset (not ``"record"``).
    values : tuple
        Its values, in order (at least one), in the units of ``attrs["units"]``.
    attrs : dict
        Attributes of the coordinate in the Dataset: ``units``, ``long_name``.

    Raises
    ------
    StudyError
        If ``values`` is empty.
    """

    name: str
    values: tuple
    attrs: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "values", tuple(self.values))
        if not self.values:
            raise StudyError(f"sweep parameter {self.name!r} has no values")


@dataclass(frozen=True)
class Point:
    """A grid node of a :class:`Plan`.

    Attributes
    ----------
    model : murus.rocking.RockingModel
        The rocking model of the node.
    scale : float or tuple of float
        Factor on the records [-]: one number, or one per record.
    excitation : object, optional
        For generated motions (a pulse of the case), the node's own excitation; ``None``
        with records.
    """

    model: object
    scale: float | tuple = 1.0
    excitation: object | None = None


@dataclass
class Plan:
    """A resolved study (see the module docstring): a grid of models times a set of records.

    Attributes
    ----------
    name : str
        Name of the study.
    dims : list of Dim
        The swept parameters, in order; the grid's shape is their lengths.
    points : list of Point
        One per grid node, in C order (as many as the grid has nodes).
    records : RecordSet or None
        The ground motions; ``None``: every point carries its ``excitation``.
    spec : dict
        The study's description, JSON-ready (stored in ``study.json`` and the Dataset).
    duration : float or None
        Duration of each history [s]; ``None``: the default of
        :func:`murus.rocking.simulate_batch` (the end of the motion and a free tail).
    rtol : float
        Relative tolerance of the event-driven solver [-].
    chunk_size : int
        Histories per chunk (nodes per chunk = ``chunk_size / n_records``, at least one).

    Raises
    ------
    StudyError
        If the number of points is not that of the grid, the dimensions are not distinct or
        one is named ``"record"``, a point lacks an excitation without records, or
        ``chunk_size`` is not a positive integer.
    """

    name: str
    dims: list[Dim]
    points: list[Point]
    records: RecordSet | None = None
    spec: dict = field(default_factory=dict)
    duration: float | None = None
    rtol: float = RTOL
    chunk_size: int = 256

    def __post_init__(self) -> None:
        if len(self.points) != int(np.prod(self.shape)):
            raise StudyError(f"the plan has {len(self.points)} points for a grid of shape "
                             f"{self.shape}")
        names = [d.name for d in self.dims]
        if len(set(names)) != len(names) or "record" in names:
            raise StudyError(f"sweep dimensions must be distinct and not 'record': {names}")
        if self.records is None and any(p.excitation is None for p in self.points):
            raise StudyError("a plan without records needs an excitation on every point")
        if not (isinstance(self.chunk_size, int) and self.chunk_size >= 1):
            raise StudyError(f"chunk_size must be a positive integer, got {self.chunk_size!r}")

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(d.values) for d in self.dims)

    @property
    def n_records(self) -> int:
        return 1 if self.records is None else len(self.records.load())

    @property
    def n_histories(self) -> int:
        return len(self.points) * self.n_records

    def chunks(self) -> list[tuple[int, int]]:
        """``[(start, stop), ...]`` ranges of grid nodes, each run with all the records."""
        per = max(1, int(round(self.chunk_size / self.n_records)))
        n = len(self.points)
        return [(a, min(a + per, n)) for a in range(0, n, per)]

    def digest(self) -> str:
        """A digest of everything that determines the numbers (models, scales, excitations,
        records, solver options, chunk layout)."""
        h = hashlib.sha256()
        h.update(json.dumps({"v": FORMAT_VERSION, "spec": self.spec, "duration": self.duration,
                             "rtol": self.rtol, "chunks": self.chunks(),
                             "dims": [[d.name, [_jsonable(v) for v in d.values]]
                                      for d in self.dims]},
                            sort_keys=True, default=str).encode())
        h.update((self.records.key() if self.records is not None else "none").encode())
        for p in self.points:
            h.update(p.model.params().tobytes())
            h.update(np.asarray(p.scale, dtype=float).tobytes())
            if p.excitation is not None:
                h.update(p.excitation.vector().tobytes())
                for a in p.excitation.arrays():
                    h.update(np.asarray(a).tobytes())
        return h.hexdigest()[:20]


def _jsonable(v):
    if isinstance(v, np.generic):
        return v.item()
    return v


# ----------------------------------------------------------------------------- chunks ----
@dataclass
class ChunkTask:
    """What a worker needs to run one chunk (pickled to it)."""

    index: int
    points: list[Point]
    records: RecordSet | None
    duration: float | None
    rtol: float
    threads: int | None = 1
    hook: Callable | None = None


def run_chunk(task: ChunkTask) -> np.ndarray:
    """Run the histories of one chunk: ``(n_nodes, n_records, S_SIZE)`` kernel summaries."""
    from murus.rocking import kernels as K
    from murus.rocking.engine import simulate_batch
    from murus.studies.executors import limit_threads

    limit_threads(task.threads)
    if task.hook is not None:
        task.hook(task.index)
    pts = task.points
    recs = task.records.load() if task.records is not None else None
    n_rec = 1 if recs is None else len(recs)
    out = np.full((len(pts), n_rec, K.S_SIZE), np.nan)
    groups: list[tuple[object, list[int]]] = []
    for i, p in enumerate(pts):
        key = p.excitation if recs is None else _scale_key(p.scale, n_rec)
        for gk, members in groups:
            if _same(gk, key):
                members.append(i)
                break
        else:
            groups.append((key, [i]))
    for key, members in groups:
        if recs is None:
            motions = [key]
        else:
            motions = [r if s == 1.0 else r.scaled(s) for r, s in zip(recs, key, strict=True)]
        br = simulate_batch([pts[i].model for i in members], motions, duration=task.duration,
                            rtol=task.rtol)
        out[members] = br.raw
    return out


def _scale_key(scale, n: int) -> tuple:
    s = np.broadcast_to(np.asarray(scale, dtype=float), (n,))
    return tuple(float(x) for x in s)


def _same(a, b) -> bool:
    if a is b:
        return True
    try:
        return bool(a == b)
    except (TypeError, ValueError):  # arrays inside: compare by identity only
        return False


# ----------------------------------------------------------------------------- storage ---
def _atomic_write_bytes(path: Path, data: bytes) -> None:
    """Write a piece of a study atomically and durably (:func:`murus.outputs.atomic_write`)."""
    atomic_write(path, lambda p: Path(p).write_bytes(data), tmp_name=process_tmp_name(path))


def _write_json(path: Path, data) -> None:
    text = json.dumps(data, indent=1, sort_keys=True, default=str).encode()
    _atomic_write_bytes(path, text)


def _chunk_path(out: Path, index: int) -> Path:
    return out / "chunks" / f"c{index:05d}.npz"


def file_sha256(path) -> str:
    """The SHA-256 of a file's bytes (hex)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _sidecar(path: Path) -> Path:
    return path.with_name(path.name + ".sha256")


def write_checksum(path, sha: str | None = None) -> None:
    """Write ``PATH.sha256`` (``sha256sum`` format: hex digest, two spaces, file name) next to
    ``path``, atomically, after ``path`` itself was written (``sha``: its digest if known)."""
    path = Path(path)
    sha = file_sha256(path) if sha is None else sha
    text = f"{sha}  {path.name}\n".encode()
    _atomic_write_bytes(_sidecar(path), text)


def check_file(path) -> str | None:
    """Whether a stored piece is intact: ``None`` if its bytes match its ``.sha256`` sidecar,
    else a reason: ``"missing"``, ``"no checksum"`` (written before checksums were, or its
    write was cut before the checksum: the caller checks its content instead) or
    ``"checksum mismatch (truncated or corrupt)"``."""
    path = Path(path)
    if not path.exists():
        return "missing"
    side = _sidecar(path)
    if not side.exists():
        return "no checksum"
    try:
        want = side.read_text(encoding="ascii", errors="replace").split()[0]
        got = file_sha256(path)
    except (OSError, IndexError):
        return "checksum mismatch (truncated or corrupt)"
    return None if got == want else "checksum mismatch (truncated or corrupt)"


def _save_chunk(out: Path, index: int, digest: str, raw: np.ndarray) -> None:
    import io

    buf = io.BytesIO()
    np.savez(buf, raw=raw, digest=np.array(digest))
    data = buf.getvalue()
    path = _chunk_path(out, index)
    _sidecar(path).unlink(missing_ok=True)  # a stale checksum never vouches for new bytes
    _atomic_write_bytes(path, data)
    write_checksum(path, hashlib.sha256(data).hexdigest())


def _read_chunk(p: Path) -> tuple[str, np.ndarray] | None:
    try:
        with np.load(p, allow_pickle=False) as z:
            return str(z["digest"]), z["raw"].copy()
    except Exception:  # noqa: BLE001 - truncated zip, bad header, missing key: damaged
        return None


def _load_chunk(out: Path, index: int, digest: str, shape: tuple) -> np.ndarray | None:
    p = _chunk_path(out, index)
    state = check_file(p)
    if state not in (None, "no checksum"):
        return None  # missing or damaged: recomputed
    got = _read_chunk(p)
    if got is None or got[0] != digest or got[1].shape != shape:
        return None
    return got[1]


def _chunk_state(out: Path, index: int) -> str | None:
    """None if chunk ``index`` is stored intact, else "missing" or why it is damaged."""
    p = _chunk_path(out, index)
    state = check_file(p)
    if state == "no checksum":  # older folders: a chunk that reads back is done
        return None if _read_chunk(p) is not None else "unreadable (truncated or corrupt)"
    return state


def prepare_folder(out, digest: str, meta: dict) -> None:
    """Create the study folder ``out`` (and ``out/chunks`` unless ``meta`` has ``task_files``)
    and write ``study.json`` (``meta`` with the format and ``digest``) if it is new; a folder
    that holds another study (another digest) or an unreadable ``study.json`` is refused
    (:class:`StudyError`, nothing written).

    ``meta`` may declare ``"task_files"`` (one path per task, relative to ``out``: a task is
    done when its file is intact, :func:`task_file_state`), ``"unit"`` (what a task is, for
    messages: "chunks", "cases") and ``"result_file"`` (default ``result.nc``), read by
    :func:`study_status`."""
    out = Path(out)
    check_folder(out, digest)
    out.mkdir(parents=True, exist_ok=True)
    if "task_files" not in meta:
        (out / "chunks").mkdir(exist_ok=True)
    sj = out / "study.json"
    if sj.exists():
        return
    _write_json(sj, {"format": FORMAT_VERSION, **meta, "digest": digest})


def check_folder(out, digest: str) -> None:
    """Refuse ``out`` if it holds another study (as :func:`prepare_folder`), writing nothing."""
    sj = Path(out) / "study.json"
    if Path(out).exists() and not Path(out).is_dir():
        raise StudyError(f"{out}: exists and is not a directory")
    if sj.exists():
        try:
            old = json.loads(sj.read_text())
        except (OSError, ValueError):
            raise StudyError(f"{sj}: unreadable study file; remove the folder or use another "
                             "--out") from None
        if old.get("digest") != digest:
            raise StudyError(f"{out} holds results of a different study (digest "
                             f"{old.get('digest')} != {digest}); use another output folder")


def write_json(path, data) -> None:
    """Write ``data`` as indented JSON to ``path`` atomically (temporary file, fsync,
    os.replace): a reader never sees a partial file."""
    _write_json(Path(path), data)


def _prepare_folder(out: Path, plan: Plan, digest: str) -> None:
    prepare_folder(out, digest, {
        "name": plan.name, "spec": plan.spec,
        "dims": [{"name": d.name, "values": [_jsonable(v) for v in d.values], "attrs": d.attrs}
                 for d in plan.dims],
        "n_records": plan.n_records, "chunks": plan.chunks(), "n_histories": plan.n_histories,
    })


def study_status(out) -> dict:
    """Tasks (chunks, or the ``task_files`` of ``study.json``) done, missing, damaged and
    failed in a study folder.

    A task is done when its file is intact (its checksum matches, :func:`check_file`); a
    truncated or corrupt one is "damaged" (a resume recomputes it).

    Parameters
    ----------
    out : str or pathlib.Path
        The study folder (it holds ``study.json``).

    Returns
    -------
    dict
        ``name`` and ``digest`` of the study; ``unit`` (what a task is, default
        ``"chunks"``); ``total`` (number of tasks); ``done`` and ``missing`` (lists of task
        indices); ``damaged`` (``{index: reason}``); ``failed`` (``{index: error}``, from
        ``failures.json``, tasks not done); ``paths`` (``{index: file relative to the
        folder}``); ``complete`` (all done); ``result_file`` (name of the Dataset file) and
        ``result`` (whether it exists).

    Raises
    ------
    StudyError
        If ``out`` has no ``study.json`` or it is unreadable.
    """
    out = Path(out)
    sj = out / "study.json"
    if not sj.exists():
        raise StudyError(f"{out}: not a study folder (no study.json)")
    try:
        meta = json.loads(sj.read_text())
    except (OSError, ValueError):
        raise StudyError(f"{sj}: unreadable study file") from None
    files = meta.get("task_files")
    states: dict[int, str | None] = {}
    if files is not None:
        total = len(files)
        for i, f in enumerate(files):
            states[i] = task_file_state(out / f)
    else:
        total = len(meta["chunks"])
        for i in range(total):
            states[i] = _chunk_state(out, i)
    done = [i for i in range(total) if states[i] is None]
    damaged = {i: states[i] for i in range(total) if states[i] not in (None, "missing")}
    fj = out / "failures.json"
    failed = {}
    if fj.exists():
        try:
            failed = {int(k): v for k, v in json.loads(fj.read_text()).items()
                      if states.get(int(k)) is not None}
        except (OSError, ValueError, AttributeError):
            failed = {}
    missing = [i for i in range(total) if states[i] == "missing" and i not in failed]
    damaged = {i: r for i, r in damaged.items() if i not in failed}
    if files is not None:
        paths = {i: str(f) for i, f in enumerate(files)}
    else:
        paths = {i: str(_chunk_path(Path(""), i)) for i in range(total)}
    return {"name": meta.get("name"), "digest": meta.get("digest"),
            "unit": meta.get("unit", "chunks"), "total": total,
            "done": done, "missing": missing, "damaged": damaged, "failed": failed,
            "paths": paths, "complete": len(done) == total,
            "result_file": meta.get("result_file", "result.nc"),
            "result": (out / meta.get("result_file", "result.nc")).exists()}


def task_file_state(path) -> str | None:
    """None if the task file ``path`` (the ``task_files`` of a study) is stored intact, else
    ``"missing"`` or why it is damaged. A JSON task file may list further files of the task
    with their SHA-256 under ``"sha256"`` (``{file name in the same folder: hex}``): they are
    checked too. A file without a checksum (older folders) is done when it reads back."""
    path = Path(path)
    state = check_file(path)
    if state not in (None, "no checksum"):
        return state
    if path.suffix != ".json":
        return None
    try:
        rec = json.loads(path.read_text())
    except (OSError, ValueError):
        return "unreadable (truncated or corrupt)"
    sums = rec.get("sha256") if isinstance(rec, dict) else None
    for name, want in (sums or {}).items():
        p = path.parent / name
        if not p.exists():
            return f"{name} missing"
        if file_sha256(p) != want:
            return f"{name}: checksum mismatch (truncated or corrupt)"
    return None


# ----------------------------------------------------------------------------- tasks -----
def _run_task(fn: Callable, index: int, payload, threads: int | None, hook: Callable | None):
    """Worker side of :func:`run_tasks`: limit numba's threads, run the hook, run the task."""
    from murus.studies.executors import limit_threads

    limit_threads(threads)
    if hook is not None:
        hook(index)
    return fn(payload)


def run_tasks(
    fn: Callable,
    tasks: Iterable[tuple[int, object]],
    executor="process",
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    retries: int = 2,
    on_result: Callable[[int, object], Iterable[tuple[int, object]] | None],
    progress: Callable[[int, int, int], None] | None = None,
    total: int | None = None,
    done: int = 0,
    hook: Callable | None = None,
    window: int | None = None,
    grace: float = 0.5,
) -> dict[int, dict]:
    """Run ``fn(payload)`` for every ``(index, payload)`` of ``tasks`` on an executor, with
    retries, a bounded window of tasks in flight and progress: the engine of :func:`run_plan`,
    for any picklable module-level ``fn`` (a chunk of rocking histories, a DEM run, ...).

    ``KeyboardInterrupt`` (Ctrl-C: SIGINT raises it in this process while the run lasts,
    whatever a task installs, e.g. the DEM engine) and ``SystemExit`` are not retried: they
    stop the run within about a second. The tasks that finish within ``grace`` seconds are
    stored with those that had finished; the others running then are abandoned (the workers
    of a process pool are killed, a Dask cluster opened here is closed), the queued ones
    dropped; then the exception propagates.

    Parameters
    ----------
    fn : callable
        A picklable module-level function of one payload.
    tasks : iterable of (int, object)
        ``(index, payload)`` pairs.
    executor : str or ExecutorHandle
        As for :func:`run_plan`.
    workers : int, optional
        Number of workers of the executor.
    scheduler : str, optional
        Address of a Dask scheduler, or ``"local"``.
    retries : int
        A task that raises (or whose worker dies) is submitted again up to this many times.
    on_result : callable
        ``on_result(index, result)``, called in this process as each task finishes, in index
        order among the tasks that finish together (store the result there: an interruption
        loses no finished task); it may return further ``(index, payload)`` tasks, queued
        at once (a stage that needs this result, e.g. the S1 checks of a collapse run).
    progress : callable, optional
        ``progress(done, total, failed)``, counts of tasks.
    total : int, optional
        Number of tasks of the whole study, for ``progress``; default those given plus
        ``done``.
    done : int
        Number of tasks already done (stored by an earlier run), for ``progress``.
    hook : callable, optional
        A picklable ``hook(index)`` run in the worker before the task.
    window : int, optional
        Tasks in flight at once; default as for :func:`run_plan`.
    grace : float
        Time given to the running tasks to finish after an interruption [s].

    Returns
    -------
    dict of int to dict
        The tasks that failed after their retries, ``{index: {"error", "attempts"}}``; the
        others went on.

    Raises
    ------
    StudyError
        If ``retries`` is not a non-negative integer.
    KeyboardInterrupt, SystemExit
        Passed on after the grace time (see above).
    """
    from murus.studies.executors import ExecutorHandle, is_broken_pool, open_executor

    if not (isinstance(retries, int) and retries >= 0):
        raise StudyError(f"retries must be a non-negative integer, got {retries!r}")
    queue = deque(tasks)
    total = len(queue) + done if total is None else total
    failures: dict[int, dict] = {}
    if progress is not None:
        progress(done, total, 0)
    if not queue:
        return failures
    handle = executor if isinstance(executor, ExecutorHandle) else open_executor(
        executor, workers, scheduler)
    old_sigint = _raise_on_sigint()
    try:
        attempts: dict[int, int] = {}
        payloads: dict[int, object] = {}

        def submit(i, payload):
            payloads[i] = payload
            attempts[i] = attempts.get(i, 0) + 1
            return handle.executor.submit(_run_task, fn, i, payload, handle.threads, hook)

        # a window of tasks in flight: memory stays bounded, a serial run stores each task
        # before the next starts, retries go to the front of the queue
        if window is None:
            window = 1 if handle.kind == "serial" else max(64, 4 * handle.workers)
        pending: dict = {}

        def fill():
            while queue and len(pending) < window:
                i, payload = queue.popleft()
                pending[submit(i, payload)] = i

        fill()
        try:
            while pending:
                finished, _ = wait(list(pending), return_when=FIRST_COMPLETED)
                broken = False
                retry = []
                for f in sorted(finished, key=lambda f: pending[f]):
                    i = pending.pop(f)
                    try:
                        res = f.result()
                    except BaseException as exc:  # noqa: BLE001 - recorded, then retried
                        if isinstance(exc, KeyboardInterrupt | SystemExit):
                            raise
                        if is_interrupt(exc):  # Ctrl-C inside a numba kernel (SystemError)
                            raise KeyboardInterrupt from exc
                        broken = broken or is_broken_pool(exc)
                        if attempts[i] <= retries:
                            retry.append((i, payloads[i]))
                        else:
                            failures[i] = {"error": _one_line(exc), "attempts": attempts[i]}
                            payloads.pop(i, None)
                            if progress is not None:
                                progress(done, total, len(failures))
                        continue
                    payloads.pop(i, None)
                    more = on_result(i, res)
                    done += 1
                    if progress is not None:
                        progress(done, total, len(failures))
                    if more:
                        queue.extend(more)
                if broken:
                    # a dead process breaks the whole pool: every task in flight comes back
                    handle.restart()
                    retry += [(i, payloads[i]) for i in sorted(pending.values())]
                    pending.clear()
                queue.extendleft(reversed(retry))
                fill()
        except (KeyboardInterrupt, SystemExit):
            # interrupted: a second Ctrl-C cannot cut the storing of the finished tasks; the
            # tasks that finish within the grace time are kept, the others abandoned
            _ignore_sigint()
            running = [f for f in pending if not f.done()]
            if running and grace > 0:
                wait(running, timeout=grace)
            finished = {f: pending[f] for f in pending if f.done()}
            handle.abort()
            for f in sorted(finished, key=lambda f: finished[f]):
                if not f.cancelled() and f.exception() is None:
                    on_result(finished[f], f.result())
            raise
    finally:
        _restore_sigint(old_sigint)
        if handle is not executor:
            handle.close()
    return failures


def is_interrupt(exc: BaseException) -> bool:
    """Whether ``exc`` is a Ctrl-C: a ``KeyboardInterrupt``, or an exception caused by one. A
    SIGINT that arrives while a numba kernel runs raises ``KeyboardInterrupt`` when the kernel
    next calls into Python (e.g. numba's ``_numba_unpickle``), and numba turns it into a
    ``SystemError`` ("returned a result with an exception set") whose cause is the
    ``KeyboardInterrupt``: retried as an ordinary failure, the Ctrl-C was lost."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def _interrupt(signum, frame):
    raise KeyboardInterrupt


def _raise_on_sigint():
    """Make SIGINT raise KeyboardInterrupt in this process (main thread only) with a handler
    of our own, so that a task run here (serial executor) cannot catch it (the DEM engine
    leaves a non-default handler alone); returns the previous handler (or a marker)."""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        return _NOT_SET
    return signal.signal(signal.SIGINT, _interrupt)


def _ignore_sigint():
    import signal
    import threading

    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)


def _restore_sigint(old):
    import signal
    import threading

    if old is not _NOT_SET and threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, old if old is not None else signal.default_int_handler)


_NOT_SET = object()


# ----------------------------------------------------------------------------- runner ----
def run_plan(
    plan: Plan,
    executor="process",
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    out=None,
    retries: int = 2,
    progress: Callable[[int, int, int], None] | None = None,
    hook: Callable | None = None,
    window: int | None = None,
):
    """Run a plan and return its Dataset (written to ``out/result.nc`` when ``out`` is given).

    Parameters
    ----------
    plan : Plan
        The resolved study.
    executor : str or ExecutorHandle
        ``"serial"``, ``"process"``, ``"dask"`` (see :func:`murus.studies.executors.
        open_executor`, with ``workers`` and ``scheduler``) or an open
        :class:`~murus.studies.executors.ExecutorHandle`.
    workers : int, optional
        Number of workers of the executor.
    scheduler : str, optional
        Address of a Dask scheduler (``"tcp://HOST:PORT"``), or ``"local"``.
    out : str or pathlib.Path, optional
        Study folder: chunks are stored as they finish and a re-run computes only the missing
        ones (module docstring).
    retries : int
        A chunk that raises (or whose worker dies) is submitted again up to ``retries`` times,
        then recorded as failed (its cases are NaN, its error in ``attrs["failures"]`` and
        ``failures.json``); the other chunks go on.
    progress : callable, optional
        ``progress(done, total, failed)`` after each finished chunk (counts of chunks).
    hook : callable, optional
        A picklable ``hook(chunk_index)`` called in the worker before the chunk runs (fault
        injection in tests, see :mod:`murus.studies.faults`).
    window : int, optional
        Chunks in flight at once (default: 1 for the serial executor, so that each chunk is
        stored before the next starts; else 64 or 4 per worker, whichever is larger: enough
        to keep a Dask cluster's queues full, bounded for very long sweeps).

    Returns
    -------
    xarray.Dataset
        Dimensions: the swept parameters, in order, and ``record``. One variable per entry of
        :data:`SUMMARY_VARS` (units in its ``units`` attribute: rotations [rad], times [s],
        energy [J], counts), ``theta_max_over_alpha`` [-], ``failed`` (bool), ``record_scale``
        [-], and per grid node ``alpha`` [rad], ``p`` [rad/s], ``tie_stiffness`` [N/m],
        ``bed_stiffness`` [N/m/m], ``damper_coefficient`` [N s/m]; the attributes carry the
        study, its digest, the limit states, the failures and the solver options.

    Raises
    ------
    StudyError
        If ``retries`` is invalid or ``out`` holds another study.
    """
    from murus.rocking import kernels as K

    if not (isinstance(retries, int) and retries >= 0):
        raise StudyError(f"retries must be a non-negative integer, got {retries!r}")
    digest = plan.digest()
    chunks = plan.chunks()
    n_rec = plan.n_records
    raw = np.full((len(plan.points), n_rec, K.S_SIZE), np.nan)
    out = Path(out) if out is not None else None
    todo = []
    if out is not None:
        _prepare_folder(out, plan, digest)
    for i, (a, b) in enumerate(chunks):
        got = None if out is None else _load_chunk(out, i, digest, (b - a, n_rec, K.S_SIZE))
        if got is None:
            todo.append(i)
        else:
            raw[a:b] = got

    def store(i, res):
        a, b = chunks[i]
        raw[a:b] = res
        if out is not None:
            _save_chunk(out, i, digest, res)

    tasks = [(i, ChunkTask(i, plan.points[chunks[i][0]:chunks[i][1]], plan.records,
                           plan.duration, plan.rtol, None, None)) for i in todo]
    failures = run_tasks(run_chunk, tasks, executor, workers=workers, scheduler=scheduler,
                         retries=retries, on_result=store, progress=progress,
                         total=len(chunks), done=len(chunks) - len(todo), hook=hook,
                         window=window)
    for i, f in failures.items():
        f["nodes"] = list(chunks[i])
    ds = to_dataset(plan, raw, failures, digest)
    if out is not None:
        if failures:
            _write_json(out / "failures.json", {str(k): v for k, v in failures.items()})
        elif (out / "failures.json").exists():
            (out / "failures.json").unlink()
        write_netcdf(ds, out / "result.nc")
    return ds


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0] if text else ''}".rstrip(": ")


# ----------------------------------------------------------------------------- dataset ---
def to_dataset(plan: Plan, raw: np.ndarray, failures: dict, digest: str):
    """The Dataset of a plan from the kernel summaries ``raw`` (n_points, n_records, S)."""
    import xarray as xr

    import murus

    shape = plan.shape
    n_rec = raw.shape[1]
    dims = [d.name for d in plan.dims] + ["record"]
    full = shape + (n_rec,)
    coords = {}
    for d in plan.dims:
        vals = list(d.values)
        arr = np.array(vals, dtype=object if isinstance(vals[0], str) else float)
        if arr.dtype == object:
            arr = arr.astype(str)
        coords[d.name] = xr.Variable((d.name,), arr, dict(d.attrs))
    if plan.records is not None:
        names = plan.records.names()
        coords["record"] = xr.Variable(("record",), np.array(names, dtype=str))
        for k, (vals, attrs) in plan.records.coords().items():
            arr = np.array(vals)
            coords[k] = xr.Variable(("record",), arr.astype(str) if arr.dtype.kind in "OU"
                                    else arr.astype(float), attrs)
    else:
        exc = plan.points[0].excitation
        coords["record"] = xr.Variable(("record",), np.array([type(exc).__name__]))
    data = {}
    alpha = np.array([p.model.body.alpha for p in plan.points])
    for name, k, units, long in SUMMARY_VARS:
        data[name] = xr.Variable(dims, raw[..., k].reshape(full),
                                 {"units": units, "long_name": long})
    for old, name in RENAMED_VARS.items():
        data[old] = data[name].copy(deep=False)
        data[old].attrs = {**data[name].attrs, "deprecated": f"earlier name of {name}"}
    data["theta_max_over_alpha"] = xr.Variable(
        dims, (raw[..., 0] / alpha[:, None]).reshape(full),
        {"units": "1", "long_name": "largest absolute rotation over the slenderness angle alpha"})
    failed = np.isnan(raw[..., 0])
    data["failed"] = xr.Variable(dims, failed.reshape(full),
                                 {"long_name": "the chunk of this case failed"})
    pdims = [d.name for d in plan.dims]
    per_point = _point_quantities(plan)
    for name, (vals, attrs) in per_point.items():
        data[name] = xr.Variable(pdims, np.asarray(vals, float).reshape(shape), attrs)
    scales = np.stack([np.broadcast_to(np.asarray(p.scale, float), (n_rec,))
                       for p in plan.points])
    data["record_scale"] = xr.Variable(dims, scales.reshape(full),
                                       {"units": "1", "long_name": "factor applied to the record"})
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update({
        "title": f"murus study {plan.name}",
        "study": json.dumps(plan.spec, sort_keys=True, default=str),
        "digest": digest,
        "murus_version": murus.__version__,
        "limit_states": json.dumps(LIMIT_STATES),
        "failures": json.dumps({str(k): v for k, v in failures.items()}),
        "n_failed_chunks": len(failures),
        "solver": json.dumps({"method": "event", "rtol": plan.rtol, "duration": plan.duration}),
        "conventions": "SI units; theta > 0 clockwise (murus.rocking)",
    })
    return ds


def _point_quantities(plan: Plan) -> dict:
    def get(fn):
        return [fn(p.model) for p in plan.points]

    def bed(m):
        w = m.transverse_walls
        return math.nan if w is None else w.stiffness

    return {
        "alpha": (get(lambda m: m.body.alpha), {"units": "rad", "long_name": "slenderness angle"}),
        "p": (get(lambda m: m.p), {"units": "rad/s", "long_name": "frequency parameter p"}),
        "tie_stiffness": (get(lambda m: 0.0 if m.tie is None else m.tie.stiffness),
                          {"units": "N/m", "long_name": "tie stiffness K (0: no tie)"}),
        "bed_stiffness": (get(bed), {"units": "N/m/m", "long_name":
                                     "transverse walls K' (NaN: none, inf: rigid)"}),
        "damper_coefficient": (get(lambda m: 0.0 if m.damper is None else m.damper.coefficient),
                               {"units": "N s/m", "long_name": "damper coefficient c"}),
    }


def write_netcdf(ds, path) -> Path:
    """Write a Dataset to NetCDF4 with the h5netcdf engine, atomically and durably
    (:func:`murus.outputs.atomic_write`).

    Parameters
    ----------
    ds : xarray.Dataset
        The Dataset, e.g. that of :func:`run_plan`.
    path : str or pathlib.Path
        The file written (replaced if it exists).

    Returns
    -------
    pathlib.Path
        The path written.
    """
    path = Path(path)
    return atomic_write(path, lambda p: ds.to_netcdf(p, engine="h5netcdf"),
                        tmp_name=process_tmp_name(path))


def open_result(path):
    """Read a result written by :func:`write_netcdf` into memory (the file is closed).

    Parameters
    ----------
    path : str or pathlib.Path
        The NetCDF file.

    Returns
    -------
    xarray.Dataset
        The Dataset, loaded.

    Raises
    ------
    StudyError
        If the file does not exist or is not a readable NetCDF result.
    """
    import xarray as xr

    path = Path(path)
    if not path.exists():
        raise StudyError(f"{path}: no such result file")
    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            ds = ds.load()
    except (OSError, ValueError) as exc:
        raise StudyError(f"{path.name}: not a readable NetCDF result ({_one_line(exc)})") from None
    for old, name in RENAMED_VARS.items():  # a file of an earlier version
        if old in ds and name not in ds:
            ds[name] = ds[old]
    return ds


def grid_points(dims: Sequence[Dim]):
    """The grid nodes in C order as dictionaries ``{name: value}``."""
    import itertools

    for combo in itertools.product(*[d.values for d in dims]):
        yield {d.name: v for d, v in zip(dims, combo, strict=True)}
