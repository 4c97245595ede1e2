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
    "trim_arias", "scale_to_pga", "scale_to_sa", "resample", "process", "PROCESSING_ORDER",
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


def resample(motion: GroundMotion, dt: float, antialias: bool = True,
             order: int = 4) -> GroundMotion:
    """Resample onto a uniform step ``dt`` [s] by linear interpolation; when the step grows
    (down-sampling) and ``antialias``, a zero-phase Butterworth low-pass of ``order`` at 0.8
    times the new Nyquist frequency, ``0.4 / dt``, is applied first, so that no energy above
    the new Nyquist frequency folds back into the band kept (Boore and Bommer 2005, §5).

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    dt : float
        New time step [s].
    antialias : bool
        Low-pass before down-sampling.
    order : int
        Order of the anti-alias filter.

    Returns
    -------
    GroundMotion
        A new record.

    References
    ----------
    Boore and Bommer (2005), doi:10.1016/j.soildyn.2004.10.007.
    """
    dt = float(dt)
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"resampling step must be positive, got {dt!r} s")
    if dt > motion.duration:
        raise ValueError(f"resampling step {dt:g} s is longer than the record "
                         f"({motion.duration:g} s)")
    m = motion
    if antialias and dt > motion.dt * (1 + 1e-9):  # then 0.4 / dt is below the old Nyquist
        m = _filter(motion, "lowpass", 0.4 / dt, order)
    return m.resampled(dt)


#: The order in which :func:`process` applies its operations (the usual sequence of
#: strong-motion processing, Boore and Bommer 2005: remove a baseline, taper the ends, filter
#: with zero pads, then resample, cut and scale the processed record).
PROCESSING_ORDER = ("baseline", "taper", "filter", "resample", "trim", "scale")


def _step(m: GroundMotion, text: str) -> GroundMotion:
    done = list(m.meta.get("processing", ()))
    return m.with_meta(processing=done + [text])


