"""Cached long runs of the validation scripts: one JSON record per run under a cache folder,
computed only when missing or unreadable (or with ``recompute``), on ``jobs`` processes of one
numba thread, with progress (murus.progress) and a clean stop on Ctrl-C: the runs finished are
kept (the next ``make validate`` resumes from them), the runs in progress abandoned."""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Callable
from pathlib import Path


def _readable(path: Path) -> bool:
    try:
        json.loads(path.read_text())
    except (OSError, ValueError):
        return False
    return True


def ensure(keys, compute: Callable[[str], object], cache: Path, recompute: bool = False,
           jobs: int = 1) -> dict[str, dict]:
    """The records ``cache/KEY.json`` of ``keys``; ``compute(key)`` (a module-level function
    that writes that file) runs for the missing or unreadable ones (all of them with
    ``recompute``). A run that raises is reported after the others finished
    (``RuntimeError``); Ctrl-C raises ``KeyboardInterrupt`` within about a second."""
    todo = [k for k in keys if recompute or not _readable(cache / f"{k}.json")]
    if todo:
        os.environ.setdefault("NUMBA_NUM_THREADS", "1")
        from murus.progress import progress
        from murus.studies.sweep import run_tasks

        kind = "process" if jobs > 1 and len(todo) > 1 else "serial"
        with progress(len(todo), f"  runs in {cache.name}", unit="runs") as p:
            def done(i, _res):
                print(f"  computed {todo[i]}", file=sys.stderr, flush=True)
                p.advance()

            fails = run_tasks(compute, list(enumerate(todo)), kind, workers=jobs, retries=0,
                              on_result=done)
        if fails:
            raise RuntimeError("validation runs failed: " + "; ".join(
                f"{todo[i]}: {f['error']}" for i, f in sorted(fails.items())))
    return {k: json.loads((cache / f"{k}.json").read_text()) for k in keys}


def emit(text: str, out: str | None) -> None:
    """Write a section to the file ``out``, or to standard output without one."""
    if out:
        Path(out).write_text(text)
    else:
        sys.stdout.write(text)
