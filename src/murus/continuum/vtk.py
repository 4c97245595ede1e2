"""VTK XML output of continuum zones for ParaView, beside the blocks of :mod:`murus.dem.vtk`.

The zones are written as a VTK XML UnstructuredGrid (``.vtu``) of ``VTK_QUAD`` cells (cell type
9): one point per gridpoint, one cell per zone with its four gridpoints counter-clockwise (the
FLAC/UDEC quadrilateral zone), so neighbouring zones share their points and ParaView draws a
continuous field. Cell data hold per-zone fields (stress, strain, plastic state), point data
per-gridpoint fields (displacement, velocity). The XML pieces, the file formats (ASCII with an
exact float64 round trip, or inline base64) and the file-safety rules are those of
:mod:`murus.dem.vtk` (shared in :mod:`murus._vtkxml`): every file is written atomically through
:func:`murus.outputs.write_text`, a series is built in a temporary sibling folder and moved into
place only when every frame has succeeded, and a series replaces only the files it owns by name
(``zones_NNNN.vtu``, ``zones.pvd``) and leaves every other file alone, so that the blocks'
``frame_NNNN.vtp`` / ``series.pvd`` of :func:`murus.dem.vtk.write_series` can share the folder
(ParaView opens both collections together).

Data layout of murus's zones (plain arrays):

- gridpoints ``xy`` (ng, 2) [m] (current coordinates: large-strain runs move them);
- zones (nz, 4) int64 gridpoint indices, counter-clockwise;
- stress (nz, 4): ``sxx, syy, sxy, szz`` [Pa], tension positive (FLAC's convention), written as
  a symmetric tensor of 6 components in VTK's order ``XX, YY, ZZ, XY, YZ, XZ`` (ParaView shows
  it as a tensor and offers its components and eigenvalues);
- strain (nz, 3) ``exx, eyy, exy`` or (nz, 4) with ``ezz`` [-], tensor components (``exy`` is
  half the engineering shear strain), written likewise;
- plastic state (nz,) int8 bit field: 1 shear now, 2 tension now, 4 shear in the past,
  8 tension in the past (FLAC's ``state``; :data:`STATE_BITS`).

References
----------
Kitware. VTK File Formats (VTK User's Guide), XML formats: UnstructuredGrid, cell type
``VTK_QUAD = 9``; the ParaView Data (``.pvd``) collection.
Itasca. FLAC manual, zone plastic-state indicators ("shear-n", "tension-p", ...).
"""

from __future__ import annotations

import re
import shutil
import tempfile
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from murus._vtkxml import HEADER, VTKFILE, as_data, data_array, data_section, move_series
from murus.dem.vtk import PvdWriter
from murus.outputs import write_text

__all__ = ["STATE_BITS", "VTK_QUAD", "write_vtu", "write_zone_series", "zone_cell_data"]

#: VTK cell type of a linear quadrilateral.
VTK_QUAD = 9

#: Bits of the plastic-state field of a zone (FLAC's state indicators).
STATE_BITS = {"shear-n": 1, "tension-n": 2, "shear-p": 4, "tension-p": 8}

_OURS = re.compile(r"zones_\d{4,}\.vtu|zones\.pvd")


def _as_mesh(xy, zones) -> tuple[np.ndarray, np.ndarray]:
    """Gridpoints (ng, 2) float64 and zones (nz, 4) int64, checked."""
    try:
        p = np.asarray(xy, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError("gridpoints xy must be an (ng, 2) array of numbers") from None
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"gridpoints xy have shape {p.shape}; expected (ng, 2)")
    bad = np.flatnonzero(~np.isfinite(p).all(axis=1))
    if len(bad):
        raise ValueError(f"gridpoint {bad[0]} has non-finite coordinates")
    z = np.asarray(zones)
    if z.size == 0:
        z = z.reshape(0, 4)
    if z.dtype.kind not in "iu":
        raise ValueError(f"zones have dtype {z.dtype}; expected integer gridpoint indices")
    if z.ndim != 2 or z.shape[1] != 4:
        raise ValueError(f"zones have shape {z.shape}; expected (nz, 4) gridpoint indices")
    z = z.astype(np.int64)
    out = np.flatnonzero(((z < 0) | (z >= len(p))).any(axis=1))
    if len(out):
        raise ValueError(f"zone {out[0]} names a gridpoint outside 0..{len(p) - 1}: "
                         f"{z[out[0]].tolist()}")
    s = np.sort(z, axis=1)
    dup = np.flatnonzero((s[:, 1:] == s[:, :-1]).any(axis=1))
    if len(dup):
        raise ValueError(f"zone {dup[0]} repeats a gridpoint: {z[dup[0]].tolist()}")
    return p, z


