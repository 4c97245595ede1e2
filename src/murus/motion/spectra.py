"""Linear elastic response spectra (SD, SV, SA, PSV, PSA) of a ground motion.

The response of a linear single-degree-of-freedom oscillator of period T [s] and damping ratio xi
to the piecewise-linear interpolant of the record is computed by the exact recurrence of
Nigam and Jennings (1969, Bull. Seismol. Soc. Am. 59(2), 909-922) in a numba kernel
(:mod:`murus.motion._kernels`). The peak between two steps is missed by any step-based method, so
short periods (T < 10 dt) are sub-stepped (``oversample``) and every interior extremum is refined
by cubic Hermite interpolation of the exact state and its derivative.

Definitions (omega = 2 pi / T): SD = max |u| [m], SV = max |u'| [m/s], SA = max |u'' + a_g|
[m/s²] (absolute acceleration), PSV = omega SD [m/s], PSA = omega² SD [m/s²].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus.motion._kernels import sdof_peaks, sdof_sd_peaks
from murus.motion.core import GroundMotion

__all__ = ["ResponseSpectrum", "response_spectrum", "pseudo_spectrum", "default_periods", "psa"]

#: minimum number of (sub-)steps per oscillator period with ``oversample="auto"``
POINTS_PER_PERIOD = 10


def default_periods(n: int = 100, t_min: float = 0.01, t_max: float = 10.0) -> np.ndarray:
    """``n`` log-spaced periods [s] from ``t_min`` to ``t_max``.

    Parameters
    ----------
    n : int
        Number of periods.
    t_min, t_max : float
        [s].

    Returns
    -------
    numpy.ndarray
    """
    return np.geomspace(t_min, t_max, n)


@dataclass(frozen=True)
class ResponseSpectrum:
    """Response spectrum arrays (SI units), one value per period.

    period [s], sd [m], sv [m/s], sa [m/s²] (absolute), psv [m/s], psa [m/s²]; damping ratio;
    ``substeps`` the number of sub-steps per record step used at each period. Also readable as a
    mapping: ``spec["psa"]``.

    Attributes
    ----------
    period : numpy.ndarray
        [s].
    sd, sv, sa : numpy.ndarray
        [m], [m/s], [m/s²] (``sa`` absolute).
    psv, psa : numpy.ndarray
        [m/s], [m/s²].
    damping : float
        [-].
    substeps : numpy.ndarray
        Sub-steps per record step at each period.
    """

    period: np.ndarray
    sd: np.ndarray
    sv: np.ndarray
    sa: np.ndarray
    psv: np.ndarray
    psa: np.ndarray
    damping: float
    substeps: np.ndarray

    def __getitem__(self, key: str) -> np.ndarray:
        if key not in ("period", "sd", "sv", "sa", "psv", "psa"):
            raise KeyError(key)
        return getattr(self, key)

    def keys(self):
        return ("period", "sd", "sv", "sa", "psv", "psa")

    def at(self, period: float, what: str = "psa") -> float:
        """Value of ``what`` at ``period`` [s] (log-log interpolation between computed periods)."""
        y = getattr(self, what)
        return float(np.exp(np.interp(np.log(period), np.log(self.period), np.log(y))))


def damping_and_periods(damping, periods, zero_ok: bool = False) -> tuple[float, np.ndarray]:
    """The damping ratio (in [0, 1)) and the periods [s] of a spectrum, checked: ``periods``
    ``None`` gives :func:`default_periods`; finite and > 0 (>= 0 with ``zero_ok``: T = 0 is the
    peak ground acceleration). Raises ``ValueError`` naming what is wrong."""
    xi = float(damping)
    if not (0.0 <= xi < 1.0):
        raise ValueError(f"damping ratio must be in [0, 1), got {damping!r}")
    T = default_periods() if periods is None else np.atleast_1d(np.asarray(periods, float))
    if T.ndim != 1 or np.any(~np.isfinite(T)) or np.any(T < 0 if zero_ok else T <= 0):
        raise ValueError(f"periods must be finite and {'>=' if zero_ok else '>'} 0 s")
    return xi, T


def _substeps(periods: np.ndarray, dt: float, oversample) -> np.ndarray:
    if oversample == "auto" or oversample is None:
        m = np.ceil(POINTS_PER_PERIOD * dt / periods)
        return np.maximum(m, 1).astype(np.int64)
    m = int(oversample)
    if m < 1:
        raise ValueError(f"oversample must be 'auto' or an integer >= 1, got {oversample!r}")
    return np.full(periods.size, m, dtype=np.int64)


def response_spectrum(
    motion: GroundMotion,
    periods=None,
    damping: float = 0.05,
    oversample="auto",
    tail: float = 0.0,
    refine: bool = True,
) -> ResponseSpectrum:
    """Response spectrum of ``motion`` (horizontal component).

    Parameters
    ----------
    motion : GroundMotion
        Record (acceleration in m/s²).
    periods : array_like of float, optional
        Oscillator periods [s], > 0 (a period of 0 returns PGA for SA and PSA and 0 for SD, SV).
        Default: 100 log-spaced periods from 0.01 to 10 s.
    damping : float
        Damping ratio xi (fraction of critical), 0 <= xi < 1.
    oversample : "auto" or int
        Sub-steps per record step: "auto" uses ceil(10 dt / T) at each period (at least 10
        points per oscillator period), an integer forces that number at every period.
    tail : float
        Seconds of zero acceleration appended (free vibration after the record) [s].
    refine : bool
        Refine peaks between (sub-)steps by cubic Hermite interpolation (default). With
        ``refine=False, oversample=1`` the peaks are sampled at the record steps only, the
        classical (biased low at short periods) definition used by most published tables.

    Returns
    -------
    ResponseSpectrum
        With ``period``, ``sd``, ``sv``, ``sa``, ``psv``, ``psa`` arrays.

    Reference: Nigam and Jennings (1969), exact for the piecewise-linear input.
    """
    xi, T = damping_and_periods(damping, periods, zero_ok=True)
    acc = motion.acc
    if tail > 0:
        acc = np.concatenate([acc, np.zeros(int(math.ceil(tail / motion.dt)))])
    pos = T > 0
    Tp = T[pos]
    m = _substeps(Tp, motion.dt, oversample)
    sd = np.zeros(T.size)
    sv = np.zeros(T.size)
    sa = np.zeros(T.size)
    msub = np.ones(T.size, dtype=np.int64)
    if Tp.size:
        d, v, a = sdof_peaks(acc, motion.dt, 2.0 * np.pi / Tp, xi, m, refine)
        sd[pos], sv[pos], sa[pos] = d, v, a
        msub[pos] = m
    pga = float(np.max(np.abs(acc)))
    sa[~pos] = pga
    w = np.zeros(T.size)
    w[pos] = 2.0 * np.pi / Tp
    psa_ = w * w * sd
    psa_[~pos] = pga
    return ResponseSpectrum(
        period=T, sd=sd, sv=sv, sa=sa, psv=w * sd, psa=psa_, damping=xi, substeps=msub
    )


def pseudo_spectrum(motion: GroundMotion, periods=None, damping: float = 0.05,
                    oversample="auto", refine: bool = True) -> np.ndarray:
    """Pseudo-spectral acceleration PSA = omega² SD [m/s²] only, at ``periods`` [s] (> 0).

    Same method and accuracy as :func:`response_spectrum` (which it matches to round-off), about
    7 times faster: only the displacement peak is tracked, all oscillators advance together, and
    a record step is sub-stepped only when a rigorous bound says that it may hold a new peak
    (see :func:`murus.motion._kernels.sdof_sd_peaks`). Use it for PSA-only work (scaling,
    spectrum matching, sweeps).

    Parameters
    ----------
    motion : GroundMotion
        The record (m/s²).
    periods : array_like, optional
        [s] (default :func:`default_periods`).
    damping : float
        [-].
    oversample : int or str
        Sub-steps per record step, or ``"auto"``.
    refine : bool
        Refine the peaks between samples.

    Returns
    -------
    numpy.ndarray
        PSA [m/s²].

    References
    ----------
    Nigam and Jennings (1969).
    """
    xi, T = damping_and_periods(damping, periods)
    w = 2.0 * np.pi / T
    sd = sdof_sd_peaks(motion.acc, motion.dt, w, xi, _substeps(T, motion.dt, oversample), refine)
    return w * w * sd


def psa(motion: GroundMotion, period: float, damping: float = 0.05) -> float:
    """Pseudo-spectral acceleration [m/s²] at one period [s].

    Parameters
    ----------
    motion : GroundMotion
        The record (m/s²).
    period : float
        [s].
    damping : float
        [-].

    Returns
    -------
    float
        [m/s²].
    """
    return float(pseudo_spectrum(motion, [period], damping)[0])
