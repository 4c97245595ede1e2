"""Speed of the 2D distinct-element engine (issue 5, item 7): steps and contact updates per second
for (a) a 50-block dry running-bond wall on a base shaken by a harmonic ramp and (b) the same wall
retaining 5000 backfill discs, on 1 and 2 numba threads; peak memory; where the time goes (each
kernel timed in isolation on the state of the run); extrapolation to a full-scale retaining wall
(10 simulated seconds) against the issue's goal of 2e7 contact updates per second.

UDEC (the tool of Savalle et al. (2022), commercial) cannot run here: its figure from
Savalle et al. (2022) (12 hours of computation per simulated second for the scaled-down wall model)
is quoted as the peer point.

``python benchmarks/bench_dem.py [--out benchmarks/RESULTS_dem.md] [--quick]``
"""

from __future__ import annotations

import copy
import math
import os
import platform
import resource
import sys
import time
from pathlib import Path

import numba
import numpy as np
from numba import njit

from murus.dem import Joint, Model
from murus.dem import _kdata as kd
from murus.dem import kernels as K
from murus.motion.synthetic import ramp_velocity

HERE = Path(__file__).resolve().parent
GOAL = 2e7  # contact updates per second (issue 5, item 7)
# harmonic ramp S(t) = A t sin(2 pi f t) [m/s³, Hz] (Savalle et al. (2022), eq. 5)
RAMP_A, RAMP_F = 0.5, 2.0
# Savalle et al. (2022): 12 h of computation per simulated second (scaled-down model)
UDEC_H_PER_S = 12.0
# measured by hand with A/B scripts (not by this benchmark): the texts they feed below
# contact loop on the state of (b), 1 thread, in one process [us/step]: 95d826a, + disc pairs
# specialised (c70d14a), + joint law inlined (0677a4b), + narrow-phase dispatch inlined (fbee899)
CONTACT_AB = (977.0, 608.0, 288.0, 269.0)
AB_ROUND2 = (
    "Second round (commits 27edf3e, c70d14a, 0677a4b, fbee899 against 95d826a), subprocess A/B "
    "script: the settled states of (a) and (b) saved once, runs of 10000 (a) and 1000 (b) steps "
    "alternated A B B A A B, two per process, best of 6 per version; load average 1.4-2.6 "
    "(another engineer's jobs held one core or more): case (a) 6.53e6 -> 8.64e6 updates/s on "
    "1 thread (1.32 x); case (b) 6.60e6 -> 1.43e7 on 1 thread (2.16 x) and 1.21e7 -> 2.32e7 on "
    "2 threads (1.92 x; the best 2-thread runs of both versions came in a quiet minute at load "
    "1.4, their medians, 1.26e6 and 1.82e6, show how the 2-thread runs stall whenever other "
    "jobs hold the cores). Final positions, angles, velocities and energy accumulators "
    "bitwise identical to 95d826a after 1000 steps of (b) and 20000 of (a), on 1 and 2 "
    "threads.")
LEFT_NOTES = (
    "Tried and dropped in the second round: (i) a parallel gather of the pair resultants by "
    "body, through compressed-row lists of the pairs of each body in pair order (the same sums "
    "as the serial scatter, whatever the number of threads): its reads of the pair records are "
    "random and cost about 74 us of CPU per step on (b) against 35 us for the serial scatter, "
    "no gain on two cores; writing the resultants from the contact loop straight into rows by "
    "body moves the random accesses into the contact loop (+100 us); (ii) skipping the "
    "rotation of disc centres in the world-vertex transform: 22 % of the disc centres of (b) "
    "sit 1e-16 m off their body's centroid (recomputed from the mass moments), so the skip "
    "cannot be exact for them, and the branch cost as much as the sine and cosine of small "
    "angles it saves; (iii) dynamic scheduling of the contact loop (numba's "
    "`set_parallel_chunksize`) to balance the threads: a kernel that calls it cannot be cached. "
    "Left: the pairs of the wall (polygon-polygon and polygon-disc, ~10 x the cost of a disc "
    "pair) sit at the start of the pair list and all fall to the first thread of the static "
    "split (two loops, one over the polygon pairs and one over the disc pairs, would balance "
    "them); the serial scatter; the body update (six divisions, two square roots, a sine and "
    "a cosine per body); single-precision contact records; a tighter broad-phase margin for "
    "discs (fewer candidate pairs per active contact); on a shared machine, the 2-thread runs "
    "stall whenever another job holds a core.")


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: kB


