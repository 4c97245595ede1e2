"""Front end of the rocking engine: :func:`simulate` (one history) and :func:`simulate_batch`
(many, in parallel), in the style of ``scipy.integrate.solve_ivp``: a thin function over the
kernels returning a result object with arrays and a status message."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from murus import threads as _threads
from murus.results import Result, deprecated_alias
from murus.rocking import kernels as K
from murus.rocking.defaults import RTOL, WINKLER_RTOL
from murus.rocking.excitation import Excitation, as_excitation, default_duration
from murus.rocking.model import ModelError, as_model
from murus.rocking.summary import (  # noqa: F401 (FREE_TAIL, LIMIT_STATES: public here too)
    FREE_TAIL,
    LIMIT_STATES,
    SUMMARY,
    table_summary,
    values,
)

#: What each integration method is to be trusted for (VALIDATION.md, issue 15).
METHOD_NOTES = {
    "event": "event-driven Dormand-Prince 5(4), events located: trust it for verdicts "
             "(overturning, limit states), fragility and responses near collapse",
    "newmark": "fixed-step Newmark (constant average acceleration): at dt = 1 ms it gives a "
               "wrong overturning verdict (false or missed) in about 2 % of real-record cases "
               "and errs by more than 1 % on theta_max in about 15 %; check a verdict near the "
               "threshold with method = 'event'",
}

_STATUS = {
    0: "ok",
    1: "step size underflow: the integration stopped early",
    2: "step budget exhausted: the integration stopped early",
}


@dataclass
class RockingResult(Result):
    """A single time history of a rocking body on a rigid base (SI units: s, rad, rad/s, m/s², J).

    Arrays are on the output grid ``t``. The scalar quantities are declared in
    :data:`murus.rocking.summary.SUMMARY` (units, description); ``uplift_time`` is the
    deprecated name of ``t_uplift``.

    Attributes
    ----------
    t : ndarray
        Output times [s].
    theta : ndarray
        Rotation [rad], positive when the body turns about the corner O (held at the
        overturning rotation after overturning; nan after an early stop).
    omega : ndarray
        Angular velocity [rad/s] (nan after overturning or an early stop).
    ag, av : ndarray
        Horizontal and vertical (upward) ground accelerations on the grid [m/s²].
    pivot : ndarray
        Pivot [-]: 0 at rest, +1/-1 rocking about O/O'.
    impacts : ndarray
        Rows ``(t, omega_before, omega_after)`` [s, rad/s, rad/s], one per impact.
    uplift_intervals : ndarray
        Rows ``(start, end)`` [s] of each rocking interval (``end`` nan while still rocking at
        the end of the run).
    peaks : ndarray
        Rows ``(t, theta)`` [s, rad] at each extremum of the rotation while rocking.
    alpha : float
        Slenderness angle [rad].
    p : float
        Frequency parameter ``sqrt(m g R / I_O)`` [rad/s].
    restitution : float
        Coefficient of restitution ``omega_after / omega_before`` of the constant-valued laws
        [-].
    theta_max : float
        Largest absolute rotation [rad].
    theta_signed_max : float
        Signed rotation at the largest absolute rotation [rad].
    t_theta_max : float
        Time of the largest absolute rotation [s].
    theta_pos, theta_neg : float
        Largest positive and largest negative rotation [rad].
    n_impacts : int
        Number of impacts [-].
    t_uplift : float or None
        Time of first uplift [s] (None: never).
    overturned : bool
        Whether the body overturned.
    t_overturn : float or None
        Time of overturning [s] (None: no overturning).
    t_exceed_alpha : float or None
        First time ``|theta| > alpha`` [s] (None: never).
    energy_dissipated : float
        Energy dissipated at impacts [J].
    status : int
        0 ok, 1 step size underflow, 2 step budget exhausted.
    message : str
        ``"ok"``, or why and when the integration stopped early.
    n_steps : int
        Runge-Kutta (or Newmark) steps [-].
    meta : dict
        Input of the run: model, motion and solver options.
    lever : ndarray or None
        Lever of the weight about a moving pivot [m] on the grid (None: corner pivots,
        ``b/2``).

    References
    ----------
    Housner (1963) (rocking equations, restitution at impacts); Mordant et al. (SERIES),
    eqs. 9 and 11 (:attr:`rocking_criterion`); EURODYN (2020), §2 (``p``) and §4
    (:attr:`limit_states`).
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    ag: np.ndarray
    av: np.ndarray
    pivot: np.ndarray
    impacts: np.ndarray
    uplift_intervals: np.ndarray
    peaks: np.ndarray
    alpha: float
    p: float
    restitution: float
    theta_max: float
    theta_signed_max: float
    t_theta_max: float
    theta_pos: float
    theta_neg: float
    n_impacts: int
    t_uplift: float | None
    overturned: bool
    t_overturn: float | None
    t_exceed_alpha: float | None
    energy_dissipated: float
    status: int
    message: str
    n_steps: int
    meta: dict = field(default_factory=dict)
    lever: np.ndarray | None = None

    uplift_time = deprecated_alias("t_uplift", "uplift_time")

    def headline(self) -> str:
        """``theta_max/alpha = ..., impacts = ..., overturned = ...`` (the CLI's line)."""
        return (f"theta_max/alpha = {self.theta_max_over_alpha:.4f}, impacts = {self.n_impacts}"
                f", overturned = {self.overturned}")

    def _lever(self) -> np.ndarray:
        if self.lever is not None:
            return self.lever
        return np.full_like(self.t, 0.5 * self.meta["model"]["body"]["width"])

    @property
    def theta_max_over_alpha(self) -> float:
        return self.theta_max / self.alpha

    @property
    def limit_states(self) -> dict[str, bool]:
        """Limit states reached (:data:`murus.rocking.summary.LIMIT_STATES`, EURODYN (2020),
        §4: ``theta/alpha >= 0.1`` and ``0.4``) and collapse."""
        out = {k: bool(self.theta_max_over_alpha >= v) for k, v in LIMIT_STATES.items()}
        out["overturning"] = self.overturned
        return out

    @property
    def rocking_criterion(self) -> np.ndarray:
        """``RC(t) = |a_g| z_G / ((g + a_v) b_n)`` with ``b_n`` the lever of the weight about
        the pivot: ``b/2`` on the corner (Mordant et al. (SERIES) eq. 9: ``m a_g H / (m g B/2)``),
        the compressive-length lever with a moving pivot (eq. 11); > 1: rocking starts (without
        restraints)."""
        g = self.meta.get("model", {}).get("gravity", 9.81)
        zg = self.meta["model"]["body"]["z_G"]
        return np.abs(self.ag) * zg / ((g + self.av) * self._lever())

    @property
    def kinetic_energy(self) -> np.ndarray:
        I_O = self.meta["model"]["body"]["I_O"]
        return 0.5 * I_O * np.nan_to_num(self.omega) ** 2

    @property
    def potential_energy(self) -> np.ndarray:
        """Gravity potential above the rest position [J] (corner pivots; with a moving pivot it
        is the corner's value, an approximation) plus the elastic energy of an elastic tie and
        of the spring bed."""
        b = self.meta["model"]["body"]
        g = self.meta["model"]["gravity"]
        a = b["alpha"]
        th = np.nan_to_num(self.theta)
        out = b["mass"] * g * b["R"] * (np.cos(a - np.abs(th)) - np.cos(a))
        return out + restraint_energy(self.meta["model"], th, self.pivot)

    @property
    def dissipated_energy(self) -> np.ndarray:
        """Energy dissipated at impacts up to each output time [J] (logged impacts)."""
        I_O = self.meta["model"]["body"]["I_O"]
        if self.impacts.shape[0] == 0:
            return np.zeros_like(self.t)
        loss = 0.5 * I_O * (self.impacts[:, 1] ** 2 - self.impacts[:, 2] ** 2)
        cum = np.cumsum(loss)
        k = np.searchsorted(self.impacts[:, 0], self.t, side="right")
        return np.where(k > 0, cum[np.maximum(k - 1, 0)], 0.0)

    def summary(self) -> dict:
        """Plain-number summary (what ``summary.json`` holds): the quantities of the declared
        table :data:`murus.rocking.summary.SUMMARY` that a result keeps (also under their
        earlier names), then the derived ones; ``status`` is the message."""
        out = table_summary(self, SUMMARY, _RESULT_FIELDS)
        out.update({
            "theta_max_over_alpha": self.theta_max_over_alpha,
            "uplift_intervals": [[_opt(a), _opt(b)] for a, b in self.uplift_intervals],
            "limit_states": self.limit_states,
            "alpha": self.alpha,
            "p": self.p,
            "restitution": self.restitution,
            "status": self.message,
            "method": self.meta.get("solver", {}).get("method", "event"),
            "method_note": METHOD_NOTES.get(self.meta.get("solver", {}).get("method", "event")),
            "input": self.meta,
        })
        return out