def _sym6(a, n: int, name: str, layout: str, allowed: tuple[int, ...]) -> np.ndarray:
    """(n, 3 or 4) in-plane components -> (n, 6) VTK symmetric tensor XX YY ZZ XY YZ XZ."""
    t = np.asarray(a, dtype=np.float64)
    if t.ndim != 2 or t.shape[0] != n or t.shape[1] not in allowed:
        want = " or ".join(f"({n}, {k})" for k in allowed)
        raise ValueError(f"{name} has shape {t.shape}; expected {want}: {layout}")
    out = np.zeros((n, 6))
    out[:, 0], out[:, 1], out[:, 3] = t[:, 0], t[:, 1], t[:, 2]
    if t.shape[1] == 4:
        out[:, 2] = t[:, 3]
    return out


def zone_cell_data(stress=None, strain=None, state=None, **extra) -> dict[str, np.ndarray]:
    """Per-zone arrays in the layout :func:`write_vtu` writes, named for ParaView.

    Parameters
    ----------
    stress : array (nz, 4), optional
        ``sxx, syy, sxy, szz`` [Pa], tension positive; written as ``stress``, a 6-component
        symmetric tensor (XX, YY, ZZ, XY, YZ, XZ), and ``mean_stress`` ``(sxx + syy + szz) / 3``
        [Pa].
    strain : array (nz, 3) or (nz, 4), optional
        ``exx, eyy, exy[, ezz]`` [-] (tensor shear component); written as ``strain``, a
        6-component symmetric tensor (``ezz = 0`` when absent: plane strain).
    state : array (nz,), optional
        Plastic-state bit field (:data:`STATE_BITS`); written as ``state`` (Int64) and
        ``yielding`` (1 where a "now" bit is set).
    **extra
        Other per-zone arrays, (nz,) or (nz, k), passed through unchanged.

    Returns
    -------
    dict
        ``{name: array}`` ready for ``write_vtu(..., cell_data=...)``.

    References
    ----------
    Kitware, VTK File Formats (symmetric tensors of 6 components); Itasca, FLAC manual (zone
    state indicators).
    """
    given = [np.asarray(a) for a in (stress, strain, state) if a is not None]
    n = len(given[0]) if given else None
    out: dict[str, np.ndarray] = {}
    if stress is not None:
        s = _sym6(stress, n, "stress", "sxx, syy, sxy, szz", (4,))
        out["stress"] = s
        out["mean_stress"] = (s[:, 0] + s[:, 1] + s[:, 2]) / 3.0
    if strain is not None:
        out["strain"] = _sym6(strain, n, "strain", "exx, eyy, exy[, ezz]", (3, 4))
    if state is not None:
        st = np.asarray(state)
        if st.ndim != 1 or len(st) != n or st.dtype.kind not in "iu":
            raise ValueError(f"state must be ({n},) integers (bit field), got {st.dtype} "
                             f"{st.shape}")
        if np.any((st < 0) | (st > 15)):
            raise ValueError("state values must be in 0..15 (bits 1, 2, 4, 8)")
        out["state"] = st.astype(np.int64)
        out["yielding"] = ((st & 3) != 0).astype(np.int64)
    for k, v in extra.items():
        if k in out:
            raise ValueError(f"cell data {k!r} clashes with a built-in zone array")
        out[k] = v
    return out


def _unstructured(points, zones, point_data, cell_data, binary) -> str:
    nz = len(zones)
    parts = [
        HEADER,
        VTKFILE.format(kind="UnstructuredGrid"),
        "  <UnstructuredGrid>\n",
        f'    <Piece NumberOfPoints="{len(points)}" NumberOfCells="{nz}">\n',
        data_section("PointData", point_data, binary),
        data_section("CellData", cell_data, binary),
        "      <Points>\n",
        data_array("Points", points, binary, "        "),
        "      </Points>\n",
        "      <Cells>\n",
        data_array("connectivity", zones.reshape(-1), binary, "        "),
        data_array("offsets", 4 * np.arange(1, nz + 1, dtype=np.int64), binary, "        "),
        data_array("types", np.full(nz, VTK_QUAD, dtype=np.uint8), binary, "        "),
        "      </Cells>\n",
        "    </Piece>\n",
        "  </UnstructuredGrid>\n",
        "</VTKFile>\n",
    ]
    return "".join(parts)


