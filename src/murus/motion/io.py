"""Readers and writers of acceleration records.

Formats, chosen by content (then extension) unless ``format`` is given:

``at2``
    PEER NGA flat file: 3 text lines (title; event, date, station, component; units line
    "ACCELERATION TIME SERIES IN UNITS OF G"), a line "NPTS= n, DT= dt SEC" (or the older
    "n dt NPTS, DT"), then the values, several per line.
``esm``
    ESM / ITACA ASCII (Engineering Strong-Motion database, Luzi et al. 2016): ``KEY: value``
    header lines (``SAMPLING_INTERVAL_S``, ``NDATA``, ``UNITS``, ``DATA_TYPE`` ...) followed by
    one value per line.
``cosmos``
    COSMOS Strong-Motion Data Format (v1.20) V0 (raw counts), V1 (uncorrected) or V2
    (processed) file: 14 text header lines, an integer header, a real header (value 62 is the
    sampling interval in ms), comment lines and a data block "N acceleration pts, approx T
    secs, units=cm/sec2 (04), Format=(...)". V0 counts (units=counts(50)) are converted with
    real-header values 22 (recorder LSB, µV/count), 42 (sensor sensitivity, V/g) and 47 (gain,
    1 when unknown), as gmprocess does: a = counts x LSB x 1e-6 / gain / sensitivity x
    ``murus.G`` (``meta["units_in"] = "counts"``, ``meta["conversion"]`` in m/s² per count);
    no offset is subtracted (the recorder's DC offset stays in the series, as in gmprocess:
    baseline-correct before use), and a missing (-999) or zero LSB or sensitivity is refused.
    Files holding several channels one after the other are read channel by channel;
    integer-header value 54 is the orientation code (1-360 azimuth from north, 400-402
    vertical, other codes no azimuth; when unknown, value 55 relative to the structure or the
    USGS ``<SCNL>`` comment); real-header value 64, the declared maximum, is checked.
``dmg``, ``knet``
    CSMIP/DMG V1 and V2 (California Geological Survey) and K-NET/KiK-net ASCII (NIED): see
    :mod:`murus.motion.networks`.
``sac``, ``mseed``
    Binary SAC and miniSEED, recognised by their first bytes, read through ObsPy (optional
    extra ``murus[seismo]``): see :mod:`murus.motion.seismo`.
``csv`` / text
    One or more columns separated by commas, semicolons or blanks. Two columns are time [s] and
    acceleration, three add the vertical acceleration, one column is acceleration at a step ``dt``.
    ``#`` lines are comments; ``# dt: ...``, ``# units: ...``, ``# npts: ...``, ``# name: ...``
    comment lines are read as a header (that is what :func:`write` produces). A first line of
    column names is skipped.

Units: g, m/s2 and cm/s2 (gal). A value in g is converted with ``murus.G`` = 9.81 m/s² (the
constant used everywhere in murus, so that a record written in g and read back is unchanged;
note that PEER and COSMOS use g = 9.80665 m/s² for their own conversions, a 0.03 % difference).

Multi-channel files: :func:`read` returns one channel (``channel=``: default the first
horizontal one), :func:`read_all` all of them, each with ``meta["channel"]``, ``"component"``,
``"azimuth_deg"`` and ``"vertical"``. A file that matches no format is refused with
"unrecognised record format" and its first line (never parsed as CSV by default).

Every error is a :class:`MotionFormatError` (a ``ValueError``) whose message is one line that
names the file and, where it applies, the line number: ``record.csv line 12: 'abc' is not a
number``. A record is refused rather than guessed: NaN or infinite values, text in a number field,
a declared number of points different from the data, a missing or non-positive step, a time
column that does not increase. The last data line is always read and dt is never rounded.
"""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

import numpy as np

from murus import G
from murus.errors import MurusError
from murus.motion.core import GroundMotion

__all__ = ["MotionFormatError", "read", "read_all", "select_channel", "write", "detect_format",
           "UNITS", "FORMATS"]

#: conversion factors to m/s²
UNITS = {
    "g": G,
    "m/s2": 1.0,
    "cm/s2": 0.01,
}
_UNIT_ALIASES = {
    "g": "g", "g0": "g", "gravity": "g",
    "m/s2": "m/s2", "m/s^2": "m/s2", "m/s**2": "m/s2", "m/s/s": "m/s2", "m/sec2": "m/s2",
    "m/sec/sec": "m/s2", "mps2": "m/s2",
    "cm/s2": "cm/s2", "cm/s^2": "cm/s2", "cm/s**2": "cm/s2", "cm/s/s": "cm/s2", "gal": "cm/s2",
    "cm/sec2": "cm/s2", "cm/sec/sec": "cm/s2", "cm/sec^2": "cm/s2", "cmps2": "cm/s2",
}
FORMATS = ("at2", "esm", "cosmos", "dmg", "knet", "csv", "sac", "mseed")

_NUM_RE = re.compile(r"^[+-]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][+-]?\d+)?$")
_MAX_ABS = 1e6  # m/s²; 100 000 g: anything larger is a corrupt file


class MotionFormatError(MurusError, ValueError):
    """A record file that cannot be read; the message names the file and line."""


def _short(tok: str) -> str:
    tok = tok.replace("\n", " ").replace("\r", " ")
    return repr(tok if len(tok) <= 24 else tok[:21] + "...")


def normalize_units(units: str, where: str = "") -> str:
    """Canonical unit name ('g', 'm/s2' or 'cm/s2') of a unit string; MotionFormatError if
    unknown."""
    key = str(units).strip().lower().replace(" ", "")
    if key in _UNIT_ALIASES:
        return _UNIT_ALIASES[key]
    prefix = f"{where}: " if where else ""
    raise MotionFormatError(
        f"{prefix}unknown acceleration units {_short(str(units))} (use g, m/s2 or cm/s2)"
    )


