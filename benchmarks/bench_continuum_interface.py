"""Speed of the zone-block interface kernels (issue 17, item 5): time per interface step and per
active contact, and the allocations of a step (none expected without a rebuild).

Model: a row of ``nb`` blocks (0.5 m x 0.4 m, 0.1 m apart) pressed by 0.1 mm onto a flat
surface of gridpoints 0.1 m apart (about 5 gridpoint contacts per block), one thread; the
steps are run by a numba loop calling :func:`murus.continuum.interface.step` (no Python between
the steps). Not part of ``benchmarks/run.py`` (the coupled loop that will call these kernels is
not written yet).

    NUMBA_NUM_THREADS=1 python benchmarks/bench_continuum_interface.py [--blocks N] [--steps N]
"""

from __future__ import annotations

import argparse
import time
from types import SimpleNamespace

import numpy as np
from numba import njit
from numba.core.runtime import _nrt_python, rtsys

from murus.continuum import interface as I
from murus.dem import Joint, Model


@njit(cache=False)
def _loop(n, P, E, C, geo, side, bodies, shapes, jprops, c, state, work):
    nodes, corners = c
    for _ in range(n):
        work.fg[:] = 0.0
        work.fb[:] = 0.0
        I.step(P, E, C, geo, side, bodies, shapes, jprops, nodes, corners, state, work)
    return 0


def build(nblocks: int):
    """The interface of ``nblocks`` blocks on a surface (module doc)."""
    h = 0.1
    width = 0.6 * nblocks + 0.4
    n = int(round(width / h)) + 1
    xy = np.column_stack([-0.2 + h * np.arange(n), np.zeros(n)])
    grid = SimpleNamespace(gxy=xy, gvel=np.zeros((n, 2)))
    edges = np.array([[i + 1, i] for i in range(n - 1)], np.int64)
    m = Model(thickness=1.0, rounding=0.005, margin=0.02, joint=Joint(kn=1e9, ks=5e8))
    for b in range(nblocks):
        m.add_rectangle(0.5, 0.4, center=(0.6 * b + 0.27, 0.2 - 1e-4))
    return I.Interface(grid, edges, m)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--blocks", type=int, default=1000)
    ap.add_argument("--steps", type=int, default=2000)
    a = ap.parse_args()
    ifc = build(a.blocks)
    ifc.P[I.IP_DT] = 1e-5
    side = I.GridSide(ifc.grid.gxy, ifc.grid.gvel)
    args = (ifc.P, ifc.E, ifc.C, ifc.geo, side, ifc.bodies, ifc.shapes, ifc.jprops,
            (ifc.nodes, ifc.corners), ifc.state, ifc.work)
    _loop(1, *args)  # compile
    _nrt_python.memsys_enable_stats()
    s0 = rtsys.get_allocation_stats()
    _loop(1, *args)
    s1 = rtsys.get_allocation_stats()
    _loop(101, *args)
    s2 = rtsys.get_allocation_stats()
    per_step = ((s2.alloc - s1.alloc) - (s1.alloc - s0.alloc)) / 100
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        _loop(a.steps, *args)
        times.append((time.perf_counter() - t0) / a.steps)
    t = float(np.median(times))
    nact = int(ifc.C[I.IC_NODES] + ifc.C[I.IC_CORNERS])
    ncand = ifc.nodes.pairs.shape[0] + ifc.corners.pairs.shape[0]
    print(f"blocks {a.blocks}, interface gridpoints {ifc.geo.ig.size}, candidate pairs {ncand}, "
          f"active contacts {nact}")
    print(f"time per step {t * 1e6:.1f} us (median of 5 x {a.steps} steps), "
          f"{t / max(nact, 1) * 1e9:.0f} ns per active contact, "
          f"{t / max(ncand, 1) * 1e9:.0f} ns per candidate pair")
    print(f"NRT allocations per step (no rebuild): {per_step:g}")


if __name__ == "__main__":
    main()