def restraint_energy(model: dict, theta: np.ndarray, pivot: np.ndarray) -> np.ndarray:
    """Elastic energy [J] stored in an elastic tie (no yielding, no pretension) and in the
    spring bed at the rotations ``theta`` about the pivots ``pivot`` (corner levers)."""
    body = model["body"]
    hb = 0.5 * body["width"]
    s = np.where(np.nan_to_num(pivot) < 0, -1.0, 1.0)
    ct, st = np.cos(theta), np.sin(theta)
    E = np.zeros_like(theta)
    tie = model.get("tie")
    if tie is not None:
        x0 = tie["x"] - s * hb
        d = x0 * (ct - 1.0) + tie["height"] * st
        if tie["tension_only"]:
            d = np.maximum(d, 0.0)
        E += 0.5 * tie["stiffness"] * d**2
    bed = model.get("transverse_walls")
    if bed is not None and bed["stiffness"] != "rigid":
        xb = hb if bed["x"] is None else bed["x"]
        x0 = xb - s * hb
        # compression c(z) = a0 + a1 z >= 0 over [z1, z2]: int c^2 dz = [c^3 / (3 a1)]
        a0 = x0 * (1.0 - ct)
        a1 = -st
        z1 = np.full_like(theta, bed["z1"])
        z2 = z1 + bed["effective_height"]
        with np.errstate(divide="ignore", invalid="ignore"):
            zc = np.where(a1 != 0.0, -a0 / a1, np.nan)
        z1 = np.where(a1 > 0.0, np.maximum(z1, zc), z1)
        z2 = np.where(a1 < 0.0, np.minimum(z2, zc), z2)
        live = (z2 > z1) & (a1 != 0.0)
        a1s = np.where(live, a1, 1.0)
        integral = ((a0 + a1s * z2) ** 3 - (a0 + a1s * z1) ** 3) / (3.0 * a1s)
        E += np.where(live, 0.5 * bed["stiffness"] * integral, 0.0)
    return E


