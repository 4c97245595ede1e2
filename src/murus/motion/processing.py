"""Record processing: baseline correction, filters, taper, trimming, scaling.

Filters are Butterworth designs of scipy.signal applied forward and backward (zero phase,
``sosfiltfilt``): the amplitude response of the zero-phase high-pass of order n at frequency f is
|H|² = 1 / (1 + (f_c / f)^(2n)), which the tests check. The record is padded with zeros of
length 1.5 n / f_c on both sides before filtering and the pads are removed after (Boore 2005,
"On pads and filters", Bull. Seismol. Soc. Am. 95(2), 745-750), so no transient of the filter is
left in the record.

scipy.signal is imported inside the functions (heavy import).
"""

from __future__ import annotations

import math

import numpy as np

from murus.motion.core import GroundMotion, integrate

__all__ = [
    "baseline_correct", "end_correction", "highpass", "lowpass", "bandpass", "taper",
    "trim_arias", "scale_to_pga", "scale_to_sa",
]


def baseline_correct(motion: GroundMotion, order: int = 2, fit: str = "velocity") -> GroundMotion:
    """Polynomial baseline correction.

    A polynomial p(t) of degree ``order`` is fitted by least squares to the ``fit`` quantity
    ("acceleration", "velocity" or "displacement", integrated from rest) and its matching
    derivative (p, p' or p'') is subtracted from the acceleration. ``fit="acceleration",
    order=0`` removes the mean; ``fit="velocity", order=1`` removes a constant acceleration
    offset. An acceleration that is itself such a polynomial is removed exactly.

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    order : int
        Degree of the polynomial.
    fit : str
        ``"acceleration"``, ``"velocity"`` or ``"displacement"``.

    Returns
    -------
    GroundMotion
        A new record.
    """
    if order < 0:
        raise ValueError("order must be >= 0")
    t = motion.time
    tau = t / max(t[-1], motion.dt)  # scaled for conditioning
    v, d = integrate(motion.acc, motion.dt)
    y = {"acceleration": motion.acc, "velocity": v, "displacement": d}.get(fit)
    if y is None:
        raise ValueError("fit must be 'acceleration', 'velocity' or 'displacement'")
    P = np.polynomial.Polynomial.fit(tau, y, order, domain=[0, 1], window=[0, 1])
    k = {"acceleration": 0, "velocity": 1, "displacement": 2}[fit]
    scale = max(t[-1], motion.dt)
    corr = P.deriv(k)(tau) / scale**k if k else P(tau)
    return motion._replace(acc=motion.acc - corr)


def end_correction(motion: GroundMotion, zero_ends: bool = False) -> GroundMotion:
    """Subtract a baseline so that the final velocity and the final displacement (from rest) are
    exactly zero (exact for the piecewise-linear integration of
    :func:`murus.motion.core.integrate`).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    zero_ends : bool
        False (default): the baseline is linear in time, c0 + c1 t; it shifts the first and last
        samples by c0 and c0 + c1 T. True: the baseline is c1 sin(pi t / T) + c2 sin(2 pi t / T),
        which vanishes at both ends, so a record that starts and ends at zero acceleration keeps
        doing so (used for the artificial EN 1998-1 records).

    Returns
    -------
    GroundMotion
        The corrected record; its ``meta['baseline']`` names the correction.
    """
    T = motion.duration
    v, d = integrate(motion.acc, motion.dt)
    if zero_ends:
        t = motion.time
        basis = [np.sin(np.pi * t / T), np.sin(2.0 * np.pi * t / T)]
        basis[0][-1] = basis[1][-1] = 0.0  # exactly zero at t = T
        ends = [integrate(b, motion.dt) for b in basis]
        M = np.array([[e[0][-1] for e in ends], [e[1][-1] for e in ends]])
        c = np.linalg.solve(M, [v[-1], d[-1]])
        corr = c[0] * basis[0] + c[1] * basis[1]
        label = "end correction: c1 sin(pi t/T) + c2 sin(2 pi t/T) (final v = d = 0, ends kept)"
    else:
        # integral of c0 + c1 t: v_end = c0 T + c1 T²/2 ; d_end = c0 T²/2 + c1 T³/6
        M = np.array([[T, T * T / 2], [T * T / 2, T**3 / 6]])
        c0, c1 = np.linalg.solve(M, [v[-1], d[-1]])
        corr = c0 + c1 * motion.time
        label = "end correction: c0 + c1 t (final v = d = 0)"
    return motion._replace(acc=motion.acc - corr).with_meta(baseline=label)


