"""Synthetic ground motions: harmonic ramps, pulses, band-limited white noise.

Harmonic ramps (Savalle et al. (2022), eq. 5 and Fig. 12):

- S(t) = A t sin(2 pi f t), A the amplitude rate [m/s³] (:func:`harmonic_ramp`);
- S1(t): the ramp up to the peak acceleration A_peak at t_p = A_peak / A, then an envelope that
  decreases linearly to zero over 2 t_p ("the duration of the decreasing part is defined as twice
  the increasing one"), total duration 3 t_p (:func:`two_ramp`);
- S2(t): the ramp truncated when its envelope A t reaches a given acceleration
  (:func:`truncated_ramp`).

Each accepts a vertical component of the same shape and ``vertical_ratio`` (default 0.5,
Savalle et al. (2022) after EN 1998-1) times the amplitude, ``vertical="in_phase"`` (positive peaks
together) or ``"opposition"`` (sign reversed). Vertical acceleration is positive upwards.

Closed forms of the ramp (from rest at t = 0, omega = 2 pi f):
v(t) = A [sin(omega t) / omega² - t cos(omega t) / omega],
u(t) = A [2 (1 - cos(omega t)) / omega³ - t sin(omega t) / omega²].

All accelerations in m/s², times in s, frequencies in Hz.
"""

from __future__ import annotations

import math

import numpy as np

from murus.motion.core import GroundMotion

__all__ = [
    "harmonic_ramp", "two_ramp", "truncated_ramp", "ramp_velocity", "ramp_displacement",
    "sine_pulse", "rectangular_pulse", "ricker", "white_noise",
]


def _grid(duration: float, dt: float) -> np.ndarray:
    if not (dt > 0 and math.isfinite(dt)):
        raise ValueError(f"dt must be positive, got {dt!r}")
    if not (duration > 0 and math.isfinite(duration)):
        raise ValueError(f"duration must be positive, got {duration!r}")
    n = int(math.floor(duration / dt + 1e-9)) + 1
    return dt * np.arange(n)


def _vertical(acc: np.ndarray, vertical: str | None, ratio: float) -> np.ndarray | None:
    if vertical is None or vertical == "none":
        return None
    if vertical in ("in_phase", "in-phase", "phase"):
        return ratio * acc
    if vertical in ("opposition", "opposite", "anti_phase"):
        return -ratio * acc
    raise ValueError(f"vertical must be None, 'in_phase' or 'opposition', got {vertical!r}")


def ramp_velocity(A: float, f: float, t) -> np.ndarray:
    """Closed-form velocity [m/s] of S(t) = A t sin(2 pi f t) from rest.

    Parameters
    ----------
    A : float
        Amplitude rate [m/s³].
    f : float
        Frequency [Hz].
    t : array_like
        Times [s].

    Returns
    -------
    numpy.ndarray
        [m/s].
    """
    w = 2 * np.pi * f
    t = np.asarray(t, float)
    return A * (np.sin(w * t) / w**2 - t * np.cos(w * t) / w)


def ramp_displacement(A: float, f: float, t) -> np.ndarray:
    """Closed-form displacement [m] of S(t) = A t sin(2 pi f t) from rest.

    Parameters
    ----------
    A : float
        Amplitude rate [m/s³].
    f : float
        Frequency [Hz].
    t : array_like
        Times [s].

    Returns
    -------
    numpy.ndarray
        [m].
    """
    w = 2 * np.pi * f
    t = np.asarray(t, float)
    return A * (2 * (1 - np.cos(w * t)) / w**3 - t * np.sin(w * t) / w**2)


def harmonic_ramp(A: float, f: float, duration: float, dt: float = 0.005,
                  vertical: str | None = None, vertical_ratio: float = 0.5) -> GroundMotion:
    """S(t) = A t sin(2 pi f t) (Savalle et al. (2022), eq. 5) for 0 <= t <= duration.

    A: amplitude rate [m/s³]; f: frequency [Hz]; duration, dt [s].

    Parameters
    ----------
    A : float
        Amplitude rate [m/s³].
    f : float
        Frequency [Hz].
    duration : float
        Duration [s].
    dt : float
        Time step [s].
    vertical : str, optional
        Vertical component: ``None``, ``"in-phase"`` or ``"opposition"``.
    vertical_ratio : float
        Its amplitude over the horizontal one [-].

    Returns
    -------
    GroundMotion

    References
    ----------
    Savalle et al. (2022), eq. 5.
    """
    t = _grid(duration, dt)
    acc = A * t * np.sin(2 * np.pi * f * t)
    return GroundMotion(dt=dt, acc=acc, acc_v=_vertical(acc, vertical, vertical_ratio),
                        name=f"ramp_A{A:g}_f{f:g}",
                        meta={"kind": "harmonic_ramp", "A": A, "f": f, "vertical": vertical})


