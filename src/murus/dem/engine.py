"""Run loop of the 2D distinct-element engine: time step, settling, dynamic runs, monitors,
stop conditions, energy balance.

Time step (UDEC "automatic time step"): ``dt = safety * min_b min(sqrt(m_b / K_b),
sqrt(I_b / Kr_b))`` with ``K_b`` the sum of the contact stiffnesses ``max(kn, ks) A`` of the
body's current sub-contacts (at least one full face: ``max(kn, ks) t L_max``) and ``Kr_b`` the
sum of ``K A r²`` (at least ``K_floor R_b²``); ``safety`` = 0.2 by default, about 1/7 of the
central-difference limit ``sqrt(2 m / K)`` of a body between springs. A user ``dt`` above it is an
error.

Settling (static solution): Cundall's local non-viscous damping ``F_d = -alpha |F| sign(v)``
(alpha = 0.7) until the unbalanced-force ratio, defined as the largest unbalanced force of a
dynamic body (``|F + m g|`` with its moment divided by the body radius) over the mean contact
force ``sqrt(Fn² + Fs²)`` of the active sub-contacts, falls below ``tol``. Settling does not
advance the model time; it ends with zero velocities and (by default) takes the settled state as
the reference of displacements and energies.

Dynamic runs: mass-proportional damping ``alpha_M = 2 xi omega = 4 pi xi f`` (fraction ``xi`` of
critical at frequency ``f``, Savalle et al. (2022), §2) on the velocity relative to the base
motion, so that it does not brake a rigid-body collapse; optional local damping on the same
relative velocity.

Energy balance (all terms in J, from the reference state): kinetic (half-step velocities),
gravitational ``-m g . x``, elastic ``0.5 Fn²/(kn A) + 0.5 Fs²/(ks A) + 0.5 Mr²/kr``; work of the
kinematic base (``-F_on_base . v_base dt``), work of the damping forces, frictional (slip) and
rolling dissipation, energy released by opening/breaking sub-contacts, work of the external
forces. ``error = (kinetic + gravity + elastic) - E0 - (base + external + damping - slip -
rolling - breaking)``.

External forces: ``model.bext (nbody, 3)`` holds a force (Fx, Fy) [N] and a moment about the
centroid [N m] applied to each dynamic body (ignored on kinematic bodies), zero by default.
It stays as set between calls; ``settle`` and ``run`` also accept ``external``, a callable
``external(model)`` that updates ``model.bext`` in place, called before the first step and then
every ``external_every`` steps (the force is constant between calls: an explicit load history
sampled at that interval). The kernels see it as a plain array.

Interpenetration: a settle or a run stops (settle: not converged; run: status
``"interpenetration"``) when a dynamic body moves by more than :data:`OVERLAP_LIMIT` (10 %) of
its smallest width in one step (it could tunnel through another body between two contact
detections), or when two bodies overlap by more than :data:`OVERLAP_LIMIT` of the
thickness, along the contact normal, of the thinner of the two (:func:`overlap_fraction`: a
block sinking into its base, of the block's height; a disc, of its diameter; kinematic bodies,
the boundaries of the model, count as infinitely thick); the overlap is the
penetration ``-gap`` of an active sub-contact, read from the contact arrays after each chunk of
steps. An overlap that deep means a contact stiffness far too low for the loads (e.g. ``kn =
1e-3`` Pa/m lets a block sink through its base): the result would not be a result. (The
thickness along the normal, rather than a body's smallest width, so that a thin sliver pushed
along its length, such as the 0.2 mm remainder course of a wall built course by course, does
not stop a sound run.)

Checkpoints: :meth:`Model.save` / :meth:`Model.load`. Runs are deterministic: a run stopped by
``max_steps`` or Ctrl-C (caught between chunks of steps, the state is always consistent), saved,
loaded and resumed reproduces the uninterrupted run bit for bit.
"""

from __future__ import annotations

import math
import signal
import threading
import time as _time
from collections.abc import Callable
from dataclasses import dataclass

import numba
import numpy as np

from murus import threads as _threads
from murus.dem import _kdata as kd
from murus.dem import kernels as K
from murus.results import Result, RunHistory

__all__ = ["OVERLAP_LIMIT", "RunResult", "SettleResult", "body_sizes", "overlap_fraction",
           "Probe", "body_probe", "relative_probe", "tilt_probe", "stop_when", "stable_dt",
           "settle", "run", "energy", "probe_from_spec"]


#: Largest overlap of two bodies, as a fraction of the thickness along the contact normal of
#: the thinner one, beyond which :func:`settle` and :func:`run` stop (module doc).
OVERLAP_LIMIT = 0.1

#: Most steps of one call of the kernel (its inputs hold 64 bytes per step).
_MAX_CHUNK = 1_000_000

#: Run statuses that are a result: the run reached its end or its stop condition.
OK_STATUSES = ("completed", "stopped")