#: Quantities of the summary table kept as attributes of a :class:`RockingResult`.
_RESULT_FIELDS = ("theta_max", "theta_signed_max", "t_theta_max", "theta_pos", "theta_neg",
                  "n_impacts", "t_uplift", "overturned", "t_overturn", "t_exceed_alpha",
                  "energy_dissipated", "status", "n_steps")


def _opt(x) -> float | None:
    return None if math.isnan(x) else float(x)


def _resolve(model, motion, duration, restitution, linearised):
    mdl = as_model(model, restitution, linearised)
    exc = as_excitation(motion)
    if duration is None:
        duration = default_duration(exc)
    duration = float(duration)
    if not (math.isfinite(duration) and duration > 0.0):
        raise ModelError(f"duration must be positive, got {duration!r}")
    return mdl, exc, duration


def _initial(theta0, omega0, theta0_over_alpha, body):
    if theta0_over_alpha is not None:
        theta0 = float(theta0_over_alpha) * body.alpha
    theta0 = float(theta0)
    omega0 = float(omega0)
    if not (math.isfinite(theta0) and math.isfinite(omega0)):
        raise ModelError("initial conditions must be finite")
    if abs(theta0) >= 0.5 * math.pi:
        raise ModelError(f"initial rotation {theta0!r} rad is beyond overturning (pi/2)")
    return theta0, omega0


