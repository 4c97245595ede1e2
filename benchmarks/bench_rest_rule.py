"""Cost of the rest rule of issue 15 (item 7): the free-standing batch of
``benchmarks/bench_rocking.py`` (10,032 histories of 20 s: 6 EURODYN (2020) blocks x 44 FEMA P695
far-field components x 38 scale factors 0.1-1.5, ``simulate_batch``, each tree at its default
rtol: 1e-9 for the old tree, 1e-11 since issue 15) with the old rule
(the wall put at rest at the first impact below ``rest_tol * p * alpha``) and the new one (the
cascade summed, at rest at its accumulation point when the ground allows), back to back in
alternating subprocesses on one numba thread.

The old rule is the source tree of another checkout: ``--old SRC`` (e.g. the merge base of the
branch exported with ``git archive BASE src | tar -x -C /tmp/old``). Each side has its own numba
cache folder under the temporary directory. ``python benchmarks/bench_rest_rule.py [--old SRC]
[--repeat 3] [--out FILE]``; without ``--old`` the old tree is exported from git.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
NEW_SRC = HERE.parent / "src"
OLD_REV = "002fc2a"  # the last commit with the old rule
REPEAT_IN_PROCESS = 2  # each worker keeps the best of this many batches


def export_old(rev: str) -> str:
    """``git archive REV src`` into a temporary folder; returns its ``src``."""
    import io
    import tarfile

    tar = subprocess.run(["git", "-C", str(HERE.parent), "archive", "--format=tar", rev, "src"],
                         check=True, capture_output=True).stdout
    dest = Path(tempfile.mkdtemp(prefix="murus_old_rule_"))
    with tarfile.open(fileobj=io.BytesIO(tar)) as tf:
        tf.extractall(dest, filter="data")
    return str(dest / "src")


def worker() -> None:
    """Time the batch once (after a warm-up that compiles or loads the kernels); print JSON."""
    import numpy as np

    from murus.motion import suite
    from murus.rocking import RockingModel, simulate_batch
    from murus.rocking import kernels as K
    try:
        from murus.rocking import restrained_wall_block
    except ImportError:  # the old tree
        from murus.rocking import seed002_block as restrained_wall_block

    recs = [m.sliced(0.0, 20.0) for m in suite("farfield")]
    blocks = [restrained_wall_block(f"block{i}") for i in range(1, 7)]
    scales = np.linspace(0.1, 1.5, 38)
    models = [RockingModel(b) for b in blocks]
    motions = [m.scaled(s) for m in recs for s in scales]
    simulate_batch(models[:1], motions[:2], duration=20.0)
    el = float("inf")
    for _ in range(REPEAT_IN_PROCESS):
        t0 = time.perf_counter()
        br = simulate_batch(models, motions, duration=20.0)
        el = min(el, time.perf_counter() - t0)
    raw = br.raw
    print(json.dumps({"time": el, "n": int(raw[..., 0].size),
                      "steps": float(raw[..., K.S_N_STEPS].mean()),
                      "impacts": float(raw[..., K.S_N_IMPACTS].mean()),
                      "over": float((raw[..., K.S_OVERTURNED] > 0).mean()),
                      "theta": raw[..., K.S_THETA_MAX].ravel().tolist(),
                      "status_bad": int((raw[..., K.S_STATUS] != 0).sum())}))


def run(src: str, tag: str) -> dict:
    env = dict(os.environ, PYTHONPATH=src, NUMBA_NUM_THREADS="1", PYTHONDONTWRITEBYTECODE="1",
               NUMBA_CACHE_DIR=str(Path(tempfile.gettempdir()) / f"murus_bench_rest_{tag}"))
    out = subprocess.run([sys.executable, __file__, "--worker"], env=env, check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--worker", action="store_true")
    ap.add_argument("--old", help="src folder with the old rule (default: exported from "
                    f"git revision {OLD_REV})")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=str(HERE / "RESULTS_rest_rule.md"))
    ap.add_argument("--note", default="", help="a line added to the results (e.g. the load)")
    a = ap.parse_args()
    if a.worker:
        worker()
        return
    if a.old is None:
        a.old = export_old(OLD_REV)
    res = {"old": [], "new": []}
    for _ in range(a.repeat):
        res["old"].append(run(a.old, "old"))
        res["new"].append(run(str(NEW_SRC), "new"))
    import numpy as np

    to = [r["time"] for r in res["old"]]
    tn = [r["time"] for r in res["new"]]
    ratios = [n / o for n, o in zip(tn, to, strict=True)]
    o, n = res["old"][0], res["new"][0]
    tho, thn = np.array(o["theta"]), np.array(n["theta"])
    moved = np.abs(thn - tho) > 1e-3 * np.maximum(np.abs(tho), 1e-300)
    import numba

    lines = [
        "# Cost of the rest rule (issue 15, item 7)", "",
        f"Machine: {os.cpu_count()} cores; numba {numba.__version__}; command: "
        "`python benchmarks/bench_rest_rule.py` (old rule: the source tree of git revision "
        f"{OLD_REV}). The free-standing batch of the engine benchmark, 10,032 histories of 20 s "
        "(6 EURODYN (2020) blocks x 44 FEMA P695 far-field components x 38 scale factors 0.1-1.5), "
        "`simulate_batch`, each at its default tolerance (old: rtol 1e-9; new: rtol 1e-11), one "
        "numba thread, old and new rule in alternating "
        f"subprocesses, each the best of {REPEAT_IN_PROCESS} batches.", "",
        "| rule | batch time on 1 thread [s] (runs) | median [s] | steps per history | "
        "impacts per history | overturned [%] | runs not ok |", "|---|---|---|---|---|---|---|",
        f"| old: at rest at the first impact below 1e-3 p alpha | "
        f"{', '.join(f'{x:.2f}' for x in to)} | {statistics.median(to):.2f} | "
        f"{o['steps']:.0f} | {o['impacts']:.1f} | {100 * o['over']:.1f} | {o['status_bad']} |",
        f"| new: cascade summed, at rest at its accumulation point | "
        f"{', '.join(f'{x:.2f}' for x in tn)} | {statistics.median(tn):.2f} | "
        f"{n['steps']:.0f} | {n['impacts']:.1f} | {100 * n['over']:.1f} | {n['status_bad']} |",
        "",
        f"Cost ratio new/old per run pair (alternating): {', '.join(f'{r:.3f}' for r in ratios)}; "
        f"median {statistics.median(ratios):.3f}; ratio of the best times "
        f"{min(tn) / min(to):.3f}. {o['n']} histories; theta_max moved by more "
        f"than 0.1 % in {int(moved.sum())} of them ({100 * moved.mean():.1f} %), chaotic "
        "histories included (validation/rest_rule.py separates them).",
    ]
    if a.note:
        lines += ["", a.note]
    text = "\n".join(lines) + "\n"
    if a.out:
        Path(a.out).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