# ---------------------------------------------------------------------- probes
@dataclass(frozen=True)
class Probe:
    """A scalar monitor of the model state, rebuilt from ``spec`` after a checkpoint.

    Calling it on a model returns the value (a float). Quantities ``q`` of a body and their
    units: ``x``, ``y`` (centroid position) [m], ``angle`` [rad], ``vx``, ``vy`` [m/s],
    ``omega`` [rad/s], ``ux``, ``uy`` (displacement since the reference state) [m], ``rot``
    (rotation since the reference state) [rad].

    Attributes
    ----------
    spec : tuple
        The kind and its arguments: ``("body", b, q)``: quantity ``q`` of body ``b``;
        ``("relative", b, ref, q)``: the same of body ``b`` minus that of body ``ref`` (``q``
        in ux, uy, rot); ``("tilt",)``: gravity tilt [deg]; ``("time",)``: model time [s];
        of blocks coupled with zones (:class:`murus.continuum.CoupledModel`), ``("gp", g,
        q)`` and ``("zone", z, q)``: a gridpoint's or a zone's quantity
        (:func:`murus.continuum.engine.monitor_value`).
    """

    spec: tuple

    def __call__(self, m) -> float:
        kind = self.spec[0]
        if kind == "body":
            _, b, q = self.spec
            return float(_body_q(m, b, q))
        if kind == "relative":
            _, b, r, q = self.spec
            return float(_body_q(m, b, q) - _body_q(m, r, q))
        if kind == "tilt":
            return math.degrees(float(m.tilt_angle(m.time)))
        if kind == "time":
            return float(m.time)
        if kind in ("gp", "zone"):
            from murus.continuum.engine import monitor_value

            return monitor_value(_zones_of(m), self.spec)
        raise ValueError(f"unknown probe kind {kind!r}")


def _zones_of(m):
    cp = m.__dict__.get("coupled")
    if cp is None:
        raise ValueError("a gridpoint or zone probe needs blocks coupled with zones "
                         "(murus.continuum.CoupledModel)")
    return cp.zones


def _body_q(m, b, q):
    if q == "x":
        return m.bpos[b, 0]
    if q == "y":
        return m.bpos[b, 1]
    if q == "angle":
        return m.bang[b]
    if q == "vx":
        return m.bvel[b, 0]
    if q == "vy":
        return m.bvel[b, 1]
    if q == "omega":
        return m.bomg[b]
    if q == "ux":
        return m.bpos[b, 0] - m.bref[b, 0]
    if q == "uy":
        return m.bpos[b, 1] - m.bref[b, 1]
    if q == "rot":
        return m.bang[b] - m.bref[b, 2]
    raise ValueError(f"unknown body quantity {q!r}")


def body_probe(body: int, q: str) -> Probe:
    """Position, angle, velocity or displacement ``q`` of one body (see :class:`Probe`).

    Parameters
    ----------
    body : int
        Index of the body.
    q : str
        ``"x"``, ``"y"`` [m], ``"angle"`` [rad], ``"vx"``, ``"vy"`` [m/s], ``"omega"``
        [rad/s], or since the reference state ``"ux"``, ``"uy"`` [m], ``"rot"`` [rad].

    Returns
    -------
    Probe
    """
    _body_q_check(q)
    return Probe(("body", int(body), q))


def relative_probe(body: int, ref: int, q: str = "ux") -> Probe:
    """Displacement of ``body`` relative to ``ref`` (e.g. d_top: top block relative to the
    base).

    Parameters
    ----------
    body : int
        Index of the body monitored.
    ref : int
        Index of the reference body.
    q : str
        ``"ux"``, ``"uy"`` [m] or ``"rot"`` [rad] (any quantity of :func:`body_probe` is
        accepted: the difference of the two bodies' values).

    Returns
    -------
    Probe
    """
    _body_q_check(q)
    return Probe(("relative", int(body), int(ref), q))


def tilt_probe() -> Probe:
    """The gravity tilt of the model (tilting table) [deg].

    Returns
    -------
    Probe
    """
    return Probe(("tilt",))


def _body_q_check(q):
    if q not in ("x", "y", "angle", "vx", "vy", "omega", "ux", "uy", "rot"):
        raise ValueError(f"unknown body quantity {q!r}")


def probe_from_spec(spec) -> Probe:
    return Probe(tuple(spec))


def stop_when(probe: Callable, op: str, value: float) -> Callable:
    """A stop condition ``probe(model) op value`` for :func:`run` (its ``stop``).

    Parameters
    ----------
    probe : callable
        A :class:`Probe` or any ``callable(model) -> float``.
    op : str
        ``">"``, ``"<"`` or ``"abs>"`` (``|probe(model)| > value``).
    value : float
        The threshold, in the units of the probe (e.g. [m] for a displacement).

    Returns
    -------
    callable
        ``cond(model) -> bool``, named after the condition (the name appears in the run's
        message when it stops the run).
    """
    if op not in (">", "<", "abs>"):
        raise ValueError(f"op must be '>', '<' or 'abs>', got {op!r}")

    def cond(m):
        x = probe(m)
        if op == ">":
            return x > value
        if op == "<":
            return x < value
        return abs(x) > value

    cond.__name__ = f"stop_when({getattr(probe, 'spec', probe)} {op} {value:g})"
    return cond


