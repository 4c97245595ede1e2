"""Bit-for-bit comparison of the DEM engine between two source trees (issue 16, item 1: the
named kernel data must not change a result).

Runs, in each tree (a subprocess with ``PYTHONPATH=<tree>/src``), the DEM example case files
(``examples/dem/*.toml``, run as ``murus dem run`` runs them) and the DEM verification cases of
``murus verify`` (quick set), recording after every chunk of steps a SHA-1 digest of the whole
kernel state (positions, angles, velocities, snapshots, pair list, sub-contact records, energy
accumulators, counters, statistics), and at the end of each case the state arrays, the run
results' arrays and the verification rows; then compares everything exactly.

``python benchmarks/compare_dem.py BEFORE_TREE AFTER_TREE [--full]``
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

STATE = ("bpos", "bang", "bvel", "bomg", "bsnap", "blast", "pairs", "pj", "pbond", "sid", "sf",
         "sbr", "E", "C", "S", "wv")


def _state(m) -> dict:
    return {k: np.asarray(getattr(m, k)) for k in STATE}


def _digest(m) -> str:
    h = hashlib.sha1()
    for k, a in _state(m).items():
        h.update(k.encode())
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def worker(tree: Path, out: Path, full: bool) -> None:
    from murus.dem import engine, verify

    digests: list[str] = []
    last: dict = {}
    orig = engine._chunk

    def hooked(m, n, moving):
        orig(m, n, moving)
        digests.append(_digest(m))
        last["m"] = m

    engine._chunk = hooked
    arrays: dict[str, np.ndarray] = {}
    from murus.dem.case import build, load_case, run_case

    for f in sorted((tree / "examples" / "dem").glob("*.toml")):
        case, path, text = load_case(f)
        if not full:
            dem = case.dem.model_copy(update={"duration": min(case.dem.duration or 0.5, 0.5)})
            case = case.model_copy(update={"dem": dem})
        built = build(case, path, text)
        cr = run_case(built)
        for k, a in _state(built.model).items():
            arrays[f"{f.stem}/state/{k}"] = a
        for k, v in vars(cr.result).items():
            if isinstance(v, np.ndarray):
                arrays[f"{f.stem}/result/{k}"] = v
        for k, v in getattr(cr.result, "histories", {}).items():
            arrays[f"{f.stem}/history/{k}"] = np.asarray(v, float)
    rows = verify.run_verification(quick=not full)
    arrays["verify/obtained"] = np.array([r["obtained"] for r in rows])
    arrays["verify/cases"] = np.array([r["case"] for r in rows])
    arrays["digests"] = np.array(digests)
    np.savez(out, **arrays)


def main(before: Path, after: Path, full: bool) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        outs = []
        for name, tree in (("before", before), ("after", after)):
            out = Path(tmp) / f"{name}.npz"
            env = dict(os.environ, PYTHONPATH=str(tree / "src"))
            env.setdefault("NUMBA_NUM_THREADS", "1")
            subprocess.run([sys.executable, __file__, "--worker", str(tree), str(out)]
                           + (["--full"] if full else []), env=env, check=True)
            outs.append(np.load(out))
        a, b = outs
        bad = []
        for k in sorted(set(a.files) | set(b.files)):
            if k not in a.files or k not in b.files:
                bad.append(f"{k}: only in {'after' if k not in a.files else 'before'}")
                continue
            x, y = a[k], b[k]
            if x.shape != y.shape or x.dtype != y.dtype or not np.array_equal(x, y):
                d = (float(np.max(np.abs(x.astype(float) - y.astype(float))))
                     if x.shape == y.shape and x.dtype.kind in "fiu" else "shape/dtype")
                bad.append(f"{k}: differs (max abs diff {d})")
        print(json.dumps({"arrays compared": len(a.files), "chunk digests": int(a["digests"].size),
                          "differences": bad}, indent=1))
        return 1 if bad else 0


if __name__ == "__main__":
    args = sys.argv[1:]
    full = "--full" in args
    args = [x for x in args if x != "--full"]
    if args and args[0] == "--worker":
        worker(Path(args[1]), Path(args[2]), full)
    else:
        sys.exit(main(Path(args[0]).resolve(), Path(args[1]).resolve(), full))
