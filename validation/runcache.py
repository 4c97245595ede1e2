"""Cached long runs of the validation scripts: one JSON record per run under a cache folder,
computed only when missing or unreadable (or with ``recompute``), on ``jobs`` processes of one
numba thread, with progress (murus.progress) and a clean stop on Ctrl-C: the runs finished are
kept (the next ``make validate`` resumes from them), the runs in progress abandoned."""

from __future__ import annotations

import json
import sys
from collections.abc import Callable
from pathlib import Path

#: Field of a record holding the key of the engine's source that computed it.
ENGINE_FIELD = "_engine_source"


from murus._source import NOT_ENGINE  # noqa: E402,F401  (re-exported)
from murus.outputs import write_text  # noqa: E402


def source_key(*packages: str, root: Path | None = None,
               exclude: tuple[str, ...] = NOT_ENGINE) -> str:
    """A short hash of the source of ``packages`` (sub-packages of murus, e.g. ``"dem"``,
    ``"continuum"``, or modules, ``"motion/synthetic.py"``) without their docstrings
    (:func:`murus._source.source_key`), by default of this checkout's ``src/murus``: a change of
    code recomputes the cached runs, a change of documentation or comments does not."""
    from murus import _source

    src = Path(__file__).resolve().parents[1] / "src" / "murus" if root is None else Path(root)
    return _source.source_key(*packages, root=src, exclude=exclude)


def _readable(path: Path, engine: str | None = None) -> bool:
    try:
        rec = json.loads(path.read_text())
    except (OSError, ValueError):
        return False
    return engine is None or (isinstance(rec, dict) and rec.get(ENGINE_FIELD) == engine)


#: The machine a record was computed on (:func:`platform`): the same source gives the same
#: numbers bit for bit only on a machine of the same arithmetic (session 24: a CPU without
#: AVX-512 settled DSRW1 in another number of steps than the machines before it).
PLATFORM_FIELD = "_platform"


def platform() -> dict:
    """This machine as far as it decides the arithmetic: the CPU's name, the instruction-set
    extensions numpy dispatches on (AVX-512, AVX2, FMA), the versions of numpy and numba."""
    import numba
    import numpy as np

    cpu = ""
    try:
        with open("/proc/cpuinfo") as fh:
            cpu = next((ln.split(":", 1)[1].strip() for ln in fh
                        if ln.startswith("model name")), "")
    except OSError:
        pass
    try:
        from numpy._core._multiarray_umath import __cpu_features__ as feats
    except ImportError:  # numpy < 2
        from numpy.core._multiarray_umath import __cpu_features__ as feats
    isa = [k for k in ("AVX512F", "AVX512_SKX", "AVX2", "FMA3") if feats.get(k)]
    return {"cpu": cpu, "isa": isa, "numpy": np.__version__, "numba": numba.__version__}


def _stamp(path: Path, engine: str) -> None:
    rec = json.loads(path.read_text())
    rec[ENGINE_FIELD] = engine
    rec[PLATFORM_FIELD] = platform()
    write_text(path, json.dumps(rec))


class _Missing:
    """``compute(key)`` unless a current record of ``key`` appeared in the meantime (another
    process computing the same cache)."""

    def __init__(self, compute, cache: Path, engine: str | None, recompute: bool):
        self.compute, self.cache, self.engine = compute, cache, engine
        self.recompute = recompute

    def __call__(self, key):
        if not self.recompute and _readable(self.cache / f"{key}.json", self.engine):
            return None
        return self.compute(key)


