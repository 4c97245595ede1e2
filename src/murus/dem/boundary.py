"""Generic boundaries and boundary forces of disc assemblies in :mod:`murus.dem`.

- :class:`AbsorbingBoundary`: a Lysmer-Kuhlemeyer viscous boundary (Lysmer & Kuhlemeyer 1969)
  on the discs of the last layer of a granular assembly, as an ``external(model)`` hook of the
  engine (used by the backfill of :mod:`murus.retaining.backfill`, whose module docstring
  derives the wave speeds and the tributary lengths);
- :func:`wall_thrust`: the resultant of the contact forces of one group of bodies on another
  (the thrust of a backfill on the stones of a wall);
- :func:`contact_forces_from`: the contact force and moment of one body on each of a set of
  others.

Units: SI (m, kg, s, N, Pa).

References
----------
Lysmer, J. & Kuhlemeyer, R. L. (1969). Finite dynamic model for infinite media. Journal of the
Engineering Mechanics Division 95(EM4), 859-877.
"""

from __future__ import annotations

import numpy as np

from murus.dem.packing import PackingError

__all__ = ["AbsorbingBoundary", "wall_thrust", "contact_forces_from"]

#: Largest ``c dt_hook / m`` of the explicit dashpots of :class:`AbsorbingBoundary` (0.5: a
#: stable, non-oscillating explicit update of ``m dv/dt = -c v``, whose limit is 2).
DASHPOT_STABILITY = 0.5


class AbsorbingBoundary:
    """Lysmer-Kuhlemeyer viscous boundary on the discs of the last layer, as an
    ``external(model)`` hook: on each disc ``bodies[i]``, the static force ``static[i]``
    (Fx, Fy, M) [N, N m] plus ``-c_n (v_x - v_bx)`` and ``-c_t (v_y - v_by)`` [N], ``c_n = rho
    Vp L_i t``, ``c_t = rho Vs L_i t`` with ``L_i`` the tributary length [m] and ``t`` the
    thickness [m]; velocities relative to the base. ``dashpots=False`` applies only the static
    force (settling). The boundary is vertical, normal x (the backfill of
    :mod:`murus.retaining.backfill`, whose module docstring explains the set-up).

    Parameters
    ----------
    bodies : array_like of int
        The discs of the last layer.
    lengths : array_like of float
        Their tributary lengths along the boundary [m].
    static : array_like, shape (n, 3)
        Static force on each (Fx, Fy, M) [N, N, N m].
    rho : float
        Mass density of the medium [kg/m³].
    vp, vs : float
        P- and S-wave speeds [m/s].
    thickness : float
        Out-of-plane thickness [m].

    Raises
    ------
    PackingError
        A non-positive ``rho``, ``vp`` or ``vs``, arrays of different lengths, or a negative
        length.

    References
    ----------
    Lysmer & Kuhlemeyer (1969), module docstring.
    """

    def __init__(self, bodies, lengths, static, rho: float, vp: float, vs: float,
                 thickness: float = 1.0) -> None:
        self.bodies = np.asarray(bodies, np.int64)
        self.lengths = np.asarray(lengths, float)
        self.static = np.asarray(static, float).reshape(-1, 3)
        if not (rho > 0 and vp > 0 and vs > 0):
            raise PackingError(f"rho, Vp, Vs must be positive, got {rho!r}, {vp!r}, {vs!r}")
        if self.bodies.size != self.lengths.size or self.static.shape[0] != self.bodies.size:
            raise PackingError("bodies, lengths and static forces must have the same length")
        if np.any(self.lengths < 0):
            raise PackingError("tributary lengths must be >= 0")
        self.rho, self.vp, self.vs = float(rho), float(vp), float(vs)
        self.cn = self.rho * self.vp * self.lengths * thickness
        self.ct = self.rho * self.vs * self.lengths * thickness
        self.dashpots = True

    def forces(self, vel, vbase) -> np.ndarray:
        """Forces (n, 3) for disc velocities ``vel (n, 2)`` and base velocity ``(vbx, vby)``."""
        v = np.asarray(vel, float).reshape(-1, 2)
        out = self.static.copy()
        if self.dashpots:
            out[:, 0] -= self.cn * (v[:, 0] - vbase[0])
            out[:, 1] -= self.ct * (v[:, 1] - vbase[1])
        return out

    def interval(self, model) -> int:
        """Steps between hook calls for a stable explicit dashpot: ``c dt_hook / m <= 0.5``."""
        if self.bodies.size == 0 or model.dt is None:
            return 1
        cm = float(np.max(np.maximum(self.cn, self.ct) / model.bmass[self.bodies]))
        return max(1, int(DASHPOT_STABILITY / (cm * model.dt)))

    def __call__(self, model) -> None:
        if self.bodies.size == 0:
            return
        vb = (0.0, 0.0)
        if self.dashpots and model.dt is not None:
            vb = model.base_velocity(model.time - 0.5 * model.dt)[0]
        model.bext[self.bodies] = self.forces(model.bvel[self.bodies], vb)


