"""Re-key cached validation runs after a change of the engine that does not change them.

The cached runs of ``validation/retaining_continuum.py`` are keyed by a hash of the engine's
source (``runcache.source_key``): any change of the engine recomputes all of them (tens of
core-hours). A change that adds an option, off by default, leaves every run the same; this
script shows it and then re-keys: it recomputes the given runs with this checkout's engine into a
temporary folder and compares them with the cached records field by field (the history ``t``,
``d_top``, the mode and every summary value but the wall time) for exact equality. Only when
every run is identical are the records of the old engine re-keyed to the new one
(``runcache.restamp``, which keeps ``_restamped_from`` and the evidence in each record).

Where the records were computed on a machine whose floating point differs from this one's
(another CPU: numpy's and libm's elementary functions are chosen by its instruction set), no
recomputation here can follow them to their stored digits. ``--old-tree DIR`` (a checkout of the
old engine, e.g. a ``git worktree`` of the commit before the change) then computes each run with
both engines on this machine, cut at ``--t-max`` seconds of shaking, each in its own process, and
compares the two: the evidence is then that the change does not change a run on one machine.

Usage::

    python validation/restamp_check.py OLD_KEY t7_DSRW1_5_none_r0 mock_3.3_r0 [--apply]
        [--except-subcycled]
    python validation/restamp_check.py OLD_KEY t7_DSRW1_5_none_r0 --old-tree /tmp/old \\
        --t-max 1.0 [--apply]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

#: One run of a tree's engine, cut at ``t_max`` (``--old-tree``): run as ``python -c`` with the
#: tree's ``src`` and ``validation`` first on the path, so that it needs nothing of this file.
_ONE_RUN = r"""
import json, sys, tempfile
from pathlib import Path
key, t_max, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
import retaining_continuum as rc
import murus.retaining.collapse as C
rc.CACHE = Path(tempfile.mkdtemp(prefix="restamp_"))
rc.CHECKPOINTS = rc.CACHE / "checkpoints"
run = C.collapse_run
def cut(*a, **kw):
    kw["t_max"] = t_max
    return run(*a, **kw)
C.collapse_run = cut
Path(out).write_text(json.dumps(rc.compute(key)))
"""


def _tree_env(tree: Path) -> dict:
    """The environment of a process that runs the checkout ``tree``'s murus and validation."""
    return dict(os.environ, PYTHONPATH=os.pathsep.join([str(tree / "src"),
                                                        str(tree / "validation")]))


def _run_in(tree: Path, key: str, t_max: float, out: Path) -> dict:
    """The record of ``key`` computed by the engine of the checkout ``tree``, cut at
    ``t_max``, in a process of its own (its own modules and numba caches)."""
    subprocess.run([sys.executable, "-c", _ONE_RUN, key, repr(t_max), str(out)],
                   env=_tree_env(tree), check=True)
    return json.loads(out.read_text())


#: The digest a run's checkpoint must carry under a tree's engine (``--checkpoint``): the run
#: is stopped at its check of the checkpoint, before anything is built.
_DIGEST = r"""
import json, sys, tempfile
from pathlib import Path
import retaining_continuum as rc
import murus.retaining.collapse as C
rc.CHECKPOINTS = Path(tempfile.mkdtemp(prefix="restamp_"))
class Got(Exception):
    pass
def grab(path, digest):
    raise Got(json.dumps({"digest": digest, "code": C._code_key()}))
C._check_checkpoint = grab
run = C.collapse_run
def no_run(*a, **kw):  # a run without a checkpoint (discs) would run whole: refused
    if kw.get("checkpoint") is None:
        raise SystemExit(f"{sys.argv[1]}: a run without a checkpoint")
    return run(*a, **kw)
C.collapse_run = no_run
try:
    rc.compute(sys.argv[1])
except Got as e:
    print(e.args[0])
"""