class _Src:
    """Decoded text of a file with helpers that raise one-line errors naming file and line."""

    def __init__(self, path: Path, text: str):
        self.path = path
        self.name = path.name
        self.lines = text.splitlines()

    def err(self, lineno: int | None, msg: str) -> MotionFormatError:
        where = self.name if lineno is None else f"{self.name} line {lineno}"
        return MotionFormatError(f"{where}: {msg}")

    def num(self, tok: str, lineno: int) -> float:
        if not _NUM_RE.match(tok):
            low = tok.lower().lstrip("+-")
            if low in ("nan", "inf", "infinity"):
                raise self.err(lineno, f"{_short(tok)} is not a finite number")
            raise self.err(lineno, f"{_short(tok)} is not a number")
        x = float(tok.replace("d", "e").replace("D", "e"))
        if not math.isfinite(x):
            raise self.err(lineno, f"{_short(tok)} is not a finite number")
        return x

    def values(self, start: int, stop: int | None = None) -> tuple[np.ndarray, list[int]]:
        """All numbers on lines[start:stop] (0-based); blank lines skipped. Returns the values
        and, for each value, its 1-based line number."""
        out: list[float] = []
        where: list[int] = []
        stop = len(self.lines) if stop is None else stop
        for i in range(start, stop):
            toks = self.lines[i].replace(",", " ").split()
            for tok in toks:
                out.append(self.num(tok, i + 1))
                where.append(i + 1)
        return np.asarray(out, dtype=np.float64), where


def _read_text(path: Path) -> str:
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise MotionFormatError(f"{path.name}: no such file") from None
    except IsADirectoryError:
        raise MotionFormatError(f"{path.name or path}: is a folder, not a record file") from None
    except OSError as exc:
        raise MotionFormatError(f"{path.name}: cannot read ({exc.strerror})") from None
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")) or b"\x00" in raw:
        from murus.config import describe_encoding

        kind = describe_encoding(path)
        hint = (": save it as UTF-8 (or ASCII) text" if kind.startswith("UTF")
                else ", not a text record")
        raise MotionFormatError(f"{path.name}: {kind}{hint}")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def _num(x) -> str:
    """A number as a user wrote it (``5``, ``0.01``), never a numpy repr."""
    return f"{float(x):.10g}"


_ESM_KEY = re.compile(r"^([A-Z][A-Z0-9_/^.\-()]*):(.*)$")


def detect_format(path, text: str | None = None) -> str:
    """Format name from the content, then the extension.

    'at2', 'esm', 'cosmos', 'dmg', 'knet' or 'csv'. A file that looks like none of them is
    refused with a message quoting its first line (it is never parsed as CSV by default: a
    text header would give a puzzling number error on line 2).

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    text : str, optional
        Its content, if already read.

    Returns
    -------
    str

    Raises
    ------
    MotionFormatError
        "unrecognised record format" for anything else.
    """
    path = Path(path)
    if text is None:
        text = _read_text(path)
    lines = text.splitlines()
    head = [ln for ln in lines[:20]]
    first = next((ln for ln in head if ln.strip()), "")
    low = first.lower()
    if "peer" in low and "record" in low:
        return "at2"
    if any("integer-header values follow" in ln.lower() for ln in lines[:40]):
        return "cosmos"
    if _ESM_KEY.match(first.strip()) and any(
        ln.startswith("SAMPLING_INTERVAL_S") for ln in lines[:120]
    ):
        return "esm"
    from murus.motion.networks import is_dmg, is_knet

    if is_dmg(lines):
        return "dmg"
    if is_knet(lines):
        return "knet"
    ext = path.suffix.lower()
    if ext == ".at2":
        return "at2"
    if ext in (".v2", ".smc", ".cosmos") and not first.lower().startswith(
            ("uncorrected", "corrected")):
        return "cosmos"
    if ext == ".asc" and _ESM_KEY.match(first.strip()):
        return "esm"
    if ext in (".csv", ".tsv") or _looks_like_columns(lines):
        return "csv"
    raise MotionFormatError(
        f"{path.name}: unrecognised record format (first line: {_first_line(first)}); "
        f"murus reads {_FORMAT_NAMES}"
    )


_FORMAT_NAMES = ("PEER AT2, ESM ASCII, COSMOS V0/V1/V2, CSMIP/DMG V1/V2, K-NET/KiK-net ASCII, "
                 "CSV/text columns, and SAC and miniSEED with ObsPy")


def _first_line(line: str) -> str:
    s = "".join(c if c.isprintable() else "?" for c in line.strip())
    return repr(s if len(s) <= 48 else s[:45] + "...")


def _looks_like_columns(lines: list[str]) -> bool:
    """True if the first lines that are not blank or '#' comments are rows of numbers,
    optionally after one line of column names (a CSV/text record)."""
    rows = [ln.strip() for ln in lines[:200] if ln.strip() and not ln.lstrip().startswith(
        ("#", "%"))][:2]
    if not rows:
        return True  # comments only: the CSV reader says what is missing

    def numeric(row):
        toks = [t for t in _SPLIT.split(row) if t]
        return bool(toks) and _NUM_RE.match(toks[0]) is not None

    return numeric(rows[0]) or (len(rows) > 1 and numeric(rows[1]))


# ----------------------------------------------------------------------------------- readers


def _check_units(src: _Src, declared: str, given: str | None, lineno: int | None) -> str:
    if given is not None and normalize_units(given) != declared:
        raise src.err(
            lineno, f"the file declares units {declared} but units {given} were given"
        )
    return declared


def _check_dt(src: _Src, dt: float, lineno: int | None) -> float:
    if not (math.isfinite(dt) and dt > 0):
        raise src.err(lineno, f"time step dt = {_num(dt)} s is not positive")
    return dt


_AT2_NEW = re.compile(
    r"NPTS\s*=\s*([^\s,]+)\s*,?\s*DT\s*=\s*([^\s,]+)", re.IGNORECASE
)
_AT2_OLD = re.compile(r"^\s*(\S+)\s+(\S+)\s+NPTS\s*,\s*DT", re.IGNORECASE)


