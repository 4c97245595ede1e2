"""Blocks and zones in one time loop: a distinct-element model (:mod:`murus.dem`), a continuum
(:mod:`murus.continuum`) and the interfaces between them (:mod:`murus.continuum.interface`),
advanced together by explicit central differences, as UDEC advances its blocks and zones.

A step (:func:`run_chunk`):

1. the blocks' contact forces (:func:`murus.dem.kernels.step_forces`);
2. the zones' stresses and corner forces (:func:`murus.continuum.kernels.zone_forces`);
3. the interface contacts (:func:`murus.continuum.interface.step`): their forces added to the
   blocks' forces and written, per metre of thickness, to the interface gridpoints' extra
   force ``grid.gff``;
4. the blocks move (:func:`murus.dem.kernels.step_update`), then the gridpoints
   (:func:`murus.continuum.kernels.grid_update`, the free-field columns first), with the same
   base motion and gravity (one :class:`murus.dem._kdata.Drive`).

One time step for all: the smallest of the blocks' stable step, the zones' critical step and
the interface's (each with its safety factor). Units: the blocks' forces are for their model's
thickness ``t``; the continuum is per metre of thickness, so the interface forces on gridpoints
are divided by ``t``.

References
----------
Itasca UDEC, Theory and Background (deformable blocks: zones and contacts in one calculation
cycle); Savalle et al. (2022), §2 (the wall of blocks and the backfill continuum in UDEC).
"""

from __future__ import annotations

import math
import time as _time

import numpy as np
from numba import njit

from murus._jit import guard_cache as _guard_cache
from murus.continuum import _kdata as ckd
from murus.continuum import interface as IF
from murus.continuum import kernels as ZK
from murus.dem import _kdata as dkd
from murus.dem import kernels as DK
from murus.errors import MurusError

__all__ = ["CoupledModel", "CoupledError", "run_chunk"]


class CoupledError(MurusError, ValueError):
    """Blocks and zones that cannot be coupled (thickness, gravity, shared gridpoints)."""


@njit(cache=True, error_model="numpy")
def run_chunk(nsteps, drive, dem, zon, itf):
    """Advance blocks, zones and interfaces ``nsteps`` steps together (module doc).

    Parameters
    ----------
    nsteps : int
        Steps.
    drive : murus.dem._kdata.Drive
        Base velocities and gravity of the steps.
    dem : tuple
        ``(P, E, C, S, bodies, shapes, joints, contacts)`` of the blocks
        (:func:`murus.dem.kernels.run_chunk`).
    zon : tuple
        ``(P, E, C, S, grid, zones, mprops, part, ff)`` of the zones
        (:func:`murus.continuum.kernels.run_chunk`).
    itf : tuple
        ``(P, E, C, geo, jprops, nodes, corners, state, work)`` of the interface
        (:func:`murus.continuum.interface.step`).

    Returns
    -------
    tuple
        The arrays of the blocks' contacts, then of the interface's node and corner contacts
        (6 each, in the order of :class:`murus.dem._kdata.Contacts`), as a plain tuple.
    """
    P, E, C, S, bodies, shapes, joints, c = dem
    ZP, ZE, ZC, ZS, grid, zones, mprops, part, ff = zon
    IP, IE, IC, geo, jprops, nodes, corners, state, work = itf
    nb = bodies.bmass.size
    fb = np.zeros((nb, 3))
    cap = c.pairs.shape[0] + 16
    pw = np.zeros((cap, DK.NW))
    nact = np.zeros(cap, np.int64)
    bpart = np.zeros((DK.NBLK, DK.NQ))
    if C[DK.C_NEED_REBUILD] == 0 and DK._moved(bodies, P[DK.P_MARGIN]):
        C[DK.C_NEED_REBUILD] = 1
    DK.world_vertices(bodies.bpos, bodies.bang, shapes)
    bsp, bsh = DK.incidence(shapes.sbody, nb)
    zpar = zones.zg.shape[0] >= ZP[ZK.P_PARMIN]
    side = IF.GridSide(grid.gxy, grid.gvel)
    gff = grid.gff
    fg = work.fg
    wfb = work.fb
    ig = geo.ig
    inv_t = 1.0 / IP[IF.IP_THICK]
    for i in range(nsteps):
        c, pw, nact, dpar = DK.step_forces(P, E, C, S, bodies, shapes, joints, c,
                                           (pw, nact, fb))
        ZK.zone_forces(ZP, grid, zones, mprops, zpar)
        for k in range(ig.size):
            fg[ig[k], 0] = 0.0
            fg[ig[k], 1] = 0.0
        wfb[:, :] = 0.0
        t = IF.step(IP, IE, IC, geo, side, bodies, shapes, jprops, nodes, corners, state, work)
        nodes = dkd.Contacts(t[0], t[1], t[2], t[3], t[4], t[5])
        corners = dkd.Contacts(t[6], t[7], t[8], t[9], t[10], t[11])
        for b in range(nb):
            fb[b, 0] += wfb[b, 0]
            fb[b, 1] += wfb[b, 1]
            fb[b, 2] += wfb[b, 2]
        for k in range(ig.size):
            g = ig[k]
            gff[g, 0] = fg[g, 0] * inv_t
            gff[g, 1] = fg[g, 1] * inv_t
        fr = DK._frame(i, drive)
        DK.step_update(P, E, C, S, fr, fb, bodies, shapes, bpart, (bsp, bsh), dpar)
        ZK.grid_update(ZP, ZE, ZC, ZS, fr, grid, zones.zf, (part, ff, mprops), zpar)
    # mean force of the blocks' and the interface's active contacts (unbalanced-force ratio)
    tot = 0.0
    na = 0
    for cc in (c, nodes, corners):
        for k in range(cc.pairs.shape[0]):
            for o in range(2):
                if cc.sid[k, o] >= 0:
                    tot += math.sqrt(cc.sf[k, o, DK.F_FN] ** 2 + cc.sf[k, o, DK.F_FS] ** 2)
                    na += 1
    S[DK.S_MEANF] = tot / na if na > 0 else 0.0
    return (c.pairs, c.pj, c.pbond, c.sid, c.sf, c.sbr,
            nodes.pairs, nodes.pj, nodes.pbond, nodes.sid, nodes.sf, nodes.sbr,
            corners.pairs, corners.pj, corners.pbond, corners.sid, corners.sf, corners.sbr)