def write_vtu(
    path,
    xy,
    zones,
    cell_data: Mapping[str, np.ndarray] | None = None,
    point_data: Mapping[str, np.ndarray] | None = None,
    z: float = 0.0,
    binary: bool = False,
) -> Path:
    """Write zones as a VTK XML UnstructuredGrid (``.vtu``) of quadrilateral cells.

    Parameters
    ----------
    path : path-like
        Output file [``.vtu``]; parent folders are created. Written atomically.
    xy : array (ng, 2)
        Gridpoint coordinates x, y [m] (current positions).
    zones : array (nz, 4) of int
        Gridpoint indices of each zone, counter-clockwise (``VTK_QUAD`` order).
    cell_data : mapping, optional
        ``{name: array}``, one value (nz,) or vector (nz, k) per zone (float -> Float64,
        int/bool -> Int64; 2-vectors padded to 3); :func:`zone_cell_data` builds the stress,
        strain and plastic-state arrays.
    point_data : mapping, optional
        ``{name: array}``, one value or vector per gridpoint, e.g. ``displacement`` (ng, 2) [m]
        and ``velocity`` (ng, 2) [m/s] (padded to 3 components, so that ParaView's Warp By
        Vector and Glyph filters take them).
    z : float
        Out-of-plane coordinate of every point [m].
    binary : bool
        ``False``: ASCII (exact round trip); ``True``: inline base64, smaller and faster.

    Returns
    -------
    pathlib.Path
        The path written. A bad input raises a one-line ``ValueError`` and writes nothing.

    References
    ----------
    Kitware, VTK File Formats, XML UnstructuredGrid (cell type 9, ``VTK_QUAD``).
    """
    p, zz = _as_mesh(xy, zones)
    z = float(z)
    if not np.isfinite(z):
        raise ValueError(f"z must be finite, got {z!r}")
    cells = {k: as_data(k, v, len(zz), "cell_data", "zones") for k, v in (cell_data or {}).items()}
    pts = {k: as_data(k, v, len(p), "point_data", "gridpoints")
           for k, v in (point_data or {}).items()}
    points = np.column_stack([p, np.full(len(p), z)])
    return write_text(path, _unstructured(points, zz, pts, cells, binary))


def write_zone_series(folder, frames: Iterable, z: float = 0.0, binary: bool = False) -> Path:
    """Write a time series of zone frames as ``zones_0000.vtu``, ... and ``zones.pvd``.

    Parameters
    ----------
    folder : path-like
        Output folder (created if missing). It may hold the blocks' series of
        :func:`murus.dem.vtk.write_series` (``frame_NNNN.vtp``, ``series.pvd``): the names do
        not clash and neither writer touches the other's files.
    frames : iterable
        ``(time, frame)`` pairs (a generator is fine): ``time`` in s, strictly increasing;
        ``frame`` a mapping with keys ``xy`` and ``zones`` and optional ``cell_data`` and
        ``point_data`` (as in :func:`write_vtu`).
    z : float
        Out-of-plane coordinate [m].
    binary : bool
        Inline base64 instead of ASCII.

    Returns
    -------
    pathlib.Path
        The path of ``zones.pvd``.

    Notes
    -----
    All files are first written into a temporary sibling folder; only when every frame has
    succeeded are they moved into ``folder`` (``zones.pvd`` last). Files of an earlier zone
    series (``zones_*.vtu``, ``zones.pvd``) are replaced or removed; other files are left
    alone. A bad frame raises a one-line ``ValueError`` (``frame i: ...``) and changes nothing.

    References
    ----------
    Kitware, VTK File Formats (``.pvd`` collections of XML datasets).
    """
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise ValueError(f"{folder} exists and is not a folder")
    folder.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{folder.name}.", dir=folder.parent))
    try:
        pvd = PvdWriter(tmp / "zones.pvd")
        for i, item in enumerate(frames):
            try:
                time, frame = item
            except (TypeError, ValueError):
                raise ValueError(f"frame {i} is not a (time, mapping) pair") from None
            if not isinstance(frame, Mapping) or "xy" not in frame or "zones" not in frame:
                raise ValueError(f"frame {i} must be a mapping with keys 'xy' and 'zones'")
            unknown = set(frame) - {"xy", "zones", "cell_data", "point_data"}
            if unknown:
                raise ValueError(f"frame {i} has unknown keys {sorted(unknown)}")
            name = f"zones_{i:04d}.vtu"
            try:
                pvd.add(time, name)
                write_vtu(tmp / name, frame["xy"], frame["zones"], frame.get("cell_data"),
                          frame.get("point_data"), z, binary)
            except ValueError as exc:
                raise ValueError(f"frame {i}: {exc}") from None
        pvd.write()
        move_series(tmp, folder, _OURS)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return folder / "zones.pvd"
