"""Re-key cached validation runs after a change of the engine that does not change them.

The cached runs of ``validation/retaining_continuum.py`` are keyed by a hash of the engine's
source (``runcache.source_key``): any change of the engine recomputes all of them (tens of
core-hours). A change that adds an option, off by default, leaves every run the same; this
script shows it and then re-keys: it recomputes the given runs with this checkout's engine into a
temporary folder and compares them with the cached records field by field (the history ``t``,
``d_top``, the mode and every summary value but the wall time) for exact equality. Only when
every run is identical are the records of the old engine re-keyed to the new one
(``runcache.restamp``, which keeps ``_restamped_from`` and the evidence in each record).

Usage::

    python validation/restamp_check.py OLD_KEY t7_DSRW1_5_none_r0 mock_3.3_r0 [--apply]
        [--except-subcycled]
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))


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
    args = ap.parse_args(argv)
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
        rec = rc.compute(key)
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
        skip = None
        if args.except_subcycled:
            ev += "; the subcycled runs left to be recomputed"

            def skip(rec):
                return (rec.get("spec", {}).get("kw", {}).get("subcycle") or 1) != 1
        keys = runcache.restamp(cache, args.old, new, ev, skip=skip)
        print(f"re-keyed {len(keys)} records {args.old} -> {new}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
