"""Artificial accelerograms compatible with an elastic response spectrum (EN 1998-1 §3.2.3.1.2).

Generation (:func:`spectrum_compatible`), as for the shaking-table input of Mordant et al. (SERIES):

1. a stationary Gaussian white noise (reproducible with ``seed``) is multiplied by an envelope:
   trapezoidal (linear rise ``rise``, stationary part ``stationary`` >= 10 s, linear decay
   ``decay``) or Jennings-type (quadratic rise, constant, exponential decay; Jennings, Housner
   and Tsai 1968);
2. its Fourier amplitudes are corrected iteratively by the ratio target / computed 5 % PSA,
   interpolated in frequency at f = 1/T (Gasparini and Vanmarcke 1976, SIMQKE); Fourier
   components below ``f_min`` are removed;
3. after every correction the first and last 0.5 s (at most 5 % of the duration) are tapered
   to zero by a cosine window, and a baseline correction that vanishes at both ends
   (:func:`murus.motion.processing.end_correction` with ``zero_ends=True``: c1 sin(pi t/T) +
   c2 sin(2 pi t/T)) makes the final ground velocity and displacement exactly zero; so the
   record starts and ends at zero acceleration, velocity and displacement (a linear baseline
   c0 + c1 t would shift the first sample by c0: up to 14 % of the PGA). The spectrum used for
   the next correction, and the one reported, is that of the corrected record. If the PGA falls
   below ag S the record is scaled up to it.

:func:`check_ec8` reports the EN 1998-1 §3.2.3.1.2 conditions for a set of records: (a) at least
3 records; (b) mean PGA >= ag S; (c) no value of the mean 5 % elastic spectrum below 90 % of the
target in a period range (default [0.2 T1, 2 T1], an input because a rocking wall has no fixed
T1); (d) stationary part of at least 10 s (from the generator's metadata; for other records the
D5-95 significant duration is used as an estimate and the report says so).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from murus.motion.core import GroundMotion
from murus.motion.processing import end_correction
from murus.motion.spectra import pseudo_spectrum

__all__ = ["envelope", "spectrum_compatible", "generate_ec8", "check_ec8", "Criterion",
           "CompatibilityReport"]


def envelope(t: np.ndarray, rise: float, stationary: float, decay: float,
             kind: str = "trapezoidal") -> np.ndarray:
    """Envelope (0 to 1) at times t [s]: rise, stationary and decay durations [s].

    Parameters
    ----------
    t : numpy.ndarray
        Times [s].
    rise, stationary, decay : float
        Durations [s].
    kind : str
        ``"trapezoidal"`` or ``"jennings"``.

    Returns
    -------
    numpy.ndarray
        [-].

    References
    ----------
    Jennings, Housner and Tsai (1968).
    """
    t = np.asarray(t, float)
    t1, t2 = rise, rise + stationary
    if kind == "trapezoidal":
        up = np.clip(t / max(rise, 1e-12), 0, 1)
        down = np.clip(1 - (t - t2) / max(decay, 1e-12), 0, 1)
        return np.where(t <= t2, up, down)
    if kind == "jennings":
        up = np.clip(t / max(rise, 1e-12), 0, 1) ** 2
        c = -math.log(0.05) / max(decay, 1e-12)  # 5 % at the end
        return np.where(t <= t1, up, np.where(t <= t2, 1.0, np.exp(-c * (t - t2))))
    raise ValueError("envelope kind must be 'trapezoidal' or 'jennings'")


def _end_window(n: int, dt: float) -> np.ndarray:
    """Weights of ``n`` samples: 1 except cosine ramps from 0 over the first and the last
    min(0.5 s, 5 % of the duration) (at least 2 samples)."""
    m = max(2, int(round(min(0.5, 0.05 * (n - 1) * dt) / dt)))
    w = np.ones(n)
    ramp = 0.5 * (1.0 - np.cos(np.pi * np.arange(m) / m))
    w[:m] = ramp
    w[n - m:] = ramp[::-1]
    return w


def spectrum_compatible(target, periods, dt: float = 0.01, rise: float = 2.0,
                        stationary: float = 10.0, decay: float = 4.0,
                        envelope_kind: str = "trapezoidal", damping: float = 0.05,
                        iterations: int = 15, f_min: float = 0.1, pga_min: float | None = None,
                        seed: int | None = 0, name: str = "artificial") -> GroundMotion:
    """One artificial record whose PSA matches ``target`` at ``periods``.

    target : array of PSA [m/s²] at ``periods`` [s] (or a callable T -> PSA).
    pga_min : the record is scaled up if its PGA is below this value [m/s²] (EC8: ag S).
    The result carries meta['stationary_duration'], meta['seed'], meta['v_end'], meta['d_end'].

    Parameters
    ----------
    target : array_like or callable
        PSA [m/s²] at ``periods``, or ``T -> PSA``.
    periods : array_like
        Matching periods [s].
    dt : float
        Time step [s].
    rise, stationary, decay : float
        Envelope durations [s].
    envelope_kind : str
        ``"trapezoidal"`` or ``"jennings"``.
    damping : float
        [-].
    iterations : int
        Spectral corrections.
    f_min : float
        Lowest frequency kept [Hz].
    pga_min : float, optional
        Smallest PGA [m/s²].
    seed : int, optional
        Seed of the noise.
    name : str
        Label.

    Returns
    -------
    GroundMotion

    References
    ----------
    Gasparini and Vanmarcke (1976); EN 1998-1 §3.2.3.1.2.
    """
    periods = np.asarray(periods, float)
    tgt = np.asarray(target(periods) if callable(target) else target, float)
    if stationary <= 0 or rise < 0 or decay < 0:
        raise ValueError("envelope durations must be positive")
    n = int(round((rise + stationary + decay) / dt)) + 1
    t = dt * np.arange(n)
    rng = np.random.default_rng(seed)
    env = envelope(t, rise, stationary, decay, envelope_kind)
    acc = rng.standard_normal(n) * env
    f = np.fft.rfftfreq(n, dt)
    fp = 1.0 / periods[::-1]  # increasing frequencies
    ends = _end_window(n, dt)
    gm = GroundMotion(dt=dt, acc=acc, name=name)
    # initial level: match the mean spectral ordinate
    s = pseudo_spectrum(gm, periods, damping)
    gm = gm.scaled(float(np.mean(tgt) / np.mean(s)))
    for _ in range(iterations):
        s = pseudo_spectrum(gm, periods, damping)
        ratio = (tgt / s)[::-1]
        r = np.interp(f, fp, ratio, left=ratio[0], right=ratio[-1])
        X = np.fft.rfft(gm.acc) * r
        X[f < f_min] = 0.0
        a = np.fft.irfft(X, n=n) * ends
        gm = end_correction(GroundMotion(dt=dt, acc=a, name=name), zero_ends=True)
    if pga_min is not None and gm.pga < pga_min:
        gm = gm.scaled(pga_min / gm.pga)
    v = gm.velocity()
    d = gm.displacement()
    meta = {"kind": "artificial", "seed": seed, "baseline": gm.meta.get("baseline"),
            "envelope": envelope_kind, "rise": rise,
            "stationary_duration": stationary, "decay": decay, "iterations": iterations,
            "v_end": float(v[-1]), "d_end": float(d[-1])}
    return GroundMotion(dt=dt, acc=gm.acc, name=name, meta=meta)


def generate_ec8(ag: float, ground: str = "B", spectrum_type: int = 1, n: int = 7,
                 seed: int = 1, damping: float = 0.05, importance=None, dt: float = 0.01,
                 stationary: float = 10.0, rise: float = 2.0, decay: float = 4.0,
                 envelope_kind: str = "trapezoidal", periods=None, iterations: int = 15
                 ) -> list[GroundMotion]:
    """``n`` artificial records compatible with the EN 1998-1 §3.2.2.2 elastic spectrum.

    ag [m/s²] reference PGA on rock; records are reproducible for a given ``seed`` (record k
    uses the seed sequence spawned from ``seed``). Default matching periods: 80 log-spaced
    periods from 0.03 to 4 s.

    Parameters
    ----------
    ag : float
        Reference PGA on rock [m/s²].
    ground : str
        Ground type ``"A"`` ... ``"E"``.
    spectrum_type : int
        1 or 2.
    n : int
        Number of records.
    seed : int
        Seed.
    damping : float
        [-].
    importance : str or float, optional
        Importance class or factor.
    dt : float
        Time step [s].
    stationary, rise, decay : float
        Envelope durations [s].
    envelope_kind : str
        ``"trapezoidal"`` or ``"jennings"``.
    periods : array_like, optional
        Matching periods [s].
    iterations : int
        Spectral corrections.

    Returns
    -------
    list of GroundMotion
    """
    from murus.eurocode.ec8 import elastic_spectrum, parameters

    if n < 1:
        raise ValueError("n must be >= 1")
    T = np.geomspace(0.03, 4.0, 80) if periods is None else np.asarray(periods, float)
    tgt = elastic_spectrum(T, ag, ground, spectrum_type, damping, importance)
    from murus.eurocode.ec8 import _importance

    agS = ag * _importance(importance) * parameters(ground, spectrum_type).S
    seeds = np.random.SeedSequence(seed).spawn(n)
    out = []
    for k in range(n):
        gm = spectrum_compatible(tgt, T, dt=dt, rise=rise, stationary=stationary, decay=decay,
                                 envelope_kind=envelope_kind, damping=damping,
                                 iterations=iterations, pga_min=agS,
                                 seed=int(seeds[k].generate_state(1)[0]),
                                 name=f"ec8_{ground}{spectrum_type}_{k + 1:02d}")
        out.append(gm.with_meta(target=f"EN 1998-1 Type {spectrum_type} ground {ground}",
                                ag=ag, root_seed=seed, index=k + 1))
    return out


@dataclass
class Criterion:
    """One EN 1998-1 §3.2.3.1.2 condition: ``ratio`` = value / required (>= 1 passes).

    Attributes
    ----------
    name : str
        The condition.
    passed : bool
    value, required : float
        Obtained and required values.
    ratio : float
        ``value / required``.
    period : float, optional
        Period of the worst ratio [s].
    note : str
    """

    name: str
    passed: bool
    value: float
    required: float
    ratio: float
    period: float | None = None
    note: str = ""


@dataclass
class CompatibilityReport:
    """Result of :func:`check_ec8`: criteria, the mean spectrum and the target.

    Attributes
    ----------
    criteria : list of Criterion
    periods : numpy.ndarray
        [s].
    mean_psa, target : numpy.ndarray
        [m/s²].
    period_range : tuple of float
        [s].
    spectra : list of numpy.ndarray
        PSA of each record [m/s²].
    """

    criteria: list[Criterion]
    periods: np.ndarray
    mean_psa: np.ndarray
    target: np.ndarray
    period_range: tuple[float, float]
    spectra: list[np.ndarray] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.criteria)

    def to_dict(self) -> dict:
        return {
            "passed": self.passed,
            "period_range": list(self.period_range),
            "criteria": [asdict(c) for c in self.criteria],
        }

    def to_text(self) -> str:
        lines = ["EN 1998-1 §3.2.3.1.2 compatibility check",
                 f"period range [{self.period_range[0]:.3g}, {self.period_range[1]:.3g}] s", ""]
        for c in self.criteria:
            at = f" at T = {c.period:.3g} s" if c.period is not None else ""
            lines.append(
                f"{'PASS' if c.passed else 'FAIL'}  {c.name}: {c.value:.4g} vs required "
                f"{c.required:.4g} (ratio {c.ratio:.3f}{at}){' - ' + c.note if c.note else ''}"
            )
        lines.append("")
        lines.append("overall: " + ("PASS" if self.passed else "FAIL"))
        return "\n".join(lines)


def check_ec8(records: list[GroundMotion], ag: float, ground: str = "B",
              spectrum_type: int = 1, T1: float | None = None, period_range=None,
              damping: float = 0.05, importance=None, min_stationary: float = 10.0,
              n_periods: int = 120) -> CompatibilityReport:
    """EN 1998-1 §3.2.3.1.2 checks of ``records`` against the elastic spectrum.

    ag [m/s²]; the period range is ``period_range`` (s) or [0.2 T1, 2 T1]. Each criterion has
    pass/fail, the worst ratio and, for the spectrum, the period where it occurs.

    Parameters
    ----------
    records : list of GroundMotion
        The records.
    ag : float
        Reference PGA on rock [m/s²].
    ground : str
        Ground type.
    spectrum_type : int
        1 or 2.
    T1 : float, optional
        Fundamental period [s].
    period_range : tuple of float, optional
        [s], instead of ``[0.2 T1, 2 T1]``.
    damping : float
        [-].
    importance : str or float, optional
        Importance class or factor.
    min_stationary : float
        Shortest stationary part [s].
    n_periods : int
        Periods of the check.

    Returns
    -------
    CompatibilityReport
    """
    from murus.eurocode.ec8 import _importance, elastic_spectrum, parameters

    if period_range is None:
        if T1 is None:
            raise ValueError("give T1 [s] or period_range=(T_lo, T_hi)")
        period_range = (0.2 * T1, 2.0 * T1)
    lo, hi = float(period_range[0]), float(period_range[1])
    if not 0 < lo < hi:
        raise ValueError("period range must satisfy 0 < T_lo < T_hi")
    T = np.geomspace(lo, hi, n_periods)
    tgt = elastic_spectrum(T, ag, ground, spectrum_type, 0.05, importance)
    agS = ag * _importance(importance) * parameters(ground, spectrum_type).S
    crit = []
    n = len(records)
    crit.append(Criterion("number of records >= 3", n >= 3, n, 3, n / 3))
    if n == 0:
        return CompatibilityReport(crit, T, np.zeros_like(T), tgt, (lo, hi))
    spectra = [pseudo_spectrum(r, T, damping) for r in records]
    mean = np.mean(spectra, axis=0)
    mpga = float(np.mean([r.pga for r in records]))
    crit.append(Criterion("mean PGA >= ag S", mpga >= agS * (1 - 1e-12), mpga, agS, mpga / agS))
    ratio = mean / tgt
    k = int(np.argmin(ratio))
    crit.append(Criterion("mean 5 % spectrum >= 0.9 Se in range", bool(ratio[k] >= 0.9),
                          float(mean[k]), float(0.9 * tgt[k]), float(ratio[k] / 0.9),
                          float(T[k]), note=f"min mean/target = {ratio[k]:.3f}"))
    durs = []
    estimated = False
    for r in records:
        if "stationary_duration" in r.meta:
            durs.append(float(r.meta["stationary_duration"]))
        else:
            from murus.motion.measures import d5_95

            durs.append(d5_95(r))
            estimated = True
    dmin = float(np.min(durs))
    crit.append(Criterion("stationary part >= 10 s", dmin >= min_stationary, dmin,
                          min_stationary, dmin / min_stationary,
                          note="D5-95 used as estimate" if estimated else ""))
    return CompatibilityReport(crit, T, mean, tgt, (lo, hi), spectra)
