"""Calibration of the modified rocking model against measured rotations (issue 8, item 6).

Mordant et al. (SERIES), §3.3 tunes its modified rocking model (the pivot at the zero-stress point
and the restitution laws of eqs. 14-18) by comparing simulated and measured rotation histories of
the tested walls, step by step (Figures 12 and 15-18), without stating an objective. This module
makes that a least-squares problem:

- parameters: any of ``k0, k1, k0_free, k1_free, A0`` of
  :class:`murus.rocking.restitution.AmplitudeDependent` (Mordant et al. (SERIES), eqs. 14-18), each
  with bounds; the pivot law and the rest of the model are those of the model passed in;
- data: one or several measured rotation histories, each with the base motion that produced
  it (and an initial state for free-vibration tests);
- objective (stated): over a time window (the strong-motion window of the input, Arias
  intensity 5-95 %, extended by ``tail`` seconds to keep the free vibration after it; the
  whole record for free vibration), ``objective="peaks"`` (default) takes the ``n_peaks``
  largest measured half-cycle peaks and compares the extreme rotation (largest |theta|, with
  its sign) within +-``window``/2 of each instant, measured and simulated;
  ``objective="envelope"`` compares the signed extremes in consecutive windows of ``window``
  seconds. Residuals are divided by the largest
  measured |theta| of the history. Rocking is sensitive to small changes (chaotic over long
  records), so peak amplitudes and when they occur, at the resolution of the window, are
  compared rather than the histories point by point. On the synthetic tests of the test suite
  the peaks objective identifies k0 and k1 apart better than the envelope (which mostly fixes
  their sum, the coefficient of the largest half-cycle);
- search: :func:`scipy.optimize.least_squares` (trust region reflective, bounds) from
  ``starts`` points (the initial guess and the best ``starts - 1`` of ``screen`` points of a
  seeded Latin hypercube in the bounds), the best solution kept; finite differences with a
  relative step ``diff_step`` of 2 % (the objective is piecewise smooth: impacts move
  discretely); the measured and the simulated rotations are both smoothed by a centred moving
  average of ``smooth`` seconds (sensor noise would bias every measured maximum upwards);
- report (:class:`CalibrationResult`): fitted values, the cost and the relative RMS error of
  each history, the normalised sensitivity of the residual to each parameter (the norm of
  p dr/dp at the optimum), approximate standard errors and correlations from the Gauss-Newton
  covariance s^2 (J^T J)^-1, and every start's outcome.

Verified in ``tests/identify/test_calibrate.py`` by recovering known parameters from
histories synthesised by :mod:`murus.rocking` with noise added.

Units: s, rad, m/s2.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from murus.errors import MurusError

__all__ = ["CalibrationError", "CalibrationResult", "Measurement", "calibrate",
           "measurement_from_test", "plot_calibration", "PARAMETERS"]

#: The parameters that can be fitted, with the bounds used when none are given.
PARAMETERS: dict[str, tuple[float, float]] = {
    "k0": (0.0, 4.0), "k1": (0.0, 4.0), "k0_free": (0.0, 4.0), "k1_free": (0.0, 4.0),
    "A0": (0.2, 20.0),
}


class CalibrationError(MurusError, ValueError):
    """Bad input to a calibration (unknown parameter, empty data, bounds)."""


@dataclass(frozen=True)
class Measurement:
    """A measured rotation history of a wall, the data of :func:`calibrate`.

    Walls of different aspect ratios calibrated together are what makes A0 of
    Mordant et al. (SERIES), eq. 18 identifiable apart from k0.

    Attributes
    ----------
    t : numpy.ndarray
        Times of the samples [s], 1-D, increasing, at least three.
    theta : numpy.ndarray
        Measured rotation [rad] at ``t``, positive as in :mod:`murus.rocking`.
    motion : murus.motion.GroundMotion or None
        The base motion that produced the history [m/s²]; ``None`` for a free-vibration test.
    theta0 : float
        Initial rotation of the simulation [rad].
    omega0 : float
        Initial angular velocity of the simulation [rad/s].
    name : str
        Label of the history (keys of :attr:`CalibrationResult.rms`).
    model : murus.rocking.RockingModel or None
        The model of this test's wall; ``None``: the model given to :func:`calibrate`.

    Raises
    ------
    CalibrationError
        If ``t`` and ``theta`` are not 1-D of the same length >= 3, not finite, or ``t`` does
        not increase.

    References
    ----------
    Mordant et al. (SERIES), §3.3 and Figures 12, 15-18.
    """

    t: np.ndarray
    theta: np.ndarray
    motion: object = None
    theta0: float = 0.0
    omega0: float = 0.0
    name: str = "test"
    model: object = None

    def __post_init__(self) -> None:
        t = np.asarray(self.t, dtype=float)
        th = np.asarray(self.theta, dtype=float)
        if t.ndim != 1 or t.shape != th.shape or t.size < 3:
            raise CalibrationError(f"{self.name}: t and theta must be 1-D of the same length >= 3")
        if not (np.isfinite(t).all() and np.isfinite(th).all()):
            raise CalibrationError(f"{self.name}: t and theta must be finite")
        if (np.diff(t) <= 0).any():
            raise CalibrationError(f"{self.name}: t must increase")
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "theta", th)


@dataclass
class CalibrationResult:
    """Outcome of :func:`calibrate` (see the module docstring for the objective).

    The residuals are dimensionless: each is a rotation difference divided by the largest
    measured |theta| of its history.

    Attributes
    ----------
    params : dict of str to float
        Fitted value of each calibrated parameter (``k0, k1, k0_free, k1_free`` [-],
        ``A0`` [-], as in :class:`murus.rocking.restitution.AmplitudeDependent`).
    cost : float
        Half the sum of the squared residuals at the optimum [-] (``scipy.optimize``'s cost).
    rms : dict of str to float
        Relative RMS error of each history at the optimum [-], by :attr:`Measurement.name`.
    sensitivity : dict of str to float
        Norm of ``p dr/dp`` at the optimum [-], per parameter: the change of the residual
        vector for a relative change of the parameter.
    std_error : dict of str to float
        Approximate standard error of each parameter [same unit as the parameter], from the
        Gauss-Newton covariance ``s^2 (J^T J)^-1`` with ``s^2 = r.r / (n - p)``.
    correlation : numpy.ndarray
        Correlation matrix of the parameters [-], shape (p, p), in the order of ``params``.
    starts : list of dict
        Every start's outcome: ``start`` and ``params`` (dicts), ``cost`` [-], ``nfev`` (number
        of evaluations) and ``status`` (of :func:`scipy.optimize.least_squares`).
    objective : str
        ``"peaks"`` or ``"envelope"``.
    n_residuals : int
        Number of residuals over all histories.

    References
    ----------
    Mordant et al. (SERIES), §3.3 and eqs. 14-18.
    """

    params: dict[str, float]
    cost: float
    rms: dict[str, float]
    sensitivity: dict[str, float]
    std_error: dict[str, float]
    correlation: np.ndarray
    starts: list[dict] = field(repr=False)
    objective: str = "envelope"
    n_residuals: int = 0

    def table(self) -> str:
        """A Markdown table of the fitted values."""
        lines = ["| parameter | value | std. error | sensitivity |", "|---|---|---|---|"]
        for k, v in self.params.items():
            lines.append(f"| {k} | {v:.4g} | {self.std_error[k]:.2g} | "
                         f"{self.sensitivity[k]:.3g} |")
        lines.append("")
        lines.append("Relative RMS error per history: " + ", ".join(
            f"{n} {e:.3f}" for n, e in self.rms.items()))
        return "\n".join(lines)


def with_params(model, params: dict):
    """``model`` with its restitution law replaced by the AmplitudeDependent law
    (Mordant et al. (SERIES) eqs. 14-18) of ``params``; the other parameters are kept from the
    model's law if it is one, else they take the law's defaults."""
    from murus.rocking.restitution import AmplitudeDependent

    law = model.restitution if isinstance(model.restitution, AmplitudeDependent) \
        else AmplitudeDependent()
    return dataclasses.replace(model, restitution=dataclasses.replace(law, **params))


def _named(names, values) -> dict[str, float]:
    return {k: float(v) for k, v in zip(names, values, strict=True)}


def _window(m: Measurement, tail: float) -> tuple[float, float]:
    if m.motion is None:
        return float(m.t[0]), float(m.t[-1])
    from murus.motion.measures import husid

    h = husid(m.motion)
    tt = np.arange(h.size) * m.motion.dt
    t0 = float(np.interp(0.05, h, tt))
    t1 = float(np.interp(0.95, h, tt)) + tail
    return max(t0, float(m.t[0])), min(t1, float(m.t[-1]))


def _signed_extreme(x: np.ndarray) -> float:
    """The value of largest magnitude, with its sign (0 for an empty array)."""
    return float(x[np.argmax(np.abs(x))]) if x.size else 0.0


def _features(t: np.ndarray, theta: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Signed extreme of theta in each window [edges[i], edges[i+1])."""
    idx = np.searchsorted(t, edges)
    return np.array([_signed_extreme(theta[idx[i]:idx[i + 1]]) for i in range(edges.size - 1)])