class CoupledModel:
    """A distinct-element model, a continuum and the interfaces between them, advanced in one
    time loop (module doc).

    Parameters
    ----------
    dem : murus.dem.Model
        The blocks (gravity and base motion are taken from the zones' model: set them there).
    zones : murus.continuum.ContinuumModel
        The zones.
    interface : murus.continuum.interface.Interface
        The interface between them (built on ``zones`` and ``dem``).

    Raises
    ------
    CoupledError
        The zones in small-strain mode, the interface built on other models, or a gridpoint of
        the interface also on a free-field side.

    References
    ----------
    Itasca UDEC, Theory and Background (one calculation cycle for blocks and zones).
    """

    def __init__(self, dem, zones, interface) -> None:
        if not zones.large_strain:
            raise CoupledError("the zones must be in large-strain mode: the interface reads the "
                               "gridpoints' current coordinates", key=("zones",))
        if interface.dem is not dem or interface.grid is not zones:
            raise CoupledError("the interface was built on other models", key=("interface",))
        if zones.ff.fy.size and np.intersect1d(zones.ff.fgp, interface.geo.ig).size:
            raise CoupledError("a gridpoint of the interface is on a free-field side",
                               key=("interface",))
        dem.build()
        self.dem = dem
        self.zones = zones
        self.iface = interface
        self.set_dt()

    # ------------------------------------------------------------------ time step
    def stable_dt(self) -> float:
        """The smallest stable step of blocks, zones and interface, each with its safety
        factor [s].

        Returns
        -------
        float
        """
        from murus.dem.engine import stable_dt as dem_dt

        d = dem_dt(self.dem)
        z = self.zones.stable_dt()
        i = self.iface.critical_dt() * self.dem.safety
        return float(min(d, z, i))

    def set_dt(self, dt: float | None = None) -> None:
        """Use one time step for all (default :meth:`stable_dt`).

        Parameters
        ----------
        dt : float, optional
            Time step [s], at most :meth:`stable_dt`.
        """
        s = self.stable_dt()
        dt = s if dt is None else float(dt)
        if not (0 < dt <= s * (1 + 1e-12)):
            raise CoupledError(f"dt = {dt!r} s: must be in (0, {s:.6g}] s", key=("dt",))
        self.dem.P[DK.P_DT] = dt
        self.dem.dt = dt
        self.zones.P[ZK.P_DT] = dt
        self.iface.P[IF.IP_DT] = dt

    @property
    def dt(self) -> float:
        """The time step [s]."""
        return float(self.zones.P[ZK.P_DT])

    # ------------------------------------------------------------------ stepping
    def _chunk(self, n: int, moving: bool) -> None:
        m, z, f = self.dem, self.zones, self.iface
        dt = self.dt
        ts = z.time + np.arange(n) * dt
        if moving:
            vfull = z.base_velocity(ts)
            vhalf = z.base_velocity(ts + 0.5 * dt)
        else:
            vfull = np.zeros((n, 2))
            vhalf = vfull
        grav = np.zeros((n, 2))
        grav[:, 1] = -z.gravity
        drive = dkd.Drive(vfull, vhalf, grav, np.zeros((n, 2)))
        dem = (m.P, m.E, m.C, m.S, dkd.pack(dkd.Bodies, m), dkd.pack(dkd.Shapes, m),
               dkd.pack(dkd.Joints, m), dkd.pack(dkd.Contacts, m))
        zon = (z.P, z.E, z.C, z.S, ckd.pack(ckd.Grid, z), ckd.pack(ckd.Zones, z), z.mprops,
               z.part, z.ff)
        itf = (f.P, f.E, f.C, f.geo, f.jprops, f.nodes, f.corners, f.state, f.work)
        out = run_chunk(n, drive, dem, zon, itf)
        for name, a in zip(dkd.Contacts._fields, out[:6], strict=True):
            setattr(m, name, a)
        f._set(out[6:])

    def _damping(self, alocal: float, amass: float, drel: float) -> None:
        for P, (ia, im, idr) in ((self.dem.P, (DK.P_ALOCAL, DK.P_AMASS, DK.P_DREL)),
                                 (self.zones.P, (ZK.P_ALOCAL, ZK.P_AMASS, ZK.P_DREL))):
            P[ia] = alocal
            P[im] = amass
            P[idr] = drel

    def unbalanced_ratio(self) -> float:
        """The largest unbalanced force of a block or a gridpoint (per the blocks' thickness)
        over the mean force of the contacts and zones [-].

        Returns
        -------
        float
        """
        t = self.iface.P[IF.IP_THICK]
        unbal = max(float(self.dem.S[DK.S_UNBAL]), float(self.zones.S[ZK.S_UNBAL]) * t)
        mean = max(float(self.dem.S[DK.S_MEANF]), float(self.zones.S[ZK.S_MEANF]) * t)
        if mean <= 0.0:
            return math.inf if unbal > 0 else 0.0
        return unbal / mean

    def settle(self, tol: float = 1e-5, alpha: float = 0.8, max_steps: int = 200_000,
               check_every: int = 100) -> tuple[bool, int, float]:
        """Static equilibrium of blocks and zones under gravity with local damping.

        Parameters
        ----------
        tol : float
            Unbalanced-force ratio to reach [-] (:meth:`unbalanced_ratio`).
        alpha : float
            Local damping coefficient [-].
        max_steps : int
            Largest number of steps.
        check_every : int
            Steps between checks of the ratio.

        Returns
        -------
        tuple
            ``(converged, steps, ratio)``.
        """
        self._damping(alpha, 0.0, 0.0)
        self.zones.P[ZK.P_PLASTIC] = 1.0
        done, ratio = 0, math.inf
        while done < max_steps:
            n = min(check_every, max_steps - done)
            self._chunk(n, moving=False)
            done += n
            ratio = self.unbalanced_ratio()
            if ratio < tol:
                break
        self._damping(0.0, 0.0, 0.0)
        self.dem.bvel[:] = 0.0
        self.dem.bomg[:] = 0.0
        self.zones.gvel[:] = 0.0
        return ratio < tol, done, ratio

    def run(self, duration: float, *, xi: float = 0.0, freq: float | None = None,
            damping_frame: str = "base", every: int = 100, monitors: dict | None = None):
        """A dynamic run over ``duration`` [s] with the zones' base motion
        (:meth:`murus.continuum.ContinuumModel.set_base_motion`) driving the zones' base
        gridpoints and the blocks of kind "base".

        Parameters
        ----------
        duration : float
            Simulated time [s].
        xi, freq : float
            Mass-proportional damping: fraction of critical at ``freq`` [Hz], on blocks and
            zones (Savalle et al. (2022), §2).
        damping_frame : {"base", "absolute"}
            Velocities damped.
        every : int
            Steps between samples of the monitors.
        monitors : dict, optional
            name -> callable(coupled model) -> float.

        Returns
        -------
        dict
            ``t`` and one array per monitor; ``wall`` [s].
        """
        if xi > 0 and not (freq and freq > 0):
            raise CoupledError("mass-proportional damping needs freq > 0 [Hz]", key=("freq",))
        amass = 4.0 * math.pi * xi * freq if xi > 0 else 0.0
        self._damping(0.0, amass, 1.0 if damping_frame == "base" else 0.0)
        moving = self.zones._motion_kind != "none"
        monitors = monitors or {}
        out = {"t": [self.zones.time]} | {k: [float(f(self))] for k, f in monitors.items()}
        total = int(math.ceil(duration / self.dt - 1e-9))
        done = 0
        t0 = _time.perf_counter()
        while done < total:
            n = min(every, total - done)
            self._chunk(n, moving)
            done += n
            self.zones.time += n * self.dt
            self.dem.time_offset = self.zones.time
            self.dem.step_offset = int(self.dem.C[DK.C_STEP])
            out["t"].append(self.zones.time)
            for k, f in monitors.items():
                out[k].append(float(f(self)))
        res = {k: np.asarray(v) for k, v in out.items()}
        res["wall"] = _time.perf_counter() - t0
        return res


# numba's cache checks only this file: flush it when the kernels it compiles in change
_guard_cache(globals(), deps=("murus.dem.kernels", "murus.dem._kdata", "murus.continuum.kernels",
                              "murus.continuum._kdata", "murus.continuum.interface",
                              "murus.continuum.freefield"))
