"""Speed of the DEM engine in two source trees, alternated in one script (issue 16, item 1:
the named kernel data must cost no speed).

The two cases of ``benchmarks/bench_dem.py``: (a) the 50-block wall on a base shaken by the
harmonic ramp, (b) the same wall with backfill discs; each settled once (in the AFTER tree) and
saved, then run from that state in subprocesses with ``PYTHONPATH=<tree>/src``, in the order
A B B A A B ..., on 1 thread and on the default number of threads. Each subprocess loads the
numba cache, runs a short warm-up, then times ``reps`` runs of ``steps`` steps from a copy of the
state; the script reports the median of the per-process best times and the ratio AFTER/BEFORE,
and whether the final states of all the runs of a case are bitwise identical.

``python benchmarks/ab_dem.py BEFORE_TREE AFTER_TREE [--discs N] [--rounds R]``
"""

from __future__ import annotations

import copy
import hashlib
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def prepare(out_dir: Path, discs: int) -> None:
    sys.path.insert(0, str(HERE))
    from bench_dem import build_wall

    m, _ = build_wall()
    m.settle(tol=1e-4, max_steps=100_000)
    m.save(out_dir / "a.npz")
    m, _ = build_wall(discs)
    m.gravity = 8 * 9.81
    m.settle(tol=1e-3, alpha=0.2, max_steps=2500)
    m.gravity = 9.81
    m.settle(tol=1e-3, max_steps=2000)
    m.save(out_dir / "b.npz")


def worker(path: Path, steps: int, threads: int, reps: int) -> None:
    import numba

    from murus.dem import Model
    from murus.motion.synthetic import ramp_velocity

    m0 = Model.load(path)
    m0.set_base_motion(velocity=lambda t: ramp_velocity(0.5, 2.0, t))
    numba.set_num_threads(threads)
    copy.deepcopy(m0).run(duration=20 * m0.dt, sample_dt=20 * m0.dt, threads=threads)
    walls = []
    for _ in range(reps):
        m = copy.deepcopy(m0)
        t0 = time.perf_counter()
        m.run(duration=steps * m.dt, sample_dt=steps * m.dt, threads=threads)
        walls.append(time.perf_counter() - t0)
    h = hashlib.sha1()
    for a in (m.bpos, m.bang, m.bvel, m.bomg, m.sf, m.sid, m.E, m.C):
        h.update(a.tobytes())
    print(json.dumps({"walls": walls, "digest": h.hexdigest()}))


def main(before: Path, after: Path, discs: int, rounds: int) -> None:
    ndef = os.cpu_count() or 1
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        env = dict(os.environ, PYTHONPATH=str(after / "src"), NUMBA_NUM_THREADS=str(ndef))
        subprocess.run([sys.executable, __file__, "--prepare", str(tmp), str(discs)], env=env,
                       check=True)
        res = {}
        load0 = os.getloadavg()
        for case, steps in (("a", 40000), ("b", 1000)):
            for th in (1, ndef):
                best = {"before": [], "after": []}
                digests = set()
                order = ["before", "after", "after", "before"] * ((rounds + 1) // 2)
                for side in order[:2 * rounds]:
                    tree = before if side == "before" else after
                    env = dict(os.environ, PYTHONPATH=str(tree / "src"),
                               NUMBA_NUM_THREADS=str(ndef))
                    out = subprocess.run(
                        [sys.executable, __file__, "--worker", str(tmp / f"{case}.npz"),
                         str(steps), str(th), "3"], env=env, check=True, capture_output=True,
                        text=True).stdout
                    rec = json.loads(out.splitlines()[-1])
                    best[side].append(min(rec["walls"]))
                    digests.add(rec["digest"])
                mb = statistics.median(best["before"])
                ma = statistics.median(best["after"])
                res[f"{case} {th} thread(s)"] = {"steps": steps, "before_s": best["before"],
                                                 "after_s": best["after"],
                                                 "ratio_after_over_before": ma / mb,
                                                 "same_final_state": len(digests) == 1}
                print(f"case {case}, {th} thread(s), {steps} steps: before {mb:.3f} s, "
                      f"after {ma:.3f} s, ratio {ma / mb:.3f}, same final state: "
                      f"{len(digests) == 1}", flush=True)
        res["load"] = {"start": load0, "end": os.getloadavg()}
        print(json.dumps(res, indent=1))


if __name__ == "__main__":
    a = sys.argv[1:]
    if a[0] == "--prepare":
        prepare(Path(a[1]), int(a[2]))
    elif a[0] == "--worker":
        worker(Path(a[1]), int(a[2]), int(a[3]), int(a[4]))
    else:
        discs = int(a[a.index("--discs") + 1]) if "--discs" in a else 5000
        rounds = int(a[a.index("--rounds") + 1]) if "--rounds" in a else 3
        main(Path(a[0]).resolve(), Path(a[1]).resolve(), discs, rounds)
