"""Benchmark of the restrained rocking wall (issue 4, item 9): the batch of the engine
benchmark (6 EURODYN (2020) blocks x 44 FEMA P695 far-field components, first 20 s, x 38 scale
factors
= 10,032 histories) run free-standing and with a tie (K_d, eq. 12), a damper (5 % c_d, eq. 13)
and one-sided contact against transverse walls (K' = 4.5e8 N/m/m), in the same process.

Writes ``benchmarks/RESULTS_restrained.md``; ``python benchmarks/bench_restrained.py``.
"""

from __future__ import annotations

import math
import platform
import time
from pathlib import Path

import numba
import numpy as np

from murus.rocking import (
    Damper,
    RockingModel,
    SpringBed,
    Tie,
    restrained_wall_block,
    simulate_batch,
)
from murus.rocking import kernels as K
from murus.rocking.design import reference_damping, tie_design

HERE = Path(__file__).resolve().parent
DELTA_T = 10.186  # s, eq. 13 characteristic time calibrated on EURODYN (2020), Figure 9


def configurations():
    blocks = [restrained_wall_block(f"block{i}") for i in range(1, 7)]

    def restrained(b, walls):
        return RockingModel(b, tie=Tie(tie_design(b).K_d, b.height),
                            damper=Damper(0.05 * reference_damping(b, DELTA_T), b.height),
                            transverse_walls=SpringBed(walls, b.height), motion_sides="one")

    return {
        "free-standing": [RockingModel(b) for b in blocks],
        "tie only (two-sided)": [RockingModel(b, tie=Tie(tie_design(b).K_d, b.height))
                                 for b in blocks],
        "tie + damper + one-sided, rigid transverse walls":
            [restrained(b, math.inf) for b in blocks],
        "tie + damper + one-sided, elastic walls K' = 4.5e8 N/m/m":
            [restrained(b, 4.5e8) for b in blocks],
    }


def main(quick: bool = False) -> None:
    from murus.motion import suite

    recs = [m.sliced(0.0, 20.0) for m in suite("farfield")]
    scales = np.linspace(0.1, 1.5, 38 if not quick else 4)
    motions = [m.scaled(s) for m in recs for s in scales]
    confs = configurations()
    for models in confs.values():
        simulate_batch(models[:1], motions[:2], duration=20.0)  # compile / load the cache
    rows = []
    base = None
    for name, models in confs.items():
        best = np.inf
        for _ in range(2):
            t0 = time.perf_counter()
            br = simulate_batch(models, motions, duration=20.0)
            best = min(best, time.perf_counter() - t0)
        n = br.raw[..., 0].size
        steps = br.raw[..., K.S_N_STEPS].sum()
        rec = {"name": name, "time": best, "n": n, "steps": steps,
               "rock": (br["theta_max"] > 0).mean(), "over": br.overturned.mean(),
               "impacts": br["n_impacts"].mean()}
        if base is None:
            base = rec
        rows.append(rec)
    lines = [
        "# Restrained rocking benchmark (issue 4)", "",
        f"Machine: {numba.config.NUMBA_NUM_THREADS} cores, {platform.processor() or 'cpu'}; "
        f"numba {numba.__version__}; command: `python benchmarks/bench_restrained.py`", "",
        f"{rows[0]['n']:,} histories of 20 s (6 EURODYN (2020) blocks x 44 FEMA P695 far-field "
        "components x 38 scale factors 0.1-1.5), `simulate_batch`, event-driven, rtol 1e-9, "
        "Housner's e. Restrained: tie K_d at the top (eq. 12), damper 5 % c_d at the top "
        "(eq. 13, delta_t = 10.186 s), transverse walls K' = 4.5e8 N/m/m (one-sided).", "",
        "| configuration | time [s] | histories/s | throughput ratio to free-standing | "
        "RK steps per history | time per step [ns] | per-step cost ratio | rock [%] | "
        "overturn [%] | impacts per history |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        ns = r["time"] / r["steps"] * 1e9 * numba.config.NUMBA_NUM_THREADS
        ns0 = base["time"] / base["steps"] * 1e9 * numba.config.NUMBA_NUM_THREADS
        lines.append(
            f"| {r['name']} | {r['time']:.2f} | {r['n'] / r['time']:.0f} | "
            f"{base['time'] / r['time']:.2f} | {r['steps'] / r['n']:.0f} | {ns:.0f} | "
            f"{ns / ns0:.2f} | {100 * r['rock']:.0f} | {100 * r['over']:.0f} | "
            f"{r['impacts']:.0f} |")
    rigid = rows[2]["time"] / base["time"]
    elastic = rows[3]
    lines += [
        "",
        "Goal of the issue: the batch throughput with tie, damper and one-sided contact active "
        "stays within a factor 1.5 of the free-standing throughput. With rigid transverse walls "
        f"the restrained batch takes {rigid:.2f} x the free-standing time: "
        f"{'met' if rigid <= 1.5 else 'NOT met'}. With elastic walls of the stiffness of "
        "EURODYN (2020) the "
        f"cost per Runge-Kutta step stays within {elastic['time'] / elastic['steps'] / (base['time'] / base['steps']):.2f} "  # noqa: E501
        "of the free-standing one, but every contact with the walls is a bounce of a few "
        "milliseconds (omega_r- ~ 800 rad/s for block1) that the error control resolves with "
        f"tens of steps, and the tie keeps the wall bouncing: {elastic['steps'] / elastic['n']:.0f} "  # noqa: E501
        f"steps and {elastic['impacts']:.0f} impacts per history against "
        f"{base['steps'] / base['n']:.0f} and {base['impacts']:.0f}. That is the physics of a "
        "stiff contact, not overhead; rigid walls are its limit as K' grows (within 1 % at "
        "K' = 4.5e10 N/m/m, tests/rocking/test_restraints.py).",
        "",
        "The per-step cost isolates the price of the extra moment terms (a step is six "
        "evaluations of the moment, each with one sine and one cosine shared by all terms).",
        "",
    ]
    (HERE / "RESULTS_restrained.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    import sys

    main(quick="--quick" in sys.argv)
