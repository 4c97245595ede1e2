"""Speed of the continuum (zones) engine (issue 17, item 8): zone updates per second (one zone
through strain rate, constitutive update and nodal forces in one step, the gridpoint update
included) for about 1e3, 1e4 and 1e5 zones on 1 and 2 threads, and the memory of the state per
zone.

Model: a square block of n x n square zones (1 m), elastic (E = 1e8 Pa, nu = 0.3, 2000 kg/m³)
or Mohr-Coulomb (same, phi = 30 deg, c = 20 kPa, psi = 0) with K0 = 0.5 initial stresses
(elastic state: the return is checked, not applied), gravity, fixed base, roller sides; the
steps are timed through the engine's chunk (no monitors, no Python work between the steps but
the base-velocity and gravity arrays of each chunk).

    NUMBA_NUM_THREADS=2 python benchmarks/bench_continuum.py [--out FILE] [--steps N]
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import time

import numba
import numpy as np

from murus.continuum import ContinuumModel, Elastic, MohrCoulomb
from murus.continuum import engine as eng
from murus.continuum import kernels as K


def block(n: int, mat) -> ContinuumModel:
    xs = np.arange(n + 1, dtype=float)
    X, Y = np.meshgrid(xs, xs)
    xy = np.column_stack([X.ravel(), Y.ravel()])
    i, j = np.meshgrid(np.arange(n), np.arange(n))
    a = (j * (n + 1) + i).ravel()
    zones = np.column_stack([a, a + 1, a + n + 2, a + n + 1]).astype(np.int64)
    m = ContinuumModel(xy, zones, mat)
    x, y = xy[:, 0], xy[:, 1]
    m.fix((x == 0) | (x == n), x=True, y=False)
    m.fix(y == 0)
    m.initial_stress_k0(k0=0.5)
    return m


def rate(m, steps: int, threads: int, repeat: int = 3) -> tuple[float, float]:
    """Best and median zone updates per second over ``repeat`` timed chunks."""
    m.P[K.P_PARMIN] = 0.0 if threads > 1 else 4000.0
    eng._chunk(m, 5, False, threads)  # warm-up (compilation is cached)
    r = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        eng._chunk(m, steps, False, threads)
        r.append(m.nz * steps / (time.perf_counter() - t0))
    return max(r), float(np.median(r))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", help="write the Markdown table here")
    ap.add_argument("--zones", type=int, nargs="*", default=[32, 100, 316],
                    help="side n of the n x n blocks (default: 32 100 316)")
    ap.add_argument("--updates", type=float, default=2e7,
                    help="zone updates per timed chunk (steps = updates / zones)")
    args = ap.parse_args()
    maxth = numba.config.NUMBA_NUM_THREADS
    load0 = os.getloadavg()
    mats = {"elastic": Elastic(density=2000.0, E=1e8, nu=0.3),
            "Mohr-Coulomb": MohrCoulomb(density=2000.0, E=1e8, nu=0.3, friction_deg=30.0,
                                        cohesion=2e4)}
    rows = []
    mem = {}
    for n in args.zones:
        for name, mat in mats.items():
            m = block(n, mat)
            steps = max(20, int(args.updates / m.nz))
            for th in sorted({1, min(2, maxth)}):
                best, med = rate(m, steps, th)
                rows.append((name, m.nz, th, steps, best, med))
                print(f"{name:13s} {m.nz:7d} zones  {th} thread(s)  {best:.3e} zone updates/s "
                      f"(median {med:.3e})", flush=True)
            mem[m.nz] = m.state_bytes() / m.nz
    load1 = os.getloadavg()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    lines = ["# Continuum engine speed (issue 17, item 8)", "",
             f"Machine: {os.cpu_count()} cores ({platform.machine()}), Python "
             f"{platform.python_version()}, numba {numba.__version__} "
             f"(NUMBA_NUM_THREADS={maxth}); load average at the start "
             f"{load0[0]:.2f} {load0[1]:.2f} {load0[2]:.2f}, at the end "
             f"{load1[0]:.2f} {load1[1]:.2f} {load1[2]:.2f}.",
             "Command: `NUMBA_NUM_THREADS=2 python benchmarks/bench_continuum.py`. "
             "A zone update: one zone through strain rate, constitutive update and corner "
             "forces in one step, the gridpoint update included (zones x steps / wall time).",
             "", "| material | zones | threads | steps | zone updates/s (best) | median | "
             "ratio to the goal 1e7/s |", "|---|---|---|---|---|---|---|"]
    for name, nz, th, steps, best, med in rows:
        lines.append(f"| {name} | {nz} | {th} | {steps} | {best:.3e} | {med:.3e} | "
                     f"{best / 1e7:.2f} |")
    lines += ["", "Memory of the state arrays (grid and zones, `ContinuumModel.state_bytes`) "
              "per zone: " + ", ".join(f"{v:.0f} B ({k} zones)" for k, v in mem.items())
              + f"; peak resident set size of the process {rss:.0f} MB."]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
