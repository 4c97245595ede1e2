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
the interface's (each with its safety factor).

Subcycling (:meth:`CoupledModel.set_subcycle`, :func:`run_chunk_sub`): when the blocks' stiff
joints set the step (the stones of a dry-stone wall: 10 to 20 times below the zones' stable
step), the zones, most of a step's cost, may mostly take one step of ``n`` blocks' steps: a
nodal partition in the manner of Belytschko, Yen & Mullen (1979), *Mixed methods for time
integration*, Comput. Methods Appl. Mech. Engrg. 17/18, 259-275 (each partition with its own
step, the slow nodes' motion interpolated for the fast elements). The fast partition is the
interface's gridpoints and the zones touching them ("fast zones"): they step with the blocks,
so every contact force between a stone and a gridpoint acts on both at every step and the
impact of a stone on the backfill conserves momentum within the step. The slow partition is
every other gridpoint and zone, stepped once every ``n`` blocks' steps. In the zones' step at
t: every zone's stresses at t (the slow zones' increments over ``n dt``, the fast zones' over
``dt``); the slow gridpoints move to ``x(t + n dt)`` under the corner forces at t; in the
blocks' steps ``t + j dt`` (j = 1 .. n-1) the fast zones see their slow corners on that
straight path, ``x(t) + j dt v`` (exactly the path central differences give them). The
zones' stable step bounds ``n dt``, and so does the interface's: its fastest motion reaches
the slow gridpoints through the fast zones, sampled once per zones' step
(:meth:`CoupledModel.subcycle_limit`). What this costs in accuracy is measured (tests;
VALIDATION.md: the A_col of the mock-ups with and without). Until session 15 the interface's
gridpoints were slow, the interface's force on them taken once per zones' step while the
stones felt it at every step, and an impact gained energy (a test measures it). At the printed
stiffness of the mock-ups the wall creeps subcycled with either partition
(``validation/subcycle_chatter.py``), and so does one step for all under any small
perturbation (a shorter time step, a 1e-12 m shift of the stones): the energy comes from a
rocking stone's corner whose share of its face jumps up and down under load (the coverage rule
of :mod:`murus.continuum.interface`; ``corner_share="shrink"`` stops it; VALIDATION.md,
*Subcycling*). With it subcycling at the printed stiffness agrees with one step for all (three
pairs of collapse runs, VALIDATION.md, *Subcycling*);
:func:`murus.retaining.collapse.collapse_run` refuses subcycling above joint stiffness x 1e-1
only with the rule "follow".
The model needs gridpoints outside the fast partition (any with a base does). Units: the
blocks' forces are for their model's thickness ``t``; the continuum is per metre of
thickness, so the interface forces on gridpoints are divided by ``t``.

References
----------
Itasca UDEC, Theory and Background (deformable blocks: zones and contacts in one calculation
cycle); Savalle et al. (2022), §2 (the wall of blocks and the backfill continuum in UDEC).
"""

from __future__ import annotations

import json
import math

import numpy as np
from numba import njit

from murus._jit import guard_cache as _guard_cache
from murus.continuum import _kdata as ckd
from murus.continuum import interface as IF
from murus.continuum import kernels as ZK
from murus.dem import _kdata as dkd
from murus.dem import kernels as DK
from murus.errors import MurusError

__all__ = ["CoupledModel", "CoupledError", "run_chunk", "stored_energy_of"]


class CoupledError(MurusError, ValueError):
    """Blocks and zones that cannot be coupled (thickness, gravity, shared gridpoints)."""


def check_subcycle(n, limit: int | None = None):
    """``n`` checked as a subcycle (:meth:`CoupledModel.set_subcycle`): ``"auto"`` or a
    positive integer, at most ``limit`` when given.

    Parameters
    ----------
    n : int or str
        The subcycle asked for.
    limit : int, optional
        The model's :meth:`CoupledModel.subcycle_limit`; None: the type only.

    Returns
    -------
    int or str
        ``n`` (``"auto"`` as given when ``limit`` is None), or with ``limit``: the number of
        blocks' steps per zones' step (``"auto"``: the limit).

    Raises
    ------
    CoupledError
        Neither "auto" nor a positive integer, or above ``limit``.
    """
    if isinstance(n, str):
        if n.strip().lower() != "auto":
            raise CoupledError(f"subcycle must be 'auto' or a positive integer, got {n!r}",
                               key=("subcycle",))
        return n if limit is None else int(limit)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise CoupledError(f"subcycle must be 'auto' or a positive integer, got {n!r}",
                           key=("subcycle",))
    if limit is not None and n > limit:
        raise CoupledError(f"subcycle = {n!r}: must be an integer in [1, {limit}] (the zones' "
                           f"and the interface's stable steps over the time step)",
                           key=("subcycle",))
    return int(n)


@njit(cache=True, error_model="numpy", inline="always")
def _chunk_start(P, C, bodies, shapes, c, ZP, zones):
    """The work arrays of a chunk of steps and the blocks' state it starts from (the pair
    list's rebuild flag, the vertices, the incidence); whether the zones run in parallel."""
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
    return fb, pw, nact, bpart, bsp, bsh, zones.zg.shape[0] >= ZP[ZK.P_PARMIN]


