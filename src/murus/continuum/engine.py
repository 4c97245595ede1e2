"""Run loop of the continuum (zones) engine: settling to static equilibrium, dynamic runs,
monitors, energy.

Time step: ``dt = safety * min_z A_z / (Cp_z L_z)`` (:meth:`ContinuumModel.critical_dt`, Itasca
FLAC, Theory and Background), rechecked every :data:`RECHECK_EVERY` steps (at the end of a chunk
of steps) in large-strain mode: it only shrinks as zones distort. A run stops (status
``"distorted"``) when a triangle of a zone turns inside out.

Settling (FLAC's "solve" to a ratio): Cundall's local non-viscous damping (alpha = 0.8) until the
unbalanced-force ratio, the largest unbalanced force of a gridpoint (free directions) over the
mean, over the gridpoints, of the sum of the magnitudes of the forces of their zones, is below
``tol``. By default an elastic settle first, then with plasticity ("elastic then plastic", as
FLAC users do for gravity stresses); the model time does not advance; velocities are zeroed and
the settled state becomes the reference of displacements and energies.

Dynamic runs: mass-proportional damping ``alpha_M = 4 pi xi f`` (fraction ``xi`` of critical
at frequency ``f``, the blocks' form, :func:`murus.dem.engine.run`) on the velocity relative to
the base motion (``damping_frame="base"``) or absolute.
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass

import numba
import numpy as np

from murus.continuum import _kdata as kd
from murus.continuum import kernels as K
from murus.dem._kdata import Drive
from murus.errors import MurusError
from murus.results import Result, RunHistory

__all__ = ["SettleResult", "RunResult", "RunError", "settle", "run", "unbalanced_ratio",
           "monitor_value"]

#: Statuses of a dynamic run that count as success.
OK_STATUSES = ("completed",)
_MAX_CHUNK = 2000

_GP_Q = {"ux": ("gdisp", 0), "uy": ("gdisp", 1), "vx": ("gvel", 0), "vy": ("gvel", 1),
         "ax": ("gacc", 0), "ay": ("gacc", 1), "x": ("gxy", 0), "y": ("gxy", 1)}
_ZONE_Q = {"sxx": 0, "syy": 1, "sxy": 2, "szz": 3}


class RunError(MurusError, ValueError):
    """Invalid arguments of :func:`settle` or :func:`run` (``key``: the argument)."""


@dataclass
class SettleResult(Result):
    """Outcome of :func:`settle`.

    Attributes
    ----------
    converged : bool
        Whether the unbalanced-force ratio fell below the tolerance.
    steps : int
        Steps taken [-].
    ratio : float
        Final unbalanced-force ratio [-] (module doc).
    message : str
        One-line account.
    """

    converged: bool
    steps: int
    ratio: float
    message: str = ""

    @property
    def status(self) -> str:
        return "converged" if self.converged else "not converged"

    @property
    def success(self) -> bool:
        return bool(self.converged)


@dataclass
class RunResult(RunHistory):
    """History of a dynamic run (:func:`run`; :class:`murus.results.RunHistory`);
    ``result[name]`` is ``values[name]``.

    Attributes
    ----------
    t : ndarray
        Sample times [s].
    values : dict
        Monitor name -> ndarray sampled at ``t`` (in the monitor's unit), and the energy terms
        ``energy.*`` [J/m] of :meth:`ContinuumModel.energy`.
    status : str
        ``completed`` | ``unstable`` (non-finite values) | ``distorted`` (a zone turned inside
        out) | ``max_steps``.
    message : str
        One-line account.
    steps : int
        Steps taken [-].
    wall : float
        Wall-clock time [s].
    dt : float
        Final time step [s].
    zone_updates : int
        Zones times steps of this call [-].
    """

    OK = OK_STATUSES

    zone_updates: int = 0


def unbalanced_ratio(m) -> float:
    """Unbalanced-force ratio of the last step (module doc).

    Parameters
    ----------
    m : ContinuumModel
        The model.

    Returns
    -------
    float
        ``max |F_unbalanced| / mean force`` [-] (``inf`` when no force acts).
    """
    mean = m.S[K.S_MEANF]
    if mean <= 0.0:
        return 0.0 if m.S[K.S_UNBAL] == 0.0 else math.inf
    return float(m.S[K.S_UNBAL] / mean)


def _chunk(m, n: int, moving: bool, threads: int | None) -> None:
    dt = m.dt
    ts = m.time + np.arange(n) * dt
    if moving:
        vfull = m.base_velocity(ts)
        vhalf = m.base_velocity(ts + 0.5 * dt)
    else:
        vfull = np.zeros((n, 2))
        vhalf = vfull
    grav = np.zeros((n, 2))
    grav[:, 1] = -m.gravity
    drive = Drive(vfull, vhalf, grav, np.zeros((n, 2)))
    nth = numba.get_num_threads()
    try:
        if threads is not None:
            numba.set_num_threads(max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS)))
        K.run_chunk(n, m.P, m.E, m.C, m.S, drive, kd.pack(kd.Grid, m), kd.pack(kd.Zones, m),
                    m.mprops, m.part, m.ff)
    finally:
        numba.set_num_threads(nth)


#: Steps between two rechecks of the time step in large strain.
RECHECK_EVERY = 100


def _recheck_dt(m, full: bool = True) -> str | None:
    """Shrink the step if the zones distorted (``full``: recompute the zones' critical step);
    a message when a zone is inverted."""
    if np.any(m.zstate & K.ST_INVERTED):
        z = int(np.flatnonzero(m.zstate & K.ST_INVERTED)[0])
        return f"zone {z} turned inside out (too distorted: large strain)"
    if m.large_strain and full:
        crit = m.critical_dt()
        if crit <= 0.0:
            return "a zone has a non-positive area"
        if m.safety * crit < m.dt:
            m.P[K.P_DT] = m.safety * crit
    return None


def settle(m, tol: float = 1e-5, alpha: float = 0.8, max_steps: int = 200_000,
           check_every: int = 100, elastic_first: bool = True, reset: bool = True,
           threads: int | None = None) -> SettleResult:
    """Static equilibrium under gravity, the applied forces and the fixities, with local
    damping (module doc).

    Parameters
    ----------
    m : ContinuumModel
        The model, updated in place.
    tol : float
        Unbalanced-force ratio to reach [-] (default 1e-5, FLAC's default).
    alpha : float
        Local damping coefficient [-], in [0, 1) (default 0.8, FLAC's).
    max_steps : int
        Largest number of steps (per stage).
    check_every : int
        Steps between checks of the ratio.
    elastic_first : bool
        Settle with every material elastic first, then with plasticity.
    reset : bool
        Take the settled state as the reference of displacements and energies.
    threads : int or None
        numba threads (None: numba's setting); below ``P_PARMIN`` zones (4000) the loops run
        serially whatever the setting.

    Returns
    -------
    SettleResult

    References
    ----------
    Cundall (1987) (local non-viscous damping); Itasca FLAC, Theory and Background (unbalanced
    force ratio, static solution).
    """
    if not (0.0 <= alpha < 1.0):
        raise RunError(f"alpha must be in [0, 1), got {alpha!r}", key=("alpha",))
    if not (tol > 0):
        raise RunError(f"tol must be > 0, got {tol!r}", key=("tol",))
    if int(check_every) < 1 or int(max_steps) < 1:
        raise RunError("check_every and max_steps must be >= 1", key=("check_every",))
    m.P[K.P_ALOCAL] = alpha
    m.P[K.P_AMASS] = 0.0
    m.P[K.P_DREL] = 0.0
    stages = [0.0, 1.0] if elastic_first else [1.0]
    done = 0
    ratio = math.inf
    converged = False
    problem = None
    for plastic in stages:
        m.P[K.P_PLASTIC] = plastic
        steps = 0
        converged = False
        while steps < max_steps:
            n = min(int(check_every), int(max_steps) - steps)
            _chunk(m, n, False, threads)
            steps += n
            ratio = unbalanced_ratio(m)
            if not np.all(np.isfinite(m.gvel)):
                problem = "non-finite velocities (lower the time step)"
                break
            problem = _recheck_dt(m)
            if problem is not None:
                break
            if ratio < tol:
                converged = True
                break
        done += steps
        if problem is not None:
            break
    m.P[K.P_PLASTIC] = 1.0
    m.P[K.P_ALOCAL] = 0.0
    m.gvel[:] = 0.0
    m.gacc[:] = 0.0
    if reset:
        m.reset_reference()
    if converged:
        msg = f"settled in {done} steps, ratio {ratio:.2e}"
    elif problem is not None:
        msg = f"not settled after {done} steps: {problem}"
    else:
        msg = f"not settled after {done} steps, ratio {ratio:.2e} > {tol:g}"
    return SettleResult(converged, done, ratio, msg)


def monitor_value(m, spec) -> float:
    """Value of one monitor.

    Parameters
    ----------
    m : ContinuumModel
        The model.
    spec : tuple or callable
        ``("gp", g, q)`` with q in ux, uy [m], vx, vy [m/s], ax, ay [m/s²], x, y [m] of
        gridpoint g; ``("zone", z, q)`` with q in sxx, syy, sxy, szz [Pa] (zone average) or
        ``state`` (plastic bits); or a callable ``f(model) -> float``.

    Returns
    -------
    float
    """
    if callable(spec):
        return float(spec(m))
    kind, i, q = spec
    if kind == "gp":
        name, d = _GP_Q[q]
        return float(getattr(m, name)[i, d])
    if q == "state":
        return float(m.zstate[i] & 15)
    s = m.zsig[i]
    return float(0.25 * s[:, _ZONE_Q[q]].sum())


def _check_monitors(m, monitors) -> None:
    for name, spec in monitors.items():
        if callable(spec):
            continue
        ok = isinstance(spec, (tuple, list)) and len(spec) == 3
        if ok:
            kind, i, q = spec
            if kind == "gp":
                ok = q in _GP_Q and isinstance(i, (int, np.integer)) and 0 <= i < m.ng
            elif kind == "zone":
                ok = (q in _ZONE_Q or q == "state") and isinstance(i, (int, np.integer)) \
                    and 0 <= i < m.nz
            else:
                ok = False
        if not ok:
            raise RunError(f"monitor {name!r}: expected ('gp', index, ux|uy|vx|vy|ax|ay|x|y) "
                           f"or ('zone', index, sxx|syy|sxy|szz|state), got {spec!r}",
                           key=("monitors", name))


def _sample(m, monitors) -> None:
    h = m.history
    vals = {"t": m.time}
    for name, spec in monitors.items():
        vals[name] = monitor_value(m, spec)
    for k, v in m.energy().items():
        vals["energy." + k] = v
    n = len(h.get("t", []))
    for k, v in vals.items():
        if k not in h:
            h[k] = [math.nan] * n
        h[k].append(v)
    for k in h:
        if k not in vals:
            h[k].append(math.nan)


def run(m, duration: float, *, motion=None, velocity=None, xi: float = 0.0,
        freq: float | None = None, local_damping: float = 0.0, monitors: dict | None = None,
        sample_dt: float | None = None, every: int | None = None,
        damping_frame: str = "base", max_steps: int | None = None,
        threads: int | None = None) -> RunResult:
    """Dynamic run over ``duration`` [s] from the current model time.

    Parameters
    ----------
    m : ContinuumModel
        The model, updated in place.
    duration : float
        Simulated time [s], > 0.
    motion : murus.motion.core.GroundMotion, optional
        Base motion of the ``base`` gridpoints (:meth:`ContinuumModel.set_base_motion`).
    velocity : callable, optional
        Base velocity in closed form instead of ``motion``.
    xi, freq : float
        Mass-proportional damping: fraction of critical ``xi`` [-] at frequency ``freq`` [Hz]
        (``alpha_M = 4 pi xi f``; Savalle et al. (2022), §2, the blocks' form).
    local_damping : float
        Cundall local damping coefficient [-] (0: none).
    monitors : dict, optional
        name -> spec of :func:`monitor_value` (added to the model's monitors).
    sample_dt : float, optional
        Sampling interval of the histories [s] (default: every step up to 2000 samples).
    every : int, optional
        Sampling interval in steps (instead of ``sample_dt``).
    damping_frame : {"base", "absolute"}
        Velocities the dampings act on.
    max_steps : int, optional
        Largest number of steps of this call.
    threads : int or None
        numba threads (None: numba's setting); below ``P_PARMIN`` zones (4000) the loops run
        serially whatever the setting.

    Returns
    -------
    RunResult

    References
    ----------
    Itasca FLAC, Theory and Background (dynamic analysis, Rayleigh damping); Savalle et al.
    (2022), §2 (mass-proportional damping).
    """
    if not (duration > 0 and math.isfinite(duration)):
        raise RunError(f"duration must be > 0 [s], got {duration!r}", key=("duration",))
    if xi < 0 or not (0.0 <= local_damping < 1.0):
        raise RunError("xi must be >= 0 and local_damping in [0, 1)", key=("xi",))
    if xi > 0 and not (freq and freq > 0):
        raise RunError("mass-proportional damping needs freq > 0 [Hz]", key=("freq",))
    if damping_frame not in ("base", "absolute"):
        raise RunError(f"damping_frame must be 'base' or 'absolute', got {damping_frame!r}",
                       key=("damping_frame",))
    if motion is not None or velocity is not None:
        m.set_base_motion(motion=motion, velocity=velocity)
    if monitors:
        _check_monitors(m, monitors)
        m.monitors.update(monitors)
    m.P[K.P_AMASS] = 4.0 * math.pi * xi * freq if xi > 0 else 0.0
    m.P[K.P_DREL] = 1.0 if damping_frame == "base" else 0.0
    m.P[K.P_ALOCAL] = local_damping
    m.P[K.P_PLASTIC] = 1.0
    total = int(math.ceil(duration / m.dt - 1e-9))
    if every is None:
        every = (max(1, int(round(sample_dt / m.dt))) if sample_dt is not None
                 else max(1, total // 2000))
    every = int(every)
    moving = m._motion_kind != "none"
    if not m.history:
        _sample(m, m.monitors)
    t_end = m.time + duration
    status = "completed"
    message = ""
    done = 0
    since = 0
    last_check = 0
    t0 = _time.perf_counter()
    while m.time < t_end - 0.5 * m.dt:
        remaining = int(math.ceil((t_end - m.time) / m.dt - 1e-9))
        n = min(every - since, remaining, _MAX_CHUNK)
        if max_steps is not None:
            n = min(n, int(max_steps) - done)
            if n <= 0:
                status = "max_steps"
                message = f"stopped after max_steps={max_steps}"
                break
        _chunk(m, n, moving, threads)
        m.time += n * m.dt
        done += n
        since += n
        if since >= every:
            since = 0
            _sample(m, m.monitors)
        if not np.all(np.isfinite(m.gvel)):
            status = "unstable"
            message = f"non-finite velocities at t={m.time:.6g} s (lower the time step)"
            break
        full = done - last_check >= RECHECK_EVERY
        if full:
            last_check = done
        problem = _recheck_dt(m, full)
        if problem is not None:
            status = "distorted"
            message = f"at t={m.time:.6g} s {problem}"
            break
    wall = _time.perf_counter() - t0
    vals = {k: np.asarray(v, float) for k, v in m.history.items() if k != "t"}
    if not message:
        message = f"completed {done} steps to t={m.time:.6g} s"
    return RunResult(t=np.asarray(m.history["t"], float), values=vals, status=status,
                     message=message, steps=done, wall=wall, dt=m.dt,
                     zone_updates=done * m.nz)