# ---------------------------------------------------------------------- results
@dataclass
class SettleResult(Result):
    """Outcome of :func:`settle` (the static solution under gravity).

    ``status``: ``"converged"`` or ``"not converged"``; ``success``: converged
    (:class:`murus.results.Result`).

    Attributes
    ----------
    converged : bool
        Whether the unbalanced-force ratio fell below the tolerance.
    steps : int
        Steps taken [-].
    ratio : float
        Final unbalanced-force ratio [-]: the largest unbalanced force of a dynamic body over
        the mean contact force (module doc).
    message : str
        One-line account of the settling.
    overlap : float
        Largest overlap of two bodies at the end [-], as a fraction of the thinner one's
        thickness along the contact normal (:func:`overlap_fraction`).
    interrupted : bool
        Whether Ctrl-C stopped the settling (``status`` ``"interrupted"``).
    """

    converged: bool
    steps: int
    ratio: float  # final unbalanced-force ratio
    message: str = ""
    overlap: float = 0.0
    interrupted: bool = False  # stopped by Ctrl-C

    @property
    def status(self) -> str:
        return ("converged" if self.converged else "interrupted" if self.interrupted
                else "not converged")

    @property
    def success(self) -> bool:
        return bool(self.converged)


@dataclass
class RunResult(RunHistory):
    """History of a dynamic run of :func:`run` (:class:`murus.results.RunHistory`).

    ``result[name]`` is ``values[name]``; :attr:`ok` (or :attr:`success`,
    :class:`murus.results.Result`) is true for the statuses ``completed`` and ``stopped``.

    Attributes
    ----------
    t : ndarray
        Sample times [s] (model time, the whole history of the model).
    values : dict
        name -> ndarray sampled at ``t``: the probes (in their units, :class:`Probe`) and the
        energy terms ``energy.*`` [J] of :func:`energy` (nan before a probe was added).
    status : str
        ``completed`` | ``stopped`` (a stop condition) | ``interrupted`` | ``max_steps`` |
        ``paused`` (``pause_every``) |
        ``unstable`` (non-finite positions) | ``interpenetration`` (two bodies overlap by more
        than :data:`OVERLAP_LIMIT` of the thinner one's thickness).
    message : str
        One-line account of how the run ended (empty when completed).
    steps : int
        Steps taken by this call [-].
    wall : float
        Wall-clock time of this call [s].
    contact_updates : int
        Contact detections done by this call [-].
    dt : float
        Time step [s].
    """

    OK = OK_STATUSES

    contact_updates: int = 0


# ---------------------------------------------------------------------- time step
def detect(m) -> None:
    """Contact detection and forces at the current positions without moving (dt = 0)."""
    m.build()
    shapes = kd.pack(kd.Shapes, m)
    K.world_vertices(m.bpos, m.bang, shapes)
    n = m.pairs.shape[0]
    dis = np.zeros((n, K.NW))
    nact = np.zeros(n, np.int64)
    # the parallel loop (on any number of threads the same numbers): the one the steps use, so
    # that a fresh process compiles one copy of the contact loop, not two (minutes, cold)
    K._contacts_parallel(kd.pack(kd.Contacts, m), dis, shapes, kd.pack(kd.Bodies, m), m.jprops,
                         0.0, m.thickness, m.P[K.P_REACH], nact)
    m.snapshot()


def stable_dt(m) -> float:
    """Stable time step [s] from the current masses and contact stiffnesses (module doc); of
    blocks coupled with zones, the smallest of the blocks', the zones' and the interface's
    (:meth:`murus.continuum.coupled.CoupledModel.stable_dt`)."""
    cp = m.__dict__.get("coupled")
    if cp is not None:
        return cp.stable_dt()
    return blocks_stable_dt(m)


def blocks_stable_dt(m) -> float:
    """Stable time step [s] of the blocks alone (:func:`stable_dt`)."""
    detect(m)
    nb = m.nbody
    kmax = float(np.max(np.maximum(m.jprops[:, K.J_KN], m.jprops[:, K.J_KS])))
    Kt = np.zeros(nb)
    Kr = np.zeros(nb)
    on = m.sid >= 0
    if on.any():
        kk = np.maximum(m.sf[..., K.F_KNA], m.sf[..., K.F_KSA])[on]
        px = m.sf[..., K.F_PX][on]
        py = m.sf[..., K.F_PY][on]
        for col in (0, 1):
            bodies = np.repeat(m.sbody[m.pairs[:, col]][:, None], 2, 1)[on]
            np.add.at(Kt, bodies, kk)
            r2 = (px - m.bpos[bodies, 0]) ** 2 + (py - m.bpos[bodies, 1]) ** 2
            np.add.at(Kr, bodies, kk * r2 + m.sf[..., K.F_KRA][on])
    floor = kmax * m.thickness * m.blen
    Kt = np.maximum(Kt, floor)
    Kr = np.maximum(Kr, floor * m.brad**2)
    dyn = m.bkin == 0
    if not dyn.any():
        raise ValueError("the model has no dynamic body")
    dtt = np.sqrt(m.bmass[dyn] / Kt[dyn])
    dtr = np.sqrt(m.binert[dyn] / Kr[dyn])
    zeta = float(np.max(m.jprops[:, K.J_CDAMP]))
    if zeta > 0.0:
        # contact damping (Joint.contact_damping): a dashpot of ratio zeta lowers the stable
        # step of central differences from 2/omega to (2/omega)(sqrt(1 + zeta^2) - zeta)
        # (Belytschko, Liu & Moran 2000, Nonlinear Finite Elements, sec. 6.2)
        return float(m.safety * min(dtt.min(), dtr.min()) * (math.sqrt(1.0 + zeta * zeta) - zeta))
    return float(m.safety * min(dtt.min(), dtr.min()))


