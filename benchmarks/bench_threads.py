"""Speed of murus's default thread choice on a busy machine (issue 15, item 6): the DEM disc case
(the wall of ``bench_dem.py`` with its backfill discs) and the rocking batch, run with the
default and with one thread, idle and with one and two competing busy processes, as ratios.

Each configuration runs in its own process (numba's threading layer and OpenMP's wait policy
are fixed when a process first runs a parallel kernel):

- ``murus``: the default of murus (``murus.threads``: OpenMP threads sleep at once when idle,
  ``OMP_WAIT_POLICY=passive``; the DEM thread count chosen per chunk of steps);
- ``before``: the default before issue 15 (two threads always, libgomp's default spin of
  300,000 iterations before an idle thread sleeps: ``GOMP_SPINCOUNT=300000``);
- ``short spin``: murus's governor, OpenMP threads spinning 10,000 iterations (about 0.3 ms
  here) before they sleep (``GOMP_SPINCOUNT=10000``), between passive and the old default;
- ``workqueue``: numba's own ``workqueue`` layer with murus's governor;
- ``tbb`` (only when asked for with ``--configs``; needs the ``tbb`` package): numba's TBB
  layer (work stealing) with murus's governor.

The busy processes (``while True: pass``) are started by the worker of each configuration,
bounded to 10 minutes of life, and killed when its measurements end. Runs alternate between
the modes (default, one thread, two threads) from the same state; the table gives the mean of
the repeats (ratios of sums over the same stretch of time).

``python benchmarks/bench_threads.py [--out benchmarks/RESULTS_threads.md] [--quick]
[--configs murus,before,...]``
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

CONFIGS = {
    "murus": {},
    "before": {"MURUS_THREADS": "2", "GOMP_SPINCOUNT": "300000"},
    "short spin": {"GOMP_SPINCOUNT": "10000"},
    "workqueue": {"NUMBA_THREADING_LAYER": "workqueue"},
    "tbb": {"NUMBA_THREADING_LAYER": "tbb"},  # only with --configs (needs the tbb package)
}
DEFAULT_CONFIGS = "murus,before,short spin,workqueue"
NFILL = 5000
BUSY = (0, 1, 2)
DECISION = (
    "What murus does (`murus.threads`): (1) OpenMP threads sleep as soon as they are idle "
    "(`OMP_WAIT_POLICY=passive`, set before numba loads its threading layer unless the user "
    "chose a wait policy): libgomp's default spin of 300,000 iterations at the end of each "
    "parallel region takes the core from the thread that still has work whenever anything "
    "else runs (the 'before' rows), and a short spin of 10,000 iterations is not enough of a "
    "cure (the 'short spin' rows); numba's `workqueue` layer also yields, but runs even a "
    "one-thread region on a worker thread (a hand-over per region), where OpenMP runs it on "
    "the calling thread. TBB (pip package `tbb`, 6.9 MB wheel, 20 MB installed, Intel "
    "Simplified Software License in its metadata) is not a dependency; where it is installed "
    "numba's default takes it before OpenMP (its threads also yield), and `--configs tbb` "
    "measures it. (2) A distinct-element run chooses its thread count "
    "per part of at most 200 steps: one thread while the other runnable threads of the "
    "machine (from /proc/loadavg) leave no core free, all of them otherwise, with timing "
    "probes of the other choice as a check; `simulate_batch` keeps all threads (one parallel "
    "loop over whole histories: a shared core delays it little, the 'rocking default / 1' "
    "column). The results do not depend on the thread count. Override: `threads=N`, "
    "`MURUS_THREADS=N` or an explicit `NUMBA_NUM_THREADS`.")
SPIN = "import time\nt = time.time() + 600\nwhile time.time() < t:\n    pass\n"


def build(path: str, quick: bool) -> dict:
    """The wall of bench_dem.py with its backfill discs, after a short settling (the discs in
    contact: the timed steps are those of the disc case, not of a settled state)."""
    from bench_dem import build_wall

    t0 = time.perf_counter()
    m, _ = build_wall(1500 if quick else NFILL)
    m.gravity = 8 * 9.81
    m.settle(tol=1e-3, alpha=0.2, max_steps=300, threads=1)
    m.gravity = 9.81
    m.save(path)
    return {"build_s": time.perf_counter() - t0, "pairs": int(m.pairs.shape[0]),
            "bodies": int(m.nbody), "dt": m.dt}


def rocking_case():
    import numpy as np

    from murus.motion import suite
    from murus.rocking import RockingModel, restrained_wall_block

    recs = [r.sliced(0.0, 20.0) for r in suite("farfield")][:4]
    models = [RockingModel(restrained_wall_block(f"block{i}")) for i in range(1, 7)]
    motions = [r.scaled(s) for r in recs for s in np.linspace(0.1, 1.5, 10)]
    return models, motions


def worker(name: str, path: str, quick: bool) -> dict:
    import numba

    from murus import threads as T
    from murus.dem import Model
    from murus.rocking import simulate_batch

    m0 = Model.load(path)
    steps = 150 if quick else 300
    reps = int(os.environ.get("BENCH_REPS", 2 if quick else 4))
    default = None
    models, motions = rocking_case()

    def dem(th):
        m = copy.deepcopy(m0)
        t0 = time.perf_counter()
        m.run(duration=steps * m.dt, sample_dt=25 * m.dt, threads=th)
        wall = time.perf_counter() - t0
        g = T.last
        return wall, g.steps.get(1, 0) / max(1, sum(g.steps.values()))

    def rock(th):
        t0 = time.perf_counter()
        simulate_batch(models, motions, duration=20.0, threads=th)
        return time.perf_counter() - t0, 0.0

    dem(1), dem(2), rock(1), rock(2)  # load the kernels
    out = {"layer": numba.threading_layer(), "threads": numba.get_num_threads(),
           "omp_wait_policy": os.environ.get("OMP_WAIT_POLICY", ""),
           "gomp_spincount": os.environ.get("GOMP_SPINCOUNT", ""), "rows": []}
    modes = [("dem", default), ("dem", 1), ("dem", 2), ("rock", default), ("rock", 1)]
    for nb in BUSY:
        procs = [subprocess.Popen([sys.executable, "-c", SPIN]) for _ in range(nb)]
        try:
            time.sleep(0.5)
            load0 = os.getloadavg()[0]
            others = T.others_running(5)
            res = {f"{k}:{th}": [] for k, th in modes}
            share = []
            for r in range(reps):
                for k, th in (modes if r % 2 == 0 else modes[::-1]):
                    wall, s1 = (dem if k == "dem" else rock)(th)
                    res[f"{k}:{th}"].append(wall)
                    if k == "dem" and th is None:
                        share.append(s1)
            out["rows"].append({"busy": nb, "load": load0, "others": others,
                                "t": {k: statistics.mean(v) for k, v in res.items()},
                                "all": res, "one_share": statistics.mean(share)})
        finally:
            for p in procs:
                p.kill()
                p.wait()
    out["steps"] = steps
    out["reps"] = reps
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=str(HERE / "RESULTS_threads.md"))
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--configs", default=DEFAULT_CONFIGS,
                    help=f"comma-separated, of {', '.join(CONFIGS)}")
    ap.add_argument("--worker", nargs=2, metavar=("CONFIG", "STATE"), help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.worker:
        print(json.dumps(worker(a.worker[0], a.worker[1], a.quick)))
        return
    t0 = time.perf_counter()
    load0 = os.getloadavg()
    with tempfile.TemporaryDirectory() as tmp:
        state = str(Path(tmp) / "disc_case.npz")
        info = build(state, a.quick)
        res = {}
        for name in a.configs.split(","):
            env = CONFIGS[name]
            e = {k: v for k, v in os.environ.items()
                 if k not in ("NUMBA_NUM_THREADS", "MURUS_THREADS", "OMP_WAIT_POLICY",
                              "GOMP_SPINCOUNT", "NUMBA_THREADING_LAYER")}
            e.update(env)
            p = subprocess.run([sys.executable, __file__, "--worker", name, state]
                               + (["--quick"] if a.quick else []), env=e, capture_output=True,
                               text=True, timeout=600)
            if p.returncode:
                sys.exit(f"worker {name} failed:\n{p.stderr[-2000:]}")
            res[name] = json.loads(p.stdout.strip().splitlines()[-1])
    write(Path(a.out), res, info, load0, os.getloadavg(), time.perf_counter() - t0,
          "" if a.configs == DEFAULT_CONFIGS else f' --configs "{a.configs}"', a.quick)


def write(out: Path, res: dict, info: dict, load0, load1, total: float, extra: str,
          quick: bool) -> None:
    import numba

    L = []
    w = L.append
    w("# Threads on a busy machine (issue 15, item 6)")
    w("")
    w(f"Machine: {os.cpu_count()} cores ({platform.processor() or platform.machine()}), Python "
      f"{platform.python_version()}, numba {numba.__version__}; load average (1, 5, 15 min) at "
      f"the start {load0[0]:.2f} {load0[1]:.2f} {load0[2]:.2f}, at the end {load1[0]:.2f} "
      f"{load1[1]:.2f} {load1[2]:.2f} (this benchmark included). "
      f"Command: `python benchmarks/bench_threads.py{' --quick' if quick else ''}{extra}`; total "
      f"{total:.0f} s.")
    w("")
    r0 = res["murus"]
    w(f"Cases: DEM, the disc case (b) of `bench_dem.py` ({info['bodies']} bodies, "
      f"{info['pairs']} candidate pairs, dt = {info['dt']:.3g} s) after 300 settling steps, "
      f"{r0['steps']} steps per run from the same state (one sample every 25 steps); rocking, "
      "`simulate_batch` of the six blocks of EURODYN (2020) under 4 far-field records x 10 scales "
      f"(240 histories of 20 s). Mean of {r0['reps']} runs per mode, the modes alternated "
      "(A B C C B A ...), so that a ratio is one of sums over the same stretch of time. "
      "Busy: `while True: pass` processes started by the benchmark. 'others' is the number "
      "of other runnable threads read from /proc/loadavg when the measurement starts "
      "(background jobs of other users included); 'share 1' the fraction of the DEM steps the "
      "default ran on one thread.")
    w("")
    idle = [row["others"] for r in res.values() for row in r["rows"] if row["busy"] == 0]
    if max(idle) >= 1:
        w(f"**Measured under background load**: other jobs held the machine during this run "
          f"({min(idle):.0f} to {max(idle):.0f} other runnable threads in the rows without busy "
          "processes of the benchmark), so the rows 'busy 0' are not idle and the absolute "
          "times vary from configuration to configuration (they ran minutes apart); compare "
          "ratios within a configuration and condition. Re-run on an idle machine for the idle "
          "speed.")
        w("")
    w("Ratios are times over the time on one thread in the same configuration and condition "
      "(< 1: faster than one thread). Goal: default / 1 thread <= 1.10 with 1 and 2 busy "
      "processes, and the idle speed of 2 threads kept.")
    w("")
    w("| configuration | busy | others | DEM 1 thread [s] | DEM 2 threads [s] | DEM default / 1 "
      "| DEM 2 / 1 | share 1 | rocking 1 thread [s] | rocking default / 1 |")
    w("|---|---|---|---|---|---|---|---|---|---|")
    for name, r in res.items():
        for row in r["rows"]:
            t = row["t"]
            w(f"| {name} ({r['layer']}) | {row['busy']} | {row['others']:.0f} "
              f"| {t['dem:1']:.3f} | {t['dem:2']:.3f} | {t['dem:None'] / t['dem:1']:.2f} "
              f"| {t['dem:2'] / t['dem:1']:.2f} | {row['one_share']:.2f} "
              f"| {t['rock:1']:.3f} | {t['rock:None'] / t['rock:1']:.2f} |")
    w("")
    if "before" in res and "murus" in res:
        b, m = res["before"]["rows"], res["murus"]["rows"]
        w("Default of murus against the default before (time ratio, < 1: murus now faster): "
          "DEM " + ", ".join(f"{x['busy']} busy {y['t']['dem:None'] / x['t']['dem:None']:.2f}"
                             for x, y in zip(b, m, strict=True))
          + "; rocking batch "
          + ", ".join(f"{x['busy']} busy {y['t']['rock:None'] / x['t']['rock:None']:.2f}"
                      for x, y in zip(b, m, strict=True)) + ".")
        w("")
    w(DECISION)
    w("")
    w("Environment of the configurations: "
      + "; ".join(f"{n}: layer {r['layer']}, OMP_WAIT_POLICY={r['omp_wait_policy'] or '-'}, "
                  f"GOMP_SPINCOUNT={r['gomp_spincount'] or '-'}" for n, r in res.items()) + ".")
    w("")
    out.write_text("\n".join(L) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
