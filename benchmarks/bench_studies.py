"""Benchmark of the sweep runner (issue 7, item 6): the full EURODYN (2020), §4.1 spectrum set, 6
geometries (Table 1) x 50 tie stiffnesses 0 <= K <= K_d (eq. 12, one-sided, K' by eq. 11) x 44
FEMA P695 far-field components = 13,200 histories, run serially in this process (numba threads
over the cores), on a local process pool (1 and 2 workers) and on a local Dask cluster (1 and 2
single-threaded worker processes on 127.0.0.1). Every run gives the same Dataset, bit for bit
(checked here).

Writes ``benchmarks/RESULTS_studies.md``: ``python benchmarks/bench_studies.py [--quick]
[--out PATH]``.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent


def make_plan(quick: bool):
    from murus.rocking import restrained_wall_block
    from murus.studies.records import RecordSet
    from murus.studies.spectrum import spectrum_case
    from murus.studies.study import make_study

    case = spectrum_case(restrained_wall_block("block1"))
    blocks = [f"block{i}" for i in range(1, 7)]
    ratios = np.linspace(0.0, 1.0, 8 if quick else 50)
    recs = RecordSet(kind="suite", suite="farfield")
    if quick:
        recs = RecordSet(kind="suite", suite="farfield", select=tuple(
            f"farfield_{i:02d}{c}" for i in range(1, 5) for c in "ab"))
    study = make_study(case, {"block": blocks, "K_over_Kd": ratios}, recs,
                       name="restrained_blocks_all")
    return study.plan()


class Pause:
    """Warm-up hook: hold each warm-up chunk 0.3 s so that the chunks spread over workers."""

    def __call__(self, index: int) -> None:
        time.sleep(0.3)


def timed(plan, kind, workers=None, repeats=2):
    """(startup [s], best run [s], Dataset): the executor is opened and warmed up (processes
    spawned, numba cache loaded) before ``repeats`` timed runs."""
    from murus.studies.executors import open_executor
    from murus.studies.sweep import Dim, Plan, run_plan

    t0 = time.perf_counter()
    h = open_executor(kind, workers)
    try:
        k = 2 * h.workers  # one-node chunks that pause: every worker gets at least one
        warm = Plan("warm", [Dim("i", tuple(range(k)))], [plan.points[-1]] * k,
                    records=plan.records, chunk_size=1)
        run_plan(warm, h, hook=Pause())
        t1 = time.perf_counter()
        best = np.inf
        for _ in range(repeats):
            t2 = time.perf_counter()
            ds = run_plan(plan, h)
            best = min(best, time.perf_counter() - t2)
    finally:
        h.close()
    return t1 - t0, best, ds


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--out", default=str(HERE / "RESULTS_studies.md"))
    ap.add_argument("--repeats", type=int, default=2)
    args = ap.parse_args()
    import numba

    load0 = os.getloadavg()[0]
    plan = make_plan(args.quick)
    n = plan.n_histories
    cores = os.cpu_count()
    runs = [("serial (in-process, numba threads)", "serial", None),
            ("process pool", "process", 1), ("process pool", "process", cores),
            ("Dask LocalCluster", "dask", 1), ("Dask LocalCluster", "dask", cores)]
    rows = []
    ref = None
    for label, kind, w in runs:
        start, run, ds = timed(plan, kind, w, args.repeats)
        if ref is None:
            ref = ds
        same = ds.identical(ref)
        rows.append({"label": label, "kind": kind, "workers": w, "start": start, "run": run,
                     "same": same})
        print(f"{label} x{w}: startup {start:.2f} s, run {run:.2f} s, identical {same}",
              flush=True)
    th = ref["theta_max_over_alpha"]
    pool2 = next(r for r in rows if r["kind"] == "process" and r["workers"] == cores)
    pool1 = next(r for r in rows if r["kind"] == "process" and r["workers"] == 1)
    dask2 = next(r for r in rows if r["kind"] == "dask" and r["workers"] == cores)
    dask1 = next(r for r in rows if r["kind"] == "dask" and r["workers"] == 1)
    steps = float(ref["n_steps"].sum())
    lines = [
        "# Sweep runner benchmark (issue 7)", "",
        f"Machine: {cores} cores, {platform.processor() or 'cpu'}; numba {numba.__version__}; "
        "command: `python benchmarks/bench_studies.py`", "",
        f"{n:,} histories: the EURODYN (2020), §4.1 rocking spectra of all six geometries (Table "
        f"1) "
        f"x {plan.shape[1]} tie stiffnesses 0 <= K <= K_d (tension-only tie at the top, eq. 12; "
        "one-sided, transverse walls K' by eq. 11; free-standing at K = 0) x "
        f"{plan.n_records} FEMA P695 far-field components (whole records + 5 s of free motion), "
        f"Housner's e, event-driven kernel, rtol 1e-9; {len(plan.chunks())} chunks of "
        f"{plan.chunks()[0][1] * plan.n_records} histories (one `simulate_batch` each). "
        f"{steps / n:.0f} Runge-Kutta steps per history on average; "
        f"{100 * float((ref['overturned'] > 0.5).mean()):.0f} % of the cases overturn, "
        f"{100 * float((th >= 0.4).mean()):.0f} % exceed theta/alpha = 0.4.", "",
        "Times exclude opening the executor (spawning the processes and loading the numba "
        "cache in each, reported apart): the executors are warmed up first; each time is the "
        f"best of {args.repeats} runs (load average before the benchmark: {load0:.2f}; other "
        "jobs on the machine make single runs noisy).", "",
        "| executor | workers | startup [s] | run [s] | histories/s | time / process pool "
        f"({cores}) | identical to serial |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        w = "-" if r["workers"] is None else r["workers"]
        lines.append(f"| {r['label']} | {w} | {r['start']:.1f} | {r['run']:.2f} | "
                     f"{n / r['run']:.0f} | {r['run'] / pool2['run']:.2f} | "
                     f"{'yes' if r['same'] else 'NO'} |")
    over = dask2["run"] / pool2["run"] - 1.0
    lines += [
        "",
        f"- Process pool, {cores} workers: {pool2['run']:.1f} s for {n:,} histories "
        f"({n / pool2['run']:.0f} histories/s); goal < 60 s: "
        f"{'met' if pool2['run'] < 60 else 'NOT met'}.",
        f"- Scaling 1 -> {cores} workers: process pool x{pool1['run'] / pool2['run']:.2f}, "
        f"Dask x{dask1['run'] / dask2['run']:.2f} (ideal x{cores}).",
        f"- Dask overhead against the process pool ({cores} workers): {100 * over:+.1f} % "
        f"(goal < 20 %: {'met' if over < 0.20 else 'NOT met'}); cluster startup "
        f"{dask2['start']:.1f} s against {pool2['start']:.1f} s for the pool.",
        "- Serial runs the chunks in this process with numba's `prange` over the cores "
        "(the engine's own parallelism): the reference for the cost of chunking and "
        "process transport.",
        "",
    ]
    text = "\n".join(lines)
    Path(args.out).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