def _set_dt(m, dt) -> None:
    m.build()
    if m.dt is not None and (dt is None or dt == m.dt):
        return  # a time step once accepted stays (it is not re-checked after settling)
    dts = stable_dt(m)
    if dt is None:
        dt = dts
    elif not (dt > 0 and math.isfinite(dt)):
        raise ValueError(f"dt must be positive, got {dt!r}")
    elif dt > dts * (1 + 1e-12):
        raise ValueError(f"dt={dt:g} s exceeds the stable time step {dts:g} s "
                         f"(safety {m.safety:g}); lower it or leave dt=None")
    if m.dt is not None and dt != m.dt:
        m.time_offset = m.time
        m.step_offset = int(m.C[K.C_STEP])
    m.dt = float(dt)
    m.P[K.P_DT] = m.dt


# ---------------------------------------------------------------------- overlaps
def _outlines(m) -> np.ndarray:
    """Each body's outline in its own frame (centroid, angle 0) as points with a radius,
    padded to one array ``(nbody, k, 3)`` of (x, y, r) [m]: the outer vertices of its polygons
    (r = 0) and the centres of its discs (r = the radius), so that its extent along a unit
    direction n is ``max(p.n + r) - min(p.n - r)``, exactly. Cached per model."""
    cached = m.__dict__.get("_outlines")
    if cached is not None and cached.shape[0] == m.nbody:
        return cached
    pts = [[] for _ in range(m.nbody)]
    for s, v in zip(m.poly_shape, m._outer, strict=True):
        v = np.asarray(v, float)
        pts[m.sbody[s]].append(np.column_stack([v, np.zeros(len(v))]))
    for s in m.disc_shape:
        c = m.lv[m.svs[s]]
        pts[m.sbody[s]].append(np.array([[c[0], c[1], m.srad[s]]]))
    pts = [np.concatenate(p) if p else np.zeros((1, 3)) for p in pts]
    k = max(len(p) for p in pts)
    out = np.array([np.concatenate([p, np.repeat(p[:1], k - len(p), axis=0)]) for p in pts])
    m.__dict__["_outlines"] = out
    return out


def _proj_extent(pts: np.ndarray, lx, ly) -> np.ndarray:
    """Extent of outlines ``pts (..., k, 3)`` along the directions (lx, ly) (broadcast)."""
    p = pts[..., 0] * lx + pts[..., 1] * ly
    return (p + pts[..., 2]).max(axis=-1) - (p - pts[..., 2]).min(axis=-1)


def body_sizes(m) -> np.ndarray:
    """Smallest width across [m] of each body: its smallest extent over the normals of its
    polygon edges and 32 directions (exact for a convex polygon and a disc, within 0.5 % for a
    clump): a lower bound of the thicknesses that :func:`overlap_fraction` compares a
    penetration with. Cached per model."""
    m.build()
    cached = m.__dict__.get("_body_sizes")
    if cached is not None and cached.shape[0] == m.nbody:
        return cached
    pts = _outlines(m)
    ang = np.linspace(0.0, math.pi, 32, endpoint=False)
    dirs = [np.column_stack([np.cos(ang), np.sin(ang)])]
    for v in m._outer:
        e = np.roll(v, -1, axis=0) - v
        ln = np.hypot(e[:, 0], e[:, 1])
        dirs.append(np.column_stack([-e[ln > 0, 1], e[ln > 0, 0]]) / ln[ln > 0, None])
    dirs = np.concatenate(dirs)
    size = _proj_extent(pts[:, None, :, :], dirs[None, :, 0, None],
                        dirs[None, :, 1, None]).min(axis=1)
    m.__dict__["_body_sizes"] = size
    return size


def _extent(m, body: np.ndarray, nx: np.ndarray, ny: np.ndarray) -> np.ndarray:
    """Extent [m] of each ``body`` along the world direction (nx, ny) (its thickness there);
    infinite for a kinematic body (a boundary of the model)."""
    c, s = np.cos(m.bang[body]), np.sin(m.bang[body])
    lx, ly = nx * c + ny * s, -nx * s + ny * c  # the direction in the body frame
    ext = _proj_extent(_outlines(m)[body], lx[:, None], ly[:, None])
    return np.where(m.bkin[body] == 0, ext, np.inf)


