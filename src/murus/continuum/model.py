"""Python front end of the continuum (zones) engine: gridpoints, zones, materials, boundaries,
initial stresses, state.

Conventions: SI units (m, kg, s, N, Pa); x horizontal, y upward, gravity ``-g y``; plane strain
per metre of out-of-plane thickness (masses in kg/m, forces in N/m, energies in J/m); stresses
tension positive (a soil at rest has negative ``syy``).

A model takes plain arrays: gridpoint coordinates ``xy (ng, 2)`` [m] and quadrilateral zones
``zones (nz, 4)`` (gridpoint indices, counter-clockwise), each zone with a material
(:class:`~murus.continuum.materials.Elastic` or :class:`~murus.continuum.materials.MohrCoulomb`).
Meshes come from :mod:`murus.continuum.mesh` or any generator.

Boundaries, per gridpoint and direction: free, ``fix`` (zero velocity; a roller is a gridpoint
fixed in one direction), ``base`` (moves with the base motion in that direction: a rigid shaking
base, a :class:`~murus.motion.core.GroundMotion` with ``acc`` and optional ``acc_v``, or a
callable velocity, as :meth:`murus.dem.model.Model.set_base_motion`); applied forces
(:meth:`ContinuumModel.add_load`) and pressures on boundary edges
(:meth:`ContinuumModel.apply_pressure`).

>>> import numpy as np
>>> from murus.continuum import ContinuumModel, Elastic
>>> xy = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
>>> m = ContinuumModel(xy, [[0, 1, 2, 3]], Elastic(density=2000.0, E=1e7, nu=0.3))
>>> m.fix([0, 1])
>>> res = m.settle()
>>> bool(res.converged)
True
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from murus.continuum import _kdata as kd
from murus.continuum import kernels as K
from murus.continuum.materials import Elastic
from murus.errors import MurusError

__all__ = ["ContinuumModel", "ModelError", "TRIANGLES"]

#: Corners of the four triangles of a zone (two overlays; :mod:`murus.continuum.kernels`).
TRIANGLES = np.array(K.TRI, dtype=np.int64)


class ModelError(MurusError, ValueError):
    """Invalid continuum model input (``key``: the offending argument, and the index of the
    offending row where there is one)."""


def _tri_geometry(xy, zg):
    """Twice the signed area (nz, 4) and the corner coordinates (nz, 4, 3, 2) of the four
    triangles of each zone."""
    pts = xy[zg[:, TRIANGLES]]  # (nz, 4, 3, 2)
    a2 = ((pts[..., 1, 0] - pts[..., 0, 0]) * (pts[..., 2, 1] - pts[..., 0, 1])
          - (pts[..., 2, 0] - pts[..., 0, 0]) * (pts[..., 1, 1] - pts[..., 0, 1]))
    return a2, pts


def _ids(name, idx, ng):
    a = np.atleast_1d(np.asarray(idx))
    if a.dtype == bool:
        if a.size != ng:
            raise ModelError(f"{name}: a mask needs {ng} entries, got {a.size}", key=(name,))
        a = np.flatnonzero(a)
    if a.size and not np.issubdtype(a.dtype, np.integer):
        raise ModelError(f"{name}: gridpoint indices must be integers", key=(name,))
    a = a.astype(np.int64).ravel()
    if a.size == 0:
        raise ModelError(f"{name}: names no gridpoint", key=(name,))
    bad = (a < 0) | (a >= ng)
    if bad.any():
        raise ModelError(f"{name}: gridpoint {int(a[bad][0])} out of range 0..{ng - 1}",
                         key=(name,))
    return a


class ContinuumModel:
    """A 2D plane-strain continuum of quadrilateral zones (mixed discretisation, Marti &
    Cundall (1982)), explicit, with Mohr-Coulomb plasticity.

    Parameters
    ----------
    xy : array_like (ng, 2)
        Gridpoint coordinates [m].
    zones : array_like (nz, 4) of int
        Gridpoints of each zone, counter-clockwise.
    materials : material or sequence of materials
        :class:`~murus.continuum.materials.Elastic` or
        :class:`~murus.continuum.materials.MohrCoulomb` instances.
    zone_material : array_like (nz,) of int, optional
        Index into ``materials`` of each zone (default: all 0).
    gravity : float
        Gravitational acceleration [m/s²] (along -y), default 9.81.
    large_strain : bool
        True (default): coordinates follow the gridpoints and stresses rotate (Jaumann);
        False: small strain.
    safety : float
        Safety factor of the time step on the zones' critical step (:meth:`critical_dt`),
        default 0.5.

    Raises
    ------
    ModelError
        Malformed arrays, an index out of range, a zone that is not counter-clockwise and
        convex (key ``("zones", i)``), a wrong material (key ``("materials", i)``).

    References
    ----------
    Marti & Cundall (1982); Itasca FLAC, Theory and Background.
    """

    def __init__(self, xy, zones, materials, zone_material=None, *, gravity: float = 9.81,
                 large_strain: bool = True, safety: float = 0.5) -> None:
        xy = np.array(xy, dtype=float)
        if xy.ndim != 2 or xy.shape[1] != 2 or xy.shape[0] < 3:
            raise ModelError(f"xy must be an (ng, 2) array of coordinates, got shape {xy.shape}",
                             key=("xy",))
        if not np.all(np.isfinite(xy)):
            raise ModelError("xy must be finite", key=("xy",))
        zg = np.asarray(zones)
        if zg.ndim != 2 or zg.shape[1] != 4 or zg.shape[0] < 1:
            raise ModelError(f"zones must be an (nz, 4) array of gridpoints, got shape "
                             f"{zg.shape}", key=("zones",))
        if not np.issubdtype(zg.dtype, np.integer):
            raise ModelError("zones must hold integer gridpoint indices", key=("zones",))
        zg = zg.astype(np.int64)
        ng = xy.shape[0]
        bad = np.flatnonzero(((zg < 0) | (zg >= ng)).any(axis=1))
        if bad.size:
            raise ModelError(f"zone {bad[0]}: gridpoint index out of range 0..{ng - 1}",
                             key=("zones", int(bad[0])))
        a2, _ = _tri_geometry(xy, zg)
        bad = np.flatnonzero((a2 <= 0.0).any(axis=1))
        if bad.size:
            raise ModelError(f"zone {bad[0]}: not a counter-clockwise convex quadrilateral",
                             key=("zones", int(bad[0])))
        mats = list(materials) if isinstance(materials, (list, tuple)) else [materials]
        for i, mt in enumerate(mats):
            if not isinstance(mt, Elastic):
                raise ModelError(f"materials[{i}]: not a zone material ({type(mt).__name__})",
                                 key=("materials", i))
        if not mats:
            raise ModelError("give at least one material", key=("materials",))
        zm = (np.zeros(zg.shape[0], np.int64) if zone_material is None
              else np.asarray(zone_material))
        if zm.shape != (zg.shape[0],) or not np.issubdtype(zm.dtype, np.integer):
            raise ModelError(f"zone_material must hold {zg.shape[0]} integers",
                             key=("zone_material",))
        if zm.size and (zm.min() < 0 or zm.max() >= len(mats)):
            raise ModelError(f"zone_material: index out of range 0..{len(mats) - 1}",
                             key=("zone_material",))
        if not (math.isfinite(gravity) and gravity >= 0):
            raise ModelError(f"gravity must be >= 0, got {gravity!r}", key=("gravity",))
        if not (0.0 < safety <= 1.0):
            raise ModelError(f"safety must be in (0, 1], got {safety!r}", key=("safety",))
        used = np.zeros(ng, bool)
        used[zg.ravel()] = True
        if not used.all():
            raise ModelError(f"gridpoint {int(np.flatnonzero(~used)[0])} belongs to no zone",
                             key=("xy", int(np.flatnonzero(~used)[0])))
        self.materials = mats
        self.gravity = float(gravity)
        self.large_strain = bool(large_strain)
        self.safety = float(safety)
        nz = zg.shape[0]
        # ---- state arrays (murus.continuum._kdata)
        self.gxy = xy.copy()
        self.gx0 = xy.copy()  # coordinates of the reference state
        self.gvel = np.zeros((ng, 2))
        self.gacc = np.zeros((ng, 2))
        self.gdisp = np.zeros((ng, 2))
        self.gfix = np.zeros((ng, 2), np.int64)
        self.gext = np.zeros((ng, 2))
        self.gdash = np.zeros((ng, 3))
        self.gff = np.zeros((ng, 4))
        #: The fast gridpoints and their step ``(indices, dt)`` of a subcycled coupled model
        #: (:meth:`murus.continuum.coupled.CoupledModel.set_subcycle`), or None.
        self.fast = None
        from murus.continuum.freefield import empty as _no_free_field

        self.ff = _no_free_field()
        self.zg = np.ascontiguousarray(zg)
        self.zmat = np.ascontiguousarray(zm.astype(np.int64))
        self.zsig = np.zeros((nz, 4, 4))
        self.zstate = np.zeros(nz, np.int64)
        self.zwork = np.zeros((nz, 2))
        self.zf = np.zeros((4 * nz, 2))
        self.mprops = np.array([mt.row() for mt in mats])
        # CSR incidence gridpoint -> zone corners (ascending 4 z + c)
        corners = self.zg.ravel()
        order = np.argsort(corners, kind="stable")
        self.gzc = order.astype(np.int64)
        self.gsp = np.zeros(ng + 1, np.int64)
        np.cumsum(np.bincount(corners, minlength=ng), out=self.gsp[1:])
        # lumped masses: rho A / 3 per triangle node, halved per overlay
        rho = self.mprops[self.zmat, K.M_RHO]
        w = (0.5 * a2 / 3.0 * 0.5) * rho[:, None]  # (nz, 4)
        self.gmass = np.zeros(ng)
        np.add.at(self.gmass, self.zg[:, TRIANGLES].reshape(nz, 12),
                  np.repeat(w, 3, axis=1))
        # ---- records
        self.P = np.zeros(K.NP)
        self.E = np.zeros(K.NE)
        self.C = np.zeros(K.NC, np.int64)
        self.S = np.zeros(K.NS)
        self.part = np.zeros((K.NBLK, K.NQ))
        self.P[K.P_LARGE] = 1.0 if self.large_strain else 0.0
        self.P[K.P_PLASTIC] = 1.0
        self.P[K.P_PARMIN] = 4000.0
        self.time = 0.0
        self.K0 = 0.0
        self._motion_kind = "none"
        self._motion_dt = 0.0
        self._motion_acc = np.zeros(0)
        self._motion_accv = np.zeros(0)
        self._motion_callable: Callable | None = None
        self.monitors: dict = {}
        self.history: dict = {}
        self.P[K.P_DT] = self.stable_dt()

    # ------------------------------------------------------------------ sizes
    @property
    def ng(self) -> int:
        """Number of gridpoints."""
        return self.gxy.shape[0]

    @property
    def nz(self) -> int:
        """Number of zones."""
        return self.zg.shape[0]

    @property
    def dt(self) -> float:
        """Current time step [s]."""
        return float(self.P[K.P_DT])

    def gdt(self):
        """The last step of each gridpoint [s], as a column ``(ng, 1)``: the time step, but
        the blocks' step for the fast partition of a subcycled coupled model (``fast``,
        :meth:`murus.continuum.coupled.CoupledModel.set_subcycle`).

        Returns
        -------
        ndarray (ng, 1)
        """
        d = np.full((self.ng, 1), self.dt)
        if self.fast is not None:
            d[self.fast[0]] = self.fast[1]
        return d

    # ------------------------------------------------------------------ time step
    def critical_dt(self) -> float:
        """The zones' critical time step ``min_z A / (Cp L)`` [s] at the current geometry
        (:func:`murus.continuum.kernels.zone_dt`), before the safety factor: the value to
        combine with the contacts' step of a mixed model (take the smaller).

        Returns
        -------
        float
            The critical step [s] (0 when a zone is inverted).

        References
        ----------
        Itasca FLAC, Theory and Background (stability of the explicit scheme).
        """
        return float(K.zone_dt(self.gxy, self.zg, self.zmat, self.mprops).min())

    def stable_dt(self, safety: float | None = None) -> float:
        """``safety * critical_dt()`` [s].

        Parameters
        ----------
        safety : float, optional
            Safety factor (default: the model's, 0.5).

        Returns
        -------
        float
            The time step [s].
        """
        return (self.safety if safety is None else float(safety)) * self.critical_dt()

    def set_dt(self, dt: float | None = None) -> float:
        """Set the time step: ``dt`` [s] (a mixed model passes the smaller of the zones' and
        the contacts' steps), or None for :meth:`stable_dt`.

        Parameters
        ----------
        dt : float or None
            The step [s], ``0 < dt <= critical_dt()``.

        Returns
        -------
        float
            The step set [s].

        Raises
        ------
        ModelError
            A step above the zones' critical step (key ``("dt",)``).
        """
        if dt is None:
            dt = self.stable_dt()
        crit = self.critical_dt()
        if not (math.isfinite(dt) and 0.0 < dt <= crit):
            raise ModelError(f"dt must be in (0, {crit:.4g}] s (the zones' critical step), "
                             f"got {dt!r}", key=("dt",))
        self.P[K.P_DT] = float(dt)
        return float(dt)

    # ------------------------------------------------------------------ boundaries
    def fix(self, gridpoints, x: bool = True, y: bool = True) -> None:
        """Fix gridpoints (zero velocity) in x and/or y; ``x=True, y=False`` is a roller on a
        vertical boundary.

        Parameters
        ----------
        gridpoints : array_like of int or bool mask
            The gridpoints.
        x, y : bool
            Directions to fix.
        """
        g = _ids("fix", gridpoints, self.ng)
        if x:
            self.gfix[g, 0] = 1
            self.gvel[g, 0] = 0.0
        if y:
            self.gfix[g, 1] = 1
            self.gvel[g, 1] = 0.0

    def set_base(self, gridpoints, x: bool = True, y: bool = True) -> None:
        """Gridpoints moved by the base motion (:meth:`set_base_motion`) in x and/or y (a rigid
        shaking base: the bottom gridpoints in both directions).

        Parameters
        ----------
        gridpoints : array_like of int or bool mask
            The gridpoints.
        x, y : bool
            Directions driven by the base.
        """
        g = _ids("base", gridpoints, self.ng)
        if x:
            self.gfix[g, 0] = 2
        if y:
            self.gfix[g, 1] = 2

    def free(self, gridpoints, x: bool = True, y: bool = True) -> None:
        """Release gridpoints in x and/or y.

        Parameters
        ----------
        gridpoints : array_like of int or bool mask
            The gridpoints.
        x, y : bool
            Directions to release.
        """
        g = _ids("free", gridpoints, self.ng)
        if x:
            self.gfix[g, 0] = 0
        if y:
            self.gfix[g, 1] = 0

    def add_load(self, gridpoints, fx: float = 0.0, fy: float = 0.0) -> None:
        """Add a constant force (fx, fy) [N per metre of thickness] to each of the gridpoints.

        Parameters
        ----------
        gridpoints : array_like of int or bool mask
            The gridpoints.
        fx, fy : float
            Force components [N/m].
        """
        g = _ids("load", gridpoints, self.ng)
        if not (math.isfinite(fx) and math.isfinite(fy)):
            raise ModelError("load: the force must be finite", key=("load",))
        np.add.at(self.gext, g, np.array([fx, fy]))

    def boundary_edges(self) -> np.ndarray:
        """The edges that belong to one zone only, oriented with the zone on their left.

        Returns
        -------
        ndarray (ne, 2) of int
            Gridpoint pairs (a, b): walking from a to b, the zone is on the left and the
            outward normal is ``(dy, -dx) / L``.
        """
        e = np.stack([self.zg, np.roll(self.zg, -1, axis=1)], axis=2).reshape(-1, 2)
        key = np.sort(e, axis=1)
        _, inv, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        return e[cnt[inv.ravel()] == 1]

    def apply_pressure(self, edges, pressure: float) -> None:
        """A uniform pressure on boundary edges (positive: compression, pushing into the
        body), lumped half to each end gridpoint (constant direction: the normal at the time
        of the call).

        Parameters
        ----------
        edges : array_like (k, 2) of int
            Gridpoint pairs, each an edge of exactly one zone (either orientation).
        pressure : float
            Pressure [Pa].

        Raises
        ------
        ModelError
            An edge that is not a boundary edge (key ``("edges", i)``).
        """
        if not math.isfinite(pressure):
            raise ModelError("pressure must be finite", key=("pressure",))
        ed, _ = self._orient(edges, "edges")
        for p, q in ed:
            d = self.gxy[q] - self.gxy[p]
            n = np.array([d[1], -d[0]])  # outward, times L
            self.gext[p] -= 0.5 * pressure * n
            self.gext[q] -= 0.5 * pressure * n

    def _orient(self, edges, name):
        """Boundary edges (k, 2) oriented with their zone on the left, and each edge's zone."""
        ed = np.asarray(edges)
        if ed.ndim != 2 or ed.shape[1] != 2 or ed.shape[0] == 0:
            raise ModelError(f"{name} must be a non-empty (k, 2) array of gridpoints",
                             key=(name,))
        e = np.stack([self.zg, np.roll(self.zg, -1, axis=1)], axis=2).reshape(-1, 2)
        key = np.sort(e, axis=1)
        _, inv, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        single = cnt[inv.ravel()] == 1
        lookup = {(int(a), int(b)): k // 4 for k, (a, b) in enumerate(e) if single[k]}
        out = np.zeros((ed.shape[0], 2), np.int64)
        zone = np.zeros(ed.shape[0], np.int64)
        for i, (a, b) in enumerate(ed.astype(np.int64)):
            if (a, b) in lookup:
                out[i] = a, b
                zone[i] = lookup[(a, b)]
            elif (b, a) in lookup:
                out[i] = b, a
                zone[i] = lookup[(b, a)]
            else:
                raise ModelError(f"{name}: edge {i} ({a}, {b}) is not a boundary edge of a zone",
                                 key=(name, i))
        return out, zone

    def add_quiet(self, edges, *, frame: str = "rest", static: bool = False) -> None:
        """Quiet (viscous) boundary on boundary edges: dashpots ``rho Cp`` normal and
        ``rho Cs`` tangential per unit length (the material of each edge's zone), lumped half
        to each end gridpoint (Lysmer and Kuhlemeyer 1969).

        Parameters
        ----------
        edges : array_like (k, 2) of int
            Gridpoint pairs, each an edge of exactly one zone (either orientation).
        frame : {"rest", "base"}
            The velocity the dashpots act against: rest (a base or a side where the waves
            leave an unbounded medium at rest, the classical quiet boundary) or the base
            motion (a lateral side of a model shaken from below: dashpots on the velocity
            relative to the base do not resist the rigid motion of the whole model with its
            base, which dashpots on the absolute velocity would). One frame for every quiet
            edge of a model (set by the first call).
        static : bool
            Replace the supports of the edges' gridpoints by the forces they carry now, as FLAC
            does when a quiet boundary replaces a fixed one: each fixed direction of those
            gridpoints is released and gets, as a constant applied force, its reaction (minus
            the zones' corner forces of the last step, the applied and free-field forces on it;
            directions moved by the base stay so). Call it after the static stage.

        Raises
        ------
        ModelError
            An edge that is not a boundary edge (key ``("quiet", i)``), an unknown frame, or a
            frame other than that of the quiet edges already added (key ``("quiet",
            "frame")``).

        References
        ----------
        Lysmer & Kuhlemeyer (1969), J. Eng. Mech. Div. ASCE 95(4) 859-877; Itasca FLAC,
        Dynamic Analysis ("quiet boundaries"; the static reactions applied when a fixed
        boundary becomes quiet).
        """
        fr = str(frame).strip().lower()
        if fr not in ("rest", "base"):
            raise ModelError(f"quiet: frame must be 'rest' or 'base', got {frame!r}",
                             key=("quiet", "frame"))
        want = 1.0 if fr == "base" else 0.0
        had = getattr(self, "_quiet_frame", None)  # (free-field sides have dashpots too)
        if had is not None and had != fr:
            raise ModelError(f"quiet: the quiet edges already added act against "
                             f"{'the base' if had == 'base' else 'rest'}: one frame for every "
                             f"quiet edge of a model, got {frame!r}", key=("quiet", "frame"))
        ed, zone = self._orient(edges, "quiet")
        for (a, b), z in zip(ed, zone, strict=True):
            mt = self.materials[self.zmat[z]]
            d = self.gxy[b] - self.gxy[a]
            L = float(np.hypot(d[0], d[1]))
            n = np.array([d[1], -d[0]]) / L
            t = d / L
            C = 0.5 * L * mt.density * (mt.vp * np.outer(n, n) + mt.vs * np.outer(t, t))
            for g in (a, b):
                self.gdash[g] += (C[0, 0], C[0, 1], C[1, 1])
        if static:
            gw = np.array([0.0, -self.gravity])
            for g in np.unique(ed):
                corners = self.gzc[self.gsp[g]:self.gsp[g + 1]]
                fint = self.zf[corners].sum(axis=0)
                for k in range(2):
                    if self.gfix[g, k] == 1:
                        self.gext[g, k] -= (fint[k] + self.gext[g, k] + self.gff[g, k]
                                            + self.gmass[g] * gw[k])
                        self.gfix[g, k] = 0
        self.P[K.P_QFRAME] = want
        self._quiet_frame = fr

    def add_free_field(self, sides) -> None:
        """Free-field lateral boundaries on vertical sides (:mod:`murus.continuum.freefield`),
        in the current state: call it after the static stage, as in FLAC (the columns take the
        stresses of the zones beside them; the sides are released horizontally and get the
        dashpots ``L rho Cp``, ``L rho Cs``).

        Parameters
        ----------
        sides : sequence of array_like of int
            The gridpoints of each vertical side.

        Raises
        ------
        murus.continuum.freefield.FreeFieldError
            A side that is not vertical or not on the boundary (key: the side's index).

        References
        ----------
        Itasca FLAC, Dynamic Analysis, "Free-field boundaries".
        """
        from murus.continuum.freefield import build_free_field, merge

        self.ff = merge(self.ff, build_free_field(self, sides))

    def set_base_motion(self, motion=None, velocity: Callable | None = None) -> None:
        """Motion of the ``base`` gridpoints: a GroundMotion (``acc`` and optional ``acc_v``
        [m/s²], zero after its end, integrated exactly as the blocks' base) or a callable
        ``velocity(t) -> vx`` or ``(vx, vy)`` [m/s] (vectorised over a time array).

        Parameters
        ----------
        motion : murus.motion.core.GroundMotion, optional
            The input motion.
        velocity : callable, optional
            The base velocity in closed form.
        """
        if (motion is None) == (velocity is None):
            raise ModelError("give either a GroundMotion or a velocity callable",
                             key=("motion",))
        if motion is not None:
            self._motion_kind = "record"
            self._motion_dt = float(motion.dt)
            self._motion_acc = np.asarray(motion.acc, float).copy()
            av = getattr(motion, "acc_v", None)
            self._motion_accv = (np.zeros_like(self._motion_acc) if av is None
                                 else np.asarray(av, float).copy())
            self._motion_callable = None
        else:
            if not callable(velocity):
                raise ModelError("velocity must be a callable v(t)", key=("velocity",))
            self._motion_kind = "callable"
            self._motion_callable = velocity

    def base_velocity(self, t) -> np.ndarray:
        """Velocity of the base [m/s] at times t (n, 2).

        Parameters
        ----------
        t : array_like
            Times [s].

        Returns
        -------
        ndarray (n, 2)
        """
        from murus.dem.model import motion_velocity

        return motion_velocity(self, t)

    # ------------------------------------------------------------------ stresses
    def set_stress(self, sxx, syy, sxy=0.0, szz=None, zones=None) -> None:
        """Set the stress of zones (all four triangles) [Pa, tension positive].

        Parameters
        ----------
        sxx, syy, sxy : float or array_like (k,)
            Stress components [Pa].
        szz : float or array_like, optional
            Out-of-plane stress [Pa] (default: ``nu (sxx + syy)`` of the zone's material).
        zones : array_like of int or bool mask, optional
            The zones (default: all).
        """
        z = np.arange(self.nz) if zones is None else np.atleast_1d(np.arange(self.nz)[zones])
        sxx = np.broadcast_to(np.asarray(sxx, float), z.shape)
        syy = np.broadcast_to(np.asarray(syy, float), z.shape)
        sxy = np.broadcast_to(np.asarray(sxy, float), z.shape)
        if szz is None:
            nu = np.array([self.materials[i].poisson for i in self.zmat[z]])
            szz = nu * (sxx + syy)
        szz = np.broadcast_to(np.asarray(szz, float), z.shape)
        s = np.stack([sxx, syy, sxy, szz], axis=1)
        if not np.all(np.isfinite(s)):
            raise ModelError("stresses must be finite", key=("stress",))
        self.zsig[z] = s[:, None, :]

    def initial_stress_k0(self, k0=None, surface: float | None = None) -> None:
        """Geostatic initial stresses: ``syy = -rho g (surface - y)`` at each zone centroid,
        ``sxx = szz = K0 syy``, ``sxy = 0``.

        Parameters
        ----------
        k0 : float, optional
            Coefficient of earth pressure at rest [-] (default: ``nu / (1 - nu)`` of each
            zone's material, the elastic value under lateral constraint).
        surface : float, optional
            Elevation of the free surface [m] (default: the highest gridpoint).

        Notes
        -----
        Each zone uses its own density over the whole depth (a homogeneous deposit); a layered
        deposit is brought to equilibrium by :meth:`settle` after this.
        """
        if k0 is not None and not (math.isfinite(k0) and k0 >= 0):
            raise ModelError(f"k0 must be >= 0, got {k0!r}", key=("k0",))
        top = float(self.gxy[:, 1].max()) if surface is None else float(surface)
        yc = self.gxy[self.zg, 1].mean(axis=1)
        rho = self.mprops[self.zmat, K.M_RHO]
        sv = -rho * self.gravity * np.maximum(top - yc, 0.0)
        if k0 is None:
            nu = np.array([self.materials[i].poisson for i in self.zmat])
            kk = nu / (1.0 - nu)
        else:
            kk = float(k0)
        self.set_stress(kk * sv, sv, 0.0, kk * sv)

    # ------------------------------------------------------------------ outputs
    def zone_stress(self) -> np.ndarray:
        """Zone-averaged stresses (nz, 4): sxx, syy, sxy, szz [Pa] (mean of the four triangles
        weighted by their areas within each overlay).

        Returns
        -------
        ndarray (nz, 4)
        """
        a2, _ = _tri_geometry(self.gxy, self.zg)
        w = a2.copy()
        w[:, :2] /= w[:, :2].sum(axis=1, keepdims=True)
        w[:, 2:] /= w[:, 2:].sum(axis=1, keepdims=True)
        return 0.5 * np.einsum("zt,ztk->zk", w, self.zsig)

    def zone_strain(self) -> np.ndarray:
        """Zone-averaged small strain (nz, 3): exx, eyy, exy (tensor shear) [-] of the
        displacement since the reference state, on the reference geometry.

        Returns
        -------
        ndarray (nz, 3)
        """
        a2, pts = _tri_geometry(self.gx0, self.zg)
        u = self.gdisp[self.zg[:, TRIANGLES]]  # (nz, 4, 3, 2)
        y = pts[..., 1]
        x = pts[..., 0]
        b = np.stack([y[..., 1] - y[..., 2], y[..., 2] - y[..., 0], y[..., 0] - y[..., 1]], -1)
        c = np.stack([x[..., 2] - x[..., 1], x[..., 0] - x[..., 2], x[..., 1] - x[..., 0]], -1)
        exx = (u[..., 0] * b).sum(-1) / a2
        eyy = (u[..., 1] * c).sum(-1) / a2
        exy = 0.5 * ((u[..., 0] * c).sum(-1) + (u[..., 1] * b).sum(-1)) / a2
        w = a2.copy()
        w[:, :2] /= w[:, :2].sum(axis=1, keepdims=True)
        w[:, 2:] /= w[:, 2:].sum(axis=1, keepdims=True)
        return 0.5 * np.stack([(w * exx).sum(1), (w * eyy).sum(1), (w * exy).sum(1)], axis=1)

    def plastic_state(self) -> np.ndarray:
        """Plastic state bits of each zone (nz,) int: ``ST_SHEAR_NOW`` (1), ``ST_TENSION_NOW``
        (2), ``ST_SHEAR_PAST`` (4), ``ST_TENSION_PAST`` (8) of
        :mod:`murus.continuum.kernels`.

        Returns
        -------
        ndarray (nz,) of int
        """
        return self.zstate & 15

    def centroids(self) -> np.ndarray:
        """Zone centroids (mean of the corners) (nz, 2) [m].

        Returns
        -------
        ndarray (nz, 2)
        """
        return self.gxy[self.zg].mean(axis=1)

    def energy(self) -> dict:
        """Energy terms [J per metre] since the reference state (:meth:`reset_reference`).

        Returns
        -------
        dict
            ``kinetic`` (``m v(t - dt/2) . v(t + dt/2) / 2`` over the free directions, at the
            time t of the stresses), ``gravity`` (``-sum m g . u(t)`` over the free
            directions), ``strain`` (elastic strain energy stored since the reference: the
            work of the stresses on the strain increments, ``(sigma_old + sigma_new) / 2 :
            de`` per triangle and step, minus the plastic work; for a linear elastic zone in
            small strain, exactly the change of ``sigma : C^-1 : sigma / 2``), ``plastic``
            (work dissipated by plastic flow), ``damping_work`` (work of the damping forces,
            negative), ``base_work`` (work of the fixed and base-driven gridpoints on the zones),
            ``external_work`` (applied forces), ``dashpot_work`` (quiet boundaries, negative)
            and ``error``: the balance ``kinetic - kinetic_0 + gravity + strain + plastic -
            (base + external + damping + dashpot)``, with ``kinetic_0`` the kinetic energy of
            the reference state. The works are those done up to the time t of the stresses
            (the force of a step times the mean of the half-step velocities around it; of the
            last step, only the half before t), the form in which central differences balance
            the energy of a linear system exactly.
        """
        free = self.gfix == 0
        m = self.gmass[:, None]
        ke = self._kinetic()
        g = np.array([0.0, -self.gravity])
        # displacement at the time of the stresses (one step behind the gridpoints)
        u = self.gdisp - self.gdt() * self.gvel
        pe = -float((m * u * g * free).sum())
        plastic = float(self.zwork[:, 0].sum())
        se = float(self.zwork[:, 1].sum()) - plastic
        out = {"kinetic": ke, "gravity": pe, "strain": se, "plastic": plastic,
               "damping_work": float(self.E[K.E_WDAMP] - self.E[K.E_TDAMP]),
               "base_work": float(self.E[K.E_WBASE] - self.E[K.E_TBASE]),
               "external_work": float(self.E[K.E_WEXT] - self.E[K.E_TEXT]),
               "dashpot_work": float(self.E[K.E_WDASH] - self.E[K.E_TDASH])}
        out["error"] = (ke - self.K0 + pe + se + out["plastic"]
                        - (out["base_work"] + out["external_work"] + out["damping_work"]
                           + out["dashpot_work"]))
        return out

    def _kinetic(self) -> float:
        """Kinetic energy at the time of the stresses, ``m v(t - dt/2) . v(t + dt/2) / 2``
        over the free directions (the leapfrog's conserved form)."""
        free = self.gfix == 0
        vm = self.gvel - self.gdt() * self.gacc
        return 0.5 * float((self.gmass[:, None] * self.gvel * vm * free).sum())

    def stored_strain_energy(self) -> float:
        """Elastic energy of the current stresses, ``sum sigma : C^-1 : sigma / 2`` over the
        triangles (each weighted by half its area) [J/m] (initial stresses included).

        Returns
        -------
        float
        """
        return self._strain_energy()

    def _strain_energy(self) -> float:
        a2, _ = _tri_geometry(self.gxy, self.zg)
        s = self.zsig
        Km = self.mprops[self.zmat, K.M_K][:, None]
        Gm = self.mprops[self.zmat, K.M_G][:, None]
        p = (s[..., 0] + s[..., 1] + s[..., 3]) / 3.0
        dev2 = ((s[..., 0] - p) ** 2 + (s[..., 1] - p) ** 2 + (s[..., 3] - p) ** 2
                + 2.0 * s[..., 2] ** 2)
        dens = 0.5 * (dev2 / (2.0 * Gm) + p * p / Km)
        return float((dens * 0.25 * a2).sum())

    def reset_reference(self) -> None:
        """Take the current state as the reference of displacements, strains and energies."""
        self.gdisp[:] = 0.0
        self.gx0[:] = self.gxy
        self.E[:] = 0.0
        self.zwork[:] = 0.0
        self.K0 = self._kinetic()

    # ------------------------------------------------------------------ run
    def settle(self, **kw):
        """Static equilibrium (:func:`murus.continuum.engine.settle`)."""
        from murus.continuum.engine import settle

        return settle(self, **kw)

    def run(self, duration: float, **kw):
        """Dynamic run (:func:`murus.continuum.engine.run`)."""
        from murus.continuum.engine import run

        return run(self, duration, **kw)

    def state_bytes(self) -> int:
        """Bytes of the state arrays that the kernels read or write (grid and zones).

        Returns
        -------
        int
        """
        return int(sum(getattr(self, f).nbytes for f in kd.STATE_ARRAYS))