def _read_at2(src: _Src, units: str | None, dt_arg: float | None) -> GroundMotion:
    lines = src.lines
    if len(lines) < 4:
        raise src.err(None, "PEER AT2 file has fewer than 4 header lines")
    unit_line = lines[2].upper()
    if "ACCEL" not in unit_line:
        raise src.err(3, "PEER AT2 line 3 does not declare an acceleration time series")
    m = re.search(r"UNITS?\s+OF\s+([A-Z/\^0-9*]+)", unit_line)
    if m is None:
        raise src.err(3, "PEER AT2 units not found (expected 'IN UNITS OF G')")
    declared = normalize_units(m.group(1), f"{src.name} line 3")
    uname = _check_units(src, declared, units, 3)
    mm = _AT2_NEW.search(lines[3]) or _AT2_OLD.search(lines[3])
    if mm is None:
        raise src.err(4, "expected 'NPTS= n, DT= dt SEC'")
    ntok, dtok = mm.group(1), mm.group(2)
    if not re.fullmatch(r"\d+", ntok):
        raise src.err(4, f"NPTS {_short(ntok)} is not a whole number")
    npts = int(ntok)
    dt = _check_dt(src, src.num(dtok, 4), 4)
    if dt_arg is not None and not math.isclose(dt_arg, dt, rel_tol=1e-9):
        raise src.err(4, f"the file declares DT = {_num(dt)} s but a time step of "
                         f"{_num(dt_arg)} s was given")
    vals, where = src.values(4)
    if vals.size != npts:
        last = where[-1] if where else 4
        raise src.err(last, f"header declares NPTS = {npts} but the file has {vals.size} values")
    if npts < 2:
        raise src.err(4, f"NPTS = {npts}: a record needs at least 2 points")
    info = lines[1].strip()
    parts = [p.strip() for p in info.split(",")]
    meta = {"format": "at2", "source_file": str(src.path), "units_in": uname, "title": info}
    if len(parts) >= 4:  # NGA-West2: event, date, station, component
        meta["event"] = parts[0]
        if parts[1]:
            meta["date"] = parts[1]
        meta["station"] = ", ".join(parts[2:-1])
        meta["component"] = parts[-1]
    elif len(parts) == 3:  # NGA (2005): event date, station, component
        meta["event"], meta["station"], meta["component"] = parts
    return _make(src, vals * UNITS[uname], dt, meta)


_ESM_UNITS_KEYS = ("UNITS",)


def _read_esm(src: _Src, units: str | None, dt_arg: float | None) -> GroundMotion:
    hdr: dict[str, tuple[str, int]] = {}
    i = 0
    lines = src.lines
    while i < len(lines):
        s = lines[i].strip()
        m = _ESM_KEY.match(s)
        if m is None:
            if s == "":
                i += 1
                continue
            break
        hdr[m.group(1)] = (m.group(2).strip(), i + 1)
        i += 1
    data_start = i

    def need(key):
        if key not in hdr or hdr[key][0] == "":
            raise src.err(None, f"ESM header key {key} is missing or empty")
        return hdr[key]

    dtype_ = hdr.get("DATA_TYPE", ("ACCELERATION", 0))
    if "ACC" not in dtype_[0].upper():
        raise src.err(dtype_[1], f"DATA_TYPE {_short(dtype_[0])} is not ACCELERATION")
    sdt, ldt = need("SAMPLING_INTERVAL_S")
    dt = _check_dt(src, src.num(sdt, ldt), ldt)
    if dt_arg is not None and not math.isclose(dt_arg, dt, rel_tol=1e-9):
        raise src.err(ldt, f"the file declares SAMPLING_INTERVAL_S = {_num(dt)} s but a time step "
                                  f"of {_num(dt_arg)} s was given")
    sn, ln = need("NDATA")
    if not re.fullmatch(r"\d+", sn):
        raise src.err(ln, f"NDATA {_short(sn)} is not a whole number")
    npts = int(sn)
    su, lu = need("UNITS")
    uname = _check_units(src, normalize_units(su, f"{src.name} line {lu}"), units, lu)
    vals, where = src.values(data_start)
    if vals.size != npts:
        last = where[-1] if where else ln
        raise src.err(last, f"header declares NDATA = {npts} but the file has {vals.size} values")
    if npts < 2:
        raise src.err(ln, f"NDATA = {npts}: a record needs at least 2 points")

    def g(key):
        return hdr.get(key, ("", 0))[0]

    meta = {
        "format": "esm",
        "source_file": str(src.path),
        "units_in": uname,
        "event": g("EVENT_NAME"),
        "event_id": g("EVENT_ID"),
        "date": g("EVENT_DATE_YYYYMMDD"),
        "network": g("NETWORK"),
        "station": g("STATION_CODE"),
        "station_name": g("STATION_NAME"),
        "component": g("STREAM"),
    }
    for key in ("MAGNITUDE_W", "MAGNITUDE_L"):
        v = g(key)
        if v and _NUM_RE.match(v):
            meta["magnitude"] = float(v)
            break
    acc = vals * UNITS[uname]
    # consistency of the declared PGA (ESM writes it rounded): warn, the data are authoritative
    for key, (val, lno) in hdr.items():
        if key.startswith("PGA_") and _NUM_RE.match(val):
            ukey = key[4:]
            try:
                fac = UNITS[normalize_units(ukey)]
            except MotionFormatError:
                continue
            declared_pga = abs(float(val)) * fac
            actual = float(np.max(np.abs(acc)))
            if not math.isclose(declared_pga, actual, rel_tol=1e-3, abs_tol=1e-6):
                warnings.warn(
                    f"{src.name} line {lno}: declared {key} = {val} differs from the data "
                    f"({actual / fac:.6g})",
                    stacklevel=3,
                )
    return _make(src, acc, dt, meta)