def process(motion: GroundMotion, *, baseline: int | None = None,
            baseline_fit: str = "acceleration", taper_fraction: float | None = None,
            highpass_hz: float | None = None, lowpass_hz: float | None = None,
            filter_order: int = 4, resample_dt: float | None = None,
            trim_s: tuple[float, float] | None = None,
            trim_arias_fractions: tuple[float, float] | None = None,
            pga: float | None = None, sa: tuple[float, float] | None = None,
            sa_damping: float = 0.05) -> GroundMotion:
    """Process a record: the operations given, in the order :data:`PROCESSING_ORDER`, each one
    recorded as a line of ``meta['processing']`` (which the writers put in the file's header,
    so that the processing can be repeated).

    The sequence and the defaults follow the common practice of strong-motion processing
    (Boore and Bommer 2005): a polynomial baseline (order 0 on the acceleration: the mean)
    removed first; a cosine taper of the ends (5 % is usual); an acausal (zero-phase)
    Butterworth filter of order 4 with zero pads of 1.5 n / f_c on both sides (Boore 2005);
    high-pass and low-pass together make a band-pass. Then resampling (with an anti-alias
    low-pass when down-sampling, :func:`resample`), trimming by time or by the Arias
    intensity, and scaling to a PGA or to a pseudo-spectral acceleration.

    Parameters
    ----------
    motion : GroundMotion
        The record (acceleration in m/s²).
    baseline : int, optional
        Degree of the polynomial baseline removed (:func:`baseline_correct`).
    baseline_fit : str
        Quantity the baseline is fitted to: ``"acceleration"``, ``"velocity"`` or
        ``"displacement"``.
    taper_fraction : float, optional
        Fraction of the duration tapered at each end [-] (:func:`taper`).
    highpass_hz, lowpass_hz : float, optional
        Corner frequencies [Hz]; both given: a band-pass.
    filter_order : int
        Order of the Butterworth filter.
    resample_dt : float, optional
        New time step [s] (:func:`resample`).
    trim_s : (float, float), optional
        Keep the part between these times [s].
    trim_arias_fractions : (float, float), optional
        Keep the part between these fractions of the Arias intensity (:func:`trim_arias`).
    pga : float, optional
        Scale to this PGA [m/s²].
    sa : (float, float), optional
        (period [s], PSA [m/s²]): scale to this pseudo-spectral acceleration.
    sa_damping : float
        Damping of ``sa`` [-].

    Returns
    -------
    GroundMotion
        The processed record, ``meta['processing']`` listing the operations.

    References
    ----------
    Boore and Bommer (2005), Processing of strong-motion accelerograms: needs, options and
    consequences, Soil Dyn. Earthq. Eng. 25(2), 93-115, doi:10.1016/j.soildyn.2004.10.007.
    Boore (2005), doi:10.1785/0120040160.
    """
    if trim_s is not None and trim_arias_fractions is not None:
        raise ValueError("trim by time or by Arias intensity, not both")
    if pga is not None and sa is not None:
        raise ValueError("scale to a PGA or to a spectral acceleration, not both")
    if not (isinstance(filter_order, int) and 1 <= filter_order <= 12):
        raise ValueError(f"filter order {filter_order!r} must be an integer in 1..12")
    m = motion
    if baseline is not None:
        if not (isinstance(baseline, int) and 0 <= baseline <= 10):
            raise ValueError(f"baseline order {baseline!r} must be an integer in 0..10")
        m = _step(baseline_correct(m, baseline, baseline_fit),
                  f"baseline: polynomial of degree {baseline} fitted to the {baseline_fit} "
                  "removed")
    if taper_fraction is not None:
        if not (math.isfinite(taper_fraction) and 0 < taper_fraction <= 0.5):
            raise ValueError(f"taper fraction {taper_fraction!r} must be in (0, 0.5]")
        m = _step(taper(m, taper_fraction), f"taper: cosine over {taper_fraction:g} of the "
                  "duration at both ends")
    if highpass_hz is not None or lowpass_hz is not None:
        for name, f in (("high-pass", highpass_hz), ("low-pass", lowpass_hz)):
            if f is not None and not (math.isfinite(f) and f > 0):
                raise ValueError(f"{name} corner {f!r} Hz must be positive")
        if highpass_hz is not None and lowpass_hz is not None:
            m = bandpass(m, highpass_hz, lowpass_hz, filter_order)
            what = f"band-pass {highpass_hz:g}-{lowpass_hz:g} Hz"
        elif highpass_hz is not None:
            m = highpass(m, highpass_hz, filter_order)
            what = f"high-pass {highpass_hz:g} Hz"
        else:
            m = lowpass(m, lowpass_hz, filter_order)
            what = f"low-pass {lowpass_hz:g} Hz"
        m = _step(m, f"filter: acausal Butterworth {what}, order {filter_order}, zero pads "
                  "(Boore 2005)")
    if resample_dt is not None:
        old = m.dt
        m = _step(resample(m, resample_dt, order=filter_order),
                  f"resample: dt {old:g} -> {float(resample_dt):g} s by linear interpolation"
                  + (f", anti-alias low-pass {0.4 / resample_dt:g} Hz" if resample_dt > old
                     else ""))
    if trim_s is not None:
        t0, t1 = (float(x) for x in trim_s)
        if not (0 <= t0 < t1 and t0 < m.duration):
            raise ValueError(f"trim [{t0:g}, {t1:g}] s is not inside the record "
                             f"(0 to {m.duration:g} s)")
        m = _step(m.sliced(t0, t1), f"trim: {t0:g} to {min(t1, m.duration):g} s, time origin "
                  "moved to the start")
    if trim_arias_fractions is not None:
        a, b = (float(x) for x in trim_arias_fractions)
        if not 0 <= a < b <= 1:
            raise ValueError(f"Arias fractions {a:g}, {b:g} must satisfy 0 <= start < end <= 1")
        m = trim_arias(m, a, b)
        t0, t1 = m.meta["trim"]
        m = _step(m, f"trim: {a:g} to {b:g} of the Arias intensity ({t0:.4g} to {t1:.4g} s "
                  "of the record before), time origin moved to the start")
    if pga is not None:
        if not (math.isfinite(pga) and pga > 0):
            raise ValueError(f"target PGA {pga!r} m/s² must be positive")
        before = m.pga
        m = scale_to_pga(m, pga)
        m = _step(m, f"scale: x {pga / before:.6g} to PGA {pga:.6g} m/s²")
    if sa is not None:
        T, target = (float(x) for x in sa)
        if not (math.isfinite(T) and T > 0 and math.isfinite(target) and target > 0):
            raise ValueError(f"spectral target ({T!r} s, {target!r} m/s²) must be positive")
        from murus.motion.spectra import psa

        before = psa(m, T, sa_damping)
        m = scale_to_sa(m, T, target, sa_damping)
        m = _step(m, f"scale: x {target / before:.6g} to PSA({T:g} s, {sa_damping:.0%}) "
                  f"{target:.6g} m/s²")
    return m