def _message(status: int, t_final: float, t_end: float, mdl) -> str:
    """Status message of a run: ``"ok"``, or why and when the integration stopped early."""
    msg = _STATUS.get(status, "unknown")
    if status == 0:
        return msg
    msg += f" at t = {t_final:.6g} s of {t_end:.6g} s (results up to there only)"
    if status == 1 and getattr(mdl, "rest_tol", None) == 0.0:
        msg += "; rest_tol = 0 never ends a cascade of impacts (a Zeno point): use the default"
    return msg


def simulate(
    model,
    motion=None,
    *,
    method: str = "event",
    duration: float | None = None,
    theta0: float = 0.0,
    omega0: float = 0.0,
    theta0_over_alpha: float | None = None,
    restitution=None,
    linearised: bool | None = None,
    rtol: float | None = None,
    dt: float | None = None,
    out_dt: float | None = None,
    max_impacts: int = 100_000,
    max_steps: int = 50_000_000,
) -> Result:
    """Time-history analysis of a rocking body, on a rigid base or on an elastic layer.

    The one front end of the rocking engines, in the manner of ``scipy.integrate.solve_ivp``:
    it dispatches on the model. A :class:`RockingModel` or a :class:`RigidBlock` (rigid base)
    returns a :class:`RockingResult`; a :class:`~murus.rocking.winkler.WinklerModel` (body on a
    no-tension elastic layer) is run by :func:`~murus.rocking.winkler.simulate_winkler` and
    returns a :class:`~murus.rocking.winkler.WinklerResult` (options of the rigid base only:
    ``restitution``, ``linearised``, ``dt``, ``max_impacts``, ``method = "newmark"``). Both
    results derive from :class:`murus.results.Result`.

    Parameters
    ----------
    model:
        A :class:`RockingModel` or a :class:`RigidBlock` (Housner restitution by default), or a
        :class:`~murus.rocking.winkler.WinklerModel`.
    motion:
        A GroundMotion (``dt``, ``acc`` [m/s²], optional ``acc_v``), an excitation of
        :mod:`murus.rocking.excitation`, or ``None`` for free vibration.
    method:
        ``"event"`` (default): adaptive Dormand-Prince 5(4) stepping exactly on the input's
        breakpoints, events located to ~1e-12 s; ``"newmark"``: constant average acceleration
        with the step ``dt`` and impacts located inside the step (second order). Trust the
        event-driven method for verdicts (overturning, limit states), fragility and anything
        near collapse: it agrees with a tight reference within 0.1 % on theta_max wherever the
        response is not chaotic. Newmark reproduces the fixed-step analyses of Mordant et al.
        (SERIES); at
        ``dt = 1 ms`` on FEMA P695 records it gives a wrong overturning verdict in 10 of 576
        runs (4 false, 6 missed overturns) and errs by more than 1 % on theta_max in 59 of 390
        stable cases (VALIDATION.md, "The rest rule against an accurate solver"): use it for
        smooth, well-resolved responses, and check a verdict near the threshold with the
        default.
    duration:
        End of the analysis [s]; default: end of the input plus 5 s of free motion, 20 s for a
        free vibration (:func:`murus.rocking.excitation.default_duration`; the same from a case
        file).
    theta0, omega0, theta0_over_alpha:
        Initial rotation [rad] (or as a fraction of alpha) and angular velocity [rad/s].
    rtol:
        Relative tolerance of the event-driven integrator (absolute: ``rtol * alpha``); default
        :data:`murus.rocking.defaults.RTOL` (1e-11, where verdicts and impact counts agree with an
        accurate reference) on a rigid base, :data:`~murus.rocking.defaults.WINKLER_RTOL` (1e-9)
        on an elastic layer.
    dt:
        Newmark time step [s] (required for ``method="newmark"``).
    out_dt:
        Output grid step [s] for the event-driven method (default: the record's step).
    """
    from murus.rocking.winkler import WinklerModel, simulate_winkler

    if isinstance(model, WinklerModel):
        rigid_only = {"restitution": restitution, "linearised": linearised, "dt": dt}
        given = [k for k, v in rigid_only.items() if v is not None]
        if method != "event" or given:
            what = f"method {method!r}" if method != "event" else ", ".join(given)
            raise ModelError(f"{what}: an option of the rigid base, not of a WinklerModel")
        return simulate_winkler(model.body, model.base, motion, duration=duration,
                                theta0=theta0, omega0=omega0,
                                theta0_over_alpha=theta0_over_alpha, gravity=model.gravity,
                                rtol=WINKLER_RTOL if rtol is None else rtol, out_dt=out_dt,
                                max_steps=max_steps)
    if rtol is None:
        rtol = RTOL
    mdl, exc, t_end = _resolve(model, motion, duration, restitution, linearised)
    th0, om0 = _initial(theta0, omega0, theta0_over_alpha, mdl.body)
    if mdl.rigid_walls and (th0 < 0.0 or (th0 == 0.0 and om0 < 0.0)):
        raise ModelError("rigid transverse walls: the wall cannot start rotating inward "
                         "(theta0 < 0 or omega0 < 0)")
    P = mdl.params()
    drv = K.Drive(exc.vector(), *exc.arrays())
    if method == "event":
        if not (0.0 < rtol < 1e-2):
            raise ModelError(f"rtol must be in (0, 1e-2), got {rtol!r}")
        step = float(out_dt) if out_dt is not None else exc.default_output_step()
        if not (math.isfinite(step) and step > 0.0):
            raise ModelError(f"out_dt must be positive, got {out_dt!r}")
        n_out = int(math.floor(t_end / step + 1e-9)) + 1
        t = np.arange(n_out) * step

        def kernel(log):
            return K.event_core(P, drv, t_end, th0, om0, float(rtol), step, log, int(max_steps))
    elif method == "newmark":
        if dt is None or not (math.isfinite(dt) and dt > 0.0):
            raise ModelError("method 'newmark' needs a positive time step dt")
        n_steps = int(math.ceil(t_end / dt - 1e-9))
        n_out = n_steps + 1
        t = np.arange(n_out) * dt

        def kernel(log):
            return K.newmark_core(P, drv, float(n_steps * dt), th0, om0, float(dt), log)
    else:
        raise ModelError(f"unknown method {method!r}; expected 'event' or 'newmark'")
    law = mdl.restitution
    iterations = 0
    while True:
        S, th, om, pv, imp, up, pk = _run_logged(kernel, n_out, max_impacts)
        iterations += 1
        if getattr(law, "variant", "causal") != "iterated" or S[K.S_OVERTURNED]:
            break
        target = float(S[K.S_THETA_MAX])
        if P["e_absmax"] > 0.0 and abs(target - P["e_absmax"]) <= 1e-9 * target:
            break
        if iterations > law.max_iterations or target <= 0.0:
            break
        P["e_absmax"] = target
    gh, gv = exc.sample(t)
    vals = values(SUMMARY, S)
    n_imp = vals["n_impacts"]
    n_up = vals["n_uplifts"]
    status = vals["status"]
    meta = {
        "model": mdl.describe(),
        "motion": exc.describe(),
        "solver": {"method": method, "duration": t_end, "rtol": rtol if method == "event" else None,
                   "dt": dt if method == "newmark" else None, "theta0": th0, "omega0": om0},
    }
    if getattr(law, "variant", "causal") == "iterated":
        meta["solver"]["restitution_iterations"] = iterations
    return RockingResult(
        t=t,
        theta=th,
        omega=om,
        ag=gh,
        av=gv,
        pivot=pv,
        impacts=imp[: min(n_imp, imp.shape[0])].copy(),
        uplift_intervals=up[: min(n_up, up.shape[0])].copy(),
        peaks=pk[: min(int(S[K.S_N_PEAKS]), pk.shape[0])].copy(),
        alpha=mdl.body.alpha,
        p=mdl.p,
        restitution=mdl.e,
        **{k: v for k, v in vals.items() if k in _RESULT_FIELDS},
        message=_message(status, vals["t_final"], t_end, mdl),
        meta=meta,
        lever=mdl.pivot.lever(mdl.body, gh, gv, mdl.gravity) if mdl.pivot.code else None,
    )