def _smooth(theta: np.ndarray, n: int) -> np.ndarray:
    """Centred moving average over n samples (n = 1: unchanged)."""
    if n <= 1:
        return theta
    return np.convolve(theta, np.ones(n) / n, mode="same")


def _around(t: np.ndarray, theta: np.ndarray, instants: np.ndarray, window: float):
    """Signed extreme of theta within +-window/2 of each instant (the same statistic on the
    measured and on the simulated history, so that the residual vanishes at a perfect fit; the
    sign is kept, so a response of the wrong direction is not mistaken for a good one)."""
    return np.array([_signed_extreme(theta[(t >= tp - window / 2) & (t <= tp + window / 2)])
                     for tp in instants])


def _measured_peaks(m: Measurement, t0: float, t1: float, n: int) -> np.ndarray:
    th = m.theta
    sel = (m.t >= t0) & (m.t <= t1)
    i = np.nonzero(sel)[0]
    if i.size < 3:
        return np.zeros(0, dtype=int)
    a = np.abs(th[i])
    k = np.nonzero((a[1:-1] >= a[:-2]) & (a[1:-1] > a[2:]))[0] + 1
    k = k[np.argsort(a[k])[::-1][:n]]
    return np.sort(i[k])


def calibrate(model, measurements, params, *, bounds: dict | None = None,
              objective: str = "peaks", window: float = 0.25, tail: float = 2.0,
              n_peaks: int = 20, starts: int = 4, screen: int = 40, seed: int = 0,
              diff_step: float = 0.02, smooth: float = 0.02, rtol: float = 1e-8,
              max_nfev: int = 200, progress=None) -> CalibrationResult:
    """Fit restitution parameters of ``model`` (a :class:`murus.rocking.RockingModel`) to
    ``measurements`` (a :class:`Measurement` or a list of them).

    ``params``: the initial values, a dict name -> value among ``PARAMETERS``; the others keep
    the values of ``model.restitution`` if it is an AmplitudeDependent law (else its
    defaults). ``bounds``: name -> (low, high), default ``PARAMETERS``. ``progress``: a
    callable ``progress(evaluations, None, info)`` called after each evaluation of the
    residuals (simulations of every history), e.g. the ``update`` of a
    :func:`murus.progress.progress` block. See the module docstring for the objective and the
    report."""
    from scipy.optimize import least_squares

    from murus.rocking import simulate

    ms = [measurements] if isinstance(measurements, Measurement) else list(measurements)
    if not ms:
        raise CalibrationError("no measurement given")
    if not params:
        raise CalibrationError("no parameter to fit")
    unknown = [k for k in params if k not in PARAMETERS]
    if unknown:
        raise CalibrationError(f"unknown parameter {unknown[0]!r}; choose from "
                               f"{', '.join(PARAMETERS)}")
    if objective not in ("envelope", "peaks"):
        raise CalibrationError(f"objective must be 'envelope' or 'peaks', got {objective!r}")
    if not (window > 0 and math.isfinite(window)):
        raise CalibrationError(f"window must be > 0 s, got {window!r}")
    names = list(params)
    bnd = {**PARAMETERS, **(bounds or {})}
    lo = np.array([bnd[k][0] for k in names], dtype=float)
    hi = np.array([bnd[k][1] for k in names], dtype=float)
    if not (lo < hi).all():
        raise CalibrationError("each bound needs low < high")
    x0 = np.array([params[k] for k in names], dtype=float)
    if ((x0 < lo) | (x0 > hi)).any():
        raise CalibrationError("an initial value lies outside its bounds")

    # what each history contributes: windows (envelope) or peak instants (peaks), on the
    # measured rotation smoothed by a centred moving average of ``smooth`` seconds (sensor
    # noise would otherwise bias every measured maximum upwards)
    plans = []
    for m in ms:
        nav = max(1, int(round(smooth / float(np.median(np.diff(m.t))))))
        m = dataclasses.replace(m, theta=_smooth(m.theta, nav))
        t0, t1 = _window(m, tail)
        if t1 <= t0:
            raise CalibrationError(f"{m.name}: the comparison window is empty")
        scale = float(np.abs(m.theta[(m.t >= t0) & (m.t <= t1)]).max())
        if scale <= 0:
            raise CalibrationError(f"{m.name}: the measured rotation is zero in the window")
        if objective == "envelope":
            edges = np.arange(t0, t1 + 1e-12, window)
            if edges.size < 2:
                edges = np.array([t0, t1])
            target = _features(m.t, m.theta, edges)
            plans.append((m, edges, target, scale, nav))
        else:
            k = _measured_peaks(m, t0, t1, n_peaks)
            if k.size == 0:
                raise CalibrationError(f"{m.name}: no peak in the window")
            tp = m.t[k]
            plans.append((m, tp, _around(m.t, m.theta, tp, window), scale, nav))

    def model_for(x, mdl):
        return with_params(mdl, _named(names, x))

    def simulated(x, m):
        mdl = model_for(x, m.model if m.model is not None else model)
        return simulate(mdl, m.motion, theta0=m.theta0, omega0=m.omega0,
                        duration=float(m.t[-1]) if m.motion is None else None, rtol=rtol,
                        out_dt=min(0.005, float(np.median(np.diff(m.t)))))

    def residual_parts(x):
        parts = []
        for m, ref, target, scale, nav in plans:
            r = simulated(x, m)
            th = np.interp(m.t, r.t, r.theta, right=r.theta[-1])
            if r.overturned:
                th = np.where(m.t >= (r.t_overturn or r.t[-1]), 10 * scale, th)
            th = _smooth(th, nav)
            if objective == "envelope":
                sim = _features(m.t, th, ref)
            else:
                sim = _around(m.t, th, ref, window)
            parts.append((sim - target) / scale)
        return parts

    stage = {"n": 0, "info": "screening"}

    def residuals(x):
        r = np.concatenate(residual_parts(x))
        stage["n"] += 1
        if progress is not None:
            progress(stage["n"], None, stage["info"])
        return r

    # starts: the initial guess and the best of a Latin-hypercube screen of the bounds (the
    # objective is rough: impacts appear and vanish as the parameters move)
    rng = np.random.default_rng(seed)
    guesses = [x0]
    n_screen = max(int(screen), int(starts) - 1, 0)
    if n_screen and starts > 1:
        u = (rng.permuted(np.tile(np.arange(n_screen), (len(names), 1)), axis=1).T
             + rng.random((n_screen, len(names)))) / n_screen
        pts = lo + u * (hi - lo)
        costs = np.array([float(np.sum(residuals(q) ** 2)) for q in pts])
        guesses += list(pts[np.argsort(costs)[:int(starts) - 1]])
    runs = []
    best = None
    for k, g in enumerate(guesses):
        stage["info"] = f"least squares from start {k + 1}/{len(guesses)}"
        sol = least_squares(residuals, g, bounds=(lo, hi), method="trf", diff_step=diff_step,
                            x_scale=np.maximum(hi - lo, 1e-9) / 4, max_nfev=max_nfev)
        runs.append({"start": _named(names, g),
                     "params": _named(names, sol.x), "cost": float(sol.cost),
                     "nfev": int(sol.nfev), "status": int(sol.status)})
        if best is None or sol.cost < best.cost:
            best = sol
    x = best.x
    J = best.jac
    r = best.fun
    n, p = r.size, len(names)
    s2 = float(r @ r) / max(n - p, 1)
    try:
        cov = np.linalg.pinv(J.T @ J) * s2
        se = np.sqrt(np.maximum(np.diag(cov), 0.0))
        d = np.where(se > 0, se, 1.0)
        corr = cov / np.outer(d, d)
    except np.linalg.LinAlgError:  # pragma: no cover - pinv does not raise in practice
        se = np.full(p, np.nan)
        corr = np.full((p, p), np.nan)
    sens = np.linalg.norm(J * np.where(x != 0, x, 1.0), axis=0)
    parts = residual_parts(x)
    rms = {m.name: float(np.sqrt(np.mean(q**2))) for (m, *_), q in zip(plans, parts, strict=True)}
    return CalibrationResult(params=_named(names, x), cost=float(best.cost),
                             rms=rms, sensitivity=_named(names, sens),
                             std_error=_named(names, se), correlation=corr,
                             starts=runs, objective=objective, n_residuals=n)