def overlap_fraction(m, exclude=None) -> tuple[float, int, int, float]:
    """Largest overlap of two bodies in the current contact arrays: ``(fraction, a, b,
    depth)`` with ``depth`` [m] the penetration of an active sub-contact between the bodies a
    and b and ``fraction`` = depth / the thickness, along the contact normal, of the thinner
    of the two [-] (a block sinking into its base: the block's height; a disc: its
    diameter; a kinematic body counts as infinitely thick); ``(0, -1, -1, 0)`` when nothing
    overlaps. ``exclude``: bodies whose contacts
    are left out. Cheap: NumPy over the contact arrays, the thicknesses only for the
    sub-contacts deeper than the limit could allow (:func:`body_sizes`)."""
    m.build()
    on = m.sid >= 0
    if exclude is not None and len(exclude):
        ex = np.isin(m.sbody[m.pairs], np.asarray(exclude)).any(axis=1)
        on = on & ~ex[:, None]
    if not on.any():
        return 0.0, -1, -1, 0.0
    depth = np.where(on, -m.sf[..., K.F_GAP], 0.0)
    size = body_sizes(m)
    ba = np.repeat(m.sbody[m.pairs[:, 0]][:, None], depth.shape[1], axis=1)
    bb = np.repeat(m.sbody[m.pairs[:, 1]][:, None], depth.shape[1], axis=1)
    # the fraction is at most depth / (smallest width): only those above the best bound count
    bound = depth / np.minimum(size[ba], size[bb])
    cand = depth > 0
    if not cand.any():
        return 0.0, -1, -1, 0.0
    depth, ba, bb, bound = depth[cand], ba[cand], bb[cand], bound[cand]
    nx, ny = m.sf[..., K.F_NX][cand], m.sf[..., K.F_NY][cand]

    def exact(sel):
        ext = np.minimum(_extent(m, ba[sel], nx[sel], ny[sel]),
                         _extent(m, bb[sel], nx[sel], ny[sel]))
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(ext > 0, depth[sel] / ext, np.inf)  # (depth / inf = 0)

    # the exact fraction of the sub-contact of largest bound, then of every sub-contact whose
    # bound reaches it (the others cannot exceed it)
    i0 = int(np.argmax(bound))
    f0 = float(exact(np.array([i0]))[0])
    # (that sub-contact itself always: its exact fraction may exceed its bound by rounding, or
    # be inf for a zero extent, and then no bound reaches it)
    sel = np.union1d(np.nonzero(bound >= f0)[0], [i0])
    frac = exact(sel)
    k = int(sel[int(np.argmax(frac))])
    return float(frac.max()), int(ba[k]), int(bb[k]), float(depth[k])


def _overlap_beyond(m, limit: float):
    """``overlap_fraction(m)`` when it exceeds ``limit``, else None; a quick bound first (no
    slot, active or not, deeper than ``limit`` times the thinnest body) keeps the check to a
    few microseconds when nothing is near the limit."""
    if m.sf.size == 0:
        return None
    size = body_sizes(m)[m.bkin == 0]
    if size.size == 0 or not -float(m.sf[..., K.F_GAP].min()) > 0.99 * limit * float(size.min()):
        return None
    hit = overlap_fraction(m)
    return hit if hit[0] > limit else None


def _penetration(m, limit: float) -> str | None:
    """The one-line reason to stop, or None: two bodies overlap by more than ``limit`` of the
    thinner one's thickness (:func:`overlap_fraction`), or a dynamic body moves by more than
    ``limit`` of its smallest width in one step (it could pass through another body between
    two contact detections: a time step far too long, from a contact stiffness far too low)."""
    hit = _overlap_beyond(m, limit)
    if hit is not None:
        return _overlap_message(m, *hit, limit)
    dyn = np.nonzero(m.bkin == 0)[0]
    if dyn.size == 0 or m.dt is None:
        return None
    move = (np.hypot(m.bvel[dyn, 0], m.bvel[dyn, 1]) + np.abs(m.bomg[dyn]) * m.brad[dyn]) * m.dt
    frac = move / body_sizes(m)[dyn]
    k = int(np.argmax(frac))
    if not frac[k] > limit:
        return None
    return (f"body {int(dyn[k])} moves {move[k]:.3g} m in one time step of {m.dt:.3g} s, "
            f"{100 * frac[k]:.3g} % of its smallest width (limit {100 * limit:g} %): it can "
            "pass through other bodies (a contact stiffness far too low gives a time step "
            "far too long)")


def _overlap_message(m, frac, a, b, depth, limit) -> str:
    return (f"bodies {a} and {b} interpenetrate by {depth:.3g} m, {100 * frac:.3g} % of the "
            f"thinner one's thickness along the contact normal (limit {100 * limit:g} %): the "
            "contact stiffness kn is too low for the loads")