@njit(cache=True, error_model="numpy", inline="always")
def _interface_step(IP, IE, IC, geo, side, bodies, shapes, jprops, nodes, corners, state,
                    work, fb):
    """The interface's contacts (:func:`murus.continuum.interface.step`) with ``side`` as the
    gridpoints: its forces on the gridpoints in ``work.fg`` (zeroed first), on the blocks
    added to ``fb``; returns the node and corner contacts."""
    fg = work.fg
    wfb = work.fb
    ig = geo.ig
    for k in range(ig.size):
        fg[ig[k], 0] = 0.0
        fg[ig[k], 1] = 0.0
    wfb[:, :] = 0.0
    t = IF.step(IP, IE, IC, geo, side, bodies, shapes, jprops, nodes, corners, state, work)
    for b in range(fb.shape[0]):
        fb[b, 0] += wfb[b, 0]
        fb[b, 1] += wfb[b, 1]
        fb[b, 2] += wfb[b, 2]
    return (dkd.Contacts(t[0], t[1], t[2], t[3], t[4], t[5]),
            dkd.Contacts(t[6], t[7], t[8], t[9], t[10], t[11]))


@njit(cache=True, error_model="numpy", inline="always")
def _zones_work(IE, ig, gfix, fg, v0, gvel, dt):
    """The interface's work on the zones' free gridpoints over a zones' step ``dt``, in the
    zones' form (the force at t times the mean of the half-step velocities ``v0`` before and
    ``gvel`` after it; the half after t kept apart): the zones count it in their external
    work (module doc, energy balance)."""
    half = 0.0
    for k in range(ig.size):
        g = ig[k]
        for d in range(2):
            if gfix[g, d] == 0:
                IE[IF.IE_WZONE] += dt * fg[g, d] * 0.5 * (v0[k, d] + gvel[g, d])
                half += 0.5 * dt * fg[g, d] * gvel[g, d]
    IE[IF.IE_TZONE] = half


@njit(cache=True, error_model="numpy", inline="always")
def _chunk_end(S, c, nodes, corners):
    """The mean force of the blocks' and the interface's active contacts (the unbalanced-force
    ratio's) into ``S``; the contacts' arrays as :func:`run_chunk` returns them."""
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
    fb, pw, nact, bpart, bsp, bsh, zpar = _chunk_start(P, C, bodies, shapes, c, ZP, zones)
    side = IF.GridSide(grid.gxy, grid.gvel)
    gff = grid.gff
    fg = work.fg
    ig = geo.ig
    inv_t = 1.0 / IP[IF.IP_THICK]
    gvel = grid.gvel
    gfix = grid.gfix
    v0 = np.zeros((ig.size, 2))
    cdamp = DK.damped(joints.jprops)
    allg = np.zeros(0, np.int64)
    for i in range(nsteps):
        c, pw, nact, dpar = DK.step_forces(P, E, C, S, bodies, shapes, joints, c,
                                           (pw, nact, fb))
        ZK.zone_forces(ZP, grid, zones, mprops, zpar)
        nodes, corners = _interface_step(IP, IE, IC, geo, side, bodies, shapes, jprops, nodes,
                                         corners, state, work, fb)
        for k in range(ig.size):
            g = ig[k]
            gff[g, 0] = fg[g, 0] * inv_t
            gff[g, 1] = fg[g, 1] * inv_t
        fr = DK._frame(i, drive)
        DK.step_update(P, E, C, S, fr, fb, bodies, shapes, bpart, (bsp, bsh), dpar)
        if cdamp:
            E[DK.E_DDASH] += DK.dashpot_work(c, nact, pw, joints.jprops, shapes.sbody, bodies,
                                             P[DK.P_DT])
        for k in range(ig.size):
            g = ig[k]
            v0[k, 0] = gvel[g, 0]
            v0[k, 1] = gvel[g, 1]
        ZK.grid_update(ZP, ZE, ZC, ZS, fr, grid, zones.zf, (part, ff, mprops, allg), zpar)
        _zones_work(IE, ig, gfix, fg, v0, gvel, ZP[ZK.P_DT])
    return _chunk_end(S, c, nodes, corners)


