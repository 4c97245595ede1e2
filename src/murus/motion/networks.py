"""Readers of the formats strong-motion networks publish: CSMIP/DMG V1 and V2, K-NET/KiK-net
ASCII, and the channel loop of COSMOS V0/V1/V2 files.

Each reader returns every acceleration channel of a file as a list of :class:`GroundMotion`
(m/s²); :func:`murus.motion.io.read` picks one (``channel=``) and
:func:`murus.motion.io.read_all` returns them all. Each channel's ``meta`` holds ``channel``
(its number as written in the file, or its position from 1), ``component`` (the orientation
as written), ``azimuth_deg`` (degrees clockwise from north, ``None`` for a vertical or unknown
orientation), ``vertical`` (bool), ``station``, ``units_in`` and, where the file declares it,
``pga_declared`` [m/s²].

``dmg``
    CSMIP/DMG (California Strong Motion Instrumentation Program, California Geological Survey)
    Volume 1 (uncorrected, first line "Uncorrected Accelerogram Data") and Volume 2 (corrected,
    "Corrected Accelerogram Data"): per channel a text header ("Chan  1:  90 Deg", "Station
    Id. CLC", V1 "No. of Points = n", V1 "Max = .344 g", V2 "Peak acceleration = ..."), an
    integer and a real header, then the acceleration block, introduced by
    "n Accelerogram points at 100 pts/sec in units of g.  Format: (8f9.6)" (V1) or "n points
    of accel data equally spaced at .005 sec, in cm/sec2. (8f10.3)" (V2), values in the stated
    Fortran fixed-width format. V2 channels then hold velocity and displacement blocks (not
    read). Each channel ends with a line starting "/&" (a file that ends before it is refused);
    a V1 header "(3 Chns of  3 at Sta)" gives the number of channels the file must hold. The
    layout is that of the files the
    CGS publishes (CESMD) and follows the reader of gmprocess (USGS, public domain/CC0:
    ``gmprocess/io/dmg/core.py``); the older V1 layout of analog records (interleaved time
    and acceleration pairs, no text line before the data) is refused with a message.
``knet``
    K-NET and KiK-net ASCII (NIED): 17 header lines "Key  value" ("Station Code",
    "Sampling Freq(Hz) 100Hz", "Dir. E-W", "Scale Factor 2000(gal)/8388608",
    "Max. Acc. (gal) 4.383", ...), then integer counts, 8 per line. Acceleration = counts x
    scale factor, minus its mean (the NIED convention: the declared maximum is that of the
    record with the mean removed). The format does not declare the number of points: the
    count is checked against "Duration Time(s)" (whole seconds) to within one second.
    One channel per file (.EW, .NS, .UD; KiK-net .EW1/.NS1/.UD1 at depth, .EW2/.NS2/.UD2 at
    the surface).

References
----------
California Geological Survey, CSMIP. Strong-motion data formats (Volume 1 and 2),
https://www.strongmotioncenter.org.
COSMOS (2001). COSMOS Strong-Motion Data Format, version 1.20. Consortium of Organizations for
Strong-Motion Observation Systems.
National Research Institute for Earth Science and Disaster Resilience (NIED). K-NET and
KiK-net data format, https://www.kyoshin.bosai.go.jp.
Hearne, M., Thompson, E. M., et al. gmprocess (USGS), readers ``io/dmg``, ``io/knet``,
``io/cosmos``; https://code.usgs.gov/ghsc/esi/groundmotion-processing.
"""

from __future__ import annotations

import math
import re
import warnings

import numpy as np

from murus.motion.core import GroundMotion
from murus.motion.io import (
    UNITS,
    _check_dt,
    _check_units,
    _make,
    _num,
    _short,
    _Src,
    normalize_units,
)

__all__ = ["is_dmg", "is_knet", "read_dmg", "read_knet"]

_DMG_V1_DATA = re.compile(
    r"^\s*(\d+)\s+accelerogram\s+points\s+at\s+([0-9.]+)\s*pts/sec\s+in\s+units\s+of\s+"
    r"(.+?)\.?\s+format\s*:?\s*\(\s*(\d+)\s*f\s*(\d+)\s*\.\s*\d+\s*\)", re.IGNORECASE)
