"""Promote the validation runs of the corner rule that became the default to the main keys.

The continuum runs of ``validation/retaining_continuum.py`` were computed with the interface's
old default ``corner_share="follow"`` under their main keys (``t7_DSRW1_5_none_r0``,
``mock_1.7_r0``, ...) and with ``"shrink"`` as twins (``shrink_DSRW1_5_r0``, ``shrink_1.7_r0``,
``retaining_continuum.twin_key``), both by the old engine with the rule explicit for the
twins. With "shrink" the default, the new engine gives the twins' runs bit for bit under the
main keys and the old main runs bit for bit as the twins of "follow" (``follow_DSRW1_5_r0``):
the change of default changes no run, it swaps the names. This script shows it on the given
runs (each recomputed both ways into a temporary folder and compared field by field with the
records, as ``validation/restamp_check.py`` does: the histories, the mode, every summary value
but the wall time), and only then renames the records (old main -> "follow" twin, "shrink"
twin -> main), rewriting each one's key and spec to today's ``runs()`` and stamping it with the
new engine's key and the evidence. An old "follow" record's summary gains the rule it was run
with (``corner_share: "follow"``, which the old engine did not list for its default).

Records of the old engine that are neither (runs of the old default outside the twinned
groups, e.g. the subcycled ones) are left at the old key: recomputed by the next
``make validate``. The records of the other backfills (thrust, discs), which the corner rule
does not touch, are re-keyed after one run of each is shown identical.

Usage::

    python validation/promote_twins.py OLD_KEY --check t7_DSRW1_5_none_r0 [--apply]
"""

from __future__ import annotations

import argparse
import copy
import json
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

#: the old default and the new one
OLD, NEW = "follow", "shrink"
#: runs outside the twinned groups computed with the new rule explicit: old key -> new key
EXTRA = {"shrink_sub_1.7_k1_r0": "sub_1.7_k1_r0"}


def _with_rule(rec: dict, rule: str) -> dict:
    """``rec`` with its continuum summary listing ``rule`` (as the new engine lists it)."""
    rec = copy.deepcopy(rec)
    bo = rec.get("summary", {}).get("options", {}).get("backfill_options")
    if isinstance(bo, dict) and bo.get("model") == "continuum":
        bo.setdefault("corner_share", rule)
    return rec


def plan(rc, cache: Path, old_key: str) -> dict[str, tuple[str, str]]:
    """new key -> (old key, rule it was run with) of every record to rename, from the records
    of ``cache`` made by ``old_key``."""
    import runcache

    spec = rc.runs()
    out = {}

    def have(k):
        return runcache._readable(cache / f"{k}.json", old_key)

    for key, sp in spec.items():
        if sp["group"] not in rc.TWIN_GROUPS + ("s1",):
            continue
        old_twin = rc.twin_key(key, NEW)
        if have(key):
            out[rc.twin_key(key, OLD)] = (key, OLD)
        if have(old_twin):
            out[key] = (old_twin, NEW)
    for a, b in EXTRA.items():
        if have(a):
            out[b] = (a, NEW)
    return out


def main(argv=None) -> int:
    import retaining_continuum as rc
    import runcache

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("old", help="engine key of the records (the engine before the change)")
    ap.add_argument("--check", nargs="+", required=True,
                    help="main keys to recompute both ways and compare")
    ap.add_argument("--other", nargs="*", default=["thrust_DSRW1_5_none_r0",
                                                   "discs_DSRW1_5_none_r0"],
                    help="runs of the other backfills to recompute and compare")
    ap.add_argument("--apply", action="store_true", help="rename and re-key when identical")
    args = ap.parse_args(argv)
    default = rc.default_rule()
    if default != NEW or rc.TWIN_RULE != OLD:
        print(f"the default corner rule is {default!r} and the twins' {rc.TWIN_RULE!r}: run "
              f"this after the change to {NEW!r} (twins {OLD!r})")
        return 2
    new_key = runcache.source_key(*rc.ENGINE)
    cache = rc.CACHE
    todo = plan(rc, cache, args.old)
    spec = rc.runs()
    rc.CACHE = Path(tempfile.mkdtemp(prefix="promote_"))
    same = True
    checks = []
    for key in args.check:
        for new, rule in ((key, NEW), (rc.twin_key(key, OLD), OLD)):
            if new not in todo:
                print(f"{new}: no record of the old engine to compare with")
                return 2
            src, _ = todo[new]
            old = _with_rule(json.loads((cache / f"{src}.json").read_text()), rule)
            t0 = time.time()
            rec = rc.compute(new)
            d = runcache.record_diff(old, rec)
            same &= not d
            checks.append(new)
            verdict = "identical" if not d else "DIFFERENT: " + ", ".join(d)
            print(f"{new} (against {src}): A_col {old['summary']['A_col']!r} -> "
                  f"{rec['summary']['A_col']!r}, {verdict} ({time.time() - t0:.0f} s)",
                  flush=True)
    for key in args.other:
        old = json.loads((cache / f"{key}.json").read_text())
        t0 = time.time()
        rec = rc.compute(key)
        d = runcache.record_diff(old, rec)
        same &= not d
        print(f"{key}: {'identical' if not d else 'DIFFERENT: ' + ', '.join(d)} "
              f"({time.time() - t0:.0f} s)", flush=True)
    if not same:
        print("nothing renamed: the new engine changes a run")
        return 1
    print(f"{len(todo)} records to rename")
    if not args.apply:
        return 0
    ev = (f"{', '.join(checks + args.other)} recomputed bit for bit by engine {new_key} "
          f"(validation/promote_twins.py: the default corner rule {OLD!r} -> {NEW!r})")
    recs = {new: json.loads((cache / f"{src}.json").read_text()) for new, (src, _) in
            todo.items()}
    for new, (src, rule) in todo.items():
        rec = _with_rule(recs[new], rule)
        rec.update(key=new, spec=spec[new])
        rec[runcache.ENGINE_FIELD] = new_key
        rec["_restamped_from"] = args.old
        rec["_renamed_from"] = src
        rec["_restamp_evidence"] = ev
        tmp = cache / f"{new}.json.tmp"
        tmp.write_text(json.dumps(rec))
        tmp.replace(cache / f"{new}.json")
    gone = {src for src, _ in todo.values()} - set(todo)
    for src in sorted(gone):  # the old twins' names, now unused
        (cache / f"{src}.json").unlink()
    others = runcache.restamp(cache, args.old, new_key, ev, skip=lambda r: (
        r.get("spec", {}).get("kw", {}).get("backfill", "continuum") == "continuum"))
    print(f"renamed {len(todo)} records, removed {len(gone)} old names, re-keyed "
          f"{len(others)} records of the other backfills to {new_key}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