def _model_mb(m: Model) -> float:
    return sum(v.nbytes for v in vars(m).values() if isinstance(v, np.ndarray)) / 2**20


def build_wall(backfill: int = 0, seed: int = 0) -> tuple[Model, dict]:
    """10 courses x 5 blocks 0.4 x 0.2 m (half-block bond: courses shifted by +-0.1 m), kn = ks
    = 1e9 Pa/m, friction 35 deg, on a kinematic base; with ``backfill`` discs (radii 0.02-0.03 m
    on a grid without overlap, friction 30 deg, rolling 0.1) behind it, held by a kinematic
    back wall."""
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=35.0))
    info = {}
    x_back = 1.1  # back face of the wall [m]
    if backfill:
        pitch = 2 * 0.03 * 1.001  # hexagonal grid: centre distances >= pitch > r1 + r2
        rows = 40
        cols = int(math.ceil(backfill / rows))
        width = (cols + 0.5) * pitch
        m.set_joint(Joint(kn=1e9, ks=1e9, friction_deg=30.0, rolling=0.1), "fill", "fill")
        m.add_rectangle(width + 3.0, 0.2, center=(x_back + width / 2 - 0.5, -0.1),
                        kinematic="base")
        m.add_rectangle(0.2, 2.6, center=(x_back + width + 0.1, 1.3), kinematic="base")
    else:
        m.add_rectangle(3.0, 0.2, center=(0.0, -0.1), kinematic="base")
    for c in range(10):
        off = 0.1 if c % 2 == 0 else -0.1
        for i in range(5):
            m.add_rectangle(0.4, 0.2, center=(-0.8 + 0.4 * i + off, 0.1 + 0.2 * c))
    if backfill:
        rng = np.random.default_rng(seed)
        r = rng.uniform(0.02, 0.03, backfill)
        k = np.arange(backfill)
        row = k % rows
        x = x_back + (k // rows + 0.5 + 0.5 * (row % 2)) * pitch
        y = (row + 0.5) * pitch * math.sqrt(3) / 2
        for xi, yi, ri in zip(x, y, r, strict=True):
            m.add_disc((xi, yi), ri, group="fill")
        info["backfill_width"] = width
    m.set_base_motion(velocity=lambda t: ramp_velocity(RAMP_A, RAMP_F, t))
    return m, info


# timing loops inside numba: no Python dispatch overhead (~10-30 us for 20+ array arguments)
@njit(cache=False)  # never a stale cache of the kernels it calls
def _loop_rebuild(reps, shapes, bkin, margin, contacts, jtab):
    for _ in range(reps):
        newp = K.broad_phase(shapes, bkin, margin)
        K.transfer(contacts, newp, shapes.sgroup, jtab, 0)


@njit(cache=False)  # never a stale cache of the kernels it calls
def _loop_serial(reps, c, dis, shapes, bodies, jprops, dt, thick, reach, nact):
    for _ in range(reps):
        K._contacts_serial(c, dis, shapes, bodies, jprops, dt, thick, reach, nact)


@njit(cache=False)  # never a stale cache of the kernels it calls
def _loop_parallel(reps, c, dis, shapes, bodies, jprops, dt, thick, reach, nact):
    for _ in range(reps):
        K._contacts_parallel(c, dis, shapes, bodies, jprops, dt, thick, reach, nact)


@njit(cache=False)  # never a stale cache of the kernels it calls
def _loop_sum(reps, pairs, sbody, nact, pw, E, fb):
    for _ in range(reps):
        K._sum_pairs(pairs, sbody, nact, pw, E, fb)


@njit(cache=False)  # never a stale cache of the kernels it calls
def _loop_update(reps, par, P, fr, fb, bodies, shapes, part, bsp, bsh):
    for _ in range(reps):
        if par:
            K._update_bodies_par(P, fr, fb, bodies, shapes, part, bsp, bsh)
        else:
            K._update_bodies_ser(P, fr, fb, bodies, shapes, part, bsp, bsh)


def _contact_args(m: Model) -> tuple:
    n = m.pairs.shape[0]
    c = kd.Contacts(m.pairs, m.pj, m.pbond.copy(), m.sid.copy(), m.sf.copy(), m.sbr.copy())
    return (c, np.zeros((n, K.NW)), kd.pack(kd.Shapes, m), kd.pack(kd.Bodies, m), m.jprops,
            m.dt, m.thickness, m.P[K.P_REACH], np.zeros(n, np.int64))


def _timed(loop, args, reps, repeat=3):
    """Best of ``repeat`` timings of ``reps`` calls [s per call]."""
    loop(1, *args)  # compile / load the cache
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        loop(reps, *args)
        best = min(best, (time.perf_counter() - t0) / reps)
    return best


def kernel_split(m: Model, step_time: float, rebuild_rate: float, parallel: bool) -> dict:
    """Each kernel of a step timed in isolation (in a numba loop) on the current state (copies
    of the state arrays), as ``run_chunk`` calls them: seconds per call."""
    n = m.pairs.shape[0]
    reps = max(5, min(2000, int(4e5 / max(n, 1))))
    use_par = parallel and n >= m.P[K.P_PARMIN]
    out = {}
    c = _contact_args(m)
    t_rb = _timed(_loop_rebuild, (c[2], m.bkin, m.margin, c[0], m.jtab), max(3, reps // 10))
    out["broad phase + transfer (per rebuild)"] = t_rb
    out["broad phase + transfer (amortised per step)"] = t_rb * rebuild_rate
    out["narrow phase + joint law (contact loop)"] = _timed(_loop_parallel, c, reps)
    pw, nact = c[1], c[8]
    fb = np.zeros((m.nbody, 3))
    out["pair resultants to the bodies + dissipation sums"] = _timed(
        _loop_sum, (m.pairs, m.sbody, nact, pw, np.zeros(K.NE), fb), reps)
    st = [x.copy() for x in (m.bpos, m.bang, m.bvel, m.bomg)]
    P = m.P.copy()
    P[[K.P_DT, K.P_ALOCAL, K.P_AMASS, K.P_DREL]] = (1e-12, 0.0, 0.0, 1.0)
    fr = kd.Frame(0.0, 0.0, 0.0, 0.0, 0.0, -9.81, 0.0, 0.0)  # base at rest, gravity
    bsp, bsh = K.incidence(m.sbody, m.nbody)
    bodies = kd.Bodies(*st, m.bmass, m.binert, m.bkin, m.brad, m.blast.copy(), m.bsnap.copy(),
                       m.bpresc, m.bext)
    shapes = kd.pack(kd.Shapes, m)._replace(wv=m.wv.copy())
    out["body update (central differences, damping, energy, rebuild test, world vertices)"] = (
        _timed(_loop_update, (use_par, P, fr, fb, bodies, shapes, np.zeros((K.NBLK, K.NQ)),
                              bsp, bsh), reps))
    parts = sum(v for k, v in out.items() if k != "broad phase + transfer (per rebuild)")
    out["remainder (step bookkeeping, Python layer of Model.run)"] = step_time - parts
    return out


def _to_go(rate: float) -> str:
    """Distance of a rate [updates/s] to the goal, in words."""
    return "goal met" if rate >= GOAL else f"x{GOAL / rate:.1f} to go"


def timed_run(m0: Model, steps: int, threads: int, repeat: int = 6) -> dict:
    """Best of ``repeat`` runs of ``steps`` steps, each from a copy of the state ``m0``."""
    runs = [_one_run(copy.deepcopy(m0), steps, threads) for _ in range(repeat)]
    best = min(runs, key=lambda r: r["wall"])
    best["walls"] = [r["wall"] for r in runs]
    return best


def _one_run(m: Model, steps: int, threads: int) -> dict:
    numba.set_num_threads(threads)
    sample = steps * m.dt  # one sample at the end: no monitor overhead inside the timing
    c0 = int(m.C[K.C_REBUILD])
    p0 = 0
    t0 = time.perf_counter()
    res = m.run(duration=sample, sample_dt=sample, threads=threads)
    wall = time.perf_counter() - t0
    p0 = m.pairs.shape[0]
    return {"threads": threads, "steps": res.steps, "wall": wall, "updates": res.contact_updates,
            "steps_per_s": res.steps / wall, "updates_per_s": res.contact_updates / wall,
            "pairs": p0, "pairs_per_s": p0 * res.steps / wall,
            "rebuild_rate": (int(m.C[K.C_REBUILD]) - c0) / max(res.steps, 1),
            "status": res.status, "t_end": m.time, "model": m}


def main(out: Path, quick: bool = False) -> None:
    load0 = os.getloadavg()
    t_start = time.perf_counter()
    cmd = "python benchmarks/bench_dem.py --out benchmarks/RESULTS_dem.md"
    nthreads = [1, 2] if numba.config.NUMBA_NUM_THREADS >= 2 else [1]
    cases = {}
    rss = {"start": _rss_mb()}
    # ---- (a) the wall alone
    m, _ = build_wall()
    t0 = time.perf_counter()
    st = m.settle(tol=1e-4, max_steps=100_000)
    settle_a = (st, time.perf_counter() - t0)
    m.run(0.05)  # compile / load cache of the dynamic path
    dur_steps = int((0.6 if quick else 2.0) / m.dt)
    rows = [timed_run(m, dur_steps, th) for th in nthreads]  # from the same settled state
    m = rows[0]["model"]
    numba.set_num_threads(1)
    split = kernel_split(m, rows[0]["wall"] / rows[0]["steps"], rows[0]["rebuild_rate"], False)
    cases["a"] = {"name": "(a) 50-block wall", "model": m, "rows": rows, "split": split,
                  "settle": settle_a, "nbody": m.nbody, "model_mb": _model_mb(m)}
    rss["a"] = _rss_mb()
    # ---- (b) the wall with 5000 backfill discs
    nfill = 1500 if quick else 5000
    m, info = build_wall(nfill)
    numba.set_num_threads(nthreads[-1])
    t0 = time.perf_counter()
    # settling: the discs first fall into place under 8 g with light local damping, then 1 g
    m.gravity = 8 * 9.81
    st = m.settle(tol=1e-3, alpha=0.2, max_steps=2500 if quick else 3500)
    m.gravity = 9.81
    st = m.settle(tol=1e-3, max_steps=1000 if quick else 12000)
    settle_b = (st, time.perf_counter() - t0)
    dur_steps = 300 if quick else 1000
    rows = [timed_run(m, dur_steps, th) for th in nthreads]
    same = all(np.array_equal(r["model"].bpos, rows[0]["model"].bpos)
               and np.array_equal(r["model"].E, rows[0]["model"].E) for r in rows)
    m = rows[0]["model"]
    splits = {}
    for th, r in zip(nthreads, rows, strict=True):
        numba.set_num_threads(th)
        splits[th] = kernel_split(m, r["wall"] / r["steps"], r["rebuild_rate"], True)
    cases["b"] = {"name": f"(b) wall + {nfill} backfill discs", "model": m, "rows": rows,
                  "split": splits, "settle": settle_b, "nbody": m.nbody,
                  "model_mb": _model_mb(m), "info": info, "same": same}
    rss["b"] = _rss_mb()
    numba.set_num_threads(1)
    # ---- the plain serial loop of the contact kernel against the parallel loop (design note)
    npair = cases["b"]["model"].pairs.shape[0]
    cargs = _contact_args(cases["b"]["model"])
    t_ser = _timed(_loop_serial, cargs, 20)
    par = {}
    for th in nthreads:
        numba.set_num_threads(th)
        par[th] = _timed(_loop_parallel, cargs, 20)
    numba.set_num_threads(1)
    load1 = os.getloadavg()
    total = time.perf_counter() - t_start
    write(out, cases, rss, load0, load1, total, cmd, quick, npair, t_ser, par)


def write(out, cases, rss, load0, load1, total, cmd, quick, npair, t_ser, par) -> None:
    a = cases["a"]
    b = cases["b"]
    best_b = max(b["rows"], key=lambda r: r["updates_per_s"])
    best_a = max(a["rows"], key=lambda r: r["updates_per_s"])
    mb = b["model"]
    ndisc = len(mb.disc_shape)
    upd_per_step_b = best_b["updates"] / best_b["steps"]
    # ---- extrapolation to the full-scale wall (assumed sizes)
    H, L_fill = 4.0, 5.0  # wall height, backfill width [m]
    courses = int(round(H / 0.1))
    n_blocks = int(round(courses * 2.5))  # courses of 2 and 3 stones 0.35 m, alternately
    rmean = 0.025
    packing = 0.82  # area fraction of a dense disc packing
    n_disc_fs = int(round(packing * H * L_fill / (math.pi * rmean**2)))
    upd_per_disc = upd_per_step_b / max(ndisc, 1)  # sub-contacts per disc (and its share of
    # the wall) in case (b)
    upd_fs = upd_per_disc * n_disc_fs
    dt_b = mb.dt
    steps_fs = 10.0 / dt_b
    t_fs = steps_fs * upd_fs / best_b["updates_per_s"]
    t_goal = steps_fs * upd_fs / GOAL
    L = []
    w = L.append
    w("# Distinct-element engine speed (issue 5, item 7)")
    w("")
    w(f"Machine: {os.cpu_count()} cores ({platform.processor() or platform.machine()}), "
      f"Python {platform.python_version()}, numba {numba.__version__} "
      f"(NUMBA_NUM_THREADS={numba.config.NUMBA_NUM_THREADS}); load average (1, 5, 15 min) "
      f"at the start {load0[0]:.2f} {load0[1]:.2f} {load0[2]:.2f}, at the end "
      f"{load1[0]:.2f} {load1[1]:.2f} {load1[2]:.2f} (this benchmark included).")
    w(f"Command: `{cmd}`{' --quick' if quick else ''}; total benchmark time {total:.0f} s. "
      "Numba kernels compiled (cache) before timing; each timed run is one `Model.run` call "
      "with a single sample at its end (no monitor overhead inside).")
    w("")
    w("Cases: (a) 10 courses x 5 blocks 0.4 x 0.2 m, half-block bond (courses shifted by "
      "+-0.1 m), kn = ks = 1e9 Pa/m, friction 35 deg, on a kinematic base moved by the "
      f"harmonic ramp S(t) = A t sin(2 pi f t), A = {RAMP_A} m/s³, f = {RAMP_F} Hz (Savalle et "
      f"al. (2022) "
      "eq. 5), settled under gravity first; (b) the same wall with "
      f"{ndisc} discs (radii uniform 0.02-0.03 m, generated on a grid without overlap, "
      f"{b['info']['backfill_width']:.1f} m wide, 40 rows of a hexagonal grid of pitch 0.06 m; "
      "disc joint friction 30 deg, rolling "
      "0.1) behind it and a kinematic back wall; settled under gravity "
      f"(3500 steps under 8 g with local damping 0.2, then up to 12000 at 1 g: "
      f"{b['settle'][0].message}; "
      f"{b['settle'][1]:.0f} s), only the dynamic phase timed (best of 6 runs from the same "
      "state for each thread count). "
      "A contact update is one active sub-contact processed in one step (the engine's "
      "`RunResult.contact_updates`); a pair is a candidate pair of the broad phase (the narrow "
      "phase runs on every pair every step).")
    w("")
    w("| case | threads | bodies | steps | wall [s] (best; median of the runs) | steps/s | "
      "candidate pairs | pairs/s | contact updates/s | ratio to the goal 2e7/s | "
      "rebuilds per step |")
    w("|---|---|---|---|---|---|---|---|---|---|---|")
    for c in (a, b):
        for r in c["rows"]:
            w(f"| {c['name']} | {r['threads']} | {c['nbody']} | {r['steps']} | "
              f"{r['wall']:.2f} ({float(np.median(r['walls'])):.2f}) | "
              f"{r['steps_per_s']:.0f} | {r['pairs']} | "
              f"{r['pairs_per_s']:.3g} | {r['updates_per_s']:.3g} | "
              f"{r['updates_per_s'] / GOAL:.3f} ({_to_go(r['updates_per_s'])}) | "
              f"{r['rebuild_rate']:.3f} |")
    if len(b["rows"]) > 1:
        w("")
        if load0[0] > 0.8:
            w(f"Note: the load average was {load0[0]:.1f} at the start of this run (the "
              "benchmark itself adds about 1-2 while it settles the models): other jobs may "
              "have shared the cores, so the 2-thread runs (a parallel loop waits for its "
              "slowest thread at every step) are a lower bound of what two free cores give.")
            r1, r2 = b["rows"][0], b["rows"][1]
            if r2["updates_per_s"] < r1["updates_per_s"]:
                w(f"Here the 2-thread runs of (b) stalled outright (a step took "
                  f"{1e3 * r2['wall'] / r2['steps']:.1f} ms against "
                  f"{1e6 * r1['wall'] / r1['steps']:.0f} us on one thread): each parallel region "
                  "waits for a thread that the system has descheduled for a time slice. The "
                  "same code on two threads in a quiet minute: the A/B figures at the end.")
            w("")
        w(f"Speed-up of 2 threads over 1 on case (b): "
          f"{b['rows'][1]['updates_per_s'] / b['rows'][0]['updates_per_s']:.2f}; on case (a): "
          f"{a['rows'][1]['updates_per_s'] / a['rows'][0]['updates_per_s']:.2f} (case (a) has "
          f"{a['rows'][0]['pairs']} pairs, below the engine's parallel threshold of "
          f"{int(a['model'].P[K.P_PARMIN])} pairs: it always runs on one thread).")
    w("")
    w("## Memory")
    w("")
    w(f"Peak resident set size of the process (`ru_maxrss`): {rss['start']:.0f} MB after the "
      f"imports, {rss['a']:.0f} MB after case (a), {rss['b']:.0f} MB after case (b). Arrays "
      f"held by the models: {a['model_mb']:.2f} MB (a), {b['model_mb']:.2f} MB (b) "
      f"({b['model_mb'] * 2**20 / b['nbody']:.0f} bytes per body in (b)). The engine's memory "
      "is small; the process peak is the Python + numba runtime (and numba's compiler when "
      "a kernel is not in the cache yet: after an edit, run the benchmark twice).")
    w("")
    w("## Where the time goes")
    w("")
    w("Each kernel timed in isolation on the state at the end of the timed run (copies of the "
      "state arrays), as `run_chunk` calls it; the remainder is the measured step time minus "
      "the isolated kernels: the per-step bookkeeping in `run_chunk` and the Python layer of "
      "`Model.run` (base velocity and gravity arrays per chunk). Isolated kernels run with hot "
      "caches: their sum can exceed the measured step (remainder ~0).")
    w("")
    w("| kernel | (a) 1 thread [us/step] | share | " + " | ".join(
        f"(b) {th} thread{'s' if th > 1 else ''} [us/step] | share" for th in b["split"]) + " |")
    w("|---|---|---|" + "---|---|" * len(b["split"]))
    sa = a["split"]
    keys = [k for k in sa if k not in ("contact loop used",
                                       "broad phase + transfer (per rebuild)")]
    step_a = a["rows"][0]["wall"] / a["rows"][0]["steps"]
    steps_b = {th: r["wall"] / r["steps"] for th, r in
               zip(b["split"], b["rows"], strict=True)}
    def cell(v, step):
        if v < 0:  # the isolated kernels add up to more than the step: timing noise
            return ["~0", "~0 %"]
        return [f"{1e6 * v:.1f}", f"{100 * v / step:.0f} %"]

    for k in keys:
        cells = cell(sa[k], step_a)
        for th, s in b["split"].items():
            cells += cell(s[k], steps_b[th])
        w(f"| {k} | " + " | ".join(cells) + " |")
    cells = [f"{1e6 * step_a:.1f}", "100 %"]
    for th in b["split"]:
        cells += [f"{1e6 * steps_b[th]:.1f}", "100 %"]
    w("| **measured step** | " + " | ".join(cells) + " |")
    w("")
    s1 = b["split"][1]
    w(f"One rebuild of the pair list (broad phase + transfer of the contact state) costs "
      f"{1e6 * sa['broad phase + transfer (per rebuild)']:.0f} us in (a) and "
      f"{1e6 * s1['broad phase + transfer (per rebuild)']:.0f} us in (b). Per candidate pair the "
      f"narrow phase + joint law costs "
      f"{1e9 * sa['narrow phase + joint law (contact loop)'] / a['rows'][0]['pairs']:.0f} ns "
      f"(a, polygon pairs) and {1e9 * par[1] / npair:.0f} ns (b, mostly disc pairs), on one "
      "thread.")
    w("")
    w("## Distance to the goal and extrapolation to a full-scale wall")
    w("")
    w(f"Best measured rate on the backfill case: {best_b['updates_per_s']:.3g} contact "
      f"updates/s ({best_b['threads']} thread(s)), i.e. {best_b['updates_per_s'] / GOAL:.3f} of "
      f"the goal of 2e7/s ({_to_go(best_b['updates_per_s'])}; the median of the runs: "
      f"{best_b['updates'] / float(np.median(best_b['walls'])):.3g}/s); the wall alone: "
      f"{best_a['updates_per_s']:.3g}/s ({_to_go(best_a['updates_per_s'])}), a wall of 124 "
      "candidate pairs that runs on one thread.")
    w("")
    w(f"Assumed full-scale model (DSRW1-like, Savalle et al. (2022)): a wall {H:g} m high of 0.1 "
      f"x 0.35 m "
      f"stones, {courses} courses of 2 and 3 stones alternately = {n_blocks} blocks, and a "
      f"backfill "
      f"{L_fill:g} m wide x {H:g} m high of discs of mean radius {rmean} m (radii 0.02-0.03 m as "
      f"here) at an area fraction of {packing}: N = {n_disc_fs:,} discs. Measured in (b): "
      f"{upd_per_disc:.2f} contact updates per step per disc (wall included), time step "
      f"{dt_b:.2e} s (same joint stiffness and disc sizes at full scale), hence "
      f"{upd_fs:,.0f} updates per step and {steps_fs:,.0f} steps for 10 simulated seconds.")
    w("")
    upd_c4 = 2.0 * n_disc_fs + 4.0 * n_blocks  # coordination 4 per disc, 4 per block
    t_c4 = steps_fs * upd_c4 / best_b["updates_per_s"]
    w(f"- at the measured rate: {t_fs / 60:,.1f} min ({t_fs / 3600:.2f} h) for 10 s of shaking;")
    w(f"- the same with a fully settled backfill of coordination number 4 (2 sub-contacts per "
      f"disc, 4 per block: {upd_c4:,.0f} updates per step, the per-update cost unchanged): "
      f"{t_c4 / 60:,.1f} min ({t_c4 / 3600:.2f} h), {t_c4 / 600:.2f} x the 10-minute goal;")
    w(f"- at the goal of 2e7 updates/s: {t_goal / 60:.1f} min (the goal's 10 minutes "
      f"{'are' if t_goal <= 600 else 'are NOT'} met at that rate with these sizes);")
    w(f"- peer point, UDEC (Savalle et al. (2022)): {UDEC_H_PER_S:g} h of computation per "
      f"simulated second "
      f"for the scaled-down wall model, i.e. {10 * UDEC_H_PER_S:g} h for 10 s: the measured "
      f"extrapolation is {10 * UDEC_H_PER_S * 3600 / t_fs:.1f} x faster than that figure "
      "(different model sizes and machines: an order-of-magnitude comparison only).")
    w("")
    w("## What made the engine faster, and what is left")
    w("")
    pcells = ", ".join(f"{th} thread(s) {1e6 * t:.0f} us ({t_ser / t:.1f} x)"
                       for th, t in par.items())
    w(f"1. **The contact loop is always numba's parallel loop.** On the state of (b), the "
      f"plain serial loop over the same `process_pair` takes {1e6 * t_ser:.0f} us per step "
      f"({1e9 * t_ser / npair:.0f} ns per pair); the `prange` loop: {pcells}. Numba "
      "compiles the body of a parallel loop into a separate function (a gufunc) that LLVM "
      "optimises far better than the same body in a plain loop; below "
      f"{int(b['model'].P[K.P_PARMIN])} pairs the engine keeps the parallel loop but runs it "
      "on one thread (waking the second thread costs more than it saves there, and stalls on "
      "a loaded machine).")
    w("2. **No allocation per pair and step.** The narrow phase returns its sub-contacts as "
      "scalars and the joint law works on scalars (the previous version allocated six small "
      "arrays per pair and step, 28 % of the contact loop); pairs that are apart and held no "
      "sub-contact return at once (half the disc pairs of (b)).")
    w("3. **The pair resultants are scattered once.** The contact loop writes the resultant "
      "force of each pair and its moments about both centroids; one serial pass adds them to "
      "the bodies with the step's dissipation (the previous version re-read the two 11-float "
      "slot records of every pair).")
    w(f"4. **Body update in parallel by {K.NBLK} fixed blocks**, whose partial sums (damping, "
      "base and external work, unbalanced force) are combined in block order: the results do "
      f"not depend on the number of threads (checked here: final positions and energy "
      f"accumulators of (b) after {b['rows'][0]['steps']} steps "
      f"{'identical' if b['same'] else 'DIFFERENT'} on "
      f"{' and '.join(str(r['threads']) for r in b['rows'])} thread(s)). Each body also "
      "moves the world coordinates of its shapes there, for the next step: the separate "
      "world-vertex pass, a parallel region of its own, is gone (two thread wake-ups per step "
      "instead of three).")
    w("5. **Disc-disc pairs take a specialised copy of the contact kernel.** The contact loop "
      "calls `process_pair` with a constant flag when both shapes are discs; numba inlines it "
      "with the constant, so that LLVM drops the branches on shape kinds and everything that "
      "concerns a second sub-contact (a disc pair has one at most). On the state of (b), one "
      "thread, both versions in the same process: contact loop "
      f"{CONTACT_AB[0]:.0f} -> {CONTACT_AB[1]:.0f} us per step.")
    w("6. **The joint law and the narrow-phase dispatch are inlined into the contact "
      "kernel.** The joint law took 32 arguments; numba cannot inline a call of more than 30 "
      "(Python compiles it as a call with `*args`), so it stayed a function returning a "
      "12-tuple through memory. It now reads its joint properties itself (28 arguments) and is "
      f"inlined: contact loop {CONTACT_AB[1]:.0f} -> {CONTACT_AB[2]:.0f} us per step; "
      "inlining `collide` and the slot helpers as well: "
      f"{CONTACT_AB[3]:.0f} us ({CONTACT_AB[0] / CONTACT_AB[3]:.1f} x in all), with bitwise "
      "identical results.")
    w("")
    w("Measured against the previous version (commit 0669be0) on the same machine and states "
      "(`/tmp` A/B script, idle machine, load 0.4-0.6): case (a) 2.17e6 -> 5.89e6 updates/s "
      "(2.7 x); case (b) 1.69e6 -> 5.83e6 on 1 thread (3.4 x) and 3.07e6 -> 1.05e7 on 2 "
      "threads (3.4 x), with identical contact counts and final positions (12 digits).")
    w("")
    w(AB_ROUND2)
    w("")
    upd_pair = best_b["updates"] / best_b["steps"] / max(best_b["pairs"], 1)
    rest = steps_b[1] - par[1]  # the step on one thread outside the contact loop
    w(f"Budget: at 2e7 updates/s an update may cost 50 ns on the machine, 100 ns per core; "
      f"with {upd_pair:.2f} active sub-contacts per candidate pair in (b), the whole step may "
      f"cost {100 * upd_pair:.0f} ns per candidate pair on one core. Measured on one thread: "
      f"the contact loop {1e9 * par[1] / npair:.0f} ns per pair, the rest of the step (serial "
      f"scatter, body update, rebuilds, bookkeeping) {1e9 * rest / npair:.0f} ns per pair, "
      f"{1e9 * steps_b[1] / npair:.0f} ns in all; two threads divide it by "
      f"{steps_b[1] / min(steps_b.values()):.2f} here.")
    w("")
    w(LEFT_NOTES)
    w(f"Rebuilds are not the problem: {best_b['rebuild_rate']:.3f} rebuilds per step at "
      f"{1e6 * s1['broad phase + transfer (per rebuild)']:.0f} us each, "
      f"{100 * s1['broad phase + transfer (amortised per step)'] / steps_b[1]:.1f} % of the "
      "step.")
    w("")
    out.write_text("\n".join(L) + "\n")
    print("\n".join(L))


if __name__ == "__main__":
    args = sys.argv[1:]
    target = HERE / "RESULTS_dem.md"
    if "--out" in args:
        target = Path(args[args.index("--out") + 1])
    main(target, quick="--quick" in args)
