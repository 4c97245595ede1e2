"""Three-component records: rotation of a horizontal pair, orientation-independent RotDnn
response spectra (Boore 2010), and a record with its vertical component for the engines.

Orientation convention: an azimuth is measured in degrees clockwise from north (as the
networks write it: CSMIP "360 Deg" = north, "90 Deg" = east). A horizontal pair (a, b) is
right-handed when b points 90° clockwise of a (a = north, b = east). Rotating the pair by
``angle_deg`` gives the components along azimuths az_a + angle and az_a + angle + 90:

    a' =  a cos(angle) + b sin(angle)
    b' = -a sin(angle) + b cos(angle)

RotDnn (Boore 2010): for each oscillator period, the relative displacements u_a(t), u_b(t) of
the two components are computed once; the displacement along an azimuth theta is
u_a cos(theta) + u_b sin(theta); its peak over time is taken for theta = 0, 1, ..., 179°; RotDnn
is the nn-th percentile of those 180 peaks (linear interpolation between order statistics,
``numpy.percentile``), reported as a pseudo-spectral acceleration omega² x peak [m/s²].
RotD100 is the largest, RotD50 the median. The percentiles do not depend on the orientation
of the sensors (up to the 1° grid).

References
----------
Boore, D. M. (2010). Orientation-independent, nongeometric-mean measures of seismic intensity
from two horizontal components of motion. Bull. Seismol. Soc. Am. 100(4), 1830-1835,
doi:10.1785/0120090400.
Nigam, N. C. and Jennings, P. C. (1969). Calculation of response spectra from strong-motion
earthquake records. Bull. Seismol. Soc. Am. 59(2), 909-922 (the exact SDOF recurrence of
:mod:`murus.motion._kernels` used here).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from murus.motion.core import GroundMotion

__all__ = ["rotate", "rotd_spectrum", "RotDSpectrum", "read_components", "horizontal_pair"]

#: minimum number of (sub-)steps per oscillator period for the rotated displacement histories
POINTS_PER_PERIOD = 20


def _check_pair(gm_a: GroundMotion, gm_b: GroundMotion) -> None:
    if gm_a.dt != gm_b.dt:
        raise ValueError(f"the two components have different time steps ({gm_a.dt:g} s and "
                         f"{gm_b.dt:g} s): resample one first")
    if gm_a.npts != gm_b.npts:
        raise ValueError(f"the two components have {gm_a.npts} and {gm_b.npts} samples: "
                         "cut them to a common window first (GroundMotion.sliced)")


def _b_sign(gm_a: GroundMotion, gm_b: GroundMotion) -> float:
    """+1 if b is 90° clockwise of a (or the azimuths are unknown), -1 if 90° anticlockwise;
    ValueError if the declared azimuths are not perpendicular."""
    az_a = gm_a.meta.get("azimuth_deg")
    az_b = gm_b.meta.get("azimuth_deg")
    if az_a is None or az_b is None:
        return 1.0
    d = (float(az_b) - float(az_a)) % 360.0
    if math.isclose(d, 90.0, abs_tol=1e-6):
        return 1.0
    if math.isclose(d, 270.0, abs_tol=1e-6):
        return -1.0
    raise ValueError(f"the components are not perpendicular (azimuths {az_a:g} and {az_b:g} "
                     "degrees)")


def rotate(gm_a: GroundMotion, gm_b: GroundMotion, angle_deg: float
           ) -> tuple[GroundMotion, GroundMotion]:
    """The horizontal pair rotated clockwise by ``angle_deg``.

    Parameters
    ----------
    gm_a, gm_b : GroundMotion
        Two horizontal components with the same dt and number of samples [m/s²]. If both
        declare ``meta["azimuth_deg"]`` they must be perpendicular (b at a + 90° or a - 90°;
        the latter is turned into a right-handed pair); otherwise b is taken at a + 90°.
    angle_deg : float
        Rotation [degrees], clockwise seen from above.

    Returns
    -------
    (GroundMotion, GroundMotion)
        The components along az_a + angle and az_a + angle + 90° (``meta["azimuth_deg"]`` set
        when az_a is known). The vertical component of ``gm_a``, if any, is carried to the
        first one unchanged.

    References
    ----------
    Boore (2010), eq. 1 (the rotated component a cos(theta) + b sin(theta)).
    """
    _check_pair(gm_a, gm_b)
    if not math.isfinite(angle_deg):
        raise ValueError(f"angle_deg {angle_deg!r} is not finite")
    s = _b_sign(gm_a, gm_b)
    th = math.radians(angle_deg)
    c, sn = math.cos(th), math.sin(th)
    a, b = gm_a.acc, s * gm_b.acc
    az = gm_a.meta.get("azimuth_deg")
    az1 = None if az is None else (float(az) + angle_deg) % 360.0
    az2 = None if az is None else (float(az) + angle_deg + 90.0) % 360.0
    meta1 = {**gm_a.meta, "azimuth_deg": az1, "rotated_deg": float(angle_deg),
             "component": f"{az1:g} Deg" if az1 is not None else f"a+{angle_deg:g}"}
    meta2 = {**gm_b.meta, "azimuth_deg": az2, "rotated_deg": float(angle_deg),
             "component": f"{az2:g} Deg" if az2 is not None else f"a+{angle_deg + 90:g}"}
    r1 = GroundMotion(dt=gm_a.dt, acc=a * c + b * sn, acc_v=gm_a.acc_v,
                      name=f"{gm_a.name}_rot{angle_deg:g}", meta=meta1)
    r2 = GroundMotion(dt=gm_a.dt, acc=-a * sn + b * c, name=f"{gm_b.name}_rot{angle_deg:g}",
                      meta=meta2)
    return r1, r2


@dataclass(frozen=True)
class RotDSpectrum:
    """RotDnn pseudo-spectral accelerations of a horizontal pair.

    Attributes
    ----------
    period : numpy.ndarray
        [s].
    psa : dict of float to numpy.ndarray
        RotDnn PSA [m/s²] for each percentile nn.
    damping : float
        [-].
    angle_max_deg : numpy.ndarray
        Azimuth offset from component a [degrees, 0-179] of the RotD100 peak at each period.
    angles_deg : numpy.ndarray
        The rotation angles used [degrees].
    """

    period: np.ndarray
    psa: dict = field(default_factory=dict)
    damping: float = 0.05
    angle_max_deg: np.ndarray | None = None
    angles_deg: np.ndarray | None = None

    def __getitem__(self, nn) -> np.ndarray:
        return self.psa[float(nn)]


def _hermite_peaks(y0, y1, d0, d1, h):
    """max |p| on [0, h] of the cubic Hermite interpolants of (y0, d0), (y1, d1) (arrays)."""
    c1 = h * d0
    c2 = 3.0 * (y1 - y0) - 2.0 * h * d0 - h * d1
    c3 = 2.0 * (y0 - y1) + h * d0 + h * d1
    best = np.maximum(np.abs(y0), np.abs(y1))
    qa, qb, qc = 3.0 * c3, 2.0 * c2, c1
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = qb * qb - 4.0 * qa * qc
        sq = np.sqrt(np.maximum(disc, 0.0))
        roots = [(-qb - sq) / (2.0 * qa), (-qb + sq) / (2.0 * qa)]
        lin = np.abs(qa) < 1e-300
        roots.append(np.where(lin & (qb != 0.0), -qc / np.where(qb != 0.0, qb, 1.0), -1.0))
        for k, tau in enumerate(roots):
            ok = (tau > 0.0) & (tau < 1.0) & np.isfinite(tau)
            ok &= (disc >= 0.0) & ~lin if k < 2 else lin
            p = y0 + tau * (c1 + tau * (c2 + tau * c3))
            best = np.where(ok, np.maximum(best, np.abs(p)), best)
    return best


def _rotated_peaks(ua, va, ub, vb, cos_t, sin_t, h, refine):
    """Peak over time of |ua cos + ub sin| for every angle (column), refined by cubic Hermite
    interpolation on the two sub-steps around each sampled peak."""
    n = ua.size
    n_ang = cos_t.size
    peaks = np.zeros(n_ang)
    idx = np.zeros(n_ang, dtype=np.int64)
    chunk = max(1, 2_000_000 // max(n_ang, 1))
    for s0 in range(0, n, chunk):
        s1 = min(n, s0 + chunk)
        u = np.abs(np.outer(ua[s0:s1], cos_t) + np.outer(ub[s0:s1], sin_t))
        k = np.argmax(u, axis=0)
        val = u[k, np.arange(n_ang)]
        better = val > peaks
        peaks = np.where(better, val, peaks)
        idx = np.where(better, k + s0, idx)
    if not refine or n < 2:
        return peaks
    for off in (-1, 0):
        i0 = np.clip(idx + off, 0, n - 2)
        i1 = i0 + 1
        y0 = ua[i0] * cos_t + ub[i0] * sin_t
        y1 = ua[i1] * cos_t + ub[i1] * sin_t
        d0 = va[i0] * cos_t + vb[i0] * sin_t
        d1 = va[i1] * cos_t + vb[i1] * sin_t
        ext = d0 * d1 < 0.0
        pk = _hermite_peaks(y0, y1, d0, d1, h)
        peaks = np.where(ext, np.maximum(peaks, pk), peaks)
    return peaks


def rotd_spectrum(gm_a: GroundMotion, gm_b: GroundMotion, periods=None, damping: float = 0.05,
                  percentiles=(50, 100), angle_step_deg: float = 1.0,
                  refine: bool = True) -> RotDSpectrum:
    """RotDnn pseudo-spectral acceleration of a horizontal pair (Boore 2010).

    Parameters
    ----------
    gm_a, gm_b : GroundMotion
        Two perpendicular horizontal components, same dt and number of samples [m/s²].
    periods : array_like of float, optional
        Oscillator periods [s], > 0. Default: :func:`murus.motion.spectra.default_periods`.
    damping : float
        Damping ratio, 0 <= xi < 1.
    percentiles : sequence of float
        The nn of RotDnn, each in [0, 100].
    angle_step_deg : float
        Step of the rotation angles in [0, 180) [degrees]; 1° as in Boore (2010).
    refine : bool
        Refine each angle's peak between (sub-)steps by cubic Hermite interpolation of the
        exact state (as :func:`murus.motion.spectra.response_spectrum` does).

    Returns
    -------
    RotDSpectrum
        ``psa[nn]`` [m/s²] at each period.

    Notes
    -----
    Each record step is split into ceil(20 dt / T) sub-steps (at least 20 points per oscillator
    period; the input stays the same linear interpolant, so the Nigam-Jennings recurrence is
    exact at every sub-step). The displacement and velocity histories of both components are
    computed once per period and rotated, which costs one matrix product per period.

    References
    ----------
    Boore, D. M. (2010), Bull. Seismol. Soc. Am. 100(4), 1830-1835, doi:10.1785/0120090400.
    """
    from murus.motion._kernels import sdof_history
    from murus.motion.spectra import damping_and_periods

    _check_pair(gm_a, gm_b)
    xi, T = damping_and_periods(damping, periods)
    pcts = [float(p) for p in np.atleast_1d(percentiles)]
    if any(not (0.0 <= p <= 100.0) for p in pcts):
        raise ValueError(f"percentiles must be in [0, 100], got {percentiles!r}")
    if not (0 < angle_step_deg <= 90):
        raise ValueError("angle_step_deg must be in (0, 90]")
    angles = np.arange(0.0, 180.0, angle_step_deg)
    th = np.radians(angles)
    cos_t, sin_t = np.cos(th), np.sin(th)
    a = gm_a.acc
    b = _b_sign(gm_a, gm_b) * gm_b.acc
    dt = gm_a.dt
    t = np.arange(a.size) * dt
    out = {p: np.zeros(T.size) for p in pcts}
    angle_max = np.zeros(T.size)
    for j, Tj in enumerate(T):
        m = max(1, int(math.ceil(POINTS_PER_PERIOD * dt / Tj)))
        h = dt / m
        if m > 1:
            tf = np.arange((a.size - 1) * m + 1) * h
            af, bf = np.interp(tf, t, a), np.interp(tf, t, b)
        else:
            af, bf = a, b
        w = 2.0 * np.pi / Tj
        ua, va = sdof_history(np.ascontiguousarray(af), h, w, xi)
        ub, vb = sdof_history(np.ascontiguousarray(bf), h, w, xi)
        peaks = _rotated_peaks(ua, va, ub, vb, cos_t, sin_t, h, refine)
        psa = w * w * peaks
        for p in pcts:
            out[p][j] = float(np.percentile(psa, p))
        angle_max[j] = angles[int(np.argmax(psa))]
    return RotDSpectrum(period=T, psa=out, damping=xi, angle_max_deg=angle_max,
                        angles_deg=angles)


def horizontal_pair(channels: list[GroundMotion]) -> tuple[GroundMotion, GroundMotion]:
    """The two horizontal channels of a three-component record, cut to their common length.

    Parameters
    ----------
    channels : list of GroundMotion
        As returned by :func:`murus.motion.io.read_all`.

    Returns
    -------
    (GroundMotion, GroundMotion)
        In file order. Channels of one station recorded from the same start (CSMIP files)
        may differ in length by a few samples: both are cut to the shorter
        (``meta["cut_to_common"]`` records it).

    Raises
    ------
    ValueError
        Not exactly two horizontal channels, or different time steps.
    """
    hs = [c for c in channels if not c.meta.get("vertical")]
    if len(hs) != 2:
        raise ValueError(f"{len(hs)} horizontal channels: a pair needs exactly 2")
    return tuple(_common(hs))  # type: ignore[return-value]


def _common(chans: list[GroundMotion]) -> list[GroundMotion]:
    dts = {c.dt for c in chans}
    if len(dts) != 1:
        raise ValueError(f"the channels have different time steps {sorted(dts)}: resample "
                         "them first")
    n = min(c.npts for c in chans)
    out = []
    for c in chans:
        if c.npts != n:
            c = GroundMotion(dt=c.dt, acc=c.acc[:n].copy(), name=c.name,
                             meta={**c.meta, "cut_to_common": (c.npts, n)})
        out.append(c)
    return out


def read_components(path, horizontal=None, vertical: bool = True, units: str | None = None,
                    dt: float | None = None, scale: float = 1.0,
                    format: str | None = None) -> GroundMotion:
    """A horizontal channel of a record with the vertical channel as ``acc_v``.

    Parameters
    ----------
    path : str, Path or list of them
        A multi-channel file (CSMIP/DMG, COSMOS), or the files of one station (K-NET .EW,
        .NS, .UD), read with :func:`murus.motion.io.read_all`.
    horizontal : int or str, optional
        The horizontal channel (see :func:`murus.motion.io.select_channel`); default the
        first horizontal one.
    vertical : bool
        Attach the vertical channel (which must exist, exactly once) as ``acc_v``.
    units, dt, format
        As :func:`murus.motion.io.read`.
    scale : float
        Factor applied to both components.

    Returns
    -------
    GroundMotion
        ``acc`` the horizontal channel, ``acc_v`` the vertical one (positive upward, as the
        networks record "Up"; a "Down" channel is negated), both cut to their common length.

    Raises
    ------
    MotionFormatError
        A file that cannot be read, no such channel, or no (or several) vertical channels.
    """
    from murus.motion.io import MotionFormatError, read_all, select_channel

    paths = [path] if isinstance(path, (str, Path)) else list(path)
    if not paths:
        raise ValueError("read_components needs at least one file")
    chans: list[GroundMotion] = []
    for p in paths:
        chans.extend(read_all(p, units=units, dt=dt, format=format))
    where = Path(paths[0]).name if len(paths) == 1 else ", ".join(Path(p).name for p in paths)
    if len(paths) > 1:
        chans = [c.with_meta(channel=k) for k, c in enumerate(chans, start=1)]
    h = select_channel(chans, horizontal, where)
    if h.meta.get("vertical"):
        raise MotionFormatError(f"{where}: channel {h.meta.get('channel')} is vertical; "
                                "choose a horizontal one")
    if not vertical:
        return h.scaled(scale) if scale != 1.0 else h
    vs = [c for c in chans if c.meta.get("vertical")]
    if len(vs) != 1:
        raise MotionFormatError(f"{where}: {len(vs)} vertical channels (need exactly one for "
                                "the vertical component)")
    v = vs[0]
    try:
        h2, v2 = _common([h, v])
    except ValueError as exc:
        raise MotionFormatError(f"{where}: {exc}") from None
    sign = -1.0 if str(v.meta.get("component", "")).strip().lower().startswith("down") else 1.0
    meta = {**h2.meta, "vertical_channel": v.meta.get("channel"),
            "vertical_component": v.meta.get("component")}
    if "cut_to_common" in v2.meta:
        meta["cut_to_common"] = v2.meta["cut_to_common"]
    gm = GroundMotion(dt=h2.dt, acc=h2.acc, acc_v=sign * v2.acc, name=h2.name, meta=meta)
    return gm.scaled(scale) if scale != 1.0 else gm
