"""Base excitations as the rocking kernels see them.

Two kinds: a sampled record (uniform step, linear between samples, zero after its end), and an
analytic harmonic pulse ``a(t) = A sin(omega (t - t0) + phase)`` on ``[t0, t0 + duration]``,
evaluated exactly (no sampling error) so that closed-form solutions can be verified to 1e-4.
A :class:`murus.motion.GroundMotion` (or anything with ``dt``, ``acc`` and ``acc_v``) becomes a
:class:`Record`. Accelerations in m/s², times in s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from murus.errors import MurusError
from murus.rocking import kernels as K


class ExcitationError(MurusError, ValueError):
    """An excitation that cannot drive a simulation."""


@dataclass(frozen=True)
class Record:
    """A sampled ground acceleration with uniform step ``dt`` [s]; ``acc`` and the optional
    vertical ``acc_v`` in m/s² (positive upward).

    Parameters
    ----------
    dt : float
        Time step [s] (> 0).
    acc : array_like
        Horizontal ground acceleration [m/s²], at least two samples.
    acc_v : array_like, optional
        Vertical ground acceleration [m/s²], positive upward, as long as ``acc``.
    name : str
        Label of the record.
    meta : dict
        Free metadata (event, station ...).
    """

    dt: float
    acc: np.ndarray
    acc_v: np.ndarray | None = None
    name: str = "record"
    meta: dict = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        acc = np.ascontiguousarray(self.acc, dtype=np.float64)
        if acc.ndim != 1 or acc.size < 2:
            raise ExcitationError("a record needs at least two acceleration samples")
        if not np.all(np.isfinite(acc)):
            raise ExcitationError("the record has non-finite acceleration values")
        if not (math.isfinite(self.dt) and self.dt > 0.0):
            raise ExcitationError(f"record time step must be positive, got {self.dt!r}")
        object.__setattr__(self, "acc", acc)
        if self.acc_v is not None:
            av = np.ascontiguousarray(self.acc_v, dtype=np.float64)
            if av.shape != acc.shape or not np.all(np.isfinite(av)):
                raise ExcitationError("the vertical record must be finite and as long as acc")
            object.__setattr__(self, "acc_v", av)

    @property
    def end_time(self) -> float:
        return (self.acc.size - 1) * self.dt

    def vector(self) -> np.ndarray:
        X = np.zeros(K.X_SIZE)
        X[K.X_KIND] = 0.0
        X[K.X_DT] = self.dt
        X[K.X_INV_DT] = 1.0 / self.dt
        return X

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        av = self.acc_v if self.acc_v is not None else np.zeros(0)
        return self.acc, av

    def default_output_step(self) -> float:
        return self.dt

    def sample(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Horizontal and vertical acceleration at times ``t`` (zero after the end)."""
        tr = np.arange(self.acc.size) * self.dt
        h = np.interp(t, tr, self.acc, left=0.0, right=0.0)
        v = (
            np.interp(t, tr, self.acc_v, left=0.0, right=0.0)
            if self.acc_v is not None
            else np.zeros_like(np.asarray(t, dtype=float))
        )
        return h, v

    def describe(self) -> dict:
        return {"type": "record", "name": self.name, "dt": self.dt, "npts": int(self.acc.size),
                "pga": float(np.max(np.abs(self.acc))), **{k: v for k, v in self.meta.items()
                                                           if isinstance(v, str | int | float)}}