def _run_logged(kernel, n_out, max_impacts):
    """Run a kernel; event logs start small and a run that logs more is repeated with room for
    all (the kernel is deterministic)."""
    cap = 256
    while True:
        log = K.new_log(n_out, min(cap, max_impacts), cap)
        S = kernel(log)
        _, _, th, om, pv, imp, up, pk = log
        need = max(S[K.S_N_IMPACTS], S[K.S_N_UPLIFTS], S[K.S_N_PEAKS])
        if need <= cap or cap >= max(max_impacts, 1):
            break
        cap = int(min(max(need, 2 * cap), max_impacts))
    return S, th, om, pv, imp, up, pk


# ----------------------------------------------------------------------------- batches ----
#: Slot of each summary quantity (:data:`murus.rocking.summary.SUMMARY`), and of its earlier
#: names, in the summary vectors of a :class:`BatchResult`.
SUMMARY_FIELDS = {**{q.name: i for i, q in enumerate(SUMMARY)},
                  **{a: i for i, q in enumerate(SUMMARY) for a in q.aliases}}


@dataclass
class BatchResult:
    """Summaries of ``len(models) x len(motions)`` histories.

    ``result[name]`` is the quantity ``name`` of :data:`murus.rocking.summary.SUMMARY` (or one
    of its earlier names, :data:`SUMMARY_FIELDS`) as an array of shape ``(n_models,
    n_motions)``, in the units declared there (rad, s, J, counts; ``overturned`` 1/0, times
    not reached nan); ``theta_max_over_alpha`` [-] and ``overturned`` (bool) are properties.

    Attributes
    ----------
    raw : ndarray
        The full summary vectors, shape ``(n_models, n_motions, len(SUMMARY))``, each slot in
        the units of its quantity.
    alpha : ndarray
        Slenderness angle of each model [rad], shape ``(n_models,)``.
    """

    raw: np.ndarray
    alpha: np.ndarray

    def __getitem__(self, name: str) -> np.ndarray:
        return self.raw[..., SUMMARY_FIELDS[name]]

    @property
    def theta_max_over_alpha(self) -> np.ndarray:
        return self["theta_max"] / self.alpha[:, None]

    @property
    def overturned(self) -> np.ndarray:
        return self["overturned"] > 0.5

    @property
    def shape(self) -> tuple[int, int]:
        return self.raw.shape[:2]


