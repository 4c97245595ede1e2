"""Ground-motion intensity measures (SI units).

All integrals are exact for the piecewise-linear interpolant of the record, the interpretation used
throughout :mod:`murus.motion` (velocity and displacement by :func:`murus.motion.core.integrate`).

- PGA [m/s²], PGV [m/s], PGD [m]: peak absolute values.
- Arias intensity I_A = pi / (2 g) * integral a² dt [m/s] (Arias 1970), with g = murus.G.
- Husid plot: cumulative normalised Arias intensity.
- Significant durations D5-75 and D5-95 [s]: time between 5 % and 75 % / 95 % of I_A
  (Trifunac and Brady 1975; Bommer and Martinez-Pereira 1999).
- CAV = integral |a| dt [m/s] (EPRI 1988).
- Mean period Tm = sum(C_i² / f_i) / sum(C_i²) over 0.25 <= f_i <= 20 Hz, C_i the Fourier
  amplitudes [s] (Rathje, Abrahamson and Bray 1998, J. Geotech. Geoenviron. Eng. 124(2)).
"""

from __future__ import annotations

import numpy as np

from murus import G
from murus.motion.core import GroundMotion

__all__ = [
    "pga", "pgv", "pgd", "arias", "husid", "significant_duration", "d5_75", "d5_95", "cav",
    "mean_period", "summary", "BASELINE", "corrected_peaks",
]

#: The baseline correction used for the PGV and PGD that ``murus motion info`` reports.
BASELINE = ("end correction: a linear acceleration c0 + c1 t subtracted so that the final "
            "velocity and displacement are zero (a record that already ends at rest is "
            "unchanged)")


def pga(motion: GroundMotion) -> float:
    """Peak ground acceleration [m/s²].

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    float
        [m/s²].
    """
    return motion.pga


def pgv(motion: GroundMotion) -> float:
    """Peak ground velocity [m/s] (trapezoidal integration from rest).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    float
        [m/s].
    """
    return float(np.max(np.abs(motion.velocity())))


def pgd(motion: GroundMotion) -> float:
    """Peak ground displacement [m] (exact double integration from rest, no baseline fix).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    float
        [m].
    """
    return float(np.max(np.abs(motion.displacement())))


def _cum_sq(acc: np.ndarray, dt: float) -> np.ndarray:
    """Cumulative integral of a² [m²/s³], exact for piecewise-linear a."""
    a0 = acc[:-1]
    a1 = acc[1:]
    inc = dt * (a0 * a0 + a0 * a1 + a1 * a1) / 3.0
    out = np.empty(acc.size)
    out[0] = 0.0
    np.cumsum(inc, out=out[1:])
    return out


def arias(motion: GroundMotion) -> float:
    """Arias intensity I_A = pi/(2 g) * integral a² dt [m/s] (Arias 1970), g = murus.G.

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    float
        [m/s].

    References
    ----------
    Arias (1970).
    """
    return float(np.pi / (2.0 * G) * _cum_sq(motion.acc, motion.dt)[-1])


def husid(motion: GroundMotion) -> np.ndarray:
    """Normalised cumulative Arias intensity at each sample (0 to 1).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    numpy.ndarray
        [-], one value per sample.
    """
    c = _cum_sq(motion.acc, motion.dt)
    if c[-1] <= 0:
        return np.zeros_like(c)
    return c / c[-1]


def _crossing_time(h: np.ndarray, dt: float, level: float) -> float:
    """First time [s] where the (piecewise-linear in time) Husid curve reaches ``level``."""
    i = int(np.searchsorted(h, level, side="left"))
    if i == 0:
        return 0.0
    if i >= h.size:
        return (h.size - 1) * dt
    h0, h1 = h[i - 1], h[i]
    frac = 0.0 if h1 == h0 else (level - h0) / (h1 - h0)
    return (i - 1 + frac) * dt


def significant_duration(motion: GroundMotion, start: float = 0.05, end: float = 0.95) -> float:
    """Time [s] between the instants where the Husid curve reaches ``start`` and ``end``.

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    start, end : float
        Fractions of the Arias intensity [-].

    Returns
    -------
    float
        [s].

    References
    ----------
    Trifunac and Brady (1975); Bommer and Martínez-Pereira (1999).
    """
    if not 0.0 <= start < end <= 1.0:
        raise ValueError("need 0 <= start < end <= 1")
    h = husid(motion)
    if h[-1] <= 0:
        return 0.0
    return _crossing_time(h, motion.dt, end) - _crossing_time(h, motion.dt, start)


