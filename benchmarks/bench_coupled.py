"""A block wall against a continuum backfill of about 1e4 zones, and the same wall against the
disc backfill of the same extent (issue 17, item 8): time per simulated second, side by side in
one run.

Models (both: DSRW1 of Savalle et al. (2022), Table 5, H = 2.5 m, the stones of
:func:`murus.retaining.dem_wall.build_wall` without the backstop, joint stiffness of Table 6
times 1e-3 (the default of :func:`murus.retaining.collapse.collapse_run`); the backfill region of
:func:`murus.retaining.backfill.region_polygon`, W = 5 m behind the heel, 2.61 m high):

- ``continuum``: the region meshed into about ``--zones`` quadrilateral zones
  (:func:`murus.continuum.mesh.polygon_region`, square zones), Mohr-Coulomb with the backfill of
  Savalle et al. (2022), Table 6 (unit weight 14.9 kN/m³, E = 92.7 MPa, nu = 0.22, phi = 37.7
  deg, no cohesion, no dilation); the wall-backfill interface of Table 6 (kn = ks = 2.9e10
  Pa/m times 1e-3, friction 37.7 deg) along the back face
  (:meth:`murus.continuum.interface.Interface.from_side`); a rigid base (the bottom gridpoints
  move with the base motion); the far side on rollers for the settling (K0 = 1 - sin phi
  initial stresses, then :meth:`murus.continuum.coupled.CoupledModel.settle`), then a
  free-field column (:meth:`murus.continuum.ContinuumModel.add_free_field`) for the dynamic
  run;
- ``discs``: the disc backfill of :class:`murus.retaining.backfill.DiscreteBackfill` (the same
  W, discs of mean radius 0.04 m, absorbing far side, its generation, settling and relaxation),
  as ``murus retaining collapse --backfill discrete`` builds it.

Setup (building, settling) is timed once, apart. Then both models run under the same harmonic
base motion (``a = A sin(2 pi f t)``, 5 Hz, 1 m/s² by default, below the A_pseudo = 1.59 m/s² of
DSRW1: the wall shakes, it does not collapse), with 10 % mass-proportional damping at 5 Hz on
the velocities relative to the base (the damping of ``collapse_run``) and a ``d_top`` probe
every 0.01 s; ``--rounds`` rounds, each running each model ``--duration`` simulated seconds
further, alternating the two; the report gives the medians over the rounds of the wall-clock time
per simulated second and of the steps per second, the time step, the counts, the memory of each
model (the bytes of the NumPy arrays it holds, and the tracemalloc peak of one extra, untimed
round: the transient allocations of a run) and the ratio continuum / discs.

    python benchmarks/bench_coupled.py [--out benchmarks/RESULTS_coupled.md] [--threads 2]
        [--zones 10000] [--rounds 5] [--duration 0.2] [--quick]

``--quick``: W = 1 m, about 800 zones, 2 rounds of 0.02 s (a check of the script: under a
minute once the kernels are compiled).
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import resource
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
F = 5.0           # Hz, frequency of the base motion and of the damping
XI = 0.10         # mass-proportional damping ratio (Savalle et al. (2022), Table 6: 5 % doubled)
SCALE = 1e-3      # factor on the joint stiffness of Savalle et al. (2022), Table 6
SAMPLE_DT = 0.01  # s, the d_top probe


def _log(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def array_bytes(*objs) -> int:
    """Bytes of the distinct NumPy arrays held by ``objs`` (their attributes, and the items of
    their tuples, lists and dicts, three levels down; views counted once through their base)."""
    seen: set[int] = set()
    total = 0

    def walk(o, depth):
        nonlocal total
        if isinstance(o, np.ndarray):
            b = o if o.base is None or not isinstance(o.base, np.ndarray) else o.base
            if id(b) not in seen:
                seen.add(id(b))
                total += b.nbytes
            return
        if depth == 0 or isinstance(o, (str, bytes, int, float, bool, type(None))):
            return
        if isinstance(o, dict):
            items = o.values()
        elif isinstance(o, (tuple, list)):
            items = o
        elif hasattr(o, "__dict__"):
            items = vars(o).values()
        else:
            return
        for v in list(items):
            walk(v, depth - 1)

    for o in objs:
        walk(o, 4)
    return total


def harmonic(amplitude: float, duration: float, dt: float = 1e-3):
    """The base motion ``a = amplitude sin(2 pi F t)`` [m/s²] for ``duration`` [s]."""
    from murus.motion.core import GroundMotion

    t = np.arange(int(math.ceil(duration / dt)) + 1) * dt
    return GroundMotion(dt=dt, acc=amplitude * np.sin(2 * math.pi * F * t), name="harmonic")


class Case:
    """One model of the comparison: ``setup()`` builds and settles it, ``run(duration)``
    advances it; ``count`` is its number of zones or discs."""

    name = ""

    def __init__(self, wall, W: float, threads: int) -> None:
        self.wall, self.W, self.threads = wall, W, threads
        self.count = 0
        self.setup_time = math.nan
        self.settle_message = ""
        self.m = None
        self.dw = None

    def probes(self):
        dw = self.dw
        return {"d_top": lambda model: dw.d_top()}


class ContinuumCase(Case):
    name = "continuum"

    def __init__(self, wall, W, threads, zones: int) -> None:
        super().__init__(wall, W, threads)
        self.target = zones

    def setup(self) -> None:
        from murus import G
        from murus.continuum import ContinuumModel, MohrCoulomb
        from murus.continuum.coupled import CoupledModel
        from murus.continuum.interface import Interface
        from murus.continuum.mesh import polygon_region
        from murus.dem import Joint, polygon_properties
        from murus.retaining.backfill import SEED_ELASTIC, SEED_INTERFACE_K, region_polygon
        from murus.retaining.dem_wall import build_wall

        t0 = time.perf_counter()
        wall = self.wall
        self.dw = dw = build_wall(wall, stiffness_scale=SCALE, backstop=False)
        m = dw.model
        poly = region_polygon(wall, self.W)
        h = math.sqrt(polygon_properties(poly)[0] / self.target)
        mesh = polygon_region(poly, size=h, name="backfill")
        E, nu = SEED_ELASTIC["full"]
        phi = wall.backfill_friction_deg
        mat = MohrCoulomb(density=wall.backfill_unit_weight / G, E=E, nu=nu, friction_deg=phi,
                          cohesion=0.0, dilation_deg=0.0)
        zm = ContinuumModel(mesh.xy, mesh.zones, mat, gravity=G)
        bottom = mesh.side("backfill.bottom")
        right = mesh.side("backfill.right")
        zm.set_base(bottom)
        # rollers on the far side for the settling (its bottom gridpoint stays on the base)
        zm.fix(np.setdiff1d(right, bottom), x=True, y=False)
        zm.initial_stress_k0(k0=1.0 - math.sin(math.radians(phi)))
        k = SEED_INTERFACE_K["full"] * SCALE
        joint = Joint(kn=k, ks=k, friction_deg=wall.interface_friction_deg)
        iface = Interface.from_side(zm, mesh, "backfill.left", m, joint)
        self.cm = cm = CoupledModel(m, zm, iface)
        # the time step is the coupled model's own choice at its construction (as the disc
        # backfill's is its model's at the build: neither is re-derived after the settling)
        from murus.dem.engine import blocks_stable_dt

        self.dts = (blocks_stable_dt(m), zm.stable_dt(), iface.critical_dt() * m.safety)
        st = cm.settle(tol=1e-4, max_steps=200_000, threads=self.threads)
        self.settle_message = st.message
        # the whole side, base gridpoint included: the column's bottom node takes its fixity
        # (:func:`murus.continuum.freefield.build_free_field`), so the column stands on the base
        zm.add_free_field([right])
        self.m, self.zm, self.iface = m, zm, iface
        self.count = zm.nz
        self.h = h
        self.setup_time = time.perf_counter() - t0

    def run(self, duration: float):
        return self.cm.run(duration, xi=XI, freq=F, probes=self.probes(), sample_dt=SAMPLE_DT,
                           threads=self.threads)

    def state_bytes(self) -> int:
        return array_bytes(self.m, self.zm, self.iface)


class DiscCase(Case):
    name = "discs"

    def setup(self) -> None:
        from murus.retaining.backfill import DiscreteBackfill
        from murus.retaining.dem_wall import build_wall

        t0 = time.perf_counter()
        self.bf = bf = DiscreteBackfill(self.wall, W=self.W, boundary="absorbing",
                                        stiffness_scale=SCALE)
        self.dw = dw = build_wall(self.wall, stiffness_scale=SCALE, backstop=False,
                                  add_bodies=bf.add_to)
        st = bf.settle(dw)
        self.settle_message = f"{st.message}, then a relaxation of {bf.relax_time:.2f} s"
        self.m = dw.model
        self.count = int(bf.discs.size)
        self.setup_time = time.perf_counter() - t0

    def run(self, duration: float):
        m, bf = self.m, self.bf
        # the hook of the absorbing boundary as collapse_run calls it (its thrust update
        # every 1e-3 s, here a zero thrust, or the boundary's own interval if shorter)
        every = min(max(1, int(round(1e-3 / m.dt))), bf.interval(m))
        return m.run(duration, xi=XI, freq=F, probes=self.probes(), sample_dt=SAMPLE_DT,
                     external=bf.external(), external_every=every, threads=self.threads)

    def state_bytes(self) -> int:
        return array_bytes(self.m, self.bf)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(HERE / "RESULTS_coupled.md"))
    ap.add_argument("--threads", type=int, default=2, help="numba threads (default 2)")
    ap.add_argument("--zones", type=int, default=10_000, help="target number of zones")
    ap.add_argument("--W", type=float, default=5.0, help="backfill width behind the heel [m]")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--duration", type=float, default=0.2,
                    help="simulated seconds of each model in each round")
    ap.add_argument("--amplitude", type=float, default=1.0,
                    help="amplitude of the harmonic base acceleration [m/s²]")
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    if args.quick:
        args.W, args.zones, args.rounds, args.duration = 1.0, 800, 2, 0.02
    if args.rounds < 1 or args.duration <= 0 or args.zones < 4 or args.threads < 1:
        ap.error("rounds, duration, zones and threads must be positive")
    os.environ["NUMBA_NUM_THREADS"] = str(args.threads)
    import numba

    from murus.retaining.geometry import preset

    wall = preset("DSRW1")
    load0 = os.getloadavg()
    cases = [ContinuumCase(wall, args.W, args.threads, args.zones),
             DiscCase(wall, args.W, args.threads)]
    total = args.duration * (args.rounds + 1) + 0.5
    gm = harmonic(args.amplitude, total)
    for c in cases:
        _log(f"{c.name}: setting up")
        c.setup()
        c.m.set_base_motion(gm)
        c.run(min(0.01, args.duration))  # compile the dynamic loop (cache) before timing
        _log(f"{c.name}: {c.count} {'zones' if c.name == 'continuum' else 'discs'}, setup "
             f"{c.setup_time:.1f} s, {c.settle_message}, dt {c.m.dt:.3e} s")
    per_s = {c.name: [] for c in cases}
    steps_s = {c.name: [] for c in cases}
    for r in range(args.rounds):
        for c in (cases if r % 2 == 0 else cases[::-1]):
            t0 = time.perf_counter()
            res = c.run(args.duration)
            wall_t = time.perf_counter() - t0
            if res.status != "completed":
                raise SystemExit(f"{c.name}: run ended with status {res.status}: "
                                 f"{res.message}")
            per_s[c.name].append(wall_t / args.duration)
            steps_s[c.name].append(res.steps / wall_t)
            _log(f"round {r + 1}: {c.name} {wall_t / args.duration:.1f} s per simulated "
                 f"second, {res.steps / wall_t:.0f} steps/s, d_top {c.dw.d_top() * 1e3:.2f} mm")
    # memory: the arrays each model holds, and the transient allocations of one more round
    mem = {}
    for c in cases:
        tracemalloc.start()
        c.run(min(args.duration, 0.05))
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        mem[c.name] = (c.state_bytes(), peak)
    load1 = os.getloadavg()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    med = {k: float(np.median(v)) for k, v in per_s.items()}
    meds = {k: float(np.median(v)) for k, v in steps_s.items()}
    cont, disc = cases
    cmd = ("python benchmarks/bench_coupled.py" + (" --quick" if args.quick else "")
           + ("" if args.quick else f" --zones {args.zones} --rounds {args.rounds} "
              f"--duration {args.duration:g}") + f" --threads {args.threads}")
    L = ["# A block wall against 1e4 zones and against discs (issue 17, item 8)", ""]
    L.append(f"Machine: {os.cpu_count()} cores ({platform.machine()}), Python "
             f"{platform.python_version()}, numba {numba.__version__} "
             f"(NUMBA_NUM_THREADS={args.threads}); load average (1, 5, 15 min) at the start "
             f"{' '.join(f'{x:.2f}' for x in load0)}, at the end "
             f"{' '.join(f'{x:.2f}' for x in load1)}.")
    L.append(f"Command: `{cmd}`. Kernels compiled (cache) before timing.")
    if load1[0] > args.threads + 1.0:  # the 1-min load at the end: this run and others
        L.append("")
        L.append("**The machine was busy** (other processes held the cores: the 1-min load "
                 "average at the end above this run's threads + 1): the times are upper "
                 "bounds and the round-to-round spread is large; the ratio of the two models, "
                 "measured in alternating rounds, is the figure to read. Re-run on an idle "
                 "machine.")
    L.append("")
    L.append(f"Case: DSRW1 (Savalle et al. (2022), Table 5) with joint stiffness of Table 6 x "
             f"{SCALE:g}, backfill W = {args.W:g} m behind the heel; the continuum: "
             f"{cont.count} Mohr-Coulomb zones of {cont.h * 100:.1f} cm (Table 6), the "
             "interface of Table 6 on the back face, rigid base, free-field far side; the "
             f"discs: {disc.count} discs of mean radius "
             f"{float(disc.bf.packing.radii.mean()) * 100:.1f} cm, absorbing far side "
             "(`murus.retaining.backfill`). Harmonic base acceleration "
             f"{args.amplitude:g} m/s² at {F:g} Hz, {XI * 100:g} % mass-proportional damping; "
             f"{args.rounds} rounds of {args.duration:g} simulated seconds of each model, "
             "alternating; medians over the rounds (module doc of "
             "`benchmarks/bench_coupled.py`).")
    L.append("")
    L.append("| model | zones / discs | bodies (stones + base) | dt [s] | setup [s] | "
             "per simulated second [s] | steps/s | state arrays [MB] | tracemalloc peak of a "
             "run [MB] | state per zone / disc, wall included [B] | d_top at the end [mm] |")
    L.append("|---|---|---|---|---|---|---|---|---|---|---|")
    for c in cases:
        nb = int(c.m.bpos.shape[0]) - (c.count if c.name == "discs" else 0)
        sb, pk = mem[c.name]
        L.append(f"| {c.name} | {c.count} | {nb} | {c.m.dt:.3e} | {c.setup_time:.1f} | "
                 f"{med[c.name]:.2f} | {meds[c.name]:.0f} | {sb / 2**20:.1f} | "
                 f"{pk / 2**20:.1f} | {sb / c.count:.0f} | {c.dw.d_top() * 1e3:.2f} |")
    L.append("")
    ratio = med["continuum"] / med["discs"]
    pair = float(np.median(np.divide(per_s["continuum"], per_s["discs"])))
    L.append(f"Ratio continuum / discs of the time per simulated second: **{ratio:.2f}** "
             f"(per round: "
             + ", ".join(f"{a / b:.2f}" for a, b in zip(per_s["continuum"], per_s["discs"],
                                                        strict=True))
             + f"; their median {pair:.2f}"
             + f"); of the time step: {cont.m.dt / disc.m.dt:.2f}; of the cost of a step: "
             f"{meds['discs'] / meds['continuum']:.2f}.")
    L.append("Per round [s per simulated second]: continuum "
             + ", ".join(f"{v:.2f}" for v in per_s["continuum"]) + "; discs "
             + ", ".join(f"{v:.2f}" for v in per_s["discs"]) + ".")
    L.append("The continuum's time step is the smallest of the blocks' "
             f"({cont.dts[0]:.3e} s), the zones' ({cont.dts[1]:.3e} s) and the interface's "
             f"({cont.dts[2]:.3e} s), each with its safety factor, taken when the coupled "
             "model is made; the discs' is their model's stable step at its build; neither is "
             "re-derived after the settling (the engines' rule).")
    L.append(f"Settling: continuum {cont.settle_message}; discs {disc.settle_message}. "
             f"Peak resident set size of the process {rss:.0f} MB.")
    L.append("")
    text = "\n".join(L)
    print(text)
    Path(args.out).write_text(text)
    _log(f"wrote {args.out}")


if __name__ == "__main__":
    main()