_DMG_V2_DATA = re.compile(
    r"^\s*(\d+)\s+points\s+of\s+accel\w*\s+data\s+equally\s+spaced\s+at\s+([0-9.]+)\s*sec"
    r"\s*,?\s*in\s+(.+?)\.?\s*\(\s*(\d+)\s*f\s*(\d+)\s*\.\s*\d+\s*\)", re.IGNORECASE)
_DMG_ANY_DATA = re.compile(r"^\s*\d+\s+(accelerogram\s+points|points\s+of\s+accel)",
                           re.IGNORECASE)
_DMG_CHAN = re.compile(r"^\s*chan(?:nel)?\s*(\d+)\s*:\s*(.*?)\s*$", re.IGNORECASE)
_DMG_STATION = re.compile(r"station\s+(?:id\.?|no\.?)\s*:?\s*([A-Za-z0-9_-]+)", re.IGNORECASE)
_DMG_NPTS = re.compile(r"no\.\s*of\s*points\s*=\s*(\d+)", re.IGNORECASE)
_DMG_MAX_V1 = re.compile(r"\bmax\s*=\s*(-?[0-9]*\.?[0-9]+)\s*([A-Za-z/0-9]+?)[,.]?\s+at",
                         re.IGNORECASE)
_DMG_MAX_V2 = re.compile(
    r"peak\s+acceleration\s*=\s*(-?[0-9]*\.?[0-9]+)\s*([A-Za-z/0-9]+?)[,.]?\s+at",
    re.IGNORECASE)
_DMG_NCHAN = re.compile(r"\(\s*(\d+)\s+chns?\s+of\s+\d+\s+at\s+sta", re.IGNORECASE)
_DEG = re.compile(r"^(-?\d+(?:\.\d*)?)\s*(?:deg|degrees)?\b", re.IGNORECASE)


def is_dmg(lines: list[str]) -> bool:
    """True if the first line is a CSMIP/DMG volume 1 or 2 title line."""
    first = next((ln for ln in lines[:3] if ln.strip()), "").strip().upper()
    return first.startswith(("UNCORRECTED ACCELEROGRAM", "CORRECTED ACCELEROGRAM"))


def is_knet(lines: list[str]) -> bool:
    """True for a K-NET/KiK-net ASCII header ("Origin Time", then "Station Code", "Sampling
    Freq(Hz)" or "Scale Factor" lines)."""
    return (bool(lines) and lines[0].startswith("Origin Time")
            and any(ln.startswith(("Scale Factor", "Station Code", "Sampling Freq"))
                    for ln in lines[:20]))


def _orientation(text: str) -> tuple[float | None, bool]:
    """(azimuth in degrees from north, vertical) of a channel label such as '90 Deg', '360',
    'Up', 'E-W', 'N-S', 'U-D'."""
    t = text.strip().lower()
    if t.startswith(("up", "down", "vert", "u-d", "ud", "z")):
        return None, True
    m = _DEG.match(t)
    if m:
        az = float(m.group(1))
        if az in (500.0, 600.0):  # COSMOS/DMG codes for up and down
            return None, True
        return az % 360.0, False
    if t in ("e-w", "ew", "e", "east"):
        return 90.0, False
    if t in ("n-s", "ns", "n", "north"):
        return 0.0, False
    return None, False


def _fixed_block(src: _Src, start: int, npts: int, width: int, what: str) -> tuple[list, int]:
    """``npts`` values in fields of ``width`` characters from line ``start`` (0-based) on;
    returns the values and the index of the line after the block."""
    lines = src.lines
    vals: list[float] = []
    i = start
    while len(vals) < npts:
        if i >= len(lines):
            raise src.err(len(lines), f"file ends after {len(vals)} of the {npts} {what} "
                                      "values")
        line = lines[i].rstrip()
        if line.lstrip().startswith("/&") or re.search(r"[a-ce-zA-CE-Z]", line):
            raise src.err(i + 1, f"{what} block ends after {len(vals)} of its {npts} values")
        toks = [line[k:k + width].strip() for k in range(0, len(line), width)]
        vals.extend(src.num(t, i + 1) for t in toks if t)
        i += 1
    if len(vals) != npts:
        raise src.err(i, f"{what} block has {len(vals)} values where {npts} are declared")
    if i < len(lines) and lines[i].strip() and not lines[i].lstrip().startswith("/&") and \
            not re.search(r"[a-ce-zA-CE-Z]", lines[i]):
        raise src.err(i + 1, f"more {what} values than the {npts} declared")
    return vals, i


