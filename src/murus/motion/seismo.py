"""SAC and miniSEED records through ObsPy (optional: ``pip install murus[seismo]``).

Both are binary seismological formats. ObsPy (Beyreuther et al. 2010; Krischer et al. 2015)
reads them; murus adds the checks it applies to every record: one-line errors naming the file,
units, finite values, at least two samples, one segment per channel (a record with gaps is
refused), and any warning of ObsPy while reading (a truncated miniSEED file is otherwise read
short) is a refusal.

Units: a SAC file whose header declares acceleration (IDEP = IACC, nm/s²) is converted to m/s²;
any other SAC file, and every miniSEED file (the format carries no units: network data are
usually raw counts), needs ``units=`` from the user, which asserts that the samples already
are accelerations in those units (remove the instrument response first, e.g. with ObsPy's
``Trace.remove_response``). Displacement, velocity and volts are refused.

Orientation: SAC ``cmpaz`` (azimuth from north) and ``cmpinc`` (0 = up, 90 = horizontal); for
miniSEED the last letter of the SEED channel code (N, E, Z; 1, 2 are left unknown).

Install size measured for this choice (ObsPy 1.5.1, CPython 3.11, Linux x86-64): the wheels of
obspy, lxml and sqlalchemy weigh 25 MB and take 89 MB installed (obspy 48 MB, sqlalchemy 29 MB,
lxml 12 MB); numpy, scipy, matplotlib and requests are shared with murus. Hence an optional
extra, imported only when such a file is read.

References
----------
Beyreuther, M., Barsch, R., Krischer, L., Megies, T., Behr, Y. and Wassermann, J. (2010).
ObsPy: A Python toolbox for seismology. Seismol. Res. Lett. 81(3), 530-533,
doi:10.1785/gssrl.81.3.530.
Goldstein, P. and Snoke, A. (2005). SAC availability for the IRIS community. IRIS DMS
Electronic Newsletter 7(1) (the SAC header: IDEP, CMPAZ, CMPINC).
International Federation of Digital Seismograph Networks (2012). SEED Reference Manual,
version 2.4 (miniSEED records, channel codes).
"""

from __future__ import annotations

import math
import struct
from pathlib import Path

import numpy as np

from murus.motion.core import GroundMotion

__all__ = ["sniff_binary", "read_obspy"]

_IACC, _IUNKN, _IDISP, _IVEL, _IVOLTS = 8, 5, 6, 7, 50
_SAC_UNDEF = -12345.0


def sniff_binary(head: bytes, size: int) -> str | None:
    """'sac', 'mseed' or None from the first bytes (at least 632) and the size of a file."""
    if len(head) >= 8 and head[:2] == b"MS" and head[2] == 3:
        return "mseed"  # miniSEED 3
    if len(head) >= 48 and all(c in b"0123456789 \x00" for c in head[:6]) and \
            head[6:7] in (b"D", b"R", b"Q", b"M") and head[7:8] in (b" ", b"\x00"):
        return "mseed"  # miniSEED 2: sequence number, quality indicator, reserved byte
    if len(head) >= 632:
        for end in "<>":
            nvhdr = struct.unpack(end + "i", head[304:308])[0]
            npts = struct.unpack(end + "i", head[316:320])[0]
            if nvhdr in (6, 7) and npts >= 0 and size >= 632 + 4 * npts:
                return "sac"
    return None


def _fail(path: Path, msg: str):
    from murus.motion.io import MotionFormatError

    return MotionFormatError(f"{path.name}: {msg}")


