"""Re-key the cached DEM rocking-damping runs (validation/dem_rocking_damping.py) after a change of
the engine that does not change them, as validation/restamp_check.py does for the retaining
walls: the record farfield_14a x 0.66 (both joint stiffnesses) is recomputed with this
checkout's engine into a temporary folder and compared field by field with the cached one; only
when both are identical are the records of the old engine re-keyed (``--apply``).

Usage::

    python validation/restamp_dem_rocking.py OLD_KEY [--apply]
"""

import json
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import dem_rocking_damping as D  # noqa: E402
import runcache  # noqa: E402

old, apply_ = sys.argv[1], "--apply" in sys.argv
cache = D.CACHE
recs = {p.name: json.loads(p.read_text()) for p in cache.glob("*.json")}
if any(r["_engine_source"] != old for r in recs.values()):
    sys.exit(f"records of another engine than {old}: "
             f"{ {k: r['_engine_source'] for k, r in recs.items()} }")
D.CACHE = Path(tempfile.mkdtemp())
case = {"record": "farfield_14a", "scale": 0.66}
D.record_runs([case])
same = True
for p in sorted(D.CACHE.glob("*.json")):
    new = json.loads(p.read_text())
    ref = recs[p.name]
    # the engine key and the bookkeeping of an earlier re-key are not results
    diff = [k for k in ref if k != "_engine_source" and not k.startswith("_restamp")
            and ref[k] != new.get(k)]
    print(p.name, "identical" if not diff else f"DIFFERENT {diff}")
    same &= not diff
new_key = D._engine()
if same and apply_:
    ev = (f"farfield_14a_x0.66 (both stiffnesses) recomputed bit for bit by engine {new_key} "
          "(validation/restamp_dem_rocking.py)")
    print("re-keyed", runcache.restamp(cache, old, new_key, ev))
sys.exit(0 if same else 1)