def _pack_motions(excs: list[Excitation]):
    arrays = [e.arrays() for e in excs]
    lengths = np.array([a[0].size for a in arrays], dtype=np.int64)
    offsets = np.zeros(len(arrays), dtype=np.int64)
    if len(arrays) > 1:
        offsets[1:] = np.cumsum(lengths)[:-1]
    ag_flat = np.concatenate([a[0] for a in arrays]) if lengths.sum() else np.zeros(0)
    has_v = [a[1].size == a[0].size and a[0].size > 0 for a in arrays]
    if any(has_v):
        av_flat = np.concatenate(
            [a[1] if hv else np.zeros(a[0].size) for a, hv in zip(arrays, has_v, strict=True)]
        )
    else:
        av_flat = np.zeros(0)
    return ag_flat, av_flat, offsets, lengths


def simulate_batch(
    models,
    motions,
    *,
    duration: float | None = None,
    theta0: float = 0.0,
    omega0: float = 0.0,
    rtol: float = RTOL,
    max_steps: int = 50_000_000,
    threads: int | None = None,
) -> BatchResult:
    """Run every model under every motion, in parallel over the cores (event-driven method).

    Each case is computed by the same kernel as :func:`simulate`, so that its summary is the
    same number for number; only the histories are not kept. The batch is one parallel loop
    over whole histories, so a thread that shares its core with another process delays it
    little: the default keeps every thread on a busy machine too
    (``benchmarks/bench_threads.py``).

    Parameters
    ----------
    models : sequence
        :class:`RockingModel` or :class:`RigidBlock` objects (Housner (1963) restitution by
        default).
    motions : sequence
        GroundMotions (``acc`` [m/s²]), excitations of :mod:`murus.rocking.excitation`, or
        ``None`` for free vibration.
    duration : float, optional
        End of every analysis [s]; default: per motion, the end of the input plus 5 s of free
        motion (:func:`murus.rocking.excitation.default_duration`).
    theta0 : float
        Initial rotation [rad] of every case.
    omega0 : float
        Initial angular velocity [rad/s] of every case.
    rtol : float
        Relative tolerance of the event-driven integrator [-] (absolute: ``rtol * alpha``);
        default :data:`murus.rocking.defaults.RTOL`.
    max_steps : int
        Step budget of each history [-] (status 2 when exhausted).
    threads : int, optional
        numba threads (default: ``MURUS_THREADS``, else ``numba.get_num_threads()``;
        :mod:`murus.threads`).

    Returns
    -------
    BatchResult
        The summaries, shape ``(len(models), len(motions))``.

    References
    ----------
    Mordant et al. (SERIES), eq. 16 (the iterated restitution variant, whose cases are re-run
    until their largest rotation no longer moves).
    """
    mdls = [as_model(m) for m in models]
    excs = [as_excitation(m) for m in motions]
    if not mdls or not excs:
        raise ModelError("simulate_batch needs at least one model and one motion")
    nm, nx = len(mdls), len(excs)
    Pm = np.array([m.params() for m in mdls], dtype=K.PARAM_DTYPE)
    Xm = np.stack([e.vector() for e in excs])
    ag_flat, av_flat, offsets, lengths = _pack_motions(excs)
    t_end_m = (np.array([default_duration(e) for e in excs]) if duration is None
               else np.full(nx, float(duration)))
    im, ix = np.meshgrid(np.arange(nm), np.arange(nx), indexing="ij")
    im = im.ravel()
    ix = ix.ravel()
    nc = im.size
    if nc and av_flat.size and av_flat.size != ag_flat.size:  # pragma: no cover
        raise ModelError("internal: vertical records misaligned")
    Pc = np.ascontiguousarray(Pm[im])
    Xc = np.ascontiguousarray(Xm[ix])

    fixed = _threads.resolve(threads)

    def run(sel):
        with _threads.using(fixed):
            return K.batch_event(Pc[sel], Xc[sel], ag_flat, av_flat, offsets[ix][sel],
                                 lengths[ix][sel], t_end_m[ix][sel],
                                 np.full(sel.size, float(theta0)),
                                 np.full(sel.size, float(omega0)), float(rtol), int(max_steps))

    raw = run(np.arange(nc))
    # the iterated variant of Mordant et al. (SERIES) eq. 16: re-run the cases whose largest
    # rotation moved
    iterated = np.array([getattr(m.restitution, "variant", "") == "iterated" for m in mdls])
    todo = np.flatnonzero(iterated[im])
    for _ in range(max((m.restitution.max_iterations for m in mdls if
                        getattr(m.restitution, "variant", "") == "iterated"), default=0)):
        todo = todo[(raw[todo, K.S_OVERTURNED] == 0.0) & (raw[todo, K.S_THETA_MAX] > 0.0)]
        target = raw[todo, K.S_THETA_MAX]
        moved = np.abs(target - Pc["e_absmax"][todo]) > 1e-9 * target
        todo = todo[moved]
        if todo.size == 0:
            break
        Pc["e_absmax"][todo] = raw[todo, K.S_THETA_MAX]
        raw[todo] = run(todo)
    return BatchResult(raw=raw.reshape(nm, nx, K.S_SIZE),
                       alpha=np.array([m.body.alpha for m in mdls]))