# ---------------------------------------------------------------------- energy
def energy(m) -> dict:
    m.build()
    dyn = m.bkin == 0
    sn = m.bsnap  # state at the last force evaluation, consistent with the contact forces
    ke = 0.5 * float(np.sum(m.bmass[dyn] * (sn[dyn, 3:5] ** 2).sum(1))
                     + np.sum(m.binert[dyn] * sn[dyn, 5] ** 2))
    pe = m._potential()
    on = m.sid >= 0
    f = m.sf[on]
    el = 0.0
    if f.size:
        with np.errstate(divide="ignore", invalid="ignore"):
            el = float(np.sum(np.where(f[:, K.F_KNA] > 0, 0.5 * f[:, K.F_FN] ** 2 / f[:, K.F_KNA],
                                       0.0))
                       + np.sum(np.where(f[:, K.F_KSA] > 0,
                                         0.5 * f[:, K.F_FS] ** 2 / f[:, K.F_KSA], 0.0))
                       + np.sum(np.where(f[:, K.F_KRA] > 0,
                                         0.5 * f[:, K.F_MR] ** 2 / f[:, K.F_KRA], 0.0)))
    E = m.E
    out = {"kinetic": ke, "gravity": pe, "elastic": el, "base_work": float(E[K.E_WBASE]),
           "damping_work": float(E[K.E_WDAMP]), "slip": float(E[K.E_DSLIP]),
           "rolling": float(E[K.E_DROLL]), "breaking": float(E[K.E_DBREAK]),
           "external_work": float(E[K.E_WEXT]), "tilt_work": float(E[K.E_WTILT])}
    out["error"] = (ke + pe + el - m.E0 - (out["base_work"] + out["external_work"]
                                           + out["tilt_work"]
                                           + out["damping_work"] - out["slip"]
                                           - out["rolling"] - out["breaking"]))
    if E[K.E_DDASH] != 0.0:  # contact damping (Joint.contact_damping): only when present
        out["contact_damping"] = float(E[K.E_DDASH])
        out["error"] += out["contact_damping"]
    cp = m.__dict__.get("coupled")
    if cp is not None:  # blocks coupled with zones: one balance (CoupledModel.energy)
        z = cp.energy_terms(m.gravity_vector(np.array([m.time]))[0])
        out["error"] += z.pop("zones_error")
        out.update(z)
    return out


# ---------------------------------------------------------------------- stepping
def _chunk(m, n: int, moving: bool) -> None:
    s0 = int(m.C[K.C_STEP]) - m.step_offset
    ts = m.time_offset + (s0 + np.arange(n)) * m.dt
    if moving:
        vfull = m.base_velocity(ts)
        vhalf = m.base_velocity(ts + 0.5 * m.dt)
    else:
        vfull = np.zeros((n, 2))
        vhalf = vfull
    grav = m.gravity_vector(ts if moving else np.full(n, m.time))
    gdot = m.gravity_rate(ts) if moving else np.zeros((n, 2))
    # thread count per part of the chunk (murus.threads); few pairs: one thread (the kernels'
    # docstring of run_chunk); the results do not depend on the split nor on the count
    nth = numba.get_num_threads()
    gov = getattr(m, "_threads", None)
    cp = m.__dict__.get("coupled")
    if m.pairs.shape[0] < m.P[K.P_PARMIN] and cp is None:
        gov, nth1 = None, 1
    else:
        nth1 = nth
    bodies = kd.pack(kd.Bodies, m)
    shapes = kd.pack(kd.Shapes, m)
    joints = kd.pack(kd.Joints, m)
    zdr = None if cp is None else cp.zone_drive(ts, moving, vfull, grav, gdot)
    s = 0
    try:
        while s < n:
            k, th = gov.next(n - s) if gov is not None else (n - s, nth1)
            numba.set_num_threads(th)
            t0 = _time.perf_counter()
            drive = kd.Drive(vfull[s:s + k], vhalf[s:s + k], grav[s:s + k], gdot[s:s + k])
            if cp is not None:
                cp.step(k, drive, None if zdr is None else
                        kd.Drive(*(a[s:s + k] for a in zdr)))
            else:
                out = K.run_chunk(k, m.P, m.E, m.C, m.S, drive, bodies, shapes, joints,
                                  kd.pack(kd.Contacts, m))
                for name, a in zip(kd.Contacts._fields, out, strict=True):
                    setattr(m, name, a)
            if gov is not None:
                gov.record(th, k, _time.perf_counter() - t0)
            s += k
    finally:
        numba.set_num_threads(nth)
    m.snap_time = m.time - m.dt


def _own_handler(h) -> bool:
    """Whether the SIGINT handler ``h`` is a caller's (a Python function other than the
    default one; SIG_IGN and SIG_DFL are not functions)."""
    return callable(h) and h is not signal.default_int_handler


class _SigInt:
    """Turn Ctrl-C into a flag checked between chunks (main thread only), unless a caller has
    set a SIGINT handler of its own (a study that stops as a whole, its workers): then this
    leaves it alone and Ctrl-C does what the caller decided."""

    def __init__(self):
        self.hit = False
        self.old = None

    def __enter__(self):
        if (threading.current_thread() is threading.main_thread()
                and not _own_handler(signal.getsignal(signal.SIGINT))):
            self.old = signal.signal(signal.SIGINT, self._handler)
        return self

    def _handler(self, signum, frame):
        self.hit = True

    def __exit__(self, *exc):
        if self.old is not None:
            signal.signal(signal.SIGINT, self.old)
        return False


def unbalanced_ratio(m) -> float:
    cp = m.__dict__.get("coupled")
    if cp is not None:
        return cp.unbalanced_ratio()
    mean = m.S[K.S_MEANF]
    if mean <= 0.0:
        return math.inf if m.S[K.S_UNBAL] > 0 else 0.0
    return float(m.S[K.S_UNBAL] / mean)