def _digest_in(tree: Path, key: str) -> dict:
    """The checkpoint digest and code key of ``key`` under the engine of ``tree``."""
    out = subprocess.run([sys.executable, "-c", _DIGEST, key], env=_tree_env(tree),
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def rekey_checkpoint(checkpoints: Path, key: str, old: dict, new: dict) -> Path:
    """Write the checkpoint of ``key`` made by the engine ``old`` (its digest and code key:
    :func:`_digest_in`) as one of the engine ``new``: the same state, the new digest, the new
    name; the old file is left (the campaign's next run of ``key`` removes it)."""
    import numpy as np

    from murus.outputs import atomic_write

    src = checkpoints / f"{key}.{old['code']}.npz"
    with np.load(src, allow_pickle=False) as z:
        run = json.loads(str(z["run"]))
        body = z["model"].copy()
    if run.get("digest") != old["digest"]:
        raise SystemExit(f"{src}: its digest is not the old engine's for {key} (other "
                         f"arguments): not re-keyed")
    info = np.array(json.dumps(dict(run, digest=new["digest"])))
    dst = checkpoints / f"{key}.{new['code']}.npz"
    atomic_write(dst, lambda tmp: np.savez(tmp, model=body, run=info))
    return dst


def restamp_studies(old: str, new: str, evidence: str) -> list[str]:
    """Re-key the engine stamps of the behaviour studies (``retaining_behaviour.STAMP`` in each
    folder of ``retaining_behaviour.CACHE``) made by ``old``, with the same evidence as the
    records. Returns the studies re-keyed."""
    import retaining_behaviour as rb
    import runcache

    if not rb.CACHE.is_dir():
        return []
    return [f.name for f in sorted(rb.CACHE.iterdir())
            if f.is_dir() and runcache.restamp(f, old, new, evidence)]


def main(argv=None) -> int:
    import retaining_continuum as rc
    import runcache

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old", help="engine key of the cached records to re-key")
    ap.add_argument("keys", nargs="+", help="runs to recompute and compare")
    ap.add_argument("--apply", action="store_true", help="re-key when every run is identical")
    ap.add_argument("--except-subcycled", action="store_true",
                    help="leave the subcycled runs (spec kw subcycle set) at the old key: a "
                         "change of the subcycled scheme only (they are recomputed)")
    ap.add_argument("--old-tree", type=Path, default=None,
                    help="a checkout of the old engine: compute each run with both engines on "
                         "this machine (cut at --t-max) and compare them, not the records")
    ap.add_argument("--t-max", type=float, default=1.0,
                    help="with --old-tree: seconds of shaking of each run (default 1)")
    ap.add_argument("--checkpoint", action="append", default=[], metavar="KEY",
                    help="with --old-tree and --apply: re-key the checkpoint of the run KEY in "
                         "progress too (repeatable)")
    args = ap.parse_args(argv)
    if args.old_tree is not None and not (args.old_tree / "src" / "murus").is_dir():
        print(f"error: --old-tree {args.old_tree}: not a checkout of murus (no src/murus)",
              file=sys.stderr)
        return 2
    if args.checkpoint and (args.old_tree is None or not args.apply):
        print("error: --checkpoint needs --old-tree and --apply", file=sys.stderr)
        return 2
    new = runcache.source_key(*rc.ENGINE)
    cache = rc.CACHE
    rc.CACHE = Path(tempfile.mkdtemp(prefix="restamp_"))
    same_all = True
    for key in args.keys:
        old = json.loads((cache / f"{key}.json").read_text())
        if old.get(runcache.ENGINE_FIELD) != args.old:
            print(f"{key}: cached by {old.get(runcache.ENGINE_FIELD)}, not {args.old}")
            return 2
        t0 = time.time()
        if args.old_tree is None:
            rec = rc.compute(key)
        else:  # both engines on this machine, cut at t_max
            old = _run_in(args.old_tree, key, args.t_max, rc.CACHE / f"{key}.old.json")
            rec = _run_in(HERE.parent, key, args.t_max, rc.CACHE / f"{key}.new.json")
        so, sn = old["summary"], rec["summary"]
        diff = runcache.record_diff(old, rec)
        same_all &= not diff
        print(f"{key}: A_col {so['A_col']!r} -> {sn['A_col']!r}, "
              f"{'identical' if not diff else 'DIFFERENT: ' + ', '.join(diff)} "
              f"({time.time() - t0:.0f} s)", flush=True)
    if not same_all:
        print("not re-keyed: the new engine changes a run")
        return 1
    if args.apply:
        ev = (f"{', '.join(args.keys)} recomputed bit for bit by engine {new} "
              "(validation/restamp_check.py)")
        if args.old_tree is not None:
            ev = (f"{', '.join(args.keys)} cut at {args.t_max:g} s: engines {args.old} and "
                  f"{new} bit for bit on one machine (validation/restamp_check.py --old-tree)")
        skip = None
        if args.except_subcycled:
            ev += "; the subcycled runs left to be recomputed"

            def skip(rec):
                return (rec.get("spec", {}).get("kw", {}).get("subcycle") or 1) != 1
        keys = runcache.restamp(cache, args.old, new, ev, skip=skip)
        print(f"re-keyed {len(keys)} records {args.old} -> {new}")
        if not args.except_subcycled:  # the studies run subcycled: else recomputed
            studies = restamp_studies(args.old, new, ev)
            print(f"re-keyed {len(studies)} behaviour studies {args.old} -> {new}")
        for key in args.checkpoint:
            dst = rekey_checkpoint(rc.CHECKPOINTS, key, _digest_in(args.old_tree, key),
                                   _digest_in(HERE.parent, key))
            print(f"checkpoint of {key} re-keyed: {dst.name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
