"""The ``[motion]`` table of a case file: its record reader and its one motion builder.

Every kind of case file (rocking, distinct elements, rocking studies) describes its input motion
with the keys of :class:`murus.config.MotionFields` (a record file, or an analytic pulse); this
module turns such a table into the motion the engine takes, in one place:

- :func:`read_record` reads the record file of the table (resolved next to the case file), with
  one-line :class:`murus.config.CaseError` naming the file, line and key ``[motion.file]``;
- :func:`build_motion` builds the motion of any type: a record, a sine, cosine or rectangular
  pulse, a harmonic ramp (Savalle et al. (2022), eq. 5), free vibration.

Why here: the motion is the one input the three engines share, and this module sits beside the
readers and the synthetic signals it calls, so that no engine imports another's private helpers
(the DEM read records with the rocking case's private reader). Pulses come in two forms: the
rocking engine integrates analytic pulses exactly (:mod:`murus.rocking.excitation`, imported
lazily, only when asked for), the DEM takes sampled ones (:mod:`murus.motion.synthetic`).
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["read_record", "build_motion", "amplitude_si"]

#: Motion types without a base motion to build: no motion, a tilt of the base (DEM).
NO_MOTION = ("none", "tilt")


def amplitude_si(m) -> float:
    """The pulse amplitude of the table ``m`` in m/s², scale included: ``amplitude * scale``
    (m/s²) or ``amplitude_g * G * scale`` (``amplitude_g`` in g; 0 when neither is given).

    Parameters
    ----------
    m : murus.config.MotionFields
        The validated ``[motion]`` table.

    Returns
    -------
    float
        The amplitude [m/s²].
    """
    from murus import G

    if m.amplitude is not None:
        return m.amplitude * m.scale
    return (m.amplitude_g or 0.0) * G * m.scale


def read_record(m, path: Path, text: str):
    """The record of the ``[motion]`` table ``m`` of the case file ``path``.

    Parameters
    ----------
    m : murus.config.MotionFields
        The validated table: ``file`` (relative to the case file's folder), ``units``, ``dt``,
        ``scale``, ``format``, ``channel`` (of a multi-channel file; default the first
        horizontal one) and ``vertical`` (``true``: the file's vertical channel becomes
        ``acc_v``, which the rocking and DEM engines apply; a file name: the vertical channel
        of that file, e.g. the .UD file of a K-NET station).
    path : pathlib.Path
        The case file.
    text : str
        Its TOML text (for the line of ``[motion] file`` in messages).

    Returns
    -------
    murus.motion.GroundMotion
        The record [m/s²], scaled, with at least two samples.

    Raises
    ------
    murus.config.CaseError
        The file is missing, unreadable or too short (key path ``("motion", "file")``).
    """
    from murus.config import fail_at
    from murus.motion import MotionFormatError, read

    f = Path(m.file)
    if not f.is_absolute():
        f = path.parent / f
    if not f.exists():
        raise fail_at(path, text, ("motion", "file"), f"motion file '{m.file}' not found")
    try:
        channel = getattr(m, "channel", None)
        vertical = getattr(m, "vertical", False)
        if vertical:
            from murus.motion.components import read_components

            paths = [f]
            if isinstance(vertical, str):
                vf = Path(vertical)
                paths.append(vf if vf.is_absolute() else path.parent / vf)
            gm = read_components(paths if len(paths) > 1 else f, horizontal=channel,
                                 units=m.units, dt=m.dt, scale=m.scale, format=m.format)
        else:
            gm = read(f, units=m.units, dt=m.dt, scale=m.scale, format=m.format,
                      channel=channel)
    except MotionFormatError as exc:
        raise fail_at(path, text, ("motion", "file"), f"motion file {exc}") from None
    except ValueError as exc:
        raise fail_at(path, text, ("motion", "file"), f"motion file {f.name}: {exc}") from None
    if gm.npts < 2:
        raise fail_at(path, text, ("motion", "file"),
                      f"motion file {f.name}: the record has fewer than two samples")
    return gm


def build_motion(m, path: Path | None, text: str = "", *, kind: str | None = None,
                 sampled_dt: float | None = None, frequency: float | None = None,
                 duration: float | None = None):
    """The motion of the ``[motion]`` table ``m``.

    Parameters
    ----------
    m : murus.config.MotionFields
        The validated table (its subclass of the case schema: ``kind``, and the keys of the
        types it admits: ``duration`` of a rectangular pulse, ``A`` of a harmonic ramp).
    path : pathlib.Path or None
        The case file (a record is read relative to it); only needed for a record.
    text : str
        Its TOML text (for messages).
    kind : str, optional
        The motion type (default ``m.kind``).
    sampled_dt : float, optional
        Time step [s] of sampled pulses and ramps (:mod:`murus.motion.synthetic`, what the DEM
        takes); default: the analytic pulses of :mod:`murus.rocking.excitation`, which the
        rocking engine integrates exactly.
    frequency : float, optional
        Pulse frequency [Hz] instead of ``m.frequency`` (a study sweeping it).
    duration : float, optional
        Duration [s] of a harmonic ramp.

    Returns
    -------
    object or None
        A :class:`murus.motion.GroundMotion` (a record, a sampled pulse or ramp), an analytic
        excitation of :mod:`murus.rocking.excitation` (a pulse, free vibration), or ``None``
        for the types without a base motion (``none``, ``tilt``).

    Raises
    ------
    murus.config.CaseError
        A record that cannot be read (:func:`read_record`).
    ValueError
        A type the table does not admit.

    References
    ----------
    Savalle et al. (2022), eq. 5 (the harmonic ramp S(t) = A t sin(2 pi f t)).
    """
    kind = m.kind if kind is None else kind
    if kind == "record":
        return read_record(m, path, text)
    if kind in NO_MOTION:
        return None
    f = m.frequency if frequency is None else frequency
    if kind == "harmonic-ramp":
        from murus.motion.synthetic import harmonic_ramp

        return harmonic_ramp(m.A * m.scale, f, duration, dt=sampled_dt)
    amp = amplitude_si(m)
    if sampled_dt is not None and kind in ("sine-pulse", "cosine-pulse"):
        from murus.motion.synthetic import sine_pulse

        return sine_pulse(amp, f, m.cycles, dt=sampled_dt,
                          kind="sine" if kind == "sine-pulse" else "cosine")
    from murus.rocking import excitation as ex

    if kind == "sine-pulse":
        return ex.sine_pulse(amp, f, m.cycles)
    if kind == "cosine-pulse":
        return ex.cosine_pulse(amp, f, m.cycles)
    if kind == "rectangular-pulse":
        return ex.rectangular_pulse(amp, m.duration)
    if kind == "free":
        return ex.free_vibration()
    raise ValueError(f"unknown motion type {kind!r}")