def settle(m, tol: float = 1e-5, alpha: float = 0.7, max_steps: int = 200_000,
           check_every: int = 100, dt: float | None = None, reset: bool = True,
           external: Callable | None = None, threads: int | None = None,
           max_overlap: float | None = OVERLAP_LIMIT) -> SettleResult:
    """Static solution under gravity (at the current tilt) and the external forces
    ``model.bext`` with local damping ``alpha``: step until the unbalanced-force ratio is below
    ``tol`` (module doc). ``external(model)``, if given, updates ``model.bext`` every
    ``check_every`` steps. The base and the ``"prescribed"`` bodies do not move and the model
    time does not advance. Settling stops, not converged, when two bodies overlap by more than
    ``max_overlap`` (fraction of the thinner one's thickness along the contact normal,
    :func:`overlap_fraction`; None: no check). ``threads``: numba threads (default: chosen per
    chunk of steps by :mod:`murus.threads` from the machine's load)."""
    if not (0 <= alpha < 1):
        raise ValueError(f"alpha must be in [0, 1), got {alpha!r}")
    _set_dt(m, dt)
    m.P[K.P_ALOCAL] = alpha
    m.P[K.P_AMASS] = 0.0
    done = 0
    ratio = math.inf
    converged = False
    presc = m.bpresc.copy()
    m.bpresc[:] = 0.0
    m._threads = _threads.Governor.for_run(threads)
    over = None
    cp = m.__dict__.get("coupled")
    if cp is not None:
        cp.set_damping(alpha, 0.0, 0.0)
    try:
        with _SigInt() as sig:
            while done < max_steps and not sig.hit:
                n = min(check_every, max_steps - done)
                if external is not None:
                    external(m)
                _chunk(m, n, moving=False)
                m.step_offset += n  # settling does not advance the model time
                done += n
                ratio = unbalanced_ratio(m)
                if not np.all(np.isfinite(m.bpos)):
                    over = "non-finite positions (lower dt)"
                    break
                if cp is not None:
                    over = cp.after_chunk()
                    if over is not None:
                        break
                over = None if max_overlap is None else _penetration(m, max_overlap)
                if over is not None:
                    break
                if ratio < tol:
                    converged = True
                    break
    finally:
        m._threads = None
        m.bpresc[:] = presc
    m.bvel[:] = 0.0
    m.bomg[:] = 0.0
    if cp is not None:
        cp.set_damping(0.0, 0.0, 0.0)
        cp.at_rest()
    detect(m)
    m.snapshot()
    if reset:
        m.reset_reference()
    hit = bool(sig.hit) and not converged
    msg = (f"settled in {done} steps, ratio {ratio:.2e}" if converged
           else f"interrupted (Ctrl-C) after {done} steps, ratio {ratio:.2e}" if hit
           else f"not settled after {done} steps: {over}" if over is not None
           else f"not settled after {done} steps: no contact carries the load (the blocks "
           "fall freely, or passed through each other: a contact stiffness far too low?)"
           if ratio == math.inf
           else f"not settled after {done} steps, ratio {ratio:.2e} > {tol:g}")
    return SettleResult(converged, done, ratio, msg, overlap_fraction(m)[0], hit)