def measurement_from_test(test, channel: str = "rot_bottom", model=None) -> Measurement:
    """A :class:`Measurement` from a shaking-table test (:mod:`murus.identify.testdata`): the
    rotation ``channel`` (the rocking rotation at the base joint, ``rot_bottom``, by default)
    against the table acceleration. The test format takes accelerations positive towards +x
    and rotations positive clockwise (lifting the left end); in :mod:`murus.rocking` a positive
    ground acceleration drives a positive (clockwise) rotation, so the ground motion given to
    the model is minus the table acceleration."""
    from murus.motion import GroundMotion

    if channel not in test.channels:
        raise CalibrationError(f"{test.name}: no channel {channel!r} "
                               f"(have {', '.join(sorted(test.channels))})")
    gm = GroundMotion(dt=test.dt, acc=-test.channels["table_acc"], name=test.name)
    return Measurement(test.t, test.channels[channel], motion=gm, name=test.name, model=model)


def plot_calibration(model, measurement: Measurement, params: dict, ax=None, rtol: float = 1e-8):
    """Measured and calibrated rotation histories of one test on ``ax``; returns the Axes."""
    from murus.rocking import simulate

    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(8, 3))
    mdl = with_params(measurement.model if measurement.model is not None else model, params)
    # a free vibration runs as long as the measurement, as in the calibration itself
    r = simulate(mdl, measurement.motion, theta0=measurement.theta0, omega0=measurement.omega0,
                 duration=float(measurement.t[-1]) if measurement.motion is None else None,
                 rtol=rtol, out_dt=min(0.005, float(np.median(np.diff(measurement.t)))))
    ax.plot(measurement.t, measurement.theta * 1e3, color="0.5", lw=0.8, label="measured")
    ax.plot(r.t, r.theta * 1e3, color="C3", lw=1.0, label="calibrated model")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("rotation [mrad]")
    ax.set_title(measurement.name)
    ax.legend(loc="upper right", fontsize=8)
    return ax