def d5_75(motion: GroundMotion) -> float:
    """Significant duration D5-75 [s].

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    float
        [s].

    References
    ----------
    Trifunac and Brady (1975); Bommer and Martínez-Pereira (1999).
    """
    return significant_duration(motion, 0.05, 0.75)


def d5_95(motion: GroundMotion) -> float:
    """Significant duration D5-95 [s].

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    float
        [s].

    References
    ----------
    Trifunac and Brady (1975); Bommer and Martínez-Pereira (1999).
    """
    return significant_duration(motion, 0.05, 0.95)


def cav(motion: GroundMotion) -> float:
    """Cumulative absolute velocity integral |a| dt [m/s], exact for piecewise-linear a
    (zero crossings inside a step are located).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    float
        [m/s].
    """
    a0 = motion.acc[:-1]
    a1 = motion.acc[1:]
    s0, s1 = np.abs(a0), np.abs(a1)
    same = a0 * a1 >= 0
    denom = np.where(same, 1.0, s0 + s1)
    inc = np.where(same, 0.5 * (s0 + s1), 0.5 * (s0 * s0 + s1 * s1) / denom)
    return float(motion.dt * inc.sum())


def mean_period(motion: GroundMotion, fmin: float = 0.25, fmax: float = 20.0) -> float:
    """Mean period Tm [s] of Rathje et al. (1998): sum(C²/f)/sum(C²), fmin <= f <= fmax [Hz].

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    fmin, fmax : float
        Frequency band of the Fourier amplitudes [Hz].

    Returns
    -------
    float
        [s].

    References
    ----------
    Rathje, Abrahamson and Bray (1998).
    """
    n = motion.npts
    c = np.abs(np.fft.rfft(motion.acc)) * motion.dt
    f = np.fft.rfftfreq(n, motion.dt)
    sel = (f >= fmin) & (f <= fmax)
    if not np.any(sel) or np.sum(c[sel] ** 2) == 0:
        raise ValueError("mean_period: no Fourier amplitude in the band [fmin, fmax]")
    c2 = c[sel] ** 2
    return float(np.sum(c2 / f[sel]) / np.sum(c2))


def corrected_peaks(motion: GroundMotion) -> dict:
    """PGV [m/s] and PGD [m] after the baseline correction :data:`BASELINE`.

    Integrating a record from rest turns a small acceleration offset into a velocity that drifts
    linearly and a displacement that drifts quadratically: the raw PGD of an uncorrected record
    is often meaningless. The correction is :func:`murus.motion.processing.end_correction`: the
    ground is assumed at rest at the end of the record (no permanent displacement), and a
    record that already ends at rest (a processed record, the artificial EN 1998-1 records) is
    left unchanged, so its PGV and PGD are the raw ones. Records with a permanent (fling)
    displacement need a processing of their own (:mod:`murus.motion.processing`).

    Returns
    -------
    dict
        ``pgv``, ``pgd`` after the correction, ``pgv_raw``, ``pgd_raw`` before it, and
        ``baseline`` (the text of :data:`BASELINE`).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    dict
        ``pgv`` [m/s] and ``pgd`` [m].
    """
    from murus.motion.processing import end_correction

    c = end_correction(motion)
    return {"pgv": pgv(c), "pgd": pgd(c), "pgv_raw": pgv(motion), "pgd_raw": pgd(motion),
            "baseline": BASELINE}


def summary(motion: GroundMotion) -> dict:
    """The usual intensity measures as a dict of floats (SI units: see module docstring).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    dict
        Name -> value (SI units).
    """
    out = {
        "npts": motion.npts,
        "dt": motion.dt,
        "duration": motion.duration,
        "pga": pga(motion),
        "pgv": pgv(motion),
        "pgd": pgd(motion),
        "arias": arias(motion),
        "d5_75": d5_75(motion),
        "d5_95": d5_95(motion),
        "cav": cav(motion),
    }
    try:
        out["tm"] = mean_period(motion)
    except ValueError:
        out["tm"] = float("nan")
    return out
