"""Speed of the rocking engine in two source trees, alternated in one script (issue 16, item 1:
the named kernel data must cost no speed).

The free-standing batch of ``benchmarks/bench_rocking.py`` (10,032 histories of 20 s: 6
restrained-wall blocks x 44 FEMA P695 far-field components x 38 scale factors 0.1-1.5,
``simulate_batch``) and one ``simulate`` history, at the same explicit tolerance on both sides
(``--rtol``, default 1e-9, the default of the BEFORE tree: the trees may differ in their default),
one numba thread, in subprocesses with ``PYTHONPATH=<tree>/src`` in the order A B B A A B ...
Each subprocess loads the numba cache, warms up, and times the batch twice and the history 20
times (best of each). Reports the median of the per-process times, the ratio AFTER/BEFORE, and
whether the batch summaries of the two trees are identical.

``python benchmarks/ab_rocking.py BEFORE_TREE AFTER_TREE [--rounds R] [--rtol RTOL]``
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def worker(rtol: float) -> None:
    import time

    import numpy as np

    from murus.motion import suite
    from murus.rocking import RockingModel, simulate, simulate_batch
    try:
        from murus.rocking import restrained_wall_block as block
    except ImportError:  # an older tree
        from murus.rocking import seed002_block as block

    recs = [m.sliced(0.0, 20.0) for m in suite("farfield")]
    models = [RockingModel(block(f"block{i}")) for i in range(1, 7)]
    motions = [m.scaled(s) for m in recs for s in np.linspace(0.1, 1.5, 38)]
    simulate_batch(models[:1], motions[:2], duration=20.0, rtol=rtol, threads=1)
    batch = float("inf")
    for _ in range(2):
        t0 = time.perf_counter()
        br = simulate_batch(models, motions, duration=20.0, rtol=rtol, threads=1)
        batch = min(batch, time.perf_counter() - t0)
    one = float("inf")
    rec = recs[0].scaled(1.0)
    simulate(models[0], rec, duration=25.0, rtol=rtol)
    for _ in range(20):
        t0 = time.perf_counter()
        simulate(models[0], rec, duration=25.0, rtol=rtol)
        one = min(one, time.perf_counter() - t0)
    raw = np.asarray(br.raw, dtype=float)
    print(json.dumps({"batch": batch, "one": one, "digest": float(np.nansum(raw)),
                      "n": int(raw.size)}))


def run(tree: str, rtol: float) -> dict:
    env = dict(os.environ, PYTHONPATH=str(Path(tree) / "src"), NUMBA_NUM_THREADS="1",
               MURUS_PROGRESS="0")
    out = subprocess.run([sys.executable, __file__, "--worker", "--rtol", repr(rtol)], env=env,
                         check=True, capture_output=True, text=True, cwd="/").stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None) -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("before", nargs="?")
    ap.add_argument("after", nargs="?")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--rtol", type=float, default=1e-9)
    ap.add_argument("--worker", action="store_true")
    a = ap.parse_args(argv)
    if a.worker:
        worker(a.rtol)
        return
    res = {"before": [], "after": []}
    order = []
    for i in range(a.rounds):
        order += [("before", "after"), ("after", "before")][i % 2]
    for side in order:
        res[side].append(run(a.before if side == "before" else a.after, a.rtol))
        print(side, res[side][-1], flush=True)
    digests = {r["digest"] for r in res["before"] + res["after"]}
    out = {}
    for k in ("batch", "one"):
        b = statistics.median(r[k] for r in res["before"])
        f = statistics.median(r[k] for r in res["after"])
        out[k] = {"before_s": b, "after_s": f, "ratio": f / b}
    out["identical_summaries"] = len(digests) == 1
    out["rtol"] = a.rtol
    out["rounds"] = a.rounds
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