_FORTRAN_FMT = re.compile(r"\(\s*(\d*)\s*([FEIDGfeidg])\s*(\d+)(?:\.\d+)?\s*\)")


def _fixed_width_values(src: _Src, start: int, nlines: int, count: int, fmt: str | None,
                        what: str) -> tuple[np.ndarray, int]:
    """Read ``count`` values from ``nlines`` lines; fixed width when a Fortran format is given,
    else blank separated. Returns the values and the index of the next line."""
    width = None
    if fmt:
        m = _FORTRAN_FMT.search(fmt)
        if m:
            width = int(m.group(3))
    out: list[float] = []
    end = start + nlines
    if end > len(src.lines):
        raise src.err(len(src.lines), f"file ends inside the {what}")
    for i in range(start, end):
        line = src.lines[i].rstrip()
        if width:
            toks = [line[k:k + width].strip() for k in range(0, len(line), width)]
            toks = [t for t in toks if t]
        else:
            toks = line.split()
        for t in toks:
            out.append(src.num(t, i + 1))
    if len(out) != count:
        raise src.err(end, f"{what} declares {count} values but has {len(out)}")
    return np.asarray(out), end


def _is_text_line(line: str) -> bool:
    """True for a line with letters other than the exponent markers E and D (end of a numeric
    block); "3.437285e-04" (COSMOS Format=(1E15.6)) is a number, not text."""
    return re.search(r"[a-cf-zA-CF-Z]", line) is not None


_COSMOS_COUNT = re.compile(r"^\s*(\d+)\s+(.*)$")
_COSMOS_BLOCK = re.compile(r"^\s*\d+\s+.*\bunits\s*=", re.IGNORECASE)


