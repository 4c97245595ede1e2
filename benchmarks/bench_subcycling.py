"""Subcycling of the coupled engine (the zones step once every n steps of the stones,
:meth:`murus.continuum.coupled.CoupledModel.set_subcycle`) against one step for all, side by
side in one run, on an idle machine: the H/B = 2.7 mock-up of Savalle et al. (2022) (§3; zones
of H / 12, courses of about 10 mm, the mesh of Table 3) under its S2 ramp at 10 Hz for
``--seconds`` simulated seconds (default 0.5), at the joint stiffness of Table 1 times 1e-2 (the
default), 1e-1 and 1 (as printed: the reference of the mock-ups' validation since session 23),
and DSRW1 (§4) at 5 Hz, 1 simulated second. Subcycling at the printed stiffness is validated by
the pairs of VALIDATION.md (*Subcycling*).

Reported: the wall time per simulated second of each, the ratio, the subcycle n (``"auto"``:
the zones' and the interface's stable steps over the stones'), and the largest difference of
d_top between the two runs over the window (the accuracy of A_col is measured on whole
collapse runs in VALIDATION.md, section on the continuum backfill). Peer point: UDEC, the
paper's tool (commercial, not runnable here), 12 hours per simulated second of its mock-up
(§3.1).

``python benchmarks/bench_subcycling.py [--seconds 0.5] [--threads 1] [--out
benchmarks/RESULTS_subcycling.md]``
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
UDEC_S_PER_S = 12.0 * 3600


def _mock():
    from murus.retaining.geometry import preset

    w = preset("mockup-2.7")
    return w.with_(stone_height=w.height / max(1, round(w.height / 0.010)))


def _wall(case: str):
    from murus.retaining.geometry import preset

    return _mock() if case == "mock" else preset("DSRW1")


def _limit(case: str, scale: float) -> int:
    """The subcycle "auto" takes: the wall and its backfill built (not settled)."""
    from murus.retaining.continuum_backfill import ContinuumBackfill
    from murus.retaining.dem_wall import build_wall

    wall = _wall(case)
    bf = ContinuumBackfill(wall, stiffness_scale=scale)
    dw = build_wall(wall, stiffness_scale=scale, backstop=False)
    bf._build(dw)
    return bf.coupled.subcycle_limit()


def _run(case: str, scale: float | None, sub, seconds: float):
    from murus.retaining.collapse import collapse_run

    kw = dict(A_rate=2.6 / 19.9, t_max=seconds) if case == "mock" else dict(t_max=seconds)
    args = (_wall(case), 10.0 if case == "mock" else 5.0)
    t0 = time.perf_counter()
    r = collapse_run(*args, backfill="continuum", stiffness_scale=scale, subcycle=sub, **kw)
    return r, time.perf_counter() - t0


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=0.5)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default=str(HERE / "RESULTS_subcycling.md"))
    args = ap.parse_args(argv)
    os.environ["NUMBA_NUM_THREADS"] = str(args.threads)
    import numba

    load0 = os.getloadavg()
    _run("mock", 1e-2, None, 0.01)  # compile (numba cache) before timing
    _run("mock", 1e-2, "auto", 0.01)
    rows = []
    cases = [("mock", 1e-2, args.seconds), ("mock", 1e-1, args.seconds),
             ("mock", 1.0, args.seconds), ("DSRW1", 1e-2, 1.0)]
    for case, scale, secs in cases:
        one, t_one = _run(case, scale, None, secs)
        sub, t_sub = _run(case, scale, "auto", secs)
        per1 = (one.wall_time - one.setup_time) / one.t_end
        pers = (sub.wall_time - sub.setup_time) / sub.t_end
        n = len(one.d_top) if len(one.d_top) == len(sub.d_top) else 0
        dd = float(np.max(np.abs(one.d_top[:n] - sub.d_top[:n]))) if n else float("nan")
        rows.append((case, scale, secs, one.dt, _limit(case, scale), per1, pers,
                     float(np.max(np.abs(one.d_top))), dd))
        print(f"{case} x{scale:g}: {per1:.1f} s/s against {pers:.1f} s/s", file=sys.stderr)
    load1 = os.getloadavg()
    L = ["# Subcycling of the coupled engine (blocks and zones)", "",
         f"Machine: {os.cpu_count()} cores ({platform.machine()}), Python "
         f"{platform.python_version()}, numba {numba.__version__} (NUMBA_NUM_THREADS="
         f"{args.threads}). Command: `python benchmarks/bench_subcycling.py --seconds "
         f"{args.seconds:g} --threads {args.threads}`. Kernels compiled (cache) before timing. "
         "Wall time per simulated second, without the settling.", "",
         "| model | joint stiffness | simulated [s] | dt [s] | n | one step for all [s/s] | "
         "subcycled [s/s] | speed-up | max d_top [m] | max d_top difference [m] | "
         "UDEC (mock-up, §3.1) / subcycled |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
    for case, scale, secs, dt, n, per1, pers, dmax, dd in rows:
        name = "mock-up H/B = 2.7, 10 Hz" if case == "mock" else "DSRW1, 5 Hz"
        udec = f"{UDEC_S_PER_S / pers:.0f}" if case == "mock" else "-"
        L.append(f"| {name} | x {scale:g} | {secs:g} | {dt:.2e} | {n} | {per1:.1f} | "
                 f"{pers:.1f} | {per1 / pers:.1f} | {dmax:.2e} | {dd:.1e} | {udec} |")
    L += ["", f"Load average (1, 5, 15 min) at the start "
          f"{' '.join(f'{x:.2f}' for x in load0)}, at the end "
          f"{' '.join(f'{x:.2f}' for x in load1)}."]
    Path(args.out).write_text("\n".join(L) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
