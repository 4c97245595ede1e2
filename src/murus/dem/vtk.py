"""VTK XML output of a 2D distinct-element model, for ParaView: plain arrays in, files out.

Only NumPy is needed: the files are written by hand following the VTK XML format
(``VTKFile type="PolyData" version="0.1" byte_order="LittleEndian"``), either as ASCII text
(``binary=False``, exact round trip of every float64 through its shortest ``repr``) or as
inline base64 (``binary=True``: each DataArray is the base64 encoding of a UInt32 byte count
followed by the little-endian raw values, the layout VTK calls ``format="binary"``).

Files written here:

- :func:`write_vtp`: blocks as polygon cells. Polygonal blocks come first, in the order given,
  then discs, each approximated by a regular polygon of ``disc_resolution`` vertices (so that
  ParaView shows them without glyphs). ``cell_data`` arrays hold one value (or one vector) per
  cell in that same order: polygons first, then discs.
- :func:`write_contacts_vtp`: contact points as vertex cells with point data ``normal_force``,
  ``shear_force`` and ``normal`` (a force-chain view: Glyph filter oriented by ``normal`` and
  scaled by ``normal_force``).
- :class:`PvdWriter` and :func:`write_series`: a ``.pvd`` collection that ParaView opens as a
  time series.

Units are those of the arrays passed in (SI inside murus: m, N). 2D vectors are padded with a
zero third component. Every file is written to a temporary sibling and renamed into place, so a
failed call leaves nothing half-written; inputs are checked first and a bad input raises a
one-line ``ValueError`` naming what is wrong.
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
from collections.abc import Iterable, Mapping
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from murus._vtkxml import HEADER as _HEADER
from murus._vtkxml import VTKFILE as _VTKFILE
from murus._vtkxml import as_data as _as_data
from murus._vtkxml import data_array as _data_array
from murus._vtkxml import data_section as _data_section
from murus._vtkxml import move_series, read_base64_array
from murus.outputs import write_text

__all__ = ["PvdWriter", "read_base64_array", "write_contacts_vtp", "write_series", "write_vtp"]


# ----------------------------------------------------------------------------- validation


def _as_polygons(polygons) -> list[np.ndarray]:
    """Polygons as float64 (k, 2) arrays; a closing vertex equal to the first is dropped."""
    if polygons is None:
        return []
    if isinstance(polygons, np.ndarray) and polygons.ndim == 3:
        polygons = list(polygons)
    out = []
    for i, p in enumerate(polygons):
        try:
            a = np.asarray(p, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"polygon {i} is not an array of numbers: {exc}") from None
        if a.ndim != 2 or a.shape[1] != 2:
            raise ValueError(f"polygon {i} has shape {a.shape}; expected (k, 2) vertices x, y")
        if len(a) >= 2 and np.array_equal(a[0], a[-1]):
            a = a[:-1]
        if len(a) < 3:
            raise ValueError(f"polygon {i} has {len(a)} vertices; a polygon needs at least 3")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"polygon {i} has non-finite coordinates")
        out.append(a)
    return out


def _as_discs(discs) -> tuple[np.ndarray, np.ndarray]:
    """Discs as (centres (n, 2), radii (n,)) float64 arrays; ``None`` gives no disc."""
    if discs is None:
        return np.zeros((0, 2)), np.zeros(0)
    try:
        centres, radii = discs
    except (TypeError, ValueError):
        raise ValueError("discs must be a pair (centres (n, 2), radii (n,))") from None
    c = np.asarray(centres, dtype=np.float64)
    r = np.asarray(radii, dtype=np.float64)
    if c.size == 0 and r.size == 0:
        return np.zeros((0, 2)), np.zeros(0)
    if c.ndim != 2 or c.shape[1] != 2:
        raise ValueError(f"disc centres have shape {c.shape}; expected (n, 2)")
    if r.ndim != 1 or len(r) != len(c):
        raise ValueError(f"disc radii have shape {r.shape}; expected ({len(c)},), one per centre")
    if not np.all(np.isfinite(c)):
        raise ValueError("disc centres have non-finite coordinates")
    bad = np.flatnonzero(~(np.isfinite(r) & (r > 0)))
    if len(bad):
        i = int(bad[0])
        raise ValueError(f"disc {i} has radius {float(r[i])!r}; radii must be finite and > 0")
    return c, r


def _as_contacts(rows) -> np.ndarray:
    a = np.asarray(rows, dtype=np.float64)
    if a.size == 0:
        return np.zeros((0, 6))
    if a.ndim != 2 or a.shape[1] != 6:
        raise ValueError(
            f"contact rows have shape {a.shape}; expected (n, 6): x, y, fn, fs, nx, ny"
        )
    bad = np.flatnonzero(~np.isfinite(a).all(axis=1))
    if len(bad):
        raise ValueError(f"contact row {bad[0]} has non-finite values")
    return a


# ----------------------------------------------------------------------------- XML pieces

def _cells(tag: str, connectivity: np.ndarray, offsets: np.ndarray, binary: bool) -> str:
    return (f"      <{tag}>\n"
            + _data_array("connectivity", connectivity.astype(np.int64), binary, "        ")
            + _data_array("offsets", offsets.astype(np.int64), binary, "        ")
            + f"      </{tag}>\n")


def _polydata(points, verts, polys, point_data, cell_data, binary) -> str:
    """One-piece PolyData document; ``verts``/``polys`` are (connectivity, offsets) or None."""
    n_verts = 0 if verts is None else len(verts[1])
    n_polys = 0 if polys is None else len(polys[1])
    parts = [
        _HEADER,
        _VTKFILE.format(kind="PolyData"),
        "  <PolyData>\n",
        f'    <Piece NumberOfPoints="{len(points)}" NumberOfVerts="{n_verts}" '
        f'NumberOfLines="0" NumberOfStrips="0" NumberOfPolys="{n_polys}">\n',
        _data_section("PointData", point_data, binary),
        _data_section("CellData", cell_data, binary),
        "      <Points>\n",
        _data_array("Points", points, binary, "        "),
        "      </Points>\n",
    ]
    if verts is not None:
        parts.append(_cells("Verts", *verts, binary))
    if polys is not None:
        parts.append(_cells("Polys", *polys, binary))
    parts += ["    </Piece>\n", "  </PolyData>\n", "</VTKFile>\n"]
    return "".join(parts)


# ----------------------------------------------------------------------------- writers


def _disc_polygons(centres, radii, resolution: int) -> np.ndarray:
    """(n, resolution, 2) vertices of regular polygons inscribed in the discs,
    counter-clockwise from angle 0."""
    ang = 2.0 * np.pi * np.arange(resolution) / resolution
    ring = np.column_stack([np.cos(ang), np.sin(ang)])
    return centres[:, None, :] + radii[:, None, None] * ring[None, :, :]


def write_vtp(
    path,
    polygons,
    discs=None,
    cell_data: Mapping[str, np.ndarray] | None = None,
    disc_resolution: int = 24,
    z: float = 0.0,
    binary: bool = False,
) -> Path:
    """Write blocks as a VTK XML PolyData file (``.vtp``) of polygon cells.

    Parameters
    ----------
    path:
        Output file [``.vtp``]; parent folders are created. Written atomically.
    polygons:
        List of (k, 2) vertex arrays x, y [m], k >= 3, one per polygonal block (or a
        (n, k, 2) array). A closing vertex repeating the first is dropped. Each polygon gets its
        own points (no sharing between blocks), so cells stay independent.
    discs:
        ``(centres (n, 2) [m], radii (n,) [m])`` or ``None``. Each disc is written as a regular
        polygon of ``disc_resolution`` vertices on its circle, starting at angle 0,
        counter-clockwise.
    cell_data:
        ``{name: array}`` with one entry per cell, **polygons first, then discs**: shape (n,)
        for scalars (float -> Float64, int/bool -> Int64) or (n, k) for vectors; 2-vectors are
        padded to 3 components with zeros (so ParaView treats them as vectors).
    disc_resolution:
        Vertices per disc, >= 3.
    z:
        Out-of-plane coordinate of every point [m].
    binary:
        ``False``: ASCII (exact round trip); ``True``: inline base64, smaller and faster.

    Returns the path written. Raises ``ValueError`` (one line) on bad input; nothing is
    written then.
    """
    polys = _as_polygons(polygons)
    centres, radii = _as_discs(discs)
    if isinstance(disc_resolution, bool) or not isinstance(disc_resolution, int | np.integer):
        raise ValueError(f"disc_resolution must be an integer, got {disc_resolution!r}")
    if disc_resolution < 3:
        raise ValueError(f"disc_resolution is {disc_resolution}; a disc needs at least 3 vertices")
    z = float(z)
    if not np.isfinite(z):
        raise ValueError(f"z must be finite, got {z!r}")
    n_cells = len(polys) + len(centres)
    noun = f"cells ({len(polys)} polygons + {len(centres)} discs)"
    data = {k: _as_data(k, v, n_cells, "cell_data", noun) for k, v in (cell_data or {}).items()}

    rings = polys + list(_disc_polygons(centres, radii, int(disc_resolution)))
    sizes = np.array([len(r) for r in rings], dtype=np.int64)
    xy = np.concatenate(rings) if rings else np.zeros((0, 2))
    points = np.column_stack([xy, np.full(len(xy), z)])
    connectivity = np.arange(len(points), dtype=np.int64)
    offsets = np.cumsum(sizes)
    text = _polydata(points, None, (connectivity, offsets), {}, data, binary)
    return write_text(path, text)


def write_contacts_vtp(
    path,
    rows,
    point_data: Mapping[str, np.ndarray] | None = None,
    z: float = 0.0,
    binary: bool = False,
) -> Path:
    """Write contacts as a VTK XML PolyData file of vertex cells, for force-chain views.

    ``rows`` is an (n, 6) array, one row per contact point: x [m], y [m], normal force fn [N],
    shear force fs [N], unit normal nx, ny [-] (sign conventions are the engine's: this writer
    copies them). Point data written: ``normal_force`` (fn), ``shear_force`` (fs) and
    ``normal`` (nx, ny, 0). ``point_data`` adds arrays with one value or vector per contact
    (2-vectors padded to 3). Zero contacts give a valid empty file. In ParaView, a Glyph filter
    oriented by ``normal`` and scaled by ``normal_force`` draws the force chains. Written
    atomically; returns the path.
    """
    a = _as_contacts(rows)
    n = len(a)
    z = float(z)
    if not np.isfinite(z):
        raise ValueError(f"z must be finite, got {z!r}")
    extra = {k: _as_data(k, v, n, "point_data", "contacts") for k, v in (point_data or {}).items()}
    for name in ("normal_force", "shear_force", "normal"):
        if name in extra:
            raise ValueError(f"point_data {name!r} clashes with a built-in contact array")
    data = {
        "normal_force": a[:, 2].copy(),
        "shear_force": a[:, 3].copy(),
        "normal": np.column_stack([a[:, 4], a[:, 5], np.zeros(n)]),
        **extra,
    }
    points = np.column_stack([a[:, 0], a[:, 1], np.full(n, z)])
    idx = np.arange(n, dtype=np.int64)
    text = _polydata(points, (idx, idx + 1), None, data, {}, binary)
    return write_text(path, text)


# ----------------------------------------------------------------------------- collections


class PvdWriter:
    """A ParaView collection (``.pvd``) of time frames, written on close.

    >>> with PvdWriter(out / "series.pvd") as pvd:          # doctest: +SKIP
    ...     for i, (t, blocks) in enumerate(history):
    ...         write_vtp(out / f"frame_{i:04d}.vtp", blocks)
    ...         pvd.add(t, f"frame_{i:04d}.vtp")

    ``add(time, vtp_filename)`` records a frame: ``time`` in s, finite and strictly increasing;
    the file name is stored relative to the ``.pvd`` folder (a relative name is taken as already
    relative to it). The collection is written atomically (temporary file, then rename) by
    :meth:`close` or at the normal end of a ``with`` block; if the block raises, no ``.pvd`` is
    written. :meth:`write` writes the frames collected so far (e.g. as a checkpoint).
    """

    def __init__(self, path):
        self.path = Path(path)
        self.frames: list[tuple[float, str]] = []
        self.closed = False

    def add(self, time: float, vtp_filename) -> None:
        if self.closed:
            raise ValueError(f"PvdWriter for {self.path} is closed")
        try:
            t = float(time)
        except (TypeError, ValueError):
            raise ValueError(f"frame time must be a number, got {time!r}") from None
        if not np.isfinite(t):
            raise ValueError(f"frame {len(self.frames)} has non-finite time {t!r}")
        if self.frames and t <= self.frames[-1][0]:
            raise ValueError(
                f"frame {len(self.frames)} has time {t!r} s, not after the previous "
                f"frame's {self.frames[-1][0]!r} s; times must increase"
            )
        name = Path(vtp_filename)
        if name.is_absolute():
            try:
                name = Path(os.path.relpath(name.resolve(), self.path.parent.resolve()))
            except ValueError:  # another drive on Windows: keep it absolute
                pass
        self.frames.append((t, name.as_posix()))

    def text(self) -> str:
        """The ``.pvd`` document of the frames collected so far."""
        rows = "".join(
            f'    <DataSet timestep="{t!r}" group="" part="0" file={quoteattr(f)}/>\n'
            for t, f in self.frames
        )
        return (_HEADER + _VTKFILE.format(kind="Collection")
                + "  <Collection>\n" + rows + "  </Collection>\n</VTKFile>\n")

    def write(self) -> Path:
        """Write the collection as it stands (atomically); returns its path."""
        return write_text(self.path, self.text())

    def close(self) -> Path:
        """Write the collection and refuse further frames; returns its path."""
        if not self.closed:
            self.write()
            self.closed = True
        return self.path

    def __enter__(self) -> PvdWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            self.closed = True


_OURS = re.compile(r"(frame|contacts)_\d{4,}\.vtp|series\.pvd|contacts\.pvd")


def write_series(
    folder,
    frames: Iterable,
    disc_resolution: int = 24,
    z: float = 0.0,
    binary: bool = False,
) -> Path:
    """Write a time series of block frames as ``frame_0000.vtp``, ... and ``series.pvd``.

    ``frames`` is an iterable (a generator is fine, frames are written one at a time) of
    ``(time, frame)`` pairs: ``time`` in s, strictly increasing, and ``frame`` a mapping with
    key ``polygons`` and optional keys ``discs``, ``cell_data`` (as in :func:`write_vtp`) and
    ``contacts`` ((n, 6) rows as in :func:`write_contacts_vtp`). If any frame has
    ``contacts``, every frame gets a ``contacts_0000.vtp``, ... (possibly empty) and a
    ``contacts.pvd`` collection is written as well.

    All files are first written into a temporary sibling folder; only when every frame has
    succeeded are they moved into ``folder`` (``series.pvd`` last). Files of an earlier series
    in ``folder`` (``frame_*.vtp``, ``contacts_*.vtp``, ``series.pvd``, ``contacts.pvd``) are
    replaced; other files are left alone. Returns the path of ``series.pvd``.
    """
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise ValueError(f"{folder} exists and is not a folder")
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{folder.name}.", dir=folder.parent))
    try:
        blocks = PvdWriter(tmp / "series.pvd")
        contacts = PvdWriter(tmp / "contacts.pvd")
        contact_rows = []
        for i, item in enumerate(frames):
            try:
                time, frame = item
            except (TypeError, ValueError):
                raise ValueError(f"frame {i} is not a (time, mapping) pair") from None
            if not isinstance(frame, Mapping) or "polygons" not in frame:
                raise ValueError(f"frame {i} must be a mapping with key 'polygons'")
            unknown = set(frame) - {"polygons", "discs", "cell_data", "contacts"}
            if unknown:
                raise ValueError(f"frame {i} has unknown keys {sorted(unknown)}")
            name = f"frame_{i:04d}.vtp"
            blocks.add(time, name)
            try:
                write_vtp(tmp / name, frame["polygons"], frame.get("discs"),
                          frame.get("cell_data"), disc_resolution, z, binary)
                if frame.get("contacts") is not None:
                    _as_contacts(frame["contacts"])  # fail early, before later frames
                contact_rows.append(frame.get("contacts"))
            except ValueError as exc:
                raise ValueError(f"frame {i}: {exc}") from None
        if any(c is not None for c in contact_rows):
            for i, (rows, (t, _)) in enumerate(zip(contact_rows, blocks.frames, strict=True)):
                name = f"contacts_{i:04d}.vtp"
                write_contacts_vtp(tmp / name, np.zeros((0, 6)) if rows is None else rows,
                                   z=z, binary=binary)
                contacts.add(t, name)
            contacts.write()
        blocks.write()
        move_series(tmp, folder, _OURS)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return folder / "series.pvd"

