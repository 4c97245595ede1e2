"""Disc packings for the distinct-element model: one lattice generator, overlap check and solid
fraction.

:func:`disc_grid` places discs without overlap on a lattice of pitch ``2 r_max (1 + gap)`` and
draws their radii uniformly in ``[r_min, r_max]`` (one ``numpy.random.default_rng(seed)`` draw
after the positions). It serves both disc assemblies of murus, which use two lattices:

- ``lattice="square"``: ``n`` discs in rows of ``columns``, filled row by row from the corner at
  the origin: the sample of the biaxial test (:func:`murus.dem.biaxial.disc_assembly`), a
  rectangle closed by four servo-controlled walls;
- ``lattice="hex"``: the hexagonal lattice (odd rows shifted by half a pitch) clipped to a
  region bounded by a floor, a left boundary ``left(z)``, a right boundary and a ceiling
  ``ceiling(x)``: the backfill behind a retaining wall
  (:func:`murus.retaining.backfill.generate_packing`), an irregular region.

Both are kept, behind one function, because the calibrated constants and stored results depend
on the exact initial positions: the rolling resistance calibrated with the square sample
(:data:`murus.retaining.backfill.CALIBRATION`) and the validation numbers of the backfill with
the hexagonal one (``validation/retaining_backfill.py``). A packing is a pure function of its
inputs and ``seed``: the same inputs give the same discs, bit for bit.

Units: SI (m).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from murus.errors import MurusError

__all__ = ["PackingError", "DiscGrid", "GRID_GAP", "disc_grid", "check_overlap",
           "solid_fraction"]

#: Clearance of the lattice as a fraction of the largest radius: the pitch is
#: ``2 r_max (1 + GRID_GAP)``, so that no two discs touch initially (2 %, as in PFC's
#: "generate" examples; any small positive value works, the packing is settled afterwards).
GRID_GAP = 0.02

#: Spacing of the sampling grid of :func:`solid_fraction` as a fraction of the smallest radius
#: (a tenth: error well below 1 % of the fraction).
SAMPLE_SPACING = 0.1


class PackingError(MurusError, ValueError):
    """Invalid input to a disc packing, or discs that overlap (one-line message)."""


class DiscGrid(NamedTuple):
    """Discs on a lattice: centres (n, 2) [m], radii (n,) [m], lattice pitch [m]."""

    centres: np.ndarray
    radii: np.ndarray
    pitch: float


def disc_grid(radius: tuple[float, float], *, seed: int = 0, gap: float = GRID_GAP,
              lattice: str = "square", n: int | None = None, columns: int | None = None,
              floor: float = 0.0, top: float | None = None,
              left: Callable[[float], float] | None = None, right: float | None = None,
              ceiling: Callable[[float], float] | None = None) -> DiscGrid:
    """Discs without overlap on a square or hexagonal lattice, radii uniform in ``radius``.

    Parameters
    ----------
    radius : (float, float)
        Smallest and largest radius ``(r_min, r_max)`` [m].
    seed : int
        Seed of the radii (``numpy.random.default_rng``).
    gap : float
        Clearance of the lattice [fraction of r_max]: pitch ``2 r_max (1 + gap)``.
    lattice : {"square", "hex"}
        ``"square"``: ``n`` discs in rows of ``columns``, the first centre at half a pitch from
        the origin in x and y. ``"hex"``: rows ``dz = pitch sqrt(3) / 2`` apart from ``floor +
        c`` up to ``top - c`` (``c = r_max (1 + gap)``), each from ``left(z) + c`` (plus half a
        pitch on odd rows) to ``right - c``, a centre kept where ``z <= ceiling(x) - c``.
    n, columns : int
        Number of discs and discs per row (square lattice).
    floor, top : float
        Lowest and highest level of the region [m] (hexagonal lattice).
    left : callable
        ``left(z)``: the left boundary of the region at the level ``z`` [m] (hexagonal).
    right : float
        Right boundary of the region [m] (hexagonal).
    ceiling : callable
        ``ceiling(x)``: the top of the region above ``x`` [m] (hexagonal).

    Returns
    -------
    DiscGrid
        ``(centres, radii, pitch)``; the centres in lattice order (row by row, from the
        bottom, each row from the left).

    References
    ----------
    Itasca, PFC 2D manual, "generate" (regular lattices with a clearance, then settling).
    """
    rmin, rmax = float(radius[0]), float(radius[1])
    pitch = 2 * rmax * (1 + gap)
    if lattice == "square":
        if n is None or columns is None:
            raise PackingError("a square lattice needs n and columns")
        ii = np.arange(n)
        cx = (ii % columns + 0.5) * pitch
        cy = (ii // columns + 0.5) * pitch
        rng = np.random.default_rng(seed)
        return DiscGrid(np.column_stack([cx, cy]), rng.uniform(rmin, rmax, n), pitch)
    if lattice != "hex":
        raise PackingError(f"lattice must be 'square' or 'hex', got {lattice!r}")
    if top is None or left is None or right is None or ceiling is None:
        raise PackingError("a hexagonal lattice needs top, left, right and ceiling")
    dz = pitch * math.sqrt(3) / 2
    clear = rmax * (1 + gap)
    pts = []
    j = 0
    z = floor + clear
    while z <= top - clear:
        x = float(left(z)) + clear + (0.5 * pitch if j % 2 else 0.0)
        while x <= right - clear:
            if z <= ceiling(x) - clear:
                pts.append((x, z))
            x += pitch
        z += dz
        j += 1
    rng = np.random.default_rng(seed)
    c = np.array(pts).reshape(-1, 2)
    return DiscGrid(c, rng.uniform(rmin, rmax, len(c)), pitch)


def check_overlap(centres, radii, tol: float = 0.0) -> None:
    """Raise :class:`PackingError` if two discs overlap by more than ``tol`` [m].

    Parameters
    ----------
    centres : array_like, shape (n, 2)
        Disc centres [m].
    radii : array_like, shape (n,)
        Disc radii [m].
    tol : float
        Largest overlap accepted [m].

    Raises
    ------
    PackingError
        Naming the number of overlapping pairs, the largest overlap and its two discs.
    """
    from scipy.spatial import cKDTree

    c = np.asarray(centres, float)
    r = np.asarray(radii, float)
    if c.shape[0] < 2:
        return
    pairs = cKDTree(c).query_pairs(2.0 * float(r.max()), output_type="ndarray")
    if pairs.size == 0:
        return
    d = np.hypot(*(c[pairs[:, 0]] - c[pairs[:, 1]]).T)
    ov = r[pairs[:, 0]] + r[pairs[:, 1]] - d
    bad = ov > tol
    if bad.any():
        i, j = pairs[np.argmax(ov)]
        raise PackingError(f"{int(bad.sum())} pairs of discs overlap initially (largest "
                           f"{ov.max():.3g} m, discs {i} and {j}): the generator must place "
                           "them apart")


def solid_fraction(centres, radii, window, h: float | None = None) -> float:
    """Area fraction of discs in a rectangle, sampled on a regular grid.

    Parameters
    ----------
    centres : array_like, shape (n, 2)
        Disc centres [m].
    radii : array_like, shape (n,)
        Disc radii [m].
    window : (float, float, float, float)
        The rectangle ``(x0, x1, z0, z1)`` [m].
    h : float, optional
        Grid spacing [m]; default a tenth of the smallest radius (:data:`SAMPLE_SPACING`;
        error well below 1 %).

    Returns
    -------
    float
        Solid (area) fraction [-].

    Raises
    ------
    PackingError
        The window is empty.
    """
    from scipy.spatial import cKDTree

    x0, x1, z0, z1 = (float(v) for v in window)
    if not (x1 > x0 and z1 > z0):
        raise PackingError(f"empty window {window!r}: the backfill is too small for its "
                           "discs")
    c = np.asarray(centres, float)
    r = np.asarray(radii, float)
    h = SAMPLE_SPACING * float(r.min()) if h is None else float(h)
    xs = np.arange(x0 + 0.5 * h, x1, h)
    zs = np.arange(z0 + 0.5 * h, z1, h)
    X, Z = np.meshgrid(xs, zs)
    pts = np.column_stack([X.ravel(), Z.ravel()])
    k = min(4, len(c))
    d, idx = cKDTree(c).query(pts, k=k)
    d = d.reshape(len(pts), -1)
    idx = idx.reshape(len(pts), -1)
    inside = np.any(d < r[idx], axis=1)
    return float(inside.mean())
