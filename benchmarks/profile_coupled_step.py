"""Where a step of the coupled model (blocks, zones, interface: murus.continuum.coupled) goes,
on the H/B = 2.7 mock-up of Savalle et al. (2022) at the mesh of Table 3 (zones of H / 12,
courses of about 10 mm, validation/retaining_continuum.py), one numba thread.

The run of :func:`murus.retaining.collapse.collapse_run` is stopped at the first chunk of steps
after ``--time`` [s] of model time (0.5 s by default: the ramp under way, the backfill on the
wall; the settling before is not timed);
each part of the step of :func:`murus.continuum.coupled.run_chunk` is then timed alone, repeated
``--steps`` times on copies of that state: the blocks' contact forces, the zones' stresses and
corner forces, the interface, the blocks' update, the gridpoints' update; then the whole step.
The parts timed alone add up to about the whole step (the rest: the copies of forces between
blocks, interface and gridpoints, and the interface's work).

``python benchmarks/profile_coupled_step.py [--time 0.5] [--steps 3000]``
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "validation"))

from murus.continuum import _kdata as ckd  # noqa: E402
from murus.continuum import coupled as CP  # noqa: E402
from murus.continuum import interface as IF  # noqa: E402
from murus.continuum import kernels as ZK  # noqa: E402
from murus.dem import _kdata as dkd  # noqa: E402
from murus.dem import kernels as DK  # noqa: E402


@njit
def _forces(n, dem):
    P, E, C, S, bodies, shapes, joints, c = dem
    fb = np.zeros((bodies.bmass.size, 3))
    cap = c.pairs.shape[0] + 16
    pw = np.zeros((cap, DK.NW))
    nact = np.zeros(cap, np.int64)
    DK.world_vertices(bodies.bpos, bodies.bang, shapes)
    for _ in range(n):
        c, pw, nact, dpar = DK.step_forces(P, E, C, S, bodies, shapes, joints, c,
                                           (pw, nact, fb))
    return 0


@njit
def _zones(n, zon):
    ZP, ZE, ZC, ZS, grid, zones, mprops, part, ff = zon
    par = zones.zg.shape[0] >= ZP[ZK.P_PARMIN]
    for _ in range(n):
        ZK.zone_forces(ZP, grid, zones, mprops, par)
    return 0


@njit
def _iface(n, dem, zon, itf):
    P, E, C, S, bodies, shapes, joints, c = dem
    grid = zon[4]
    IP, IE, IC, geo, jprops, nodes, corners, state, work = itf
    side = IF.GridSide(grid.gxy, grid.gvel)
    DK.world_vertices(bodies.bpos, bodies.bang, shapes)
    for _ in range(n):
        t = IF.step(IP, IE, IC, geo, side, bodies, shapes, jprops, nodes, corners, state, work)
        nodes = dkd.Contacts(t[0], t[1], t[2], t[3], t[4], t[5])
        corners = dkd.Contacts(t[6], t[7], t[8], t[9], t[10], t[11])
    return 0


@njit
def _update(n, drive, dem):
    P, E, C, S, bodies, shapes, joints, c = dem
    nb = bodies.bmass.size
    fb = np.zeros((nb, 3))
    bpart = np.zeros((DK.NBLK, DK.NQ))
    bsp, bsh = DK.incidence(shapes.sbody, nb)
    cap = c.pairs.shape[0] + 16
    pw = np.zeros((cap, DK.NW))
    nact = np.zeros(cap, np.int64)
    c, pw, nact, dpar = DK.step_forces(P, E, C, S, bodies, shapes, joints, c, (pw, nact, fb))
    for i in range(n):
        fr = DK._frame(i % drive.vfull.shape[0], drive)
        DK.step_update(P, E, C, S, fr, fb, bodies, shapes, bpart, (bsp, bsh), dpar)
    return 0


@njit
def _grid(n, drive, zon):
    ZP, ZE, ZC, ZS, grid, zones, mprops, part, ff = zon
    par = zones.zg.shape[0] >= ZP[ZK.P_PARMIN]
    allg = np.zeros(0, np.int64)
    for i in range(n):
        fr = DK._frame(i % drive.vfull.shape[0], drive)
        ZK.grid_update(ZP, ZE, ZC, ZS, fr, grid, zones.zf, (part, ff, mprops, allg), par)
    return 0


def _copy(obj):
    if isinstance(obj, np.ndarray):
        return obj.copy()
    if isinstance(obj, tuple):
        vals = [_copy(v) for v in obj]
        return type(obj)(*vals) if hasattr(obj, "_fields") else tuple(vals)
    return obj


def _tuples(cp):
    m, z, f = cp.dem, cp.zones, cp.iface
    dem = (m.P, m.E, m.C, m.S, dkd.pack(dkd.Bodies, m), dkd.pack(dkd.Shapes, m),
           dkd.pack(dkd.Joints, m), dkd.pack(dkd.Contacts, m))
    zon = (z.P, z.E, z.C, z.S, ckd.pack(ckd.Grid, z), ckd.pack(ckd.Zones, z), z.mprops, z.part,
           z.ff)
    itf = (f.P, f.E, f.C, f.geo, f.jprops, f.nodes, f.corners, f.state, f.work)
    return _copy(dem), _copy(zon), _copy(itf)


def profile(cp, drive, steps: int) -> dict:
    """Microseconds per step of each part and of the whole step (module doc)."""
    out = {}

    def timed(name, fn, *args):
        fn(2, *_copy(args))  # compile
        a = _copy(args)
        t0 = time.perf_counter()
        fn(steps, *a)
        out[name] = (time.perf_counter() - t0) / steps * 1e6

    dem, zon, itf = _tuples(cp)
    m = cp.dem
    print(f"bodies {m.nbody}, block contacts {m.pairs.shape[0]}, zones {cp.zones.nz}, "
          f"gridpoints {cp.zones.ng}, interface node and corner contacts "
          f"{cp.iface.nodes.pairs.shape[0]} + {cp.iface.corners.pairs.shape[0]}, "
          f"dt {m.dt:.3g} s", flush=True)
    timed("blocks: contact forces", _forces, dem)
    timed("zones: stresses and corner forces", _zones, zon)
    timed("interface", _iface, dem, zon, itf)
    timed("blocks: update", _update, drive, dem)
    timed("gridpoints: update", _grid, drive, zon)
    dem, zon, itf = _tuples(cp)
    CP.run_chunk(2, drive, *_copy((dem, zon, itf)))
    t0 = time.perf_counter()
    CP.run_chunk(min(steps, drive.vfull.shape[0]), drive, dem, zon, itf)
    out["whole step (run_chunk)"] = ((time.perf_counter() - t0)
                                     / min(steps, drive.vfull.shape[0]) * 1e6)
    return out


def main(argv=None) -> int:
    from retaining_dynamic import A_MOCK, _mock_wall

    from murus.retaining.collapse import collapse_run

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time", type=float, default=0.5, help="model time to stop at [s]")
    ap.add_argument("--steps", type=int, default=3000, help="steps timed per part")
    args = ap.parse_args(argv)
    step = CP.CoupledModel.step
    found = {}

    class Done(Exception):
        pass

    def spy(self, n, drive, zdrive=None):
        if self.dem.time >= args.time and self.dem.P[DK.P_ALOCAL] == 0.0:
            found["t"] = self.dem.time
            found["res"] = profile(self, drive, args.steps)
            raise Done
        return step(self, n, drive, zdrive)

    CP.CoupledModel.step = spy
    try:
        collapse_run(_mock_wall(2.7), 10.0, "none", backfill="continuum", A_rate=A_MOCK,
                     t_max=45.0)
    except Done:
        pass
    finally:
        CP.CoupledModel.step = step
    if "res" not in found:
        print("the run ended before the time asked for")
        return 1
    print(f"at t = {found['t']:.3f} s, {os.cpu_count()} cores, load average "
          f"{os.getloadavg()[0]:.2f}, NUMBA_NUM_THREADS={os.environ['NUMBA_NUM_THREADS']}")
    whole = found["res"]["whole step (run_chunk)"]
    for k, v in found["res"].items():
        print(f"  {k:36s} {v:7.1f} us/step  ({100 * v / whole:4.0f} %)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
