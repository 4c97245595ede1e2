"""Pieces of the VTK XML writers shared by :mod:`murus.dem.vtk` (blocks, ``.vtp``) and
:mod:`murus.continuum.vtk` (zones, ``.vtu``): data-array checks, ``DataArray`` elements in ASCII
(exact ``repr`` round trip of float64) or inline base64 (``format="binary"``: a UInt32 byte count
then the little-endian values), and the final move of a series folder that replaces only the
files the series writer owns (by name) and leaves every other file alone.

Only NumPy; the documents follow the VTK XML file formats (VTK User's Guide, "VTK File Formats",
XML formats). Types written: Float64 (floats), Int64 (integers, bools), UInt8 (``numpy.uint8``
arrays passed straight to :func:`data_array`, e.g. the cell types of an UnstructuredGrid).
"""

from __future__ import annotations

import base64
import os
import re
from collections.abc import Mapping
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

HEADER = '<?xml version="1.0"?>\n'
VTKFILE = '<VTKFile type="{kind}" version="0.1" byte_order="LittleEndian">\n'

#: dtype.str of the arrays written -> (VTK type name, little-endian dtype of the raw bytes)
_VTK_TYPE = {"f": ("Float64", "<f8"), "i": ("Int64", "<i8"), "u1": ("UInt8", "u1")}


def _vtk_type(a: np.ndarray) -> tuple[str, str]:
    if a.dtype == np.uint8:
        return _VTK_TYPE["u1"]
    return _VTK_TYPE[a.dtype.kind]


def as_data(name, values, n: int, what: str, noun: str) -> np.ndarray:
    """A data array with ``n`` tuples: (n,) scalars or (n, k) vectors, 2-vectors padded to 3."""
    if not isinstance(name, str) or not name.strip():
        raise ValueError(f"{what} names must be non-empty strings, got {name!r}")
    a = np.asarray(values)
    if a.dtype == bool:
        a = a.astype(np.uint8)
    if a.dtype.kind not in "iuf":
        raise ValueError(f"{what} {name!r} has dtype {a.dtype}; expected numbers")
    if a.ndim == 0 or a.ndim > 2 or (a.ndim == 2 and a.shape[1] == 0):
        raise ValueError(f"{what} {name!r} has shape {a.shape}; expected ({n},) or ({n}, k)")
    if len(a) != n:
        raise ValueError(f"{what} {name!r} has {len(a)} values for {n} {noun}")
    if a.ndim == 2 and a.shape[1] == 1:
        a = a[:, 0]
    if a.ndim == 2 and a.shape[1] == 2:
        a = np.column_stack([a, np.zeros(n, dtype=a.dtype)])
    if a.dtype.kind == "f":
        a = a.astype(np.float64)
        bad = np.flatnonzero(~np.isfinite(a.reshape(n, -1)).all(axis=1))
        if len(bad):
            raise ValueError(f"{what} {name!r} has non-finite values (first at index {bad[0]})")
    else:
        a = a.astype(np.int64)
    return a


def values_text(a: np.ndarray, binary: bool) -> str:
    """The body of a DataArray: ASCII numbers or the base64 of byte count + raw values."""
    flat = a.ravel()
    if binary:
        raw = flat.astype(_vtk_type(a)[1]).tobytes()
        return base64.b64encode(np.uint32(len(raw)).astype("<u4").tobytes() + raw).decode("ascii")
    if a.dtype.kind == "f":
        return " ".join(map(repr, flat.tolist()))
    return " ".join(map(str, flat.tolist()))


def data_array(name: str, a: np.ndarray, binary: bool, indent: str) -> str:
    """One ``<DataArray>`` element (float64, int64 or uint8 array, (n,) or (n, k))."""
    comps = 1 if a.ndim == 1 else a.shape[1]
    fmt = "binary" if binary else "ascii"
    attrs = f'type="{_vtk_type(a)[0]}" Name={quoteattr(name)} NumberOfComponents="{comps}"'
    body = values_text(a, binary)
    return f'{indent}<DataArray {attrs} format="{fmt}">\n{indent}  {body}\n{indent}</DataArray>\n'


def data_section(tag: str, data: Mapping[str, np.ndarray], binary: bool) -> str:
    """A ``<PointData>`` or ``<CellData>`` section of the given arrays (possibly empty)."""
    if not data:
        return f"      <{tag}>\n      </{tag}>\n"
    out = [f"      <{tag}>\n"]
    for name, a in data.items():
        out.append(data_array(name, a, binary, "        "))
    out.append(f"      </{tag}>\n")
    return "".join(out)


def move_series(tmp: Path, folder: Path, ours: re.Pattern) -> None:
    """Move the files of the finished series folder ``tmp`` into ``folder``.

    A missing ``folder`` is ``tmp`` renamed. Otherwise the files of ``folder`` whose names
    match ``ours`` (the series writer's own names) and that the new series does not write are
    removed, every other file is left alone, and the new files are moved in with
    :func:`os.replace`: frames first, ``.pvd`` collections last, so that a collection never
    points at a missing frame.
    """
    if not folder.exists():
        tmp.rename(folder)
        return
    new = {p.name for p in tmp.iterdir()}
    for old in folder.iterdir():
        if old.is_file() and ours.fullmatch(old.name) and old.name not in new:
            old.unlink()
    for name in sorted(new, key=lambda s: (s.endswith(".pvd"), s)):
        os.replace(tmp / name, folder / name)


def read_base64_array(text: str, dtype) -> np.ndarray:
    """Decode one inline ``format="binary"`` DataArray written here (UInt32 byte-count
    header, then little-endian values); for tests and quick checks."""
    raw = base64.b64decode(text.strip())
    nbytes = int(np.frombuffer(raw[:4], dtype="<u4")[0])
    return np.frombuffer(raw[4 : 4 + nbytes], dtype=np.dtype(dtype).newbyteorder("<")).copy()