def _declared_pga(src: _Src, tok: str, utok: str, lineno: int, acc: np.ndarray, meta: dict):
    """Store a declared peak ``tok`` [``utok``] in ``meta`` and warn if the data disagree (to
    its printed precision)."""
    try:
        fac = UNITS[normalize_units(utok)]
    except ValueError:
        return
    declared = abs(float(tok)) * fac
    meta["pga_declared"] = declared
    decimals = len(tok.split(".")[1]) if "." in tok else 0
    tol = 0.5 * 10.0 ** (-decimals) * fac * 1.0001 + 1e-12
    actual = float(np.max(np.abs(acc)))
    if abs(actual - declared) > tol:
        warnings.warn(f"{src.name} line {lineno}: declared peak {tok} {utok} differs from the "
                      f"data ({actual / fac:.6g} {utok})", stacklevel=4)


def read_dmg(src: _Src, units: str | None, dt_arg: float | None) -> list[GroundMotion]:
    """All channels of a CSMIP/DMG V1 or V2 file (see the module docstring).

    Parameters
    ----------
    src : murus.motion.io._Src
        The file's text.
    units : str, optional
        Check against the declared units.
    dt_arg : float, optional
        Check against the declared time step [s].

    Returns
    -------
    list of GroundMotion
        One per channel, acceleration in m/s².
    """
    lines = src.lines
    title = lines[0].strip() if lines else ""
    level = "V1" if title.upper().startswith("UNCORRECTED") else "V2"
    out: list[GroundMotion] = []
    declared_chans = None
    i = 0
    n = len(lines)
    while i < n:
        if not lines[i].strip():
            i += 1
            continue
        start = i
        # find this channel's data header (before the end-of-channel line)
        k = start
        while k < n and not _DMG_ANY_DATA.match(lines[k]) and \
                not lines[k].lstrip().startswith("/&"):
            k += 1
        if k >= n or lines[k].lstrip().startswith("/&"):
            if out and k >= n and all(not ln.strip() for ln in lines[start:]):
                break
            raise src.err(min(k + 1, n), f"channel {len(out) + 1} has no acceleration data "
                                         "header ('n Accelerogram points at ...' or 'n points "
                                         "of accel data ...')")
        hdr = lines[start:k]
        m = (_DMG_V1_DATA if level == "V1" else _DMG_V2_DATA).match(lines[k])
        if m is None:
            m = _DMG_V1_DATA.match(lines[k]) or _DMG_V2_DATA.match(lines[k])
        if m is None:
            raise src.err(k + 1, f"cannot read the data header {_short(lines[k].strip())} "
                                 "(count, rate or step, units, Fortran format)")
        npts, rate, utxt, _cols, width = (int(m.group(1)), m.group(2), m.group(3),
                                          int(m.group(4)), int(m.group(5)))
        if npts < 2:
            raise src.err(k + 1, f"{npts} points: a record needs at least 2")
        if width < 1:
            raise src.err(k + 1, "field width 0 in the data format")
        rate_v = src.num(rate, k + 1)
        if rate_v <= 0:
            raise src.err(k + 1, f"sampling {_short(rate)} is not positive")
        is_v1_line = _DMG_V1_DATA.match(lines[k]) is not None
        dt = _check_dt(src, (1.0 / rate_v) if is_v1_line else rate_v, k + 1)
        if dt_arg is not None and not math.isclose(dt_arg, dt, rel_tol=1e-9):
            raise src.err(k + 1, f"the file declares dt = {_num(dt)} s but a time step of "
                                 f"{_num(dt_arg)} s was given")
        uname = _check_units(src, normalize_units(utxt.strip().rstrip("."),
                                                  f"{src.name} line {k + 1}"), units, k + 1)
        # header values
        chan_no, comp = len(out) + 1, ""
        station = ""
        max_m, max_line = None, 0
        for r, ln in enumerate(hdr):
            cm = _DMG_CHAN.match(ln)
            if cm and not comp:
                chan_no, comp = int(cm.group(1)), cm.group(2)
            sm = _DMG_STATION.search(ln)
            if sm and not station:
                station = sm.group(1)
            pm = _DMG_NPTS.search(ln)
            if pm and int(pm.group(1)) != npts:
                raise src.err(start + r + 1, f"header declares {pm.group(1)} points but the "
                                             f"data header (line {k + 1}) declares {npts}")
            mm = (_DMG_MAX_V1 if level == "V1" else _DMG_MAX_V2).search(ln)
            if mm and max_m is None:
                max_m, max_line = mm, start + r + 1
        vals, j = _fixed_block(src, k + 1, npts, width, "acceleration")
        acc = np.asarray(vals) * UNITS[uname]
        az, vert = _orientation(comp)
        # a V2 channel repeats the V1 text header one line down, under its own title line
        # ("Corrected accelerogram ..."): event on line 3, record id on line 5 (V1: 2 and 4)
        off = 1 if hdr and hdr[0].strip().upper().startswith("CORRECTED") else 0
        meta = {
            "format": "dmg", "level": level, "source_file": str(src.path), "units_in": uname,
            "title": hdr[0].strip() if hdr else title,
            "event": hdr[1 + off].strip() if len(hdr) > 1 + off else "",
            "record_id": (hdr[3 + off].split()[0]
                          if len(hdr) > 3 + off and hdr[3 + off].split() else ""),
            "station": station, "channel": chan_no, "component": comp.strip(),
            "azimuth_deg": az, "vertical": vert,
            "name": f"{src.path.stem}_ch{chan_no}",
        }
        if max_m is not None:
            _declared_pga(src, max_m.group(1), max_m.group(2), max_line, acc, meta)
        out.append(_make(src, acc, dt, meta))
        # skip the rest of the channel (V2 velocity and displacement blocks) to its '/&' line
        while j < n and not lines[j].lstrip().startswith("/&"):
            if _DMG_ANY_DATA.match(lines[j]):
                raise src.err(j + 1, "a new acceleration block before the end of the channel "
                                     "('/&' line)")
            j += 1
        if j >= n:
            raise src.err(n, f"file ends before the end of channel {chan_no} (its '/&' line)")
        if declared_chans is None:  # "(3 Chns of  3 at Sta)" in the first channel's header
            declared_chans = (0, 0)
            for r, ln in enumerate(hdr):
                cm = _DMG_NCHAN.search(ln)
                if cm:
                    declared_chans = (int(cm.group(1)), start + r + 1)
                    break
        i = j + 1
    if not out:
        raise src.err(None, "no channel found")
    if declared_chans and declared_chans[0] and declared_chans[0] != len(out):
        raise src.err(declared_chans[1], f"the header declares {declared_chans[0]} channels "
                                         f"but the file has {len(out)}")
    return out