def ensure(keys, compute: Callable[[str], object], cache: Path, recompute: bool = False,
           jobs: int = 1, engine: str | None = None) -> dict[str, dict]:
    """The records ``cache/KEY.json`` of ``keys``; ``compute(key)`` (a module-level function
    that writes that file and returns its record) runs for the missing or unreadable ones (all
    of them with ``recompute``), and with ``engine`` (a :func:`source_key`) for those computed
    by another engine, each record then stamped with it. A run that raises is reported after
    the others finished (``RuntimeError``); Ctrl-C raises ``KeyboardInterrupt`` within about a
    second (serial, ``jobs=1``: a run that checkpoints writes its checkpoint first)."""
    todo = [k for k in keys if recompute or not _readable(cache / f"{k}.json", engine)]
    if todo:
        from murus.studies.executors import fresh_pool_size

        fresh_pool_size(1)  # one numba thread, in a fresh process
        from murus.progress import progress
        from murus.studies.sweep import run_tasks

        kind = "process" if jobs > 1 and len(todo) > 1 else "serial"
        with progress(len(todo), f"  runs in {cache.name}", unit="runs") as p:
            def done(i, res):
                if engine is not None and res is not None:  # (None: skipped, current)
                    _stamp(cache / f"{todo[i]}.json", engine)
                print(f"  computed {todo[i]}", file=sys.stderr, flush=True)
                p.advance()

            missing = _Missing(compute, cache, engine, recompute)
            if kind == "serial":
                fails = _serial(missing, todo, done)
            else:
                fails = run_tasks(missing, list(enumerate(todo)), kind, workers=jobs,
                                  retries=0, on_result=done)
        if fails:
            raise RuntimeError("validation runs failed: " + "; ".join(
                f"{todo[i]}: {f['error']}" for i, f in sorted(fails.items())))
    return {k: json.loads((cache / f"{k}.json").read_text()) for k in keys}


def _serial(missing: _Missing, todo: list[str], done: Callable) -> dict[int, dict]:
    """The runs ``todo`` one after the other in this process, with no SIGINT handler of ours:
    a long run's own Ctrl-C handling (``collapse_run`` writes its checkpoint at the interrupt,
    then raises ``KeyboardInterrupt``) is in effect, which ``run_tasks``' handler would
    pre-empt (it raises inside the numba chunk, and the checkpoint kept is the last periodic
    one). A run that raises is reported in the returned ``{index: {"error"}}`` and the others
    go on."""
    fails = {}
    for i, key in enumerate(todo):
        try:
            res = missing(key)
        except Exception as exc:  # reported after the others, as run_tasks does
            fails[i] = {"error": f"{type(exc).__name__}: {exc}"}
            continue
        done(i, res)
    return fails


def _timeless(x):
    """``x`` without the wall times it holds at any depth (keys ending in ``wall_time``: the
    run's own and, e.g., the disc backfill's ``packing_wall_time``)."""
    if isinstance(x, dict):
        return {k: _timeless(v) for k, v in x.items() if not str(k).endswith("wall_time")}
    return x


def record_diff(old: dict, new: dict) -> list[str]:
    """The fields in which two records of the same run differ (exact equality): the histories
    ``t`` and ``d_top``, the mode and every summary value but the wall times (at any depth of
    the summary). Empty: the same run, bit for bit (the evidence for :func:`restamp`)."""
    so, sn = _timeless(old["summary"]), _timeless(new["summary"])
    out = [f for f in ("t", "d_top", "mode") if old[f] != new[f]]
    out += [f"summary.{k}" for k in sorted(set(so) | set(sn)) if so.get(k) != sn.get(k)]
    return out


def restamp(cache: Path, old: str, new: str, evidence: str, skip=None) -> list[str]:
    """Re-key the records of ``cache`` computed by the engine ``old`` to the engine ``new``,
    when a change of the engine's source is shown not to change a run: ``evidence`` (kept in
    each record, with ``_restamped_from``) must name the runs recomputed bit for bit by the new
    engine (``validation/restamp_check.py``); ``skip(record)`` true: a record the change does
    change (left at ``old``, so recomputed). Returns the keys re-keyed."""
    done = []
    for path in sorted(Path(cache).glob("*.json")):
        try:
            rec = json.loads(path.read_text())
        except (OSError, ValueError):
            continue
        if not isinstance(rec, dict) or rec.get(ENGINE_FIELD) != old:
            continue
        if skip is not None and skip(rec):
            continue
        rec[ENGINE_FIELD] = new
        rec["_restamped_from"] = old
        rec["_restamp_evidence"] = evidence
        write_text(path, json.dumps(rec))
        done.append(path.stem)
    return done


def emit(text: str, out: str | None) -> None:
    """Write a section to the file ``out``, or to standard output without one."""
    if out:
        write_text(out, text)
    else:
        sys.stdout.write(text)


def section_main(section: Callable[[], str], doc: str, argv=None) -> None:
    """Command line of a validation module that makes one section: ``[--out FILE]`` (default
    standard output)."""
    import argparse

    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--out", default=None, help="Markdown file (default: standard output).")
    args = ap.parse_args(argv)
    emit(section(), args.out)