def two_ramp(A: float, f: float, a_peak: float, dt: float = 0.005,
             vertical: str | None = None, vertical_ratio: float = 0.5) -> GroundMotion:
    """Signal S1 of Savalle et al. (2022) (Fig. 12a): envelope A t up to a_peak [m/s²] at t_p =
    a_peak / A, then linear decrease to zero over 2 t_p; carrier sin(2 pi f t). Duration 3 t_p
    [s].

    Parameters
    ----------
    A : float
        Amplitude rate [m/s³].
    f : float
        Frequency [Hz].
    a_peak : float
        Peak of the envelope [m/s²].
    dt : float
        Time step [s].
    vertical : str, optional
        Vertical component: ``None``, ``"in-phase"`` or ``"opposition"``.
    vertical_ratio : float
        Its amplitude over the horizontal one [-].

    Returns
    -------
    GroundMotion

    References
    ----------
    Savalle et al. (2022), Figure 12a.
    """
    if A <= 0 or a_peak <= 0:
        raise ValueError("A and a_peak must be positive")
    tp = a_peak / A
    t = _grid(3 * tp, dt)
    env = np.where(t <= tp, A * t, a_peak * (1 - (t - tp) / (2 * tp)))
    acc = np.maximum(env, 0.0) * np.sin(2 * np.pi * f * t)
    return GroundMotion(dt=dt, acc=acc, acc_v=_vertical(acc, vertical, vertical_ratio),
                        name=f"S1_A{A:g}_f{f:g}",
                        meta={"kind": "two_ramp", "A": A, "f": f, "a_peak": a_peak,
                              "t_peak": tp, "vertical": vertical})


def truncated_ramp(A: float, f: float, a_max: float, dt: float = 0.005,
                   vertical: str | None = None, vertical_ratio: float = 0.5) -> GroundMotion:
    """Signal S2 of Savalle et al. (2022) (Fig. 12b): S(t) = A t sin(2 pi f t) until the envelope A
    t reaches a_max [m/s²], i.e. for 0 <= t <= a_max / A.

    Parameters
    ----------
    A : float
        Amplitude rate [m/s³].
    f : float
        Frequency [Hz].
    a_max : float
        Largest envelope [m/s²].
    dt : float
        Time step [s].
    vertical : str, optional
        Vertical component: ``None``, ``"in-phase"`` or ``"opposition"``.
    vertical_ratio : float
        Its amplitude over the horizontal one [-].

    Returns
    -------
    GroundMotion

    References
    ----------
    Savalle et al. (2022), Figure 12b.
    """
    if A <= 0 or a_max <= 0:
        raise ValueError("A and a_max must be positive")
    gm = harmonic_ramp(A, f, a_max / A, dt, vertical, vertical_ratio)
    return gm.with_meta(kind="truncated_ramp", a_max=a_max)


def sine_pulse(amplitude: float, frequency: float, cycles: float = 1.0, dt: float = 0.001,
               kind: str = "sine", duration: float | None = None) -> GroundMotion:
    """One-sine (a = A sin(2 pi f t)) or one-cosine (a = A cos(2 pi f t)) pulse of ``cycles``
    periods, followed by zeros up to ``duration`` [s] if given. amplitude [m/s²], frequency [Hz].

    Parameters
    ----------
    amplitude : float
        [m/s²].
    frequency : float
        [Hz].
    cycles : float
        Number of periods.
    dt : float
        Time step [s].
    kind : str
        ``"sine"`` or ``"cosine"``.
    duration : float, optional
        Total duration [s].

    Returns
    -------
    GroundMotion
    """
    if frequency <= 0 or cycles <= 0:
        raise ValueError("frequency and cycles must be positive")
    tp = cycles / frequency
    t = _grid(max(tp, duration or 0.0), dt)
    arg = 2 * np.pi * frequency * t
    if kind == "sine":
        acc = amplitude * np.sin(arg)
    elif kind == "cosine":
        acc = amplitude * np.cos(arg)
    else:
        raise ValueError(f"kind must be 'sine' or 'cosine', got {kind!r}")
    acc[t > tp + 1e-12] = 0.0
    return GroundMotion(dt=dt, acc=acc, name=f"{kind}_pulse",
                        meta={"kind": f"{kind}_pulse", "amplitude": amplitude,
                              "frequency": frequency, "cycles": cycles})