@dataclass(frozen=True)
class HarmonicPulse:
    """``a(t) = amplitude sin(omega (t - t0) + phase)`` for ``t0 <= t <= t0 + duration``, zero
    elsewhere. ``omega = 0`` with ``phase = pi/2`` is a rectangular pulse.

    Parameters
    ----------
    amplitude : float
        Amplitude [m/s²].
    omega : float
        Circular frequency [rad/s] (>= 0).
    phase : float
        Phase [rad].
    duration : float
        Duration of the pulse [s] (>= 0).
    t0 : float
        Start time [s] (>= 0).
    name : str
        Label of the pulse.
    """

    amplitude: float
    omega: float
    phase: float
    duration: float
    t0: float = 0.0
    name: str = "pulse"

    def __post_init__(self) -> None:
        for key in ("amplitude", "omega", "phase", "duration", "t0"):
            v = getattr(self, key)
            if not math.isfinite(v):
                raise ExcitationError(f"pulse {key} must be finite, got {v!r}")
        if self.duration < 0.0 or self.omega < 0.0 or self.t0 < 0.0:
            raise ExcitationError("pulse duration, frequency and start must be >= 0")

    @property
    def end_time(self) -> float:
        return self.t0 + self.duration

    def vector(self) -> np.ndarray:
        X = np.zeros(K.X_SIZE)
        X[K.X_KIND] = 1.0
        X[K.X_T0] = self.t0
        X[K.X_AMP] = self.amplitude
        X[K.X_OMEGA] = self.omega
        X[K.X_PHASE] = self.phase
        X[K.X_DUR] = self.duration
        # pieces of at most 1/64 of a period for the scan of uplift at rest
        if self.omega > 0.0 and self.duration > 0.0:
            n = max(1, math.ceil(self.duration / (2.0 * math.pi / self.omega / 64.0)))
            X[K.X_PIECE] = self.duration / n
        else:
            X[K.X_PIECE] = max(self.duration, 1e-300)
        return X

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        return np.zeros(0), np.zeros(0)

    def default_output_step(self) -> float:
        if self.duration == 0.0 or self.amplitude == 0.0:
            return 1e-3
        if self.omega > 0.0:
            return min(0.01, 2.0 * math.pi / self.omega / 200.0)
        return min(0.01, max(self.duration, 1e-3) / 100.0)

    def sample(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        t = np.asarray(t, dtype=float)
        inside = (t >= self.t0) & (t <= self.t0 + self.duration)
        h = np.where(inside, self.amplitude * np.sin(self.omega * (t - self.t0) + self.phase), 0.0)
        return h, np.zeros_like(t)

    def describe(self) -> dict:
        return {"type": "harmonic-pulse", "name": self.name, "amplitude": self.amplitude,
                "omega": self.omega, "phase": self.phase, "duration": self.duration,
                "t0": self.t0}


def sine_pulse(amplitude: float, frequency: float, cycles: float = 1.0, t0: float = 0.0):
    """One-sine pulse ``A sin(2 pi f t)`` for ``cycles`` periods (amplitude in m/s², f in Hz).

    Parameters
    ----------
    amplitude : float
        Amplitude ``A`` [m/s²].
    frequency : float
        Frequency ``f`` [Hz] (> 0).
    cycles : float
        Number of periods (> 0).
    t0 : float
        Start time [s].

    Returns
    -------
    HarmonicPulse
    """
    _check_pulse(amplitude, frequency, cycles)
    w = 2.0 * math.pi * frequency
    return HarmonicPulse(amplitude, w, 0.0, cycles / frequency, t0, name="sine-pulse")


def cosine_pulse(amplitude: float, frequency: float, cycles: float = 1.0, t0: float = 0.0):
    """One-cosine pulse ``A cos(2 pi f t)`` for ``cycles`` periods (a jump to A at ``t0``).

    Parameters
    ----------
    amplitude : float
        Amplitude ``A`` [m/s²].
    frequency : float
        Frequency ``f`` [Hz] (> 0).
    cycles : float
        Number of periods (> 0).
    t0 : float
        Start time [s].

    Returns
    -------
    HarmonicPulse
    """
    _check_pulse(amplitude, frequency, cycles)
    w = 2.0 * math.pi * frequency
    return HarmonicPulse(amplitude, w, 0.5 * math.pi, cycles / frequency, t0, name="cosine-pulse")


def rectangular_pulse(amplitude: float, duration: float, t0: float = 0.0):
    """Constant acceleration ``A`` on ``[t0, t0 + duration]``.

    Parameters
    ----------
    amplitude : float
        Acceleration ``A`` [m/s²].
    duration : float
        Duration [s] (> 0).
    t0 : float
        Start time [s].

    Returns
    -------
    HarmonicPulse
    """
    if not (math.isfinite(duration) and duration > 0.0):
        raise ExcitationError(f"pulse duration must be positive, got {duration!r}")
    return HarmonicPulse(amplitude, 0.0, 0.5 * math.pi, duration, t0, name="rectangular-pulse")


def free_vibration():
    """No ground motion (free rocking from initial conditions)."""
    return HarmonicPulse(0.0, 0.0, 0.0, 0.0, 0.0, name="free")


def is_free(exc) -> bool:
    """Whether an excitation is a free vibration (:func:`free_vibration`: no input at all).

    Parameters
    ----------
    exc : Record or HarmonicPulse
        The excitation.

    Returns
    -------
    bool
    """
    return isinstance(exc, HarmonicPulse) and exc.duration == 0.0 and exc.amplitude == 0.0


def default_duration(exc) -> float:
    """Default end of a run [s]: the end of the input plus :data:`FREE_TAIL` (5 s) of free
    motion, or :data:`FREE_VIBRATION_DURATION` (20 s) for a free vibration (no input), the
    same from the API and from a case file.

    Parameters
    ----------
    exc : Excitation
        The input (:func:`murus.rocking.excitation.as_excitation`).

    Returns
    -------
    float
        The duration [s].
    """
    from murus.rocking.summary import FREE_TAIL, FREE_VIBRATION_DURATION

    if is_free(exc):
        return FREE_VIBRATION_DURATION
    return exc.end_time + FREE_TAIL


def _check_pulse(amplitude, frequency, cycles):
    if not math.isfinite(amplitude):
        raise ExcitationError(f"pulse amplitude must be finite, got {amplitude!r}")
    if not (math.isfinite(frequency) and frequency > 0.0):
        raise ExcitationError(f"pulse frequency must be positive, got {frequency!r}")
    if not (math.isfinite(cycles) and cycles > 0.0):
        raise ExcitationError(f"pulse cycles must be positive, got {cycles!r}")


Excitation = Record | HarmonicPulse


def as_excitation(motion) -> Excitation:
    """Turn a GroundMotion-like object (attributes ``dt``, ``acc``, optional ``acc_v``), a
    ``(dt, acc)`` tuple or an excitation into an excitation.

    Parameters
    ----------
    motion : GroundMotion, tuple, Record, HarmonicPulse or None
        ``dt`` [s] and ``acc`` [m/s²] (attributes or a tuple); ``None`` is free vibration.

    Returns
    -------
    Record or HarmonicPulse
    """
    if isinstance(motion, Record | HarmonicPulse):
        return motion
    if motion is None:
        return free_vibration()
    if hasattr(motion, "dt") and hasattr(motion, "acc"):
        return Record(float(motion.dt), np.asarray(motion.acc, dtype=float),
                      getattr(motion, "acc_v", None), name=getattr(motion, "name", "record"),
                      meta=dict(getattr(motion, "meta", {}) or {}))
    if isinstance(motion, tuple) and len(motion) == 2:
        return Record(float(motion[0]), np.asarray(motion[1], dtype=float))
    raise ExcitationError(f"cannot use {type(motion).__name__} as a ground motion")