def _cosmos_counts_factor(src: _Src, reals, k_real: int, nl_real: int) -> float:
    """m/s² per count of a COSMOS V0 channel from its real header (COSMOS v1.20 numbering,
    1-based; the same values gmprocess reads, gmprocess/io/cosmos/core.py): value 22 the
    recorder's least significant bit [µV/count], value 42 the sensor sensitivity [V/g],
    value 47 the gain (optional, 1 when unknown). a = counts x LSB x 1e-6 / gain /
    sensitivity x murus.G. Nothing is subtracted (as in gmprocess): the recorder's DC offset
    stays in the series (remove it, or baseline-correct, before use).
    A missing (-999) or zero LSB or sensitivity, or a zero gain, is refused on its line."""
    per_line = -(-len(reals) // max(nl_real, 1))

    def value(idx: int, what: str, optional: bool = False) -> float:
        line = k_real + 2 + idx // per_line if idx < len(reals) else k_real + 1
        v = float(reals[idx]) if idx < len(reals) else -999.0
        if optional and v == -999.0:
            return 1.0
        if v in (-999.0, 0.0) or not math.isfinite(v):
            raise src.err(line, f"raw counts (COSMOS V0) need real-header value {idx + 1} "
                                f"({what}) to give acceleration, but it is "
                                f"{'missing' if idx >= len(reals) else _num(v)}")
        return v

    lsb = value(21, "recorder least significant bit, microvolts/count")
    sens = value(41, "sensor sensitivity, volts/g")
    gain = value(46, "gain", optional=True)
    return lsb * 1e-6 / gain / sens * G


def _read_cosmos(src: _Src, units: str | None, dt_arg: float | None) -> GroundMotion:
    return _cosmos_channel(src, units, dt_arg, 0)[0]


def _read_cosmos_all(src: _Src, units: str | None, dt_arg: float | None) -> list[GroundMotion]:
    """Every channel of a COSMOS file (channels written one after the other)."""
    out = []
    start = 0
    while True:
        gm, nxt = _cosmos_channel(src, units, dt_arg, start, len(out) + 1)
        out.append(gm)
        more = next((i for i in range(nxt, len(src.lines))
                     if "integer-header values follow" in src.lines[i].lower()), None)
        if more is None:
            tail = [i for i in range(nxt, len(src.lines)) if src.lines[i].strip()]
            # other data blocks of the last channel (velocity, displacement) may follow it
            # directly; any other text is a cut or broken next channel
            rest = tail[0] if tail and not _COSMOS_BLOCK.match(src.lines[tail[0]]) else None
            if rest is not None:
                raise src.err(rest + 1, f"text after channel {len(out)} is not a COSMOS "
                                        "channel (file cut, or a channel without its "
                                        "integer header)")
            return out
        start = nxt


def _cosmos_channel(src: _Src, units: str | None, dt_arg: float | None, start: int,
                    position: int = 1) -> tuple[GroundMotion, int]:
    lines = src.lines
    # locate the integer header line (normally line 14, after 13 text lines)
    k = next(
        (i for i in range(start, min(start + 60, len(lines)))
         if "integer-header values follow" in lines[i].lower()),
        None,
    )
    if k is None:
        raise src.err(None, "COSMOS integer header line not found")
    text0 = max(start, k - 13)
    while text0 < k and not lines[text0].strip():
        text0 += 1

    def block_line(i, what):
        if i >= len(lines):
            raise src.err(len(lines), f"file ends before the {what}")
        ln = lines[i]
        m = _COSMOS_COUNT.match(ln)
        if m is None:
            raise src.err(i + 1, f"expected the {what} line, got {_short(ln.strip())}")
        nl = re.search(r"on\s+(\d+)\s+lines", ln, re.IGNORECASE)
        fm = re.search(r"format\s*=\s*(\([^)]*\))", ln, re.IGNORECASE)
        return int(m.group(1)), (int(nl.group(1)) if nl else None), (fm.group(1) if fm else None)

    nint, nl_int, fmt_int = block_line(k, "integer header")
    if nl_int is None:
        raise src.err(k + 1, "integer header line does not give its number of lines")
    ints, i = _fixed_width_values(src, k + 1, nl_int, nint, fmt_int, "integer header")
    nreal, nl_real, fmt_real = block_line(i, "real header")
    k_real = i
    if "real-header" not in lines[i].lower() or nl_real is None:
        raise src.err(i + 1, "expected 'Real-header values follow on N lines'")
    reals, i = _fixed_width_values(src, i + 1, nl_real, nreal, fmt_real, "real header")
    ncom, _, _ = block_line(i, "comment count")
    if "comment" not in lines[i].lower():
        raise src.err(i + 1, "expected 'N Comment line(s) follow'")
    i = i + 1 + ncom
    if i >= len(lines):
        raise src.err(len(lines), "file ends before the data block")
    data_hdr = lines[i]
    npts, _, fmt_data = block_line(i, "data header")
    low = data_hdr.lower()
    if "acc" not in low:
        raise src.err(i + 1, "first data block is not acceleration")
    um = re.search(r"units\s*=\s*([^\s(,]+)", data_hdr, re.IGNORECASE)
    if um is None:
        raise src.err(i + 1, "data header does not declare units")
    counts = um.group(1).lower().startswith("count")
    if counts:
        # raw counts (COSMOS V0): converted with the recorder and sensor constants of the real
        # header (see _cosmos_counts_factor); no unit can be imposed on them
        if units is not None:
            raise src.err(i + 1, f"the file holds raw counts (COSMOS V0), converted with its "
                                 f"header constants, but units {units} were given")
        uname = "counts"
        scale = _cosmos_counts_factor(src, reals, k_real, nl_real)
    else:
        # CGS writes "units=g.     (02)": the period ends the word, it is not part of the unit
        utok = um.group(1).rstrip(".")
        uname = _check_units(src, normalize_units(utok, f"{src.name} line {i + 1}"), units,
                             i + 1)
        scale = UNITS[uname]
    if len(reals) < 62:
        raise src.err(k + 1, "real header has fewer than 62 values (no sampling interval)")
    dt_ms = float(reals[61])
    dt = _check_dt(src, dt_ms / 1000.0, None)
    if dt_arg is not None and not math.isclose(dt_arg, dt, rel_tol=1e-9):
        raise src.err(None, f"the file declares dt = {_num(dt)} s but a time step of "
                            f"{_num(dt_arg)} s was given")
    # data lines run until the 'End-of-data' line (or the next block / end of file)
    j = i + 1
    stop = j
    while stop < len(lines) and not _is_text_line(lines[stop]):
        stop += 1
    width = None
    if fmt_data:
        fm = _FORTRAN_FMT.search(fmt_data)
        width = int(fm.group(3)) if fm else None
    vals: list[float] = []
    for r in range(j, stop):
        line = lines[r].rstrip()
        if width:
            toks = [line[q:q + width].strip() for q in range(0, len(line), width)]
        else:
            toks = line.split()
        vals.extend(src.num(t, r + 1) for t in toks if t)
    if len(vals) != npts:
        raise src.err(max(stop, j), f"data header declares {npts} points but has {len(vals)}")
    if npts < 2:
        raise src.err(i + 1, "a record needs at least 2 points")
    th = lines[text0:k]
    level = {0: "V0", 1: "V1", 2: "V2", 3: "V3"}.get(int(ints[0]), "") if len(ints) else ""
    # orientation code (integer header 54): 1-360 azimuth from north (360 = north), 400 up,
    # 401 down, 402 vertical; 500/501 radial/transverse, 600/601 longitudinal/tangential,
    # 700/701 H1/H2 and 2000 "other" give no azimuth. When it is unknown (0 or -999), integer
    # header 55 gives the orientation relative to the structure's reference azimuth (integer
    # header 20 or 21), as gmprocess reads it (USGS NSMP building channels); failing that, a
    # "|<SCNL>STA.CHN.NET.LOC" comment (USGS files) tells a vertical channel by its Z.
    az = None
    vert = False
    code = int(ints[53]) if len(ints) > 53 else -999
    if code in (0, -999) and len(ints) > 54 and int(ints[54]) not in (0, -999):
        rel = int(ints[54])
        ref = next((int(v) for v in ints[19:21] if int(v) != -999), None)
        if rel in (400, 401, 402):
            code = rel
        elif 1 <= rel <= 360 and ref is not None:
            code = (ref + rel - 1) % 360 + 1
    comp = ""
    if 1 <= code <= 360:
        az = float(code) % 360.0
        comp = f"{code}"
    elif code in (400, 401, 402):
        vert = True
        comp = f"{code}"
    elif code not in (0, -999):
        comp = f"{code}"
    else:
        scnl = next((ln.strip()[7:] for ln in lines[i - ncom:i]
                     if ln.strip().upper().startswith("|<SCNL>")), "")
        parts = scnl.split()[0].split(".") if scnl.split() else []
        if len(parts) > 1 and len(parts[1]) == 3:
            comp = parts[1].upper()
            vert = comp.endswith("Z")
    meta = {
        "format": "cosmos",
        "level": level,
        "source_file": str(src.path),
        "units_in": uname,
        "title": th[0].strip() if th else "",
        "event": th[1].strip() if len(th) > 1 else "",
        "station": th[4][28:34].strip() if len(th) > 4 else "",
        "channel": position,
        "component": comp,
        "azimuth_deg": az,
        "vertical": vert,
    }
    if position > 1:
        meta["name"] = f"{src.path.stem}_ch{position}"
    nxt = stop
    while nxt < len(lines) and "end-of-data" in lines[nxt].lower():
        nxt += 1
    if counts:
        meta["conversion"] = scale  # m/s² per count
        meta["lsb_uv"] = float(reals[21])
        meta["sensitivity_v_per_g"] = float(reals[41])
        meta["gain"] = float(reals[46]) if len(reals) > 46 and reals[46] != -999 else 1.0
    acc = np.asarray(vals) * scale
    # real header 64: maximum of the series, in its units (-999 when not given; counts in a V0
    # file, where no offset is removed, so it compares with the raw counts): warn if the
    # data disagree beyond rounding (the data are authoritative)
    if len(reals) > 63 and reals[63] != -999:
        declared = abs(float(reals[63])) * scale
        meta["pga_declared"] = declared
        actual = float(np.max(np.abs(acc)))
        if not math.isclose(declared, actual, rel_tol=1e-3, abs_tol=1e-9):
            warnings.warn(f"{src.name} line {i + 1}: declared maximum {reals[63]:g} (real "
                          f"header 64) differs from the data ({actual / scale:.6g})",
                          stacklevel=3)
    return _make(src, acc, dt, meta), nxt


_CSV_HDR = re.compile(r"^#\s*([A-Za-z_][A-Za-z0-9_ ]*?)\s*[:=]\s*(.*?)\s*$")
_SPLIT = re.compile(r"[,;\s]+")


def _read_csv(src: _Src, units: str | None, dt_arg: float | None) -> GroundMotion:
    hdr: dict[str, tuple[str, int]] = {}
    rows: list[list[float]] = []
    rowline: list[int] = []
    ncol = None
    seen_data = False
    names_line = None
    for i, line in enumerate(src.lines):
        s = line.strip()
        if not s:
            continue
        if s.startswith("#") or s.startswith("%"):
            m = _CSV_HDR.match(s.replace("%", "#", 1))
            if m and not seen_data:
                hdr[m.group(1).strip().lower()] = (m.group(2), i + 1)
            continue
        toks = [t for t in _SPLIT.split(s) if t]
        if not seen_data and names_line is None and not any(_NUM_RE.match(t) for t in toks):
            names_line = (toks, i + 1)  # column names
            continue
        vals = [src.num(t, i + 1) for t in toks]
        if ncol is None:
            ncol = len(vals)
            if ncol > 3:
                raise src.err(i + 1, f"{ncol} columns: expected 1 (acc), 2 (time, acc) or 3 "
                                     "(time, acc, acc_v)")
        elif len(vals) != ncol:
            raise src.err(i + 1, f"{len(vals)} columns where the first data line has {ncol}")
        seen_data = True
        rows.append(vals)
        rowline.append(i + 1)
    if not rows:
        raise src.err(None, "no data lines")
    # units
    if "units" in hdr:
        declared = normalize_units(hdr["units"][0], f"{src.name} line {hdr['units'][1]}")
        uname = _check_units(src, declared, units, hdr["units"][1])
    elif units is not None:
        uname = normalize_units(units, src.name)
    else:
        raise src.err(None, "units not declared: give them (--units g, m/s2 or cm/s2 on the "
                            "command line; units = \"g\" in a case file) or add a "
                            "'# units: g' line to the file")
    fac = UNITS[uname]
    data = np.asarray(rows, dtype=np.float64)
    n = data.shape[0]
    if "npts" in hdr:
        tok, lno = hdr["npts"]
        if not re.fullmatch(r"\d+", tok):
            raise src.err(lno, f"npts {_short(tok)} is not a whole number")
        if int(tok) != n:
            raise src.err(rowline[-1], f"header declares npts = {tok} but the file has {n} rows")
    dt_hdr = None
    if "dt" in hdr:
        tok, lno = hdr["dt"]
        tok = tok.split()[0] if tok.split() else tok
        dt_hdr = _check_dt(src, src.num(tok, lno), lno)
        if dt_arg is not None and not math.isclose(dt_arg, dt_hdr, rel_tol=1e-9):
            raise src.err(lno, f"the file declares dt = {_num(dt_hdr)} s but a time step of "
                                   f"{_num(dt_arg)} s was given")
    meta = {"format": "csv", "source_file": str(src.path), "units_in": uname}
    for key in ("name", "event", "station", "component"):
        if key in hdr:
            meta[key] = hdr[key][0]
    if n < 2:
        raise src.err(rowline[0], "a record needs at least 2 points")
    if ncol == 1:
        dt = dt_hdr if dt_hdr is not None else dt_arg
        if dt is None:
            raise src.err(None, "one-column file without a time step: give it (--dt on the command "
                                "line; dt = ... in a case file) or add a '# dt: 0.01' line")
        return _make(src, data[:, 0] * fac, _check_dt(src, float(dt), None), meta)
    t = data[:, 0]
    steps = np.diff(t)
    bad = np.nonzero(~(steps > 0))[0]
    if bad.size:
        r = int(bad[0]) + 1
        raise src.err(rowline[r], f"time {_num(t[r])} s does not increase "
                                  f"(previous {_num(t[r - 1])} s)")
    acc = data[:, 1] * fac
    acc_v = data[:, 2] * fac if ncol == 3 else None
    span_dt = float((t[-1] - t[0]) / (n - 1))
    uniform = np.max(np.abs(steps - span_dt)) <= 1e-6 * span_dt
    if uniform:
        dt = dt_hdr if dt_hdr is not None else span_dt
        if dt_hdr is not None and not math.isclose(dt_hdr, span_dt, rel_tol=1e-6):
            raise src.err(hdr["dt"][1], f"dt = {_num(dt_hdr)} s disagrees with the time "
                                        f"column ({_num(span_dt)} s)")
        if dt_arg is not None and not math.isclose(dt_arg, span_dt, rel_tol=1e-6):
            raise src.err(None, f"a time step of {_num(dt_arg)} s was given but the time "
                                f"column has a step of {_num(span_dt)} s")
        if t[0] != 0.0:
            meta["t0"] = float(t[0])
        return _make(src, acc, float(dt), meta, acc_v)
    # non-uniform: resample with a warning
    dt = dt_arg if dt_arg is not None else (dt_hdr if dt_hdr is not None else float(
        np.median(steps)))
    dt = _check_dt(src, float(dt), None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        gm = GroundMotion.from_samples(t, acc, acc_v, name=src.path.stem, meta=meta, dt=dt)
    warnings.warn(
        f"{src.name}: non-uniform time step ({steps.min():g} to {steps.max():g} s); resampled "
        f"to dt = {dt:g} s by linear interpolation",
        stacklevel=3,
    )
    return _check_range(src, gm)


def _check_range(src: _Src, gm: GroundMotion) -> GroundMotion:
    for arr in (gm.acc, gm.acc_v):
        if arr is not None and (
            not np.all(np.isfinite(arr)) or np.max(np.abs(arr)) > _MAX_ABS
        ):
            raise src.err(None, f"acceleration exceeds {_MAX_ABS:g} m/s² (wrong units or "
                                "corrupt file)")
    return gm


def _make(src: _Src, acc, dt, meta, acc_v=None) -> GroundMotion:
    name = meta.get("name") or src.path.stem
    try:
        gm = GroundMotion(dt=dt, acc=acc, acc_v=acc_v, name=name, meta=meta)
    except ValueError as exc:
        raise src.err(None, str(exc)) from None
    return _check_range(src, gm)


_READERS = {"at2": _read_at2, "esm": _read_esm, "cosmos": _read_cosmos, "csv": _read_csv}


def _read_channels(path, units, dt, format) -> tuple[list[GroundMotion], str]:
    path = Path(path)
    fmt_bin = _binary_format(path, format)
    if fmt_bin is not None:
        from murus.motion.seismo import read_obspy

        if units is not None:
            normalize_units(units, path.name)
        return read_obspy(path, fmt_bin, units, None if dt is None else float(dt)), fmt_bin
    text = _read_text(path)
    fmt = detect_format(path, text) if format is None else str(format).lower()
    if fmt not in FORMATS:
        raise MotionFormatError(f"{path.name}: unknown format '{format}' (use "
                                f"{', '.join(FORMATS)})")
    if dt is not None:
        dt = float(dt)
        if not (math.isfinite(dt) and dt > 0):
            raise MotionFormatError(f"{path.name}: the time step {_num(dt)} s must be a positive "
                                     "number")
    if units is not None:
        normalize_units(units, path.name)
    src = _Src(path, text)
    if fmt in ("dmg", "knet"):
        from murus.motion import networks

        reader = networks.read_dmg if fmt == "dmg" else networks.read_knet
        return reader(src, units, dt), fmt
    if fmt == "cosmos":
        return _read_cosmos_all(src, units, dt), fmt
    gm = _READERS[fmt](src, units, dt)
    gm.meta.setdefault("channel", 1)
    return [gm], fmt


def _binary_format(path: Path, format) -> str | None:
    """'sac' or 'mseed' for a binary seismological file (or when asked for), else None."""
    if format is not None:
        f = str(format).lower()
        return f if f in ("sac", "mseed") else None
    try:
        with open(path, "rb") as fh:
            head = fh.read(1024)
        size = path.stat().st_size
    except OSError:
        return None  # _read_text gives the message
    from murus.motion.seismo import sniff_binary

    return sniff_binary(head, size)


def _label(gm: GroundMotion) -> str:
    comp = gm.meta.get("component", "")
    return f"{gm.meta.get('channel', '?')} ({comp})" if comp else str(gm.meta.get("channel", "?"))


def select_channel(channels: list[GroundMotion], channel=None, where: str = "") -> GroundMotion:
    """One channel of a multi-channel record.

    Parameters
    ----------
    channels : list of GroundMotion
        As returned by :func:`read_all`.
    channel : int or str, optional
        An int is the channel number written in the file ("Chan  2" of a CSMIP/DMG file; the
        position from 1 for formats without numbers). A str is matched, ignoring case and
        blanks, against the component as written ("360 Deg", "Up", "E-W"), the azimuth in
        degrees ("90", "360" = "0"), or "N", "E", "Z"/"up"/"vertical". ``None``: the first
        horizontal channel (the first channel if none is horizontal).
    where : str
        File name for messages.

    Returns
    -------
    GroundMotion

    Raises
    ------
    MotionFormatError
        No channel or more than one matches.
    """
    labels = ", ".join(_label(g) for g in channels)
    if channel is None:
        return next((g for g in channels if not g.meta.get("vertical")), channels[0])
    if isinstance(channel, (int, np.integer)) and not isinstance(channel, bool):
        hits = [g for g in channels if g.meta.get("channel") == int(channel)]
    else:
        key = str(channel).strip().lower().replace(" ", "")
        if key.isdigit() and not any(
                str(g.meta.get("component", "")).lower().replace(" ", "") == key
                for g in channels):
            # a bare number: an azimuth if one matches, else the channel number
            az = float(key) % 360.0
            hits = [g for g in channels if g.meta.get("azimuth_deg") is not None
                    and math.isclose(g.meta["azimuth_deg"], az, abs_tol=1e-9)]
            if not hits:
                hits = [g for g in channels if g.meta.get("channel") == int(key)]
        elif key in ("z", "up", "u", "vertical", "v", "u-d", "ud"):
            hits = [g for g in channels if g.meta.get("vertical")]
        elif key in ("n", "north", "n-s", "ns"):
            hits = [g for g in channels if g.meta.get("azimuth_deg") is not None
                    and math.isclose(g.meta["azimuth_deg"], 0.0, abs_tol=1e-9)]
        elif key in ("e", "east", "e-w", "ew"):
            hits = [g for g in channels if g.meta.get("azimuth_deg") is not None
                    and math.isclose(g.meta["azimuth_deg"], 90.0, abs_tol=1e-9)]
        else:
            hits = [g for g in channels
                    if str(g.meta.get("component", "")).lower().replace(" ", "") == key]
    prefix = f"{where}: " if where else ""
    if len(hits) != 1:
        what = "no channel" if not hits else f"{len(hits)} channels"
        raise MotionFormatError(f"{prefix}{what} matches channel {_short(str(channel))} "
                                f"(channels: {labels})")
    return hits[0]


def read(path, units: str | None = None, dt: float | None = None, scale: float = 1.0,
         format: str | None = None, channel=None) -> GroundMotion:
    """Read an acceleration record into a :class:`GroundMotion` (m/s²).

    Parameters
    ----------
    path : str or Path
        Record file: PEER AT2, ESM ASCII, COSMOS V0/V1/V2, CSMIP/DMG V1/V2, K-NET/KiK-net ASCII,
        CSV/text (see the module docstring and :mod:`murus.motion.networks`).
    units : {"g", "m/s2", "cm/s2"}, optional
        Units of a CSV/text file that does not declare them; for the other formats, a check
        against the declared units.
    dt : float, optional
        Time step [s] of a one-column file; for the other formats a check against the file.
    scale : float
        Factor applied after conversion to m/s².
    format : {"at2", "esm", "cosmos", "dmg", "knet", "csv", "sac", "mseed"}, optional
        Skip detection.
    channel : int or str, optional
        Channel of a multi-channel file (see :func:`select_channel`); default the first
        horizontal channel. ``meta["channel"]`` and ``meta["component"]`` say which was read.

    Returns
    -------
    GroundMotion

    Raises
    ------
    MotionFormatError
        One-line message naming the file and line.
    """
    channels, _fmt = _read_channels(path, units, dt, format)
    gm = select_channel(channels, channel, Path(path).name)
    if scale != 1.0:
        gm = gm.scaled(scale)
    return gm


def read_all(path, units: str | None = None, dt: float | None = None,
             format: str | None = None) -> list[GroundMotion]:
    """Every acceleration channel of a record file, in file order (one item for single-channel
    formats).

    Parameters
    ----------
    path : str or Path
        Record file (see :func:`read`).
    units : {"g", "m/s2", "cm/s2"}, optional
        As :func:`read`.
    dt : float, optional
        As :func:`read` [s].
    format : str, optional
        Skip detection.

    Returns
    -------
    list of GroundMotion
        Acceleration in m/s²; ``meta`` holds ``channel``, ``component``, ``azimuth_deg`` and
        ``vertical`` where the format declares them.
    """
    return _read_channels(path, units, dt, format)[0]


# ----------------------------------------------------------------------------------- writers


def _clean(s) -> str:
    return str(s).replace("\n", " ").replace("\r", " ")


def format_csv(motion: GroundMotion, units: str = "m/s2") -> str:
    """CSV text: commented header (name, dt, units, npts, metadata, one ``# processing i:``
    line per operation of ``meta['processing']``) then time, acc[, acc_v]."""
    uname = normalize_units(units)
    fac = UNITS[uname]
    out = [
        "# murus ground motion",
        f"# name: {_clean(motion.name)}",
        f"# dt: {motion.dt!r}",
        f"# units: {uname}",
        f"# npts: {motion.npts}",
    ]
    for key in ("event", "station", "component"):
        if motion.meta.get(key):
            out.append(f"# {key}: {_clean(motion.meta[key])}")
    for i, step in enumerate(motion.meta.get("processing", ()), 1):
        out.append(f"# processing {i}: {_clean(step)}")
    cols = "time,acc" + (",acc_v" if motion.acc_v is not None else "")
    out.append(cols)
    t = motion.time
    a = motion.acc / fac
    if motion.acc_v is None:
        out.extend(f"{ti!r},{ai!r}" for ti, ai in zip(t.tolist(), a.tolist(), strict=True))
    else:
        av = motion.acc_v / fac
        out.extend(
            f"{ti!r},{ai!r},{vi!r}"
            for ti, ai, vi in zip(t.tolist(), a.tolist(), av.tolist(), strict=True)
        )
    return "\n".join(out) + "\n"


def format_at2(motion: GroundMotion) -> str:
    """PEER AT2 text (units of g with g = murus.G, 10 significant digits, 5 values a line).
    AT2 holds the horizontal component only (a vertical component is not written); the
    operations of ``meta['processing']`` are appended to the title line."""
    title = "PEER NGA STRONG MOTION DATABASE RECORD (written by murus)"
    steps = [_clean(x) for x in motion.meta.get("processing", ())]
    if steps:  # the processing on the title line (AT2 has no other free header line)
        title += " processing: " + " | ".join(f"{i}. {x}" for i, x in enumerate(steps, 1))
    ev = _clean(motion.meta.get("event", motion.name or "record")).replace(",", ";")
    st = _clean(motion.meta.get("station", "")).replace(",", ";")
    comp = _clean(motion.meta.get("component", "")).replace(",", ";")
    lines = [
        title,
        f"{ev}, , {st}, {comp}",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {motion.npts}, DT= {motion.dt!r} SEC",
    ]
    a = motion.acc / G
    for k in range(0, a.size, 5):
        # blank-separated (a fixed width would merge fields with 3-digit exponents)
        lines.append("".join(f" {x: .9E}" for x in a[k:k + 5]))
    return "\n".join(lines) + "\n"


def write(motion: GroundMotion, path, format: str | None = None, units: str = "m/s2") -> Path:
    """Write ``motion`` to ``path`` (CSV with a commented header, or PEER AT2 in g).

    The format follows ``format`` or the extension (.at2 -> AT2, anything else -> CSV). The
    file is written to a temporary name and renamed, so nothing is left half-written.

    Parameters
    ----------
    motion : GroundMotion
        The record.
    path : str or pathlib.Path
        The file.
    format : str, optional
        ``"csv"`` or ``"at2"``; default from the extension.
    units : str
        Units of the CSV values: ``"m/s2"``, ``"g"`` or ``"cm/s2"``.

    Returns
    -------
    pathlib.Path
    """
    path = Path(path)
    fmt = (format or ("at2" if path.suffix.lower() == ".at2" else "csv")).lower()
    if fmt == "at2":
        text = format_at2(motion)
    elif fmt == "csv":
        text = format_csv(motion, units)
    else:
        raise ValueError(f"cannot write format {fmt!r} (use 'csv' or 'at2')")
    from murus.outputs import write_text

    write_text(path, text)
    return path
