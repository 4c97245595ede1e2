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
- Fourier amplitude spectrum |C(f)| = dt |sum a_k exp(-2 pi i f k dt)| [m/s] (the discrete
  approximation of |integral a(t) exp(-2 pi i f t) dt|).
- Housner (spectrum) intensity SI = integral of PSV(T, 5 %) dT from 0.1 to 2.5 s [m]
  (Housner 1952).
- Predominant period Tp: the period of the largest 5 %-damped PSA (Rathje, Abrahamson and Bray
  1998; Rathje, Faraj, Russell and Bray 2004, Earthq. Spectra 20(1), 119-144).
"""

from __future__ import annotations

import numpy as np

from murus import G
from murus.motion.core import GroundMotion

__all__ = [
    "pga", "pgv", "pgd", "arias", "husid", "significant_duration", "d5_75", "d5_95", "cav",
    "mean_period", "summary", "BASELINE", "corrected_peaks", "fourier_amplitude",
    "housner_intensity", "predominant_period", "intensity_measures", "MEASURES",
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


def fourier_amplitude(motion: GroundMotion) -> tuple[np.ndarray, np.ndarray]:
    """Fourier amplitude spectrum of the acceleration.

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        Frequencies [Hz] from 0 to the Nyquist frequency, and amplitudes
        ``dt |rfft(acc)|`` [m/s] (a sine of amplitude A lasting T_d seconds at one of the
        frequencies of the grid has the amplitude A T_d / 2 there).
    """
    f = np.fft.rfftfreq(motion.npts, motion.dt)
    return f, np.abs(np.fft.rfft(motion.acc)) * motion.dt


def housner_intensity(motion: GroundMotion, damping: float = 0.05, t_lo: float = 0.1,
                      t_hi: float = 2.5, n: int = 241) -> float:
    """Housner's spectrum intensity SI = integral of PSV(T) dT from ``t_lo`` to ``t_hi`` [m].

    Trapezoidal rule over ``n`` equally spaced periods (0.01 s apart by default) of the
    pseudo-velocity PSV = omega SD (:func:`murus.motion.spectra.pseudo_spectrum`).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    damping : float
        Damping ratio of the oscillators [-] (5 % as usual today; Housner used 20 %).
    t_lo, t_hi : float
        Bounds of the period range [s].
    n : int
        Number of periods of the rule.

    Returns
    -------
    float
        [m] (m/s integrated over s).

    References
    ----------
    Housner, G. W. (1952), Spectrum intensities of strong-motion earthquakes, Proceedings of
    the Symposium on Earthquake and Blast Effects on Structures, EERI, Los Angeles, 20-36.
    """
    from murus.motion.spectra import pseudo_spectrum

    if not 0 < t_lo < t_hi or n < 2:
        raise ValueError("housner_intensity: need 0 < t_lo < t_hi and n >= 2")
    T = np.linspace(t_lo, t_hi, n)
    psv = pseudo_spectrum(motion, T, damping) * T / (2.0 * np.pi)
    return float(np.sum(0.5 * (psv[1:] + psv[:-1]) * np.diff(T)))


def predominant_period(motion: GroundMotion, damping: float = 0.05, t_lo: float = 0.02,
                       t_hi: float = 4.0, n: int = 400) -> float:
    """The period of the largest pseudo-spectral acceleration [s], on ``n`` log-spaced periods
    from ``t_lo`` to ``t_hi`` (grid step 1.3 % by default).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    damping : float
        [-].
    t_lo, t_hi : float
        [s].
    n : int
        Number of periods.

    Returns
    -------
    float
        [s].

    References
    ----------
    Rathje, Faraj, Russell and Bray (2004), Empirical relationships for frequency content
    parameters of earthquake ground motions, Earthq. Spectra 20(1), 119-144,
    doi:10.1193/1.1643356.
    """
    from murus.motion.spectra import pseudo_spectrum

    T = np.geomspace(t_lo, t_hi, n)
    return float(T[int(np.argmax(pseudo_spectrum(motion, T, damping)))])


#: The intensity measures of :func:`intensity_measures`: key -> (label, units).
MEASURES = {
    "pga": ("PGA", "m/s²"), "pgv": ("PGV", "m/s"), "pgd": ("PGD", "m"),
    "arias": ("Arias intensity", "m/s"), "cav": ("CAV", "m/s"),
    "d5_75": ("significant duration D5-75", "s"), "d5_95": ("significant duration D5-95", "s"),
    "housner": ("Housner intensity (5 %, 0.1-2.5 s)", "m"),
    "tp": ("predominant period (5 % PSA)", "s"), "tm": ("mean period Tm", "s"),
}


def intensity_measures(motion: GroundMotion) -> dict:
    """The measures of :data:`MEASURES` as floats (PGV and PGD after the end correction of
    :func:`corrected_peaks`, as ``murus motion info`` gives them).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).

    Returns
    -------
    dict
        Key of :data:`MEASURES` -> value (SI units).
    """
    s = summary(motion)
    s.update(corrected_peaks(motion))
    s["housner"] = housner_intensity(motion)
    s["tp"] = predominant_period(motion)
    return {k: float(s[k]) for k in MEASURES}