def rectangular_pulse(amplitude: float, duration: float, dt: float = 0.001,
                      total: float | None = None) -> GroundMotion:
    """Constant acceleration ``amplitude`` [m/s²] for ``duration`` [s], then zero up to ``total``.

    With the piecewise-linear interpretation of samples the drop is spread over one step; the
    sample at t = duration is amplitude/2 so that the velocity change is exactly
    amplitude * duration (``duration`` is rounded to a whole number of steps).

    Parameters
    ----------
    amplitude : float
        [m/s²].
    duration : float
        Duration of the pulse [s].
    dt : float
        Time step [s].
    total : float, optional
        Total duration [s].

    Returns
    -------
    GroundMotion
    """
    k = int(round(duration / dt))
    if k < 1:
        raise ValueError("duration must be at least one time step")
    n = max(k + 2, int(round((total or 0.0) / dt)) + 1)
    acc = np.zeros(n)
    acc[:k] = amplitude
    acc[k] = 0.5 * amplitude
    return GroundMotion(dt=dt, acc=acc, name="rect_pulse",
                        meta={"kind": "rectangular_pulse", "amplitude": amplitude,
                              "duration": k * dt})


def ricker(peak: float, frequency: float, dt: float = 0.001, duration: float | None = None,
           t0: float | None = None) -> GroundMotion:
    """Ricker wavelet a = peak (1 - 2 pi² f² tau²) exp(-pi² f² tau²), tau = t - t0.

    peak [m/s²] at t0 (default 1.5 / f, where the wavelet is below 1e-8 of its peak);
    frequency f [Hz] is the peak frequency of its Fourier spectrum; duration default 2 t0.

    Parameters
    ----------
    peak : float
        Peak acceleration [m/s²].
    frequency : float
        Peak frequency of the Fourier spectrum [Hz].
    dt : float
        Time step [s].
    duration : float, optional
        Total duration [s].
    t0 : float, optional
        Time of the peak [s].

    Returns
    -------
    GroundMotion
    """
    if frequency <= 0:
        raise ValueError("frequency must be positive")
    t0 = 1.5 / frequency if t0 is None else float(t0)
    t = _grid(duration if duration is not None else 2 * t0, dt)
    x = (np.pi * frequency * (t - t0)) ** 2
    acc = peak * (1 - 2 * x) * np.exp(-x)
    return GroundMotion(dt=dt, acc=acc, name="ricker",
                        meta={"kind": "ricker", "peak": peak, "frequency": frequency, "t0": t0})


def white_noise(duration: float, dt: float = 0.005, rms: float = 1.0,
                band: tuple[float, float] | None = (0.5, 25.0), seed: int | None = 0
                ) -> GroundMotion:
    """Band-limited Gaussian white noise (identification tests, Mordant et al. (SERIES)).

    Gaussian samples are filtered in the frequency domain: Fourier coefficients outside
    ``band`` = (f_lo, f_hi) [Hz] are set to zero (an ideal band-pass), then the record is scaled
    to the root-mean-square ``rms`` [m/s²] exactly. Reproducible for a given ``seed``.

    Parameters
    ----------
    duration : float
        [s].
    dt : float
        Time step [s].
    rms : float
        Root mean square acceleration [m/s²].
    band : tuple of float, optional
        ``(f_lo, f_hi)`` [Hz]; ``None``: unfiltered.
    seed : int, optional
        Seed of the generator.

    Returns
    -------
    GroundMotion
    """
    t = _grid(duration, dt)
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(t.size)
    if band is not None:
        f1, f2 = band
        if not (0 <= f1 < f2):
            raise ValueError("band must be (f_lo, f_hi) with 0 <= f_lo < f_hi")
        X = np.fft.rfft(x)
        f = np.fft.rfftfreq(t.size, dt)
        X[(f < f1) | (f > f2)] = 0.0
        x = np.fft.irfft(X, n=t.size)
    x *= rms / np.sqrt(np.mean(x * x))
    return GroundMotion(dt=dt, acc=x, name="white_noise",
                        meta={"kind": "white_noise", "rms": rms, "band": band, "seed": seed})