def wall_thrust(model, stones, fill_bodies) -> tuple[float, float]:
    """Resultant of the contact forces of the bodies ``fill_bodies`` on the bodies ``stones``.

    Parameters
    ----------
    model : murus.dem.Model
        A model (built here if needed; contact forces of its last step).
    stones : array_like of int
        Bodies receiving the forces (the stones of a wall).
    fill_bodies : array_like of int
        Bodies exerting them (the discs of a backfill).

    Returns
    -------
    (float, float)
        ``(Fx, Fy)`` [N] (for a backfill behind a wall in the frame of
        :mod:`murus.retaining.geometry`, Fx < 0 pushes the wall out of the slope).
    """
    from murus.dem import kernels as K

    model.build()
    on = model.sid >= 0
    ba = model.sbody[model.pairs[:, 0]]
    bb = model.sbody[model.pairs[:, 1]]
    st = np.zeros(model.nbody, bool)
    st[np.asarray(stones)] = True
    fl = np.zeros(model.nbody, bool)
    fl[np.asarray(fill_bodies)] = True
    f = model.sf
    fx = fy = 0.0
    for sgn, a, b in ((1.0, ba, bb), (-1.0, bb, ba)):
        # force on shape b is Fn n + Fs t; on a the opposite: stones as b (sgn +1) or a (-1)
        sel = (fl[a] & st[b])[:, None] & on
        if sel.any():
            fn = f[..., K.F_FN][sel]
            fs = f[..., K.F_FS][sel]
            nx = f[..., K.F_NX][sel]
            ny = f[..., K.F_NY][sel]
            fx += sgn * float(np.sum(fn * nx - fs * ny))
            fy += sgn * float(np.sum(fn * ny + fs * nx))
    return fx, fy


def contact_forces_from(model, body_k, others) -> dict[int, np.ndarray]:
    """Contact force and moment on each body of ``others`` from the body ``body_k``.

    Parameters
    ----------
    model : murus.dem.Model
        A built model (contact forces of its last step).
    body_k : int
        The body exerting the forces.
    others : iterable of int
        The bodies of interest.

    Returns
    -------
    dict
        ``{body: array (Fx, Fy, M)}`` [N, N, N m] for each body of ``others`` in contact with
        ``body_k``; the moment about the body's centre.
    """
    from murus.dem import kernels as K

    on = model.sid >= 0
    ba = model.sbody[model.pairs[:, 0]]
    bb = model.sbody[model.pairs[:, 1]]
    oth = set(int(o) for o in others)
    out: dict[int, np.ndarray] = {}
    f = model.sf
    for k in range(model.pairs.shape[0]):
        a, b = int(ba[k]), int(bb[k])
        if body_k not in (a, b):
            continue
        o = b if a == body_k else a
        if o not in oth:
            continue
        sgn = 1.0 if o == b else -1.0
        for s in range(2):
            if not on[k, s]:
                continue
            fn, fs = f[k, s, K.F_FN], f[k, s, K.F_FS]
            nx, ny = f[k, s, K.F_NX], f[k, s, K.F_NY]
            fx = sgn * (fn * nx - fs * ny)
            fy = sgn * (fn * ny + fs * nx)
            px = f[k, s, K.F_PX] - model.bpos[o, 0]
            py = f[k, s, K.F_PY] - model.bpos[o, 1]
            acc = out.setdefault(o, np.zeros(3))
            acc += (fx, fy, px * fy - py * fx)
    return out