def read_obspy(path: Path, fmt: str, units: str | None, dt_arg: float | None
               ) -> list[GroundMotion]:
    """Every channel of a SAC or miniSEED file (see the module docstring).

    Parameters
    ----------
    path : pathlib.Path
        The file.
    fmt : {"sac", "mseed"}
        Its format.
    units : str, optional
        Units of the samples (needed unless a SAC header declares acceleration).
    dt_arg : float, optional
        Check against the sampling interval [s].

    Returns
    -------
    list of GroundMotion
        One per channel [m/s²].

    Raises
    ------
    MotionFormatError
        ObsPy missing, an unreadable file, no or wrong units, gaps, too short a record.
    """
    from murus.motion.io import UNITS, _check_range, _Src, normalize_units

    try:
        import obspy
    except ImportError:
        raise _fail(path, f"reading {fmt.upper()} files needs ObsPy: pip install "
                          "'murus[seismo]' (or pip install obspy)") from None
    import warnings

    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            st = obspy.read(str(path), format="SAC" if fmt == "sac" else "MSEED")
    except Exception as exc:  # ObsPy raises many types for a corrupt file
        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise _fail(path, f"not a readable {fmt.upper()} file ({first[:80]})") from None
    if caught:  # e.g. a truncated miniSEED read short: refuse rather than guess
        first = str(caught[0].message).strip().splitlines()[0]
        raise _fail(path, f"not a clean {fmt.upper()} file (ObsPy: {first[:100]})")
    if len(st) == 0:
        raise _fail(path, "no data")
    ids = [tr.id for tr in st]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    if dup:
        raise _fail(path, f"channel {dup[0]} has {ids.count(dup[0])} segments (gaps or "
                          "overlaps): merge or cut it first")
    src = _Src(path, "")
    out = []
    for k, tr in enumerate(st, start=1):
        data = np.asarray(tr.data, dtype=np.float64)
        dt = float(tr.stats.delta)
        if not (math.isfinite(dt) and dt > 0):
            raise _fail(path, f"channel {tr.id}: sampling interval {dt!r} s is not positive")
        if dt_arg is not None and not math.isclose(dt_arg, dt, rel_tol=1e-6):
            raise _fail(path, f"channel {tr.id}: the file declares dt = {dt:.10g} s but a "
                              f"time step of {dt_arg:.10g} s was given")
        if data.size < 2:
            raise _fail(path, f"channel {tr.id}: {data.size} samples, a record needs 2")
        if not np.all(np.isfinite(data)):
            raise _fail(path, f"channel {tr.id}: NaN or infinite samples")
        az, vert = None, False
        fac = None
        uname = None
        if fmt == "sac":
            sac = tr.stats.get("sac", {})
            idep = int(sac.get("idep", _IUNKN))
            if idep in (_IDISP, _IVEL, _IVOLTS):
                kind = {_IDISP: "displacement", _IVEL: "velocity", _IVOLTS: "volts"}[idep]
                raise _fail(path, f"channel {tr.id}: the SAC header declares {kind} (IDEP = "
                                  f"{idep}), not acceleration")
            if idep == _IACC:
                fac, uname = 1e-9, "nm/s2"
                if units is not None:
                    raise _fail(path, f"the file declares nm/s² (SAC IDEP = IACC) but units "
                                      f"{units} were given")
            cmpinc = float(sac.get("cmpinc", _SAC_UNDEF))
            cmpaz = float(sac.get("cmpaz", _SAC_UNDEF))
            if cmpinc != _SAC_UNDEF and (cmpinc < 1e-6 or abs(cmpinc - 180.0) < 1e-6):
                vert = True
            elif cmpaz != _SAC_UNDEF and (cmpinc == _SAC_UNDEF or abs(cmpinc - 90) < 1e-6):
                az = cmpaz % 360.0
        else:
            last = (tr.stats.channel or " ")[-1].upper()
            vert = last == "Z"
            az = {"N": 0.0, "E": 90.0}.get(last)
        if fac is None:
            if units is None:
                raise _fail(path, f"{fmt.upper()} data carry no acceleration units (often raw "
                                  "counts): remove the instrument response, then give the "
                                  "units (units='m/s2', --units m/s2)")
            uname = normalize_units(units, path.name)
            fac = UNITS[uname]
        meta = {
            "format": fmt, "source_file": str(path), "units_in": uname,
            "station": tr.stats.station, "network": tr.stats.network,
            "channel": k, "component": tr.stats.channel, "seed_id": tr.id,
            "azimuth_deg": az, "vertical": vert, "start_time": str(tr.stats.starttime),
            "name": f"{path.stem}_{tr.stats.channel}" if tr.stats.channel else path.stem,
        }
        gm = GroundMotion(dt=dt, acc=data * fac, name=meta["name"], meta=meta)
        out.append(_check_range(src, gm))
    return out