@njit(cache=True, error_model="numpy")
def run_chunk_sub(nsteps, sub, drive, zdrive, dem, zon, itf):
    """Advance ``nsteps`` steps of the blocks with the zones subcycled: the fast partition
    (the interface's gridpoints and the zones touching them) at every step with the blocks,
    the slow partition (the other gridpoints and zones) once every ``nsub`` steps (module
    doc, *Subcycling*).

    Parameters
    ----------
    nsteps : int
        Steps of the blocks (of ``P_DT``; the zones' ``P_DT`` is ``nsub`` times it).
    sub : tuple
        ``(nsub, phase, fz, sz, sg, sc, ZPf, ZEf, ZSf, gxs)``: blocks' steps per zones' step
        (>= 2); the blocks' step within the zones' step at the start (ndarray (1,) int64, 0:
        the slow partition steps first; advanced in place); the fast zones, the slow zones,
        the slow gridpoints, the slow corners of the fast zones (int64 arrays); the fast
        partition's parameters (the zones' with the blocks' ``P_DT``), energy accumulators and
        statistics; scratch coordinates ``(ng, 2)`` (the fast zones' corners as they are at
        each blocks' step).
    drive : murus.dem._kdata.Drive
        The blocks' step inputs (also the fast gridpoints').
    zdrive : murus.dem._kdata.Drive
        The slow gridpoints' step inputs, row i read when their step starts at the blocks'
        step i: base velocity and gravity at t_i, base velocity at t_i + nsub dt / 2.
    dem, zon, itf : tuple
        As :func:`run_chunk`.

    Returns
    -------
    tuple
        As :func:`run_chunk`.
    """
    nsub, phase, fz, sz, sg, sc, ZPf, ZEf, ZSf, gxs = sub
    P, E, C, S, bodies, shapes, joints, c = dem
    ZP, ZE, ZC, ZS, grid, zones, mprops, part, ff = zon
    IP, IE, IC, geo, jprops, nodes, corners, state, work = itf
    fb, pw, nact, bpart, bsp, bsh, zpar = _chunk_start(P, C, bodies, shapes, c, ZP, zones)
    spar = sz.size >= ZP[ZK.P_PARMIN]
    fpar = fz.size >= ZP[ZK.P_PARMIN]
    gxy = grid.gxy
    gvel = grid.gvel
    side = IF.GridSide(gxy, gvel)
    gff = grid.gff
    fg = work.fg
    ig = geo.ig
    inv_t = 1.0 / IP[IF.IP_THICK]
    gfix = grid.gfix
    v0 = np.zeros((ig.size, 2))
    cdamp = DK.damped(joints.jprops)
    dts = P[DK.P_DT]
    for i in range(nsteps):
        j = (phase[0] + i) % nsub
        c, pw, nact, dpar = DK.step_forces(P, E, C, S, bodies, shapes, joints, c,
                                           (pw, nact, fb))
        if j == 0:  # every gridpoint at t: the slow zones over the zones' step, the fast ones
            ZK.zone_forces_sel(ZP, gxy, grid, zones, mprops, sz, spar)
            ZK.zone_forces_sel(ZPf, gxy, grid, zones, mprops, fz, fpar)
        else:  # the slow corners on their straight path of the zones' step: x(t) + j dt v
            back = (nsub - j) * dts
            for k in range(sc.size):
                g = sc[k]
                gxs[g, 0] = gxy[g, 0] - back * gvel[g, 0]
                gxs[g, 1] = gxy[g, 1] - back * gvel[g, 1]
            for k in range(ig.size):
                g = ig[k]
                gxs[g, 0] = gxy[g, 0]
                gxs[g, 1] = gxy[g, 1]
            ZK.zone_forces_sel(ZPf, gxs, grid, zones, mprops, fz, fpar)
        nodes, corners = _interface_step(IP, IE, IC, geo, side, bodies, shapes, jprops, nodes,
                                         corners, state, work, fb)
        for k in range(ig.size):
            g = ig[k]
            gff[g, 0] = fg[g, 0] * inv_t
            gff[g, 1] = fg[g, 1] * inv_t
        fr = DK._frame(i, drive)
        DK.step_update(P, E, C, S, fr, fb, bodies, shapes, bpart, (bsp, bsh), dpar)
        if cdamp:
            E[DK.E_DDASH] += DK.dashpot_work(c, nact, pw, joints.jprops, shapes.sbody, bodies,
                                             dts)
        # the fast gridpoints (the interface's) step with the blocks
        for k in range(ig.size):
            g = ig[k]
            v0[k, 0] = gvel[g, 0]
            v0[k, 1] = gvel[g, 1]
        ZK.grid_update_sel(ZPf, ZEf, ZSf, fr, grid, zones.zf, part, ig)
        _zones_work(IE, ig, gfix, fg, v0, gvel, dts)
        if j == 0:  # the slow gridpoints over the zones' step
            ZK.grid_update(ZP, ZE, ZC, ZS, DK._frame(i, zdrive), grid, zones.zf,
                           (part, ff, mprops, sg), zpar)
    phase[0] = (phase[0] + nsteps) % nsub
    return _chunk_end(S, c, nodes, corners)