_KNET_KEYS = {
    "origin time": "origin_time", "lat.": "lat", "long.": "lon", "depth. (km)": "depth_km",
    "mag.": "magnitude", "station code": "station", "station lat.": "station_lat",
    "station long.": "station_lon", "station height(m)": "station_height_m",
    "record time": "record_time", "sampling freq(hz)": "freq", "duration time(s)": "duration",
    "dir.": "dir", "scale factor": "scale", "max. acc. (gal)": "max_acc",
    "last correction": "last_correction", "memo.": "memo",
}
_KNET_REQUIRED = ("station", "freq", "duration", "dir", "scale")
_KNET_SCALE = re.compile(r"^\s*([0-9.eE+-]+)\s*\(\s*gal\s*\)\s*/\s*([0-9.eE+-]+)\s*$",
                         re.IGNORECASE)
_INT = re.compile(r"^[+-]?\d+$")


def read_knet(src: _Src, units: str | None, dt_arg: float | None) -> list[GroundMotion]:
    """The channel of a K-NET/KiK-net ASCII file (see the module docstring).

    Parameters
    ----------
    src : murus.motion.io._Src
        The file's text.
    units : str, optional
        Check: the format's units are gal (cm/s²).
    dt_arg : float, optional
        Check against the sampling frequency.

    Returns
    -------
    list of GroundMotion
        One record, acceleration in m/s² with its mean removed.
    """
    lines = src.lines
    hdr: dict[str, tuple[str, int]] = {}
    i = 0
    while i < len(lines) and i < 40:
        ln = lines[i]
        if ln.strip() and (_INT.match(ln.split()[0]) and not ln[:1].isalpha()):
            break
        key = ln[:18].strip().lower()
        if key in _KNET_KEYS:
            hdr[_KNET_KEYS[key]] = (ln[18:].strip(), i + 1)
        elif ln.strip():
            raise src.err(i + 1, f"unknown K-NET header line {_short(ln.strip())}")
        i += 1
    for key in _KNET_REQUIRED:
        if key not in hdr:
            name = next(k for k, v in _KNET_KEYS.items() if v == key)
            raise src.err(i, f"K-NET header has no '{name}' line")
    ftok, fl = hdr["freq"]
    fm = re.fullmatch(r"([0-9.]+)\s*(?:hz)?", ftok, re.IGNORECASE)
    if fm is None:
        raise src.err(fl, f"sampling frequency {_short(ftok)} is not a number of Hz")
    freq = src.num(fm.group(1), fl)
    if freq <= 0:
        raise src.err(fl, "sampling frequency is not positive")
    dt = _check_dt(src, 1.0 / freq, fl)
    if dt_arg is not None and not math.isclose(dt_arg, dt, rel_tol=1e-9):
        raise src.err(fl, f"the file declares dt = {_num(dt)} s but a time step of "
                          f"{_num(dt_arg)} s was given")
    stok, sl = hdr["scale"]
    sm = _KNET_SCALE.match(stok)
    if sm is None:
        raise src.err(sl, f"scale factor {_short(stok)} is not 'A(gal)/B'")
    num_, den = src.num(sm.group(1), sl), src.num(sm.group(2), sl)
    if den == 0 or num_ == 0:
        raise src.err(sl, f"scale factor {_short(stok)} is zero or divides by zero")
    uname = _check_units(src, "cm/s2", units, sl)
    counts: list[int] = []
    for r in range(i, len(lines)):
        for tok in lines[r].split():
            if not _INT.match(tok):
                src.num(tok, r + 1)  # raises for text, NaN, inf
                raise src.err(r + 1, f"{_short(tok)} is not a whole number of counts")
            counts.append(int(tok))
    npts = len(counts)
    if npts < 2:
        raise src.err(len(lines), f"{npts} data values: a record needs at least 2")
    dtok, dl = hdr["duration"]
    dur = src.num(dtok, dl)
    if not (dur - 1.0 - 1e-9 <= npts * dt <= dur + 1.0 + 1e-9):
        raise src.err(dl, f"Duration Time {dtok} s but the file has {npts} values "
                          f"({_num(npts * dt)} s at {_num(freq)} Hz)")
    raw = np.asarray(counts, dtype=np.float64) * (num_ / den)
    acc = (raw - raw.mean()) * UNITS[uname]
    comp, _ = hdr["dir"]
    az, vert = _orientation(comp)
    meta = {
        "format": "knet", "source_file": str(src.path), "units_in": uname,
        "station": hdr["station"][0], "component": comp, "channel": 1,
        "azimuth_deg": az, "vertical": vert, "scale_factor_gal": num_ / den,
        "mean_removed_gal": float(raw.mean()),
        "event": hdr.get("origin_time", ("", 0))[0],
        "name": f"{src.path.stem}_{src.path.suffix.lstrip('.')}" if src.path.suffix
        else src.path.stem,
    }
    if "magnitude" in hdr and re.fullmatch(r"[0-9.]+", hdr["magnitude"][0]):
        meta["magnitude"] = float(hdr["magnitude"][0])
    if "max_acc" in hdr:
        mtok, ml = hdr["max_acc"]
        if re.fullmatch(r"-?[0-9]*\.?[0-9]+", mtok):
            _declared_pga(src, mtok, "gal", ml, acc, meta)
    return [_make(src, acc, dt, meta)]