def run(m, duration: float | None = None, *, t_end: float | None = None,
        dt: float | None = None, xi: float = 0.0, freq: float | None = None,
        local_damping: float = 0.0, probes: dict | None = None, every: int | None = None,
        sample_dt: float = 0.01, stop=None, max_steps: int | None = None,
        progress: bool = False, external: Callable | None = None,
        external_every: int | None = None, damping_frame: str = "base",
        threads: int | None = None,
        max_overlap: float | None = OVERLAP_LIMIT,
        pause_every: int | None = None) -> RunResult:
    """Dynamic run up to ``t_end`` (or ``duration`` from now) [s].

    xi, freq : mass-proportional damping, fraction of critical at frequency [Hz];

    local_damping : Cundall local damping coefficient (0: none);

    damping_frame : the velocities that both dampings act on: ``"base"`` (default) relative to
        the base motion, so that damping does not brake a body that moves with the ground nor
        a collapse; ``"absolute"`` the velocities in the fixed frame, as UDEC's Rayleigh
        damping of a model shaken by a velocity boundary (it then also resists the rigid
        motion of the whole model with the base);

    probes : dict name -> :class:`Probe` or callable(model) -> float, sampled every ``every``
        steps (default ``sample_dt`` [s]); the histories are kept in ``model.history`` (they
        survive a checkpoint);

    stop : callable(model) -> bool (or a list), checked at each sample;

    max_steps : stop after that many steps of this call (status ``max_steps``);

    progress : False (nothing), True (a :func:`murus.progress.progress` block: a bar in a
        terminal, a line every 10 s on stderr otherwise) or a callable ``progress(done,
        total)`` called after each chunk with the steps done and the steps of the call;

    external : callable(model) updating ``model.bext`` (external forces and moments) in place,
        called before the first step and every ``external_every`` steps (default: at each
        sample) of the model's step count;

    threads : numba threads (default: chosen per chunk of steps by :mod:`murus.threads`: one
        thread while other processes hold the cores, else ``numba.get_num_threads()``; an
        explicit ``NUMBA_NUM_THREADS`` or ``MURUS_THREADS`` fixes it too).

    max_overlap : the run stops with status ``"interpenetration"`` when two bodies overlap by
        more than this fraction of the thinner one's thickness along the contact normal
        (checked after each chunk of steps, :func:`overlap_fraction`; None: no check).

    pause_every : return with status ``"paused"`` at the first end of a chunk of steps, at
        least this many steps into the call, where the loads are updated (a multiple of
        ``external_every`` steps since the last change of the time step, or any chunk's end
        without ``external``): a later call with the same arguments (``t_end`` then the end
        of the remaining steps, ``every`` and ``external_every`` given) goes on in the same
        chunks of steps and gives the uninterrupted run bit for bit, since the sizes of the
        chunks depend only on the step count. Used to checkpoint long runs
        (:func:`murus.retaining.collapse.collapse_run`). None: no pause.
    """
    _set_dt(m, dt)
    if (duration is None) == (t_end is None):
        raise ValueError("give either duration or t_end")
    if t_end is None:
        t_end = m.time + duration
    if xi < 0 or local_damping < 0 or local_damping >= 1:
        raise ValueError("xi must be >= 0 and local_damping in [0, 1)")
    if xi > 0 and not (freq and freq > 0):
        raise ValueError("mass-proportional damping needs freq > 0 [Hz]")
    if damping_frame not in ("base", "absolute"):
        raise ValueError(f"damping_frame must be 'base' or 'absolute', got {damping_frame!r}")
    m.P[K.P_AMASS] = 4.0 * math.pi * xi * freq if xi > 0 else 0.0
    m.P[K.P_DREL] = 1.0 if damping_frame == "base" else 0.0
    m.P[K.P_ALOCAL] = local_damping
    cp = m.__dict__.get("coupled")
    if cp is not None:
        cp.set_damping(local_damping, m.P[K.P_AMASS], m.P[K.P_DREL])
    if probes:
        m.probes.update(probes)
    if every is None:
        every = max(1, int(round(sample_dt / m.dt)))
    if external_every is None:
        external_every = every
    external_every = int(external_every)
    if external is not None and external_every < 1:
        raise ValueError(f"external_every must be >= 1, got {external_every!r}")
    stops = [] if stop is None else (list(stop) if isinstance(stop, (list, tuple)) else [stop])
    moving = m._motion_kind != "none" or m.tilt_rate != 0.0
    remaining = int(round((t_end - m.time) / m.dt))
    if max_steps is not None:
        budget = int(max_steps)
    else:
        budget = None
    if not m.history:
        _sample(m)
    status = "completed"
    message = ""
    t0 = _time.perf_counter()
    u0 = int(m.C[K.C_UPDATES])
    done = 0
    bar = None
    m._threads = _threads.Governor.for_run(threads)
    report = progress if callable(progress) else None
    if progress is True:
        from murus.progress import progress as _progress
        bar = _progress(remaining, "DEM run", unit="steps")
        bar.__enter__()
        report = bar.update
    total = remaining
    try:
        with _SigInt() as sig:
            while remaining > 0:
                rel = int(m.C[K.C_STEP]) - m.step_offset
                n = min(every - rel % every, remaining, _MAX_CHUNK)
                if external is not None:
                    if rel % external_every == 0 or done == 0:
                        external(m)
                    n = min(n, external_every - rel % external_every)
                if budget is not None:
                    n = min(n, budget - done)
                    if n <= 0:
                        status = "max_steps"
                        message = f"stopped after max_steps={max_steps}"
                        break
                _chunk(m, n, moving)
                done += n
                remaining -= n
                if report is not None:
                    report(done, total)
                if (int(m.C[K.C_STEP]) - m.step_offset) % every == 0:
                    _sample(m)
                    hit = [getattr(c, "__name__", "stop") for c in stops if c(m)]
                    if hit:
                        status = "stopped"
                        message = f"stop condition met at t={m.time:.6g} s: {hit[0]}"
                        break
                if not np.all(np.isfinite(m.bpos)):
                    status = "unstable"
                    message = "non-finite positions: lower dt"
                    break
                if cp is not None:
                    bad = cp.after_chunk()
                    if bad is not None:
                        status = "unstable"
                        message = f"at t={m.time:.6g} s {bad}"
                        break
                over = None if max_overlap is None else _penetration(m, max_overlap)
                if over is not None:
                    status = "interpenetration"
                    message = f"at t={m.time:.6g} s {over}"
                    break
                if sig.hit:
                    status = "interrupted"
                    message = f"interrupted at t = {m.time:.6g} s"
                    break
                if (pause_every is not None and done >= pause_every and remaining > 0
                        and (external is None or (int(m.C[K.C_STEP]) - m.step_offset)
                             % external_every == 0)):
                    status = "paused"
                    message = f"paused at t = {m.time:.6g} s"
                    break
    finally:
        m._threads = None
        if bar is not None:
            bar.__exit__(None, None, None)
    wall = _time.perf_counter() - t0
    vals = {k: np.asarray(v, float) for k, v in m.history.items() if k != "t"}
    return RunResult(t=np.asarray(m.history["t"], float), values=vals, status=status,
                     message=message, steps=done, wall=wall,
                     contact_updates=int(m.C[K.C_UPDATES]) - u0, dt=m.dt)


def _sample(m) -> None:
    h = m.history
    vals = {"t": m.time}
    for name, p in m.probes.items():
        vals[name] = float(p(m))
    for k, v in energy(m).items():
        vals["energy." + k] = v
    n = len(h.get("t", []))
    for k, v in vals.items():
        if k not in h:
            h[k] = [math.nan] * n
        h[k].append(v)
    for k in h:
        if k not in vals:
            h[k].append(math.nan)