class CoupledModel:
    """A distinct-element model, a continuum and the interfaces between them, advanced in one
    time loop (module doc) by the blocks' engine.

    The coupled model attaches itself to the blocks' model (``dem.coupled``): from then on
    :func:`murus.dem.engine.settle` and :func:`murus.dem.engine.run` (``dem.settle()``,
    ``dem.run()``, or :meth:`settle` and :meth:`run` here) advance blocks and zones together
    with all of the engine's machinery: probes (also of gridpoints and zones,
    :class:`murus.dem.engine.Probe`), stop conditions, progress, Ctrl-C between chunks of
    steps, the overlap checks of the blocks, and one energy balance of blocks, zones and
    interface (:meth:`energy`). The blocks' model holds the gravity (and its tilt, a
    pseudo-static load), the base motion (it drives the zones' base gridpoints too), the time
    and the time step.

    Parameters
    ----------
    dem : murus.dem.Model
        The blocks.
    zones : murus.continuum.ContinuumModel
        The zones (large-strain mode; their gravity must be the blocks' gravity; a base motion
        set on them and not on the blocks is carried over to the blocks' model).
    interface : murus.continuum.interface.Interface
        The interface between them (built on ``zones`` and ``dem``).

    Raises
    ------
    CoupledError
        The zones in small-strain mode, the interface built on other models, a gridpoint of
        the interface also on a free-field side, or two different gravities.

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
        if not math.isclose(zones.gravity, dem.gravity, rel_tol=1e-12, abs_tol=1e-12):
            raise CoupledError(f"the zones' gravity {zones.gravity:g} m/s2 differs from the "
                               f"blocks' {dem.gravity:g} m/s2", key=("gravity",))
        dem.build()
        if dem.__dict__.get("coupled") is not None:
            raise CoupledError("the blocks' model is already coupled to zones", key=("dem",))
        if zones._motion_kind != "none" and dem._motion_kind == "none":
            for a in ("_motion_kind", "_motion_dt", "_motion_acc", "_motion_accv",
                      "_motion_callable"):
                if hasattr(zones, a):
                    setattr(dem, a, getattr(zones, a))
        self.dem = dem
        self.zones = zones
        self.iface = interface
        self.stored0 = 0.0
        self._since_check = 0
        self._plastic = 1.0  # 0 during the elastic stage of settle(elastic_first=True)
        self.nsub = 1  # blocks' steps per zones' step (set_subcycle)
        self._phase = np.zeros(1, np.int64)
        self._part = None  # the partition of subcycling (_partition)
        self.fastE = np.zeros(ZK.NE)  # energy accumulators of the fast gridpoints
        dem.coupled = self
        self.set_dt()
        self.reset_reference()

    # ------------------------------------------------------------------ time step
    def stable_dt(self) -> float:
        """The smallest stable step of blocks, zones and interface, each with its safety
        factor [s].

        Returns
        -------
        float
        """
        from murus.dem.engine import blocks_stable_dt

        # blocks that are all kinematic (a prescribed wall against zones) set no step
        d = blocks_stable_dt(self.dem) if np.any(self.dem.bkin == 0) else math.inf
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
        m = self.dem
        if m.dt is not None and dt != m.dt:
            m.time_offset = m.time
            m.step_offset = int(m.C[DK.C_STEP])
        m.P[DK.P_DT] = dt
        m.dt = dt
        self._sync_dt()

    def _sync_dt(self) -> None:
        self.zones.P[ZK.P_DT] = self.dem.dt * self.nsub
        self.iface.P[IF.IP_DT] = self.dem.dt
        self.zones.fast = (self.iface.geo.ig, self.dem.dt) if self.nsub > 1 else None

    def _partition(self) -> tuple:
        """The partition of subcycling (module doc, *Subcycling*): the fast zones (touching
        an interface gridpoint), the slow zones, the slow gridpoints, the slow corners of the
        fast zones."""
        if self._part is None:
            z = self.zones
            fast = np.zeros(z.ng, bool)
            fast[self.iface.geo.ig] = True
            fz_mask = fast[z.zg].any(axis=1)
            fz = np.flatnonzero(fz_mask).astype(np.int64)
            corners = np.unique(z.zg[fz])
            self._part = (fz, np.flatnonzero(~fz_mask).astype(np.int64),
                          np.flatnonzero(~fast).astype(np.int64),
                          corners[~fast[corners]].astype(np.int64))
        return self._part

    def subcycle_limit(self) -> int:
        """The largest number of blocks' steps per zones' step: the zones' and the
        interface's stable steps over the time step, rounded down (at least 1). The
        interface steps with the blocks, but its fastest motion (a gridpoint on the
        interface's springs) reaches the slow gridpoints through the fast zones, sampled once
        per zones' step: a longer zones' step would alias it (measured: the slide of
        ``test_subcycling_closes_the_energy_balance_within_the_time_step_error`` moves by
        1.3 % at 4.6 times this limit, by 0.1 % at it).

        Returns
        -------
        int
        """
        z = self.zones.stable_dt()
        i = self.iface.critical_dt() * self.dem.safety
        return max(1, int(math.floor(min(z, i) / self.dem.dt * (1 + 1e-12))))

    def set_subcycle(self, n: int | str = "auto") -> int:
        """Step the zones once every ``n`` steps of the blocks, but the interface's
        gridpoints and the zones touching them with the blocks (module doc, *Subcycling*).

        The blocks' time step and time are unchanged; the zones' step is ``n`` times it.
        Between two steps of the zones the gridpoints are already at the end of the current
        one (a probe of a gridpoint or a zone then leads the blocks by up to ``n - 1`` of
        their steps; the energy balance is meant at the zones' steps). A checkpoint
        (:meth:`save`) holds ``n`` and the blocks' step within the zones' step. The settling
        keeps one step for all unless this is set before it.

        Parameters
        ----------
        n : int or "auto"
            Blocks' steps per zones' step, 1 (off) to :meth:`subcycle_limit`; ``"auto"``:
            that limit.

        Returns
        -------
        int
            The number set.

        Raises
        ------
        CoupledError
            ``n`` out of range, a zones' step under way (set it between two), or no gridpoint
            off the interface.
        """
        n = check_subcycle(n, self.subcycle_limit())
        if n > 1 and self._partition()[2].size == 0:
            raise CoupledError("subcycle: every gridpoint is on the interface (no slow "
                               "partition to step less often); use one step for all",
                               key=("subcycle",))
        if int(self._phase[0]) != 0:
            raise CoupledError("subcycle: a step of the zones is under way; set it between two",
                               key=("subcycle",))
        self.nsub = int(n)
        self._sync_dt()
        return self.nsub

    @property
    def dt(self) -> float:
        """The time step [s]."""
        return float(self.dem.dt)

    # ------------------------------------------------------------------ engine hooks
    def zone_drive(self, ts, moving: bool, vfull, grav, gdot):
        """The zones' step inputs of a chunk of the blocks' steps at times ``ts`` when
        subcycling (None otherwise): the base velocity at ``t + nsub dt / 2`` in place of the
        blocks' half step (called by :func:`murus.dem.engine._chunk`)."""
        if self.nsub == 1:
            return None
        m = self.dem
        vh = m.base_velocity(ts + 0.5 * self.nsub * m.dt) if moving else vfull
        return (vfull, vh, grav, gdot)

    def step(self, n: int, drive, zdrive=None) -> None:
        """``n`` steps of blocks, zones and interface with the blocks' ``drive`` (called by
        :func:`murus.dem.engine._chunk`); ``zdrive``: the zones' inputs when subcycling
        (:meth:`zone_drive`)."""
        m, z, f = self.dem, self.zones, self.iface
        self._sync_dt()
        dem = (m.P, m.E, m.C, m.S, dkd.pack(dkd.Bodies, m), dkd.pack(dkd.Shapes, m),
               dkd.pack(dkd.Joints, m), dkd.pack(dkd.Contacts, m))
        zon = (z.P, z.E, z.C, z.S, ckd.pack(ckd.Grid, z), ckd.pack(ckd.Zones, z), z.mprops,
               z.part, z.ff)
        itf = (f.P, f.E, f.C, f.geo, f.jprops, f.nodes, f.corners, f.state, f.work)
        if self.nsub > 1:
            if zdrive is None:
                raise CoupledError("subcycling needs the zones' step inputs (zone_drive)",
                                   key=("step",))
            fast_p = np.array(z.P, copy=True)
            fast_p[ZK.P_DT] = m.dt
            sub = (self.nsub, self._phase, *self._partition(), fast_p, self.fastE,
                   np.zeros(ZK.NS), np.array(z.gxy, copy=True))
            out = run_chunk_sub(n, sub, drive, zdrive, dem, zon, itf)
        else:
            out = run_chunk(n, drive, dem, zon, itf)
        for name, a in zip(dkd.Contacts._fields, out[:6], strict=True):
            setattr(m, name, a)
        f._set(out[6:])
        z.time = m.time
        self._since_check += n

    def after_chunk(self) -> str | None:
        """The zones' checks after a chunk of steps: a non-finite gridpoint velocity or an
        inverted zone (a message), and every 100 steps in large strain the zones' critical
        step against the time step (the step shrinks when the zones distorted)."""
        z = self.zones
        if not np.all(np.isfinite(z.gvel)):
            return "non-finite gridpoint velocities (lower the time step)"
        if np.any(z.zstate & ZK.ST_INVERTED):
            k = int(np.flatnonzero(z.zstate & ZK.ST_INVERTED)[0])
            return f"zone {k} turned inside out (too distorted)"
        if self._since_check >= 100:
            self._since_check = 0
            crit = z.critical_dt()
            if crit <= 0.0:
                return "a zone has a non-positive area"
            if z.safety * crit < self.dem.dt * self.nsub:
                if self.nsub == 1:
                    self.set_dt(z.safety * crit)
                elif int(self._phase[0]) == 0:  # (else at a later check, between two steps)
                    self.nsub = max(1, int(math.floor(z.safety * crit / self.dem.dt)))
                    self._sync_dt()
        return None

    def set_damping(self, alocal: float, amass: float, drel: float) -> None:
        """The zones take the blocks' damping (local coefficient, mass-proportional
        ``alpha_M`` [1/s], frame)."""
        P = self.zones.P
        P[ZK.P_ALOCAL] = alocal
        P[ZK.P_AMASS] = amass
        P[ZK.P_DREL] = drel
        P[ZK.P_PLASTIC] = self._plastic

    def at_rest(self) -> None:
        """Zero the gridpoints' velocities and accelerations (the end of a settling, which
        does not advance the time)."""
        self.zones.time = self.dem.time
        self.zones.gvel[:] = 0.0
        self.zones.gacc[:] = 0.0

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

    # ------------------------------------------------------------------ energy
    def reset_reference(self) -> None:
        """Take the current state of the zones and the interface as the reference of their
        displacements and energies (called by the blocks' ``reset_reference``)."""
        self.zones.reset_reference()
        self.fastE[:] = 0.0
        self.iface.E[:] = 0.0
        self.stored0 = stored_energy_of(self.iface)

    def energy_terms(self, g) -> dict:
        """The zones' and the interface's energy terms [J, for the blocks' thickness] since the
        reference state, and their share of the balance's error (:meth:`energy`).

        Parameters
        ----------
        g : array_like (2,)
            The gravity vector now [m/s²] (the blocks' model's, with its tilt).

        Returns
        -------
        dict
        """
        z = self.zones
        t = float(self.iface.P[IF.IP_THICK])
        e = z.energy()
        fe = self.fastE  # the fast gridpoints' works (subcycling), done to their last step
        for key, w, h in (("damping_work", ZK.E_WDAMP, ZK.E_TDAMP),
                          ("base_work", ZK.E_WBASE, ZK.E_TBASE),
                          ("external_work", ZK.E_WEXT, ZK.E_TEXT),
                          ("dashpot_work", ZK.E_WDASH, ZK.E_TDASH)):
            e[key] += float(fe[w] - fe[h])
        free = z.gfix == 0
        u = z.gdisp - z.gdt() * z.gvel
        pe = -float((z.gmass[:, None] * u * np.asarray(g, float)[None, :] * free).sum())
        fE = self.iface.E
        wz = float(fE[IF.IE_WZONE] - fE[IF.IE_TZONE])
        out = {"zones_kinetic": t * (e["kinetic"] - z.K0), "zones_gravity": t * pe,
               "zones_strain": t * e["strain"], "zones_plastic": t * e["plastic"],
               "zones_damping_work": t * e["damping_work"],
               "zones_base_work": t * e["base_work"],
               "zones_dashpot_work": t * e["dashpot_work"],
               "zones_external_work": t * e["external_work"] - wz,
               "interface_elastic": stored_energy_of(self.iface) - self.stored0,
               "interface_slip": float(fE[IF.IE_DSLIP]),
               "interface_breaking": float(fE[IF.IE_DBREAK])}
        out["zones_error"] = (out["zones_kinetic"] + out["zones_gravity"]
                              + out["zones_strain"] + out["zones_plastic"]
                              + out["interface_elastic"] + out["interface_slip"]
                              + out["interface_breaking"]
                              - (out["zones_damping_work"] + out["zones_base_work"]
                                 + out["zones_dashpot_work"] + out["zones_external_work"]))
        return out

    def energy(self) -> dict:
        """One energy balance of blocks, zones and interface [J, for the blocks' thickness]
        since the reference state (:func:`murus.dem.engine.energy`).

        The blocks' terms keep their names (``kinetic``, ``gravity``, ``elastic`` of the
        blocks' contacts, ``base_work``, ...); the zones' are prefixed ``zones_`` (their
        per-metre terms times the thickness), the interface's ``interface_`` (its springs'
        elastic energy, slip and breaking). The interface's forces are internal: the blocks'
        balance misses their work on the blocks, the zones count their work on the gridpoints
        as external; with ``zones_external_work`` the applied forces only, ``error`` closes
        over everything: ``ΔE_blocks + ΔE_zones + ΔE_interface + dissipation - work of the
        base, the dampers, the dashpots and the applied forces``.

        Returns
        -------
        dict
        """
        from murus.dem.engine import energy

        return energy(self.dem)

    # ------------------------------------------------------------------ running
    def settle(self, *, elastic_first: bool = False, **kw):
        """Static equilibrium of blocks and zones (:func:`murus.dem.engine.settle`).

        Parameters
        ----------
        elastic_first : bool
            Settle first with every zone material elastic, then with plasticity (the gravity
            initialisation of FLAC, :func:`murus.continuum.engine.settle`): a cohesionless
            backfill then starts from an elastic stress state rather than yielding under its
            first, dynamic, loading.
        **kw
            Arguments of :func:`murus.dem.engine.settle` (``tol``, ``alpha``, ``max_steps``,
            ``reset``, ...).

        Returns
        -------
        murus.dem.engine.SettleResult
            Of the (last) plastic stage; its ``steps`` count both stages.
        """
        if not elastic_first:
            return self.dem.settle(**kw)
        self._plastic = 0.0
        try:
            first = self.dem.settle(**dict(kw, reset=False))
        finally:
            self._plastic = 1.0
        if not first.converged:  # said of the elastic stage (its message counts its steps)
            first.message = "elastic stage: " + first.message
            return first
        res = self.dem.settle(**kw)
        res.steps += first.steps
        return res

    def run(self, duration: float | None = None, **kw):
        """A dynamic run of blocks and zones (:func:`murus.dem.engine.run`): the blocks'
        base motion drives the zones' base gridpoints and the blocks of kind "base".

        Parameters
        ----------
        duration : float
            Simulated time [s].
        **kw
            Arguments of :func:`murus.dem.engine.run` (``xi``, ``freq``, ``probes``, ``stop``,
            ``progress``, ...): the damping applies to blocks and zones alike.

        Returns
        -------
        murus.dem.engine.RunResult
        """
        return self.dem.run(duration, **kw)

    # ------------------------------------------------------------------ checkpoint
    #: the zones' arrays a checkpoint holds, besides the kernel state (:data:`kd.STATE_ARRAYS`)
    _ZONE_ARRAYS = ("gx0", "gff", "P", "E", "C", "S", "part", "mprops")

    def save(self, path) -> None:
        """The whole state of blocks, zones and interface to an ``.npz`` file, written
        atomically (:func:`murus.dem.model.write_npz`), to resume with :meth:`restore` on the
        same model built again (from the same case file or script): the run then continues
        bit for bit as if uninterrupted. A callable base motion is not saved (the rebuilt
        model has it).

        Parameters
        ----------
        path : str or path-like or file
            Destination (``.npz`` appended when missing).
        """
        from murus.continuum.freefield import FreeField
        from murus.dem.model import write_npz

        m, z, f = self.dem, self.zones, self.iface
        arrays, meta = m.checkpoint_arrays()
        arrays = {"dem__" + k: v for k, v in arrays.items()}
        for name in ckd.STATE_ARRAYS + self._ZONE_ARRAYS:
            arrays["zones__" + name] = getattr(z, name)
        for name, a in zip(FreeField._fields, z.ff, strict=True):
            arrays["ff__" + name] = a
        for name in ("P", "E", "C"):
            arrays["iface__" + name] = getattr(f, name)
        arrays["coupled__fastE"] = self.fastE
        for pre, cc in (("nodes", f.nodes), ("corners", f.corners)):
            for name, a in zip(dkd.Contacts._fields, cc, strict=True):
                arrays[f"{pre}__{name}"] = a
        for name, a in zip(IF.IfaceState._fields, f.state, strict=True):
            arrays["istate__" + name] = a
        meta["coupled"] = {"zones_time": z.time, "K0": z.K0, "stored0": self.stored0,
                           "since_check": int(self._since_check),
                           "nsub": int(self.nsub), "phase": int(self._phase[0]),
                           "ng": int(z.ng), "nz": int(z.nz), "nbody": int(m.nbody),
                           "nedge": int(f.geo.ie.shape[0])}
        arrays["meta"] = np.array(json.dumps(meta))
        write_npz(path, arrays)

    def restore(self, path) -> None:
        """Resume from a checkpoint of :meth:`save` written by the same model (built again the
        same way).

        Parameters
        ----------
        path : str or path-like
            The ``.npz`` file.

        Raises
        ------
        CoupledError
            The checkpoint is of another model (numbers of bodies, gridpoints, zones or
            interface edges differ).
        """
        from murus.continuum.freefield import FreeField

        m, z, f = self.dem, self.zones, self.iface
        with np.load(path, allow_pickle=False) as npz:
            meta = json.loads(str(npz["meta"]))
            c = meta.get("coupled")
            want = {"ng": int(z.ng), "nz": int(z.nz), "nbody": int(m.nbody),
                    "nedge": int(f.geo.ie.shape[0])}
            if c is None or any(c[k] != v for k, v in want.items()):
                got = None if c is None else {k: c[k] for k in want}
                raise CoupledError(f"{path}: a checkpoint of another model ({got}, this model "
                                   f"{want})", key=("restore",))
            arrays = {k: npz[k] for k in npz.files}
        keep = (m._motion_kind, getattr(m, "_motion_callable", None))
        m.restore_arrays({k[5:]: v for k, v in arrays.items() if k.startswith("dem__")}, meta)
        if keep[0] == "callable":
            m._motion_kind, m._motion_callable = keep
        for name in ckd.STATE_ARRAYS + self._ZONE_ARRAYS:
            setattr(z, name, np.array(arrays["zones__" + name], copy=True))
        if z.P.size < ZK.NP:  # a checkpoint of a version with fewer parameters: zero (off)
            z.P = np.concatenate([z.P, np.zeros(ZK.NP - z.P.size)])
        z.ff = FreeField(*[np.array(arrays["ff__" + n], copy=True) for n in FreeField._fields])
        for name in ("P", "E", "C"):
            setattr(f, name, np.array(arrays["iface__" + name], copy=True))
        f._set([np.array(arrays[f"{pre}__{n}"], copy=True) for pre in ("nodes", "corners")
                for n in dkd.Contacts._fields])
        f.state = IF.IfaceState(*[np.array(arrays["istate__" + n], copy=True)
                                  for n in IF.IfaceState._fields])
        f.bodies = dkd.pack(dkd.Bodies, m)
        f.shapes = dkd.pack(dkd.Shapes, m)
        z.time = float(c["zones_time"])
        z.K0 = float(c["K0"])
        self.stored0 = float(c["stored0"])
        self._since_check = int(c["since_check"])
        self.nsub = int(c.get("nsub", 1))
        self._phase[0] = int(c.get("phase", 0))
        self.fastE = (np.array(arrays["coupled__fastE"], copy=True)
                      if "coupled__fastE" in arrays else np.zeros(ZK.NE))
        self._sync_dt()


def stored_energy_of(iface) -> float:
    """Elastic energy of the interface's springs now [J]
    (:func:`murus.continuum.interface.stored_energy`).

    Parameters
    ----------
    iface : murus.continuum.interface.Interface
        The interface.

    Returns
    -------
    float
    """
    return float(IF.stored_energy(iface.nodes, iface.corners))


# numba's cache checks only this file: flush it when the kernels it compiles in change
_guard_cache(globals(), deps=("murus.dem.kernels", "murus.dem._kdata", "murus.continuum.kernels",
                              "murus.continuum._kdata", "murus.continuum.interface",
                              "murus.continuum.freefield"))