def _filter(motion: GroundMotion, btype: str, freq, order: int) -> GroundMotion:
    from scipy import signal

    fs = 1.0 / motion.dt
    f = np.atleast_1d(np.asarray(freq, float))
    if np.any(f <= 0) or np.any(f >= fs / 2):
        raise ValueError(f"corner frequencies must be in (0, {fs / 2:g}) Hz (Nyquist)")
    sos = signal.butter(order, f if f.size > 1 else f[0], btype=btype, fs=fs, output="sos")
    fc = float(f.min())
    npad = int(math.ceil(1.5 * order / fc / motion.dt)) if btype != "lowpass" else 0
    npad = max(npad, 3 * (2 * order + 1))

    def run(a):
        x = np.concatenate([np.zeros(npad), a, np.zeros(npad)])
        y = signal.sosfiltfilt(sos, x, padtype=None)
        return y[npad:npad + a.size]

    return motion._replace(
        acc=run(motion.acc), acc_v=None if motion.acc_v is None else run(motion.acc_v)
    ).with_meta(**{f"filter_{btype}": f.tolist(), "filter_order": order})


def highpass(motion: GroundMotion, fc: float, order: int = 4) -> GroundMotion:
    """Zero-phase Butterworth high-pass at ``fc`` [Hz] (baseline correction by filtering).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    fc : float
        Corner frequency [Hz].
    order : int
        Order of the Butterworth filter.

    Returns
    -------
    GroundMotion
        A new record.

    References
    ----------
    Boore (2005).
    """
    return _filter(motion, "highpass", fc, order)


def lowpass(motion: GroundMotion, fc: float, order: int = 4) -> GroundMotion:
    """Zero-phase Butterworth low-pass at ``fc`` [Hz].

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    fc : float
        Corner frequency [Hz].
    order : int
        Order of the Butterworth filter.

    Returns
    -------
    GroundMotion
        A new record.
    """
    return _filter(motion, "lowpass", fc, order)


def bandpass(motion: GroundMotion, f_lo: float, f_hi: float, order: int = 4) -> GroundMotion:
    """Zero-phase Butterworth band-pass between ``f_lo`` and ``f_hi`` [Hz].

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    f_lo, f_hi : float
        Corner frequencies [Hz].
    order : int
        Order of the Butterworth filter.

    Returns
    -------
    GroundMotion
        A new record.

    References
    ----------
    Boore (2005).
    """
    if not f_lo < f_hi:
        raise ValueError("need f_lo < f_hi")
    return _filter(motion, "bandpass", [f_lo, f_hi], order)


def taper(motion: GroundMotion, fraction: float = 0.05, side: str = "both") -> GroundMotion:
    """Cosine (Tukey) taper over ``fraction`` of the duration at the start, end or both.

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    fraction : float
        Fraction of the duration tapered [-].
    side : str
        ``"start"``, ``"end"`` or ``"both"``.

    Returns
    -------
    GroundMotion
        A new record.
    """
    if not 0 <= fraction <= 0.5:
        raise ValueError("fraction must be in [0, 0.5]")
    n = motion.npts
    m = int(round(fraction * (n - 1)))
    w = np.ones(n)
    if m > 0:
        ramp = 0.5 * (1 - np.cos(np.pi * np.arange(m) / m))
        if side in ("both", "start"):
            w[:m] = ramp
        if side in ("both", "end"):
            w[n - m:] = ramp[::-1]
    return motion._replace(acc=motion.acc * w,
                           acc_v=None if motion.acc_v is None else motion.acc_v * w)


def trim_arias(motion: GroundMotion, start: float = 0.001, end: float = 0.999,
               pad: float = 0.0) -> GroundMotion:
    """Keep the part between the times where the Husid curve reaches ``start`` and ``end``
    (fractions of the Arias intensity), widened by ``pad`` seconds on each side.

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    start, end : float
        Fractions of the Arias intensity [-].
    pad : float
        Time kept on each side [s].

    Returns
    -------
    GroundMotion
        A new record.
    """
    from murus.motion.measures import husid

    h = husid(motion)
    i0 = max(0, int(np.searchsorted(h, start)) - 1)
    i1 = min(motion.npts - 1, int(np.searchsorted(h, end)))
    t0 = max(0.0, i0 * motion.dt - pad)
    t1 = min(motion.duration, i1 * motion.dt + pad)
    return motion.sliced(t0, t1).with_meta(trim=(t0, t1))


def scale_to_pga(motion: GroundMotion, target: float) -> GroundMotion:
    """Scale so that PGA = ``target`` [m/s²].

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    target : float
        PGA [m/s²].

    Returns
    -------
    GroundMotion
        A new record.
    """
    if motion.pga == 0:
        raise ValueError("cannot scale a record of zero PGA")
    return motion.scaled(target / motion.pga)


def scale_to_sa(motion: GroundMotion, period: float, target: float,
                damping: float = 0.05) -> GroundMotion:
    """Scale so that the pseudo-spectral acceleration at ``period`` [s] is ``target`` [m/s²].

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    period : float
        Period [s].
    target : float
        Pseudo-spectral acceleration [m/s²].
    damping : float
        Damping ratio [-].

    Returns
    -------
    GroundMotion
        A new record.
    """
    from murus.motion.spectra import psa

    s = psa(motion, period, damping)
    if s == 0:
        raise ValueError("zero spectral acceleration: cannot scale")
    return motion.scaled(target / s)
