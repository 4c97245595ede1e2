"""The :class:`GroundMotion` type: a uniformly sampled acceleration history.

Units are SI: time in s, acceleration in m/s², velocity in m/s, displacement in m. The sampling is
uniform (``dt``) and the first sample is at t = 0. Between samples the acceleration is taken as
linear (the assumption under which the Nigam-Jennings recurrence of :mod:`murus.motion.spectra`
is exact), so integration to velocity and displacement uses the trapezoidal rule for velocity and
the exact double integral of the piecewise-linear acceleration for displacement.

Positive acceleration is in the positive direction of the horizontal axis of the model that the
motion drives (for rocking: the sign convention of :mod:`murus.rocking`); vertical acceleration
``acc_v`` is positive upwards.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

__all__ = ["GroundMotion", "integrate", "uniform_from_samples"]


def integrate(acc: np.ndarray, dt: float, v0: float = 0.0, d0: float = 0.0):
    """Velocity and displacement of a piecewise-linear acceleration (exact for that interpolant).

    v[i+1] = v[i] + dt (a[i] + a[i+1]) / 2 and
    d[i+1] = d[i] + dt v[i] + dt² (2 a[i] + a[i+1]) / 6.

    Parameters: acc in m/s², dt in s, initial velocity v0 in m/s and displacement d0 in m.
    Returns (velocity [m/s], displacement [m]) arrays of the same length as ``acc``.

    Parameters
    ----------
    acc : numpy.ndarray
        Acceleration [m/s²].
    dt : float
        Time step [s].
    v0, d0 : float
        Initial velocity [m/s] and displacement [m].

    Returns
    -------
    tuple of numpy.ndarray
        Velocity [m/s] and displacement [m].
    """
    a = np.asarray(acc, dtype=np.float64)
    n = a.size
    v = np.empty(n)
    d = np.empty(n)
    if n == 0:
        return v, d
    v[0] = v0
    v[1:] = v0 + np.cumsum(0.5 * dt * (a[:-1] + a[1:]))
    d[0] = d0
    inc = dt * v[:-1] + dt * dt * (2.0 * a[:-1] + a[1:]) / 6.0
    d[1:] = d0 + np.cumsum(inc)
    return v, d


def uniform_from_samples(t: np.ndarray, a: np.ndarray, dt: float | None = None):
    """Resample (t, a) samples onto a uniform grid starting at t[0] (linear interpolation).

    ``dt`` defaults to the median step. Returns (dt, acc). Time must be strictly increasing.

    Parameters
    ----------
    t : numpy.ndarray
        Times [s], strictly increasing.
    a : numpy.ndarray
        Accelerations [m/s²].
    dt : float, optional
        Step [s] (default the median step).

    Returns
    -------
    tuple
        ``(dt, acc)``.
    """
    t = np.asarray(t, dtype=np.float64)
    a = np.asarray(a, dtype=np.float64)
    steps = np.diff(t)
    if dt is None:
        dt = float(np.median(steps))
    n = int(math.floor((t[-1] - t[0]) / dt * (1 + 1e-12))) + 1
    tu = t[0] + dt * np.arange(n)
    return dt, np.interp(tu, t, a)


@dataclass(frozen=True, eq=False)
class GroundMotion:
    """A ground acceleration history sampled at a uniform step.

    Attributes
    ----------
    dt : float
        Time step [s], > 0.
    acc : numpy.ndarray
        Horizontal acceleration [m/s²], float64, at t = i dt.
    acc_v : numpy.ndarray or None
        Vertical acceleration [m/s²], positive upwards, same length as ``acc``.
    name : str
        Short label (file stem, record id).
    meta : dict
        Metadata: ``event``, ``station``, ``component``, ``source_file``, ``format``, ``year``,
        ``magnitude``, ``units_in`` ... (free form; readers fill what the file provides).
    """

    dt: float
    acc: np.ndarray
    acc_v: np.ndarray | None = None
    name: str = ""
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        dt = float(self.dt)
        if not (math.isfinite(dt) and dt > 0.0):
            raise ValueError(f"GroundMotion: dt must be a positive finite number, got {self.dt!r}")
        acc = np.ascontiguousarray(self.acc, dtype=np.float64)
        if acc.ndim != 1 or acc.size < 1:
            raise ValueError("GroundMotion: acc must be a non-empty 1-D array")
        if not np.all(np.isfinite(acc)):
            raise ValueError("GroundMotion: acc contains NaN or infinite values")
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "acc", acc)
        if self.acc_v is not None:
            av = np.ascontiguousarray(self.acc_v, dtype=np.float64)
            if av.shape != acc.shape:
                raise ValueError(
                    f"GroundMotion: acc_v has {av.size} samples, acc has {acc.size}"
                )
            if not np.all(np.isfinite(av)):
                raise ValueError("GroundMotion: acc_v contains NaN or infinite values")
            object.__setattr__(self, "acc_v", av)
        object.__setattr__(self, "meta", dict(self.meta))

    # ------------------------------------------------------------------ properties
    @property
    def npts(self) -> int:
        """Number of samples."""
        return int(self.acc.size)

    @property
    def time(self) -> np.ndarray:
        """Sample times [s], starting at 0."""
        return self.dt * np.arange(self.npts)

    @property
    def duration(self) -> float:
        """Duration (npts - 1) dt [s]."""
        return (self.npts - 1) * self.dt

    @property
    def pga(self) -> float:
        """Peak ground acceleration max |acc| [m/s²]."""
        return float(np.max(np.abs(self.acc)))

    # ------------------------------------------------------------------ derived motions
    def _replace(self, **kw) -> GroundMotion:
        return dataclasses.replace(self, **kw)

    def scaled(self, factor: float) -> GroundMotion:
        """Both components multiplied by ``factor`` (dimensionless); meta['scale'] accumulates."""
        f = float(factor)
        if not math.isfinite(f):
            raise ValueError(f"scale factor must be finite, got {factor!r}")
        meta = dict(self.meta)
        meta["scale"] = meta.get("scale", 1.0) * f
        return self._replace(
            acc=self.acc * f,
            acc_v=None if self.acc_v is None else self.acc_v * f,
            meta=meta,
        )

    def padded(self, seconds: float, before: float = 0.0) -> GroundMotion:
        """Zeros appended (``seconds`` after, ``before`` ahead of the record), rounded up to dt."""
        if seconds < 0 or before < 0:
            raise ValueError("padding must be >= 0 s")
        na = int(math.ceil(seconds / self.dt - 1e-9))
        nb = int(math.ceil(before / self.dt - 1e-9))

        def pad(x):
            return None if x is None else np.concatenate([np.zeros(nb), x, np.zeros(na)])

        return self._replace(acc=pad(self.acc), acc_v=pad(self.acc_v))

    def sliced(self, t0: float = 0.0, t1: float | None = None) -> GroundMotion:
        """Samples with t0 <= t <= t1 [s] (nearest samples), time origin moved to t0."""
        i0 = max(0, int(round(t0 / self.dt)))
        i1 = self.npts - 1 if t1 is None else min(self.npts - 1, int(round(t1 / self.dt)))
        if i1 < i0:
            raise ValueError(f"empty slice [{t0}, {t1}] s")
        sl = slice(i0, i1 + 1)
        return self._replace(
            acc=self.acc[sl].copy(), acc_v=None if self.acc_v is None else self.acc_v[sl].copy()
        )

    def resampled(self, dt: float) -> GroundMotion:
        """Linear interpolation onto a new uniform step ``dt`` [s] (same start, end <= old end).

        Linear interpolation keeps the piecewise-linear interpolant when ``dt`` divides the old
        step; downsampling does not low-pass filter (apply
        :func:`murus.motion.processing.bandpass` first if aliasing matters).
        """
        dt = float(dt)
        if not (math.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be positive, got {dt!r}")
        n = int(math.floor(self.duration / dt * (1 + 1e-12))) + 1
        tn = dt * np.arange(n)
        t = self.time
        return self._replace(
            dt=dt,
            acc=np.interp(tn, t, self.acc),
            acc_v=None if self.acc_v is None else np.interp(tn, t, self.acc_v),
        )

    def velocity(self) -> np.ndarray:
        """Ground velocity [m/s] (trapezoidal integration from rest, exact for linear acc)."""
        return integrate(self.acc, self.dt)[0]

    def displacement(self) -> np.ndarray:
        """Ground displacement [m] (exact double integral of piecewise-linear acc, from rest)."""
        return integrate(self.acc, self.dt)[1]

    def with_meta(self, **kw) -> GroundMotion:
        """A copy with metadata entries added or replaced."""
        meta = dict(self.meta)
        meta.update(kw)
        return self._replace(meta=meta)

    def __repr__(self) -> str:
        v = "" if self.acc_v is None else ", vertical"
        return (
            f"GroundMotion(name={self.name!r}, dt={self.dt:g} s, npts={self.npts}, "
            f"pga={self.pga:.4g} m/s²{v})"
        )

    @classmethod
    def from_samples(cls, t, acc, acc_v=None, name: str = "", meta: dict | None = None,
                     dt: float | None = None) -> GroundMotion:
        """Build from (time, acceleration) samples; non-uniform time is resampled with a warning.

        Time [s] must be strictly increasing; the origin is moved to t[0].
        """
        t = np.asarray(t, dtype=np.float64)
        a = np.asarray(acc, dtype=np.float64)
        if t.size != a.size or t.size < 2:
            raise ValueError("from_samples: need >= 2 samples and equal lengths")
        steps = np.diff(t)
        if np.any(steps <= 0):
            k = int(np.argmax(steps <= 0)) + 1
            raise ValueError(f"time is not increasing at sample {k}")
        meta = dict(meta or {})
        h = float(np.median(steps)) if dt is None else float(dt)
        if np.max(np.abs(steps - h)) > 1e-6 * h:
            warnings.warn(
                f"{name or 'record'}: non-uniform time step ({steps.min():g} to {steps.max():g} s);"
                f" resampled to dt = {h:g} s by linear interpolation",
                stacklevel=2,
            )
            _, a2 = uniform_from_samples(t, a, h)
            av2 = None if acc_v is None else uniform_from_samples(t, acc_v, h)[1]
            meta["resampled"] = True
            return cls(dt=h, acc=a2, acc_v=av2, name=name, meta=meta)
        if dt is None:  # uniform: the span is the most accurate estimate of the step
            h = float((t[-1] - t[0]) / (t.size - 1))
        return cls(dt=h, acc=a, acc_v=acc_v, name=name, meta=meta)
