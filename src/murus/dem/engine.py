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
critical at frequency ``f``, seed 001 §2) on the velocity relative to the base motion, so that
it does not brake a rigid-body collapse; optional local damping on the same relative velocity.

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
from dataclasses import dataclass, field

import numba
import numpy as np

from murus.dem import kernels as K

__all__ = ["RunResult", "SettleResult", "Probe", "body_probe", "relative_probe", "tilt_probe",
           "stop_when", "stable_dt", "settle", "run", "energy", "probe_from_spec"]


# ---------------------------------------------------------------------- probes
@dataclass(frozen=True)
class Probe:
    """A scalar monitor of the model state, rebuilt from ``spec`` after a checkpoint.

    kinds: ``("body", b, q)`` with q in x, y, angle, vx, vy, omega, ux, uy, rot (ux, uy, rot:
    since the reference state); ``("relative", b, ref, q)`` with q in ux, uy, rot: of body b
    relative to body ref; ``("tilt",)``: gravity tilt [deg]; ``("time",)``.
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
        raise ValueError(f"unknown probe kind {kind!r}")


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
    """Position, angle, velocity or displacement ``q`` of one body (see :class:`Probe`)."""
    _body_q_check(q)
    return Probe(("body", int(body), q))


def relative_probe(body: int, ref: int, q: str = "ux") -> Probe:
    """Displacement of ``body`` relative to ``ref`` (e.g. d_top: top block relative to the
    base)."""
    _body_q_check(q)
    return Probe(("relative", int(body), int(ref), q))


def tilt_probe() -> Probe:
    return Probe(("tilt",))


def _body_q_check(q):
    if q not in ("x", "y", "angle", "vx", "vy", "omega", "ux", "uy", "rot"):
        raise ValueError(f"unknown body quantity {q!r}")


def probe_from_spec(spec) -> Probe:
    return Probe(tuple(spec))


def stop_when(probe: Callable, op: str, value: float) -> Callable:
    """A stop condition ``probe(model) op value`` (op one of >, <, abs>)."""
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
class SettleResult:
    converged: bool
    steps: int
    ratio: float  # final unbalanced-force ratio
    message: str = ""


@dataclass
class RunResult:
    """History of a dynamic run. ``t`` [s]; ``values[name]`` sampled with it (probes and the
    energy terms ``energy.*``); status: completed | stopped | interrupted | max_steps."""

    t: np.ndarray
    values: dict = field(default_factory=dict)
    status: str = "completed"
    message: str = ""
    steps: int = 0
    wall: float = 0.0
    contact_updates: int = 0
    dt: float = 0.0

    def __getitem__(self, name):
        return self.values[name]


# ---------------------------------------------------------------------- time step
def detect(m) -> None:
    """Contact detection and forces at the current positions without moving (dt = 0)."""
    m.build()
    K.world_vertices(m.bpos, m.bang, m.sbody, m.svs, m.svn, m.lv, m.wv)
    n = m.pairs.shape[0]
    dis = np.zeros((n, K.NW))
    nact = np.zeros(n, np.int64)
    K._contacts_serial(m.pairs, m.pj, m.pbond, m.sid, m.sf, m.sbr, dis, m.wv, m.svs, m.svn,
                       m.skind, m.srad, m.sbody, m.bpos, m.bvel, m.bomg, m.jprops, 0.0,
                       m.thickness, m.P[K.P_REACH], nact)
    m.snapshot()


def stable_dt(m) -> float:
    """Stable time step [s] from the current masses and contact stiffnesses (module doc)."""
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
    # few pairs: one thread (the kernels' docstring of run_chunk)
    nth = numba.get_num_threads()
    few = nth > 1 and m.pairs.shape[0] < m.P[K.P_PARMIN]
    if few:
        numba.set_num_threads(1)
    try:
        out = K.run_chunk(n, m.P, m.E, m.C, m.S, vhalf, vfull, grav, gdot, m.bpresc,
                          m.bpos, m.bang,
                          m.bvel, m.bomg, m.bmass, m.binert, m.bkin, m.brad, m.blast,
                          m.bsnap, m.sbody, m.skind, m.svs, m.svn, m.srad, m.sgroup, m.lv, m.wv,
                          m.jprops, m.jtab, m.pairs, m.pj, m.pbond, m.sid, m.sf, m.sbr, m.bext)
    finally:
        if few:
            numba.set_num_threads(nth)
    m.pairs, m.pj, m.pbond, m.sid, m.sf, m.sbr = out
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
    mean = m.S[K.S_MEANF]
    if mean <= 0.0:
        return math.inf if m.S[K.S_UNBAL] > 0 else 0.0
    return float(m.S[K.S_UNBAL] / mean)


def settle(m, tol: float = 1e-5, alpha: float = 0.7, max_steps: int = 200_000,
           check_every: int = 100, dt: float | None = None, reset: bool = True,
           external: Callable | None = None) -> SettleResult:
    """Static solution under gravity (at the current tilt) and the external forces
    ``model.bext`` with local damping ``alpha``: step until the unbalanced-force ratio is below
    ``tol`` (module doc). ``external(model)``, if given, updates ``model.bext`` every
    ``check_every`` steps. The base and the ``"prescribed"`` bodies do not move and the model
    time does not advance."""
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
                if ratio < tol:
                    converged = True
                    break
    finally:
        m.bpresc[:] = presc
    m.bvel[:] = 0.0
    m.bomg[:] = 0.0
    detect(m)
    m.snapshot()
    if reset:
        m.reset_reference()
    msg = (f"settled in {done} steps, ratio {ratio:.2e}" if converged
           else f"not settled after {done} steps, ratio {ratio:.2e} > {tol:g}")
    return SettleResult(converged, done, ratio, msg)


def run(m, duration: float | None = None, *, t_end: float | None = None,
        dt: float | None = None, xi: float = 0.0, freq: float | None = None,
        local_damping: float = 0.0, probes: dict | None = None, every: int | None = None,
        sample_dt: float = 0.01, stop=None, max_steps: int | None = None,
        progress: bool = False, external: Callable | None = None,
        external_every: int | None = None, damping_frame: str = "base") -> RunResult:
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
    progress : show a rich progress bar;
    external : callable(model) updating ``model.bext`` (external forces and moments) in place,
        called before the first step and every ``external_every`` steps (default: at each
        sample) of the model's step count.
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
    if progress:
        from rich.progress import Progress
        bar = Progress(transient=True)
        bar.start()
        task = bar.add_task("murus.dem", total=remaining)
    try:
        with _SigInt() as sig:
            while remaining > 0:
                rel = int(m.C[K.C_STEP]) - m.step_offset
                n = min(every - rel % every, remaining)
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
                if bar is not None:
                    bar.update(task, advance=n)
                if sig.hit:
                    status = "interrupted"
                    message = f"interrupted at t={m.time:.6g} s (save() to resume)"
                    break
    finally:
        if bar is not None:
            bar.stop()
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
