"""Cached long runs of the validation scripts: one JSON record per run under a cache folder,
computed only when missing (or with ``recompute``), on ``jobs`` processes of one numba thread."""

from __future__ import annotations

import json
import os
import sys
from collections.abc import Callable
from pathlib import Path


def ensure(keys, compute: Callable[[str], object], cache: Path, recompute: bool = False,
           jobs: int = 1) -> dict[str, dict]:
    """The records ``cache/KEY.json`` of ``keys``; ``compute(key)`` (a module-level function
    that writes that file) runs for the missing ones (all of them with ``recompute``)."""
    todo = [k for k in keys if recompute or not (cache / f"{k}.json").exists()]
    if todo:
        os.environ.setdefault("NUMBA_NUM_THREADS", "1")
        if jobs > 1 and len(todo) > 1:
            from concurrent.futures import ProcessPoolExecutor

            with ProcessPoolExecutor(jobs) as ex:
                for k, _ in zip(todo, ex.map(compute, todo), strict=True):
                    print(f"  computed {k}", file=sys.stderr)
        else:
            for k in todo:
                compute(k)
                print(f"  computed {k}", file=sys.stderr)
    return {k: json.loads((cache / f"{k}.json").read_text()) for k in keys}


def emit(text: str, out: str | None) -> None:
    """Write a section to the file ``out``, or to standard output without one."""
    if out:
        Path(out).write_text(text)
    else:
        sys.stdout.write(text)
