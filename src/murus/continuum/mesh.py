"""Mesh generation for the continuum zones: quadrilateral regions by transfinite interpolation,
polygons with their four corners, conforming merges, boundary selections and the meshes of the
verification problems.

The engine of the continuum (the mixed discretisation of Marti & Cundall (1982), as in FLAC and
UDEC) takes plain arrays, and a :class:`Mesh` is exactly that:

- ``xy`` (ng, 2) float64: gridpoint coordinates [m];
- ``zones`` (nz, 4) int64: the four gridpoints of each quadrilateral zone, counter-clockwise;
- ``region`` (nz,) int64: the region each zone comes from (index into ``region_names``);
- ``sides``: named chains of gridpoints (``"backfill.left"``), each ordered along its side, from
  which boundary conditions and interfaces are selected.

Every zone is convex, counter-clockwise, with a positive area (:meth:`Mesh.check`): each zone is
made of two overlays of two triangles (the two diagonals), and all four triangles must have a
positive area for the mixed discretisation to hold.

A region bounded by four sides (each a polyline, so that a side can be the inclined back of a wall
or a broken ground surface, sloped then level) is meshed by transfinite (Coons) interpolation
(Gordon & Hall (1973), with linear blending functions): the gridpoints of the four sides
are placed first, by a geometric progression of the zone sizes (``grading``: the ratio of the size
of a zone to the size of the one before it, along the side's direction), with a gridpoint at every
vertex of a side's polyline, and the interior gridpoints follow from the blend of the four sides.
Where a side has vertices, the graded positions are moved by an affine map within each segment
so that each vertex is a gridpoint (the ratio of successive sizes is kept within a segment), and
the blend takes, at each gridpoint, the positions interpolated between the opposite sides (the
four sides are then reproduced exactly, so the zone areas of a straight-sided region sum to its
polygon area). A target ``size`` bounds every zone edge: the smallest numbers of zones are
searched for (with a grading ``r``, the largest zone of a side of length ``L`` cannot go below
``L (1 - 1/r)``, an error says so). A polygon region picks four of its vertices as corners
(:func:`polygon_region`); a region with only three corners is meshed as three quadrilaterals that
meet at its centroid. :func:`mesh_regions` meshes and merges the regions of a case file's
``[[zones]]`` tables.

Frame and conventions (written once, here): x horizontal, y upwards, lengths in m, angles ``*_deg``
in degrees. The four sides of a quadrilateral region follow its boundary counter-clockwise from its
first corner ``c0``: ``bottom`` (c0 to c1), ``right`` (c1 to c2), ``top`` (c2 to c3), ``left`` (c3
to c0). The mesh directions are i along the bottom and top (c0 to c1 and c3 to c2: ``nx`` zones,
grading ``grading[0]``), j along the left and right (c0 to c3 and c1 to c2: ``ny`` zones, grading
``grading[1]``). Gridpoint ``(i, j)`` of a region has the index ``j (nx + 1) + i`` before merging,
and zone ``(i, j)`` the gridpoints ``(i, j), (i+1, j), (i+1, j+1), (i, j+1)``. A grading above 1
makes the zones grow along the direction, below 1 shrink: ``grading=(1.1, 1.0)`` is finer near the
left side (a wall back), ``(1.0, 1/1.1)`` finer near the top (a footing).

Errors on bad input are :class:`MeshError` (a :class:`murus.errors.MurusError` and a
``ValueError``) with a one-line message and the key path of the offending argument
(``("vertices", 3)``, ``("grading",)``), which the case-file layer prefixes with the table, e.g.
``("zones", 0, "vertices", 3)``.

References
----------
Gordon, W. J. and Hall, C. A. (1973). Construction of curvilinear co-ordinate systems and
applications to mesh generation. International Journal for Numerical Methods in Engineering 7(4),
461-477. doi:10.1002/nme.1620070405 (transfinite interpolation).

Marti, J. and Cundall, P. A. (1982). Mixed discretization procedure for accurate modelling of
plastic collapse. International Journal for Numerical and Analytical Methods in Geomechanics 6(1),
129-139. doi:10.1002/nag.1610060109 (the quadrilateral zone of two overlays of two triangles).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from murus.errors import MurusError

__all__ = [
    "MeshError", "Mesh", "MeshQuality", "quad_region", "rectangle", "polygon_region", "merge",
    "annulus", "strip_footing", "polygon_corners", "graded_fractions", "mesh_regions",
    "SIDE_NAMES", "REGION_KEYS",
]

#: Default names of the four sides of a quadrilateral region, counter-clockwise from corner c0.
SIDE_NAMES = ("bottom", "right", "top", "left")
#: Default names of the three sides of a three-cornered region.
TRIANGLE_SIDE_NAMES = ("bottom", "right", "left")

# A zone corner must turn left by more than this sine: the four triangles of the mixed
# discretisation then have a positive area. Far below any usable zone (1e-10 rad is 6e-9 deg).
_SIN_MIN = 1e-10
# Relative tolerance (to the model size) of coincident points and of points on a side.
_TOL = 1e-9
# A polygon vertex is a candidate corner when its interior angle is below 180 deg by more than this.
_CORNER_MIN_DEG = 1e-6


class MeshError(MurusError, ValueError):
    """Invalid mesh input or a mesh that cannot be built (one-line message, key path in ``key``)."""


# ---------------------------------------------------------------------------------------- Mesh


@dataclass(frozen=True)
class MeshQuality:
    """Quality measures of a mesh.

    Attributes
    ----------
    n_zones, n_gridpoints : int
        Sizes.
    min_area, max_area : float
        Smallest and largest zone area [m²].
    min_angle_deg, max_angle_deg : float
        Smallest and largest interior angle of any zone [deg] (90 for a rectangle; a convex zone
        has all its angles strictly between 0 and 180).
    max_aspect : float
        Largest aspect ratio of a zone: its longest edge over its shortest edge [-].
    max_edge : float
        Longest zone edge [m] (the zone size that a target ``size`` bounds).
    """

    n_zones: int
    n_gridpoints: int
    min_area: float
    max_area: float
    min_angle_deg: float
    max_angle_deg: float
    max_aspect: float
    max_edge: float

    def summary(self) -> str:
        """One line: sizes, area range, angle range and the worst aspect ratio.

        Returns
        -------
        str
            E.g. ``"120 zones, 143 gridpoints, area 0.01-0.04 m², angles 80.0-100.0 deg, ..."``.
        """
        return (f"{self.n_zones} zones, {self.n_gridpoints} gridpoints, area "
                f"{self.min_area:.4g}-{self.max_area:.4g} m², angles {self.min_angle_deg:.1f}-"
                f"{self.max_angle_deg:.1f} deg, aspect <= {self.max_aspect:.3g}, "
                f"edges <= {self.max_edge:.4g} m")


def _ro(a: np.ndarray) -> np.ndarray:
    a = np.array(a, copy=True)
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class Mesh:
    """A mesh of quadrilateral zones: the plain arrays the continuum engine takes, with the regions
    and named sides they came from.

    Built by :func:`quad_region`, :func:`rectangle`, :func:`polygon_region`, :func:`annulus`,
    :func:`strip_footing` and :func:`merge`; the constructor checks the arrays and every zone
    (:meth:`check`). The arrays are read-only copies.

    Attributes
    ----------
    xy : numpy.ndarray
        (ng, 2) float64 gridpoint coordinates [m].
    zones : numpy.ndarray
        (nz, 4) int64 gridpoint indices of each zone, counter-clockwise.
    region : numpy.ndarray
        (nz,) int64 region index of each zone (into ``region_names``).
    region_names : tuple of str
        Name of each region.
    sides : Mapping[str, numpy.ndarray]
        Named chains of gridpoints (int64), each ordered along its side: ``"REGION.SIDE"`` for the
        sides of the regions (``"backfill.left"``), and any extra sets of the generators
        (``"footing"``). Consecutive entries of a chain are the ends of a zone edge.
    """

    xy: np.ndarray
    zones: np.ndarray
    region: np.ndarray
    region_names: tuple[str, ...]
    sides: Mapping[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        xy = np.asarray(self.xy, dtype=np.float64)
        if xy.ndim != 2 or xy.shape[1] != 2 or not np.all(np.isfinite(xy)):
            raise MeshError("xy must be an (ng, 2) array of finite coordinates [m]", key=("xy",))
        zones = np.asarray(self.zones)
        if zones.ndim != 2 or zones.shape[1] != 4 or not np.issubdtype(zones.dtype, np.integer):
            raise MeshError("zones must be an (nz, 4) array of gridpoint indices",
                            key=("zones",))
        zones = zones.astype(np.int64)
        if zones.size and (zones.min() < 0 or zones.max() >= len(xy)):
            bad = int(np.nonzero((zones < 0).any(1) | (zones >= len(xy)).any(1))[0][0])
            raise MeshError(f"zone {bad} names a gridpoint outside 0..{len(xy) - 1}",
                            key=("zones", bad))
        region = np.asarray(self.region)
        if region.shape != (len(zones),) or not np.issubdtype(region.dtype, np.integer):
            raise MeshError("region must hold one integer per zone", key=("region",))
        region = region.astype(np.int64)
        names = tuple(str(n) for n in self.region_names)
        if region.size and (region.min() < 0 or region.max() >= len(names)):
            raise MeshError(f"region indices must be in 0..{len(names) - 1}", key=("region",))
        sides = {}
        for name, chain in dict(self.sides).items():
            c = np.asarray(chain)
            if c.ndim != 1 or not np.issubdtype(c.dtype, np.integer) or (
                    c.size and (c.min() < 0 or c.max() >= len(xy))):
                raise MeshError(f"side {name!r} must be a chain of gridpoint indices",
                                key=("sides", name))
            sides[str(name)] = _ro(c.astype(np.int64))
        object.__setattr__(self, "xy", _ro(xy))
        object.__setattr__(self, "zones", _ro(zones))
        object.__setattr__(self, "region", _ro(region))
        object.__setattr__(self, "region_names", names)
        object.__setattr__(self, "sides", MappingProxyType(sides))
        self.check()

    def __reduce__(self):
        # the sides are a read-only mapping proxy, which does not pickle: rebuild from a dict
        return (Mesh, (np.array(self.xy), np.array(self.zones), np.array(self.region),
                       self.region_names, {k: np.array(v) for k, v in self.sides.items()}))

    # ------------------------------------------------------------------ sizes and geometry
    @property
    def n_gridpoints(self) -> int:
        """Number of gridpoints."""
        return len(self.xy)

    @property
    def n_zones(self) -> int:
        """Number of zones."""
        return len(self.zones)

    @property
    def size(self) -> float:
        """Model size: the diagonal of the bounding box of the gridpoints [m]."""
        if not len(self.xy):
            return 0.0
        return float(np.hypot(*(self.xy.max(0) - self.xy.min(0))))

    def _corners(self) -> np.ndarray:
        return self.xy[self.zones]  # (nz, 4, 2)

    def areas(self) -> np.ndarray:
        """Zone areas [m²] (shoelace formula; positive for counter-clockwise zones).

        Returns
        -------
        numpy.ndarray
            (nz,) areas [m²].
        """
        p = self._corners()
        x, y = p[..., 0], p[..., 1]
        return 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)

    def edge_lengths(self) -> np.ndarray:
        """Lengths of the four edges of each zone [m]; edge k joins corners k and k+1.

        Returns
        -------
        numpy.ndarray
            (nz, 4) lengths [m].
        """
        p = self._corners()
        return np.hypot(*np.moveaxis(np.roll(p, -1, axis=1) - p, -1, 0))

    def angles_deg(self) -> np.ndarray:
        """Interior angle of each zone at each of its four corners [deg] (in (0, 360)).

        Returns
        -------
        numpy.ndarray
            (nz, 4) angles [deg]; all below 180 for a convex zone.
        """
        p = self._corners()
        a = np.roll(p, 1, axis=1) - p    # towards the previous corner
        b = np.roll(p, -1, axis=1) - p   # towards the next corner
        cross = b[..., 0] * a[..., 1] - b[..., 1] * a[..., 0]
        dot = np.sum(a * b, axis=-1)
        ang = np.degrees(np.arctan2(cross, dot))
        return np.where(ang < 0.0, ang + 360.0, ang)

    def aspect(self) -> np.ndarray:
        """Aspect ratio of each zone: its longest edge over its shortest edge [-].

        Returns
        -------
        numpy.ndarray
            (nz,) ratios (1 for a square).
        """
        e = self.edge_lengths()
        return e.max(1) / e.min(1)

    def quality(self) -> MeshQuality:
        """Quality measures: area range, worst angles, worst aspect ratio, longest edge.

        Returns
        -------
        MeshQuality
            The measures (NaN for an empty mesh).
        """
        if not self.n_zones:
            nan = float("nan")
            return MeshQuality(0, self.n_gridpoints, nan, nan, nan, nan, nan, nan)
        a, ang, e = self.areas(), self.angles_deg(), self.edge_lengths()
        return MeshQuality(self.n_zones, self.n_gridpoints, float(a.min()), float(a.max()),
                           float(ang.min()), float(ang.max()),
                           float((e.max(1) / e.min(1)).max()), float(e.max()))

    def check(self) -> None:
        """Check that every zone is convex and counter-clockwise with a positive area.

        Each corner must turn left: the sine of the turn is above ``1e-10``, so that the four
        triangles of the two overlays (Marti & Cundall (1982)) all have a positive area.

        Raises
        ------
        MeshError
            With the key ``("zones", k)`` of the first bad zone.
        """
        bad = _bad_zones(self.xy, self.zones)
        if bad.size:
            k = int(bad[0])
            c = ", ".join(f"({x:.6g}, {y:.6g})" for x, y in self.xy[self.zones[k]])
            raise MeshError(f"{bad.size} zone(s) are not convex and counter-clockwise, the first "
                            f"is zone {k} of region {self.region_names[self.region[k]]!r}: "
                            f"corners {c}", key=("zones", k))

    # ------------------------------------------------------------------ boundary
    def boundary_edges(self) -> np.ndarray:
        """The edges of the mesh boundary (edges of one zone only), oriented as in their zone
        (counter-clockwise: the mesh lies on the left of each edge, its outward normal on the
        right).

        Returns
        -------
        numpy.ndarray
            (ne, 2) int64 gridpoint pairs.
        """
        e = _zone_edges(self.zones)
        inv, cnt = _edge_groups(e, self.n_gridpoints)
        return e[cnt[inv] == 1]

    def boundary_gridpoints(self) -> np.ndarray:
        """Gridpoints on the mesh boundary, sorted.

        Returns
        -------
        numpy.ndarray
            int64 gridpoint indices.
        """
        return np.unique(self.boundary_edges())

    def edges_of(self, gridpoints) -> np.ndarray:
        """The boundary edges whose two ends are both in a set of gridpoints (the edges a
        boundary condition or an interface acts on, for tributary lengths).

        Parameters
        ----------
        gridpoints : array_like of int
            Gridpoint indices (e.g. from :meth:`side` or :meth:`on_line`).

        Returns
        -------
        numpy.ndarray
            (ne, 2) int64 boundary edges, oriented counter-clockwise around the mesh.
        """
        e = self.boundary_edges()
        s = np.zeros(self.n_gridpoints, dtype=bool)
        s[np.asarray(gridpoints, dtype=np.int64)] = True
        return e[s[e[:, 0]] & s[e[:, 1]]]

    # ------------------------------------------------------------------ selections
    def side(self, name: str, *, key=()) -> np.ndarray:
        """Gridpoints of a named side.

        Parameters
        ----------
        name : str
            ``"REGION.SIDE"`` (``"backfill.left"``), a generator's set (``"footing"``), or a bare
            side name (``"bottom"``): the union of that side over all regions that have it.
        key : tuple, optional
            Key path of the name in the caller's input, for the error.

        Returns
        -------
        numpy.ndarray
            int64 gridpoint indices: the chain in order along the side for a full name or a bare
            name that one region has, sorted for a union of several.

        Raises
        ------
        MeshError
            If no side has that name.
        """
        if name in self.sides:
            return np.array(self.sides[name])
        parts = [c for n, c in self.sides.items() if n.rpartition(".")[2] == name and "." in n]
        if not parts:
            known = ", ".join(sorted(self.sides)) or "none"
            raise MeshError(f"no side named {name!r} (sides: {known})", key=tuple(key))
        if len(parts) == 1:
            return np.array(parts[0])
        return np.unique(np.concatenate(parts))

    def on_line(self, p0, p1, tol: float | None = None, *, key=()) -> np.ndarray:
        """Gridpoints within a distance of a segment.

        Parameters
        ----------
        p0, p1 : sequence of float
            Ends (x, y) of the segment [m] (equal ends: a point).
        tol : float, optional
            Distance [m]; default ``1e-6`` times the model size.
        key : tuple, optional
            Key path of the selection in the caller's input, for the error.

        Returns
        -------
        numpy.ndarray
            int64 gridpoint indices, ordered along the segment from ``p0``.

        Raises
        ------
        MeshError
            If the selection names no gridpoint, or on a negative tolerance.
        """
        try:
            a = np.asarray(p0, dtype=float)
            b = np.asarray(p1, dtype=float)
        except (TypeError, ValueError):
            a = b = np.zeros(0)
        if a.shape != (2,) or b.shape != (2,) or not (np.isfinite(a).all()
                                                       and np.isfinite(b).all()):
            raise MeshError("a line is given by two points (x, y) [m]", key=tuple(key))
        tol = 1e-6 * self.size if tol is None else float(tol)
        if not (tol >= 0.0 and math.isfinite(tol)):
            raise MeshError(f"tol = {tol} must be >= 0 [m]", key=tuple(key))
        d = b - a
        L2 = float(d @ d)
        t = np.zeros(self.n_gridpoints) if L2 == 0.0 else np.clip((self.xy - a) @ d / L2, 0, 1)
        dist = np.hypot(*(self.xy - a - t[:, None] * d).T)
        sel = np.nonzero(dist <= tol)[0]
        if not sel.size:
            raise MeshError(f"the line from {tuple(a)} to {tuple(b)} (tol {tol:.3g} m) names no "
                            "gridpoint", key=tuple(key))
        return sel[np.argsort(t[sel], kind="stable")].astype(np.int64)

    def in_box(self, xmin: float, ymin: float, xmax: float, ymax: float, *,
               tol: float | None = None, key=()) -> np.ndarray:
        """Gridpoints inside a box (bounds included, with a tolerance).

        Parameters
        ----------
        xmin, ymin, xmax, ymax : float
            Bounds [m].
        tol : float, optional
            Widening of the box on each side [m]; default ``1e-6`` times the model size.
        key : tuple, optional
            Key path of the selection in the caller's input, for the error.

        Returns
        -------
        numpy.ndarray
            Sorted int64 gridpoint indices.

        Raises
        ------
        MeshError
            If the box is inverted or names no gridpoint.
        """
        tol = 1e-6 * self.size if tol is None else float(tol)
        if not (xmin <= xmax and ymin <= ymax):
            raise MeshError(f"box ({xmin}, {ymin})-({xmax}, {ymax}) is inverted", key=tuple(key))
        x, y = self.xy[:, 0], self.xy[:, 1]
        sel = np.nonzero((x >= xmin - tol) & (x <= xmax + tol)
                         & (y >= ymin - tol) & (y <= ymax + tol))[0]
        if not sel.size:
            raise MeshError(f"the box ({xmin}, {ymin})-({xmax}, {ymax}) names no gridpoint",
                            key=tuple(key))
        return sel.astype(np.int64)

    def with_side(self, name: str, chain) -> Mesh:
        """A copy with one more named chain of gridpoints.

        Parameters
        ----------
        name : str
            Name of the set (must be new).
        chain : array_like of int
            Gridpoint indices.

        Returns
        -------
        Mesh
            The new mesh (same arrays).
        """
        if name in self.sides:
            raise MeshError(f"side {name!r} exists already", key=("sides", name))
        sides = dict(self.sides)
        sides[name] = np.asarray(chain, dtype=np.int64)
        return Mesh(self.xy, self.zones, self.region, self.region_names, sides)


def _zone_edges(zones: np.ndarray) -> np.ndarray:
    return np.stack([zones, np.roll(zones, -1, axis=1)], axis=-1).reshape(-1, 2)


def _edge_groups(e: np.ndarray, ng: int) -> tuple[np.ndarray, np.ndarray]:
    """Group the undirected edges: the group of each edge and the size of each group."""
    k = np.minimum(e[:, 0], e[:, 1]) * np.int64(ng) + np.maximum(e[:, 0], e[:, 1])
    _, inv, cnt = np.unique(k, return_inverse=True, return_counts=True)
    return inv.ravel(), cnt


def _bad_zones(xy: np.ndarray, zones: np.ndarray) -> np.ndarray:
    """Indices of the zones that are not strictly convex and counter-clockwise."""
    if not len(zones):
        return np.zeros(0, dtype=np.int64)
    p = xy[zones]
    e = np.roll(p, -1, axis=1) - p                      # edge k: corner k -> k+1
    en = np.roll(e, 1, axis=1)                          # edge k-1
    cross = en[..., 0] * e[..., 1] - en[..., 1] * e[..., 0]
    scale = np.hypot(*np.moveaxis(e, -1, 0)) * np.hypot(*np.moveaxis(en, -1, 0))
    ok = (cross > _SIN_MIN * scale) & (scale > 0)
    return np.nonzero(~ok.all(axis=1))[0]


# ------------------------------------------------------------------------------- validation


def _int_count(v, key) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
        raise MeshError(f"{key[-1]} = {v!r} must be an integer >= 1", key=key)
    if v < 1:
        raise MeshError(f"{key[-1]} = {v} must be >= 1", key=key)
    return int(v)


def _positive(v, key, what="") -> float:
    try:
        f = float(v)
    except (TypeError, ValueError):
        raise MeshError(f"{key[-1]} = {v!r} must be a number > 0{what}", key=key) from None
    if not (f > 0.0 and math.isfinite(f)):
        raise MeshError(f"{key[-1]} = {v!r} must be > 0{what}", key=key)
    return f


def _pair(v, key, what) -> tuple[float, float]:
    """A scalar or a pair of positive numbers."""
    if isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool):
        f = _positive(v, key, what)
        return f, f
    try:
        seq = list(v)
    except TypeError:
        raise MeshError(f"{key[-1]} = {v!r} must be a number or a pair", key=key) from None
    if len(seq) != 2:
        raise MeshError(f"{key[-1]} must be one number or a pair (x, y direction)", key=key)
    return (_positive(seq[0], (*key, 0), what), _positive(seq[1], (*key, 1), what))


def _points(v, key, nmin: int) -> np.ndarray:
    try:
        p = np.asarray(v, dtype=np.float64)
    except (TypeError, ValueError):
        raise MeshError(f"{key[-1] if key else 'points'} must be a list of (x, y) points [m]",
                        key=key) from None
    if p.ndim != 2 or p.shape[1] != 2:
        raise MeshError("must be a list of (x, y) points [m]", key=key)
    if len(p) < nmin:
        raise MeshError(f"has {len(p)} point(s), needs at least {nmin}", key=key)
    bad = np.nonzero(~np.isfinite(p).all(1))[0]
    if bad.size:
        raise MeshError(f"point {int(bad[0])} is not finite", key=(*key, int(bad[0])))
    return p


def _segments_cross(a, b, c, d, tol) -> bool:
    """Whether closed segments ab and cd intersect (touching within ``tol`` counts)."""
    def orient(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    def on(p, q, r):  # r on segment pq, given collinear
        return (min(p[0], q[0]) - tol <= r[0] <= max(p[0], q[0]) + tol
                and min(p[1], q[1]) - tol <= r[1] <= max(p[1], q[1]) + tol)

    s = tol * max(math.dist(a, b), math.dist(c, d))
    o1, o2, o3, o4 = orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b)
    if ((o1 > s and o2 < -s) or (o1 < -s and o2 > s)) and \
            ((o3 > s and o4 < -s) or (o3 < -s and o4 > s)):
        return True
    return ((abs(o1) <= s and on(a, b, c)) or (abs(o2) <= s and on(a, b, d))
            or (abs(o3) <= s and on(c, d, a)) or (abs(o4) <= s and on(c, d, b)))


def _check_ring(p: np.ndarray, key, indexed: bool = True) -> None:
    """A closed ring of points: no duplicated vertex, no self-intersection, non-zero area
    (``indexed``: the error of a duplicated vertex carries its index in the ring)."""
    n = len(p)
    scale = float(np.hypot(*(p.max(0) - p.min(0))))
    if scale == 0.0:
        raise MeshError("all points coincide", key=key)
    tol = _TOL * scale
    d = np.hypot(*(p[:, None, :] - p[None, :, :]).transpose(2, 0, 1))
    iu = np.triu_indices(n, 1)
    dup = np.nonzero(d[iu] <= tol)[0]
    if dup.size:
        i, j = int(iu[0][dup[0]]), int(iu[1][dup[0]])
        raise MeshError(f"points {i} and {j} coincide at ({p[i, 0]:.6g}, {p[i, 1]:.6g})",
                        key=(*key, j) if indexed else key)
    for i in range(n):
        a, b = p[i], p[(i + 1) % n]
        for j in range(i + 1, n):
            if j == i + 1 or (i == 0 and j == n - 1):   # neighbours share a vertex
                c, dd = p[j], p[(j + 1) % n]
                # adjacent edges overlap only if they fold back onto each other
                shared = b if j == i + 1 else a
                other_e1 = a if j == i + 1 else b
                other_e2 = dd if j == i + 1 else c
                u = other_e1 - shared
                v = other_e2 - shared
                cr = u[0] * v[1] - u[1] * v[0]
                if abs(cr) <= 1e-12 * np.hypot(*u) * np.hypot(*v) and u @ v > 0:
                    raise MeshError(f"the boundary folds back on itself at point "
                                    f"{(i + 1) % n if j == i + 1 else 0}", key=key)
                continue
            if _segments_cross(a, b, p[j], p[(j + 1) % n], tol):
                raise MeshError(f"the boundary intersects itself: edge {i}-{(i + 1) % n} crosses "
                                f"edge {j}-{(j + 1) % n}", key=key)


def _signed_area(p: np.ndarray) -> float:
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


# ----------------------------------------------------------------------- sides and grading


def graded_fractions(n: int, ratio: float = 1.0) -> np.ndarray:
    """Positions of ``n + 1`` gridpoints along a side of unit length, with zone sizes in geometric
    progression.

    Parameters
    ----------
    n : int
        Number of zones (>= 1).
    ratio : float
        Ratio of the size of each zone to the size of the one before it (> 0; 1 is uniform).

    Returns
    -------
    numpy.ndarray
        (n + 1,) fractions from 0 to 1: ``s_i = (ratio**i - 1) / (ratio**n - 1)``, so that zone
        ``i`` has the size ``h_0 ratio**i`` with ``h_0 = (ratio - 1) / (ratio**n - 1)``.
    """
    n = _int_count(n, ("n",))
    r = _positive(ratio, ("ratio",))
    i = np.arange(n + 1, dtype=np.float64)
    if abs(math.log(r)) < 1e-12:
        s = i / n
    elif r < 1.0:
        q = math.log(r)                     # (r^i - 1)/(r^n - 1), no overflow for r < 1
        s = np.expm1(i * q) / math.expm1(n * q)
    else:                                   # mirror of the progression with 1/r
        q = -math.log(r)
        s = 1.0 - (np.expm1((n - i) * q) / math.expm1(n * q))
    s[0], s[-1] = 0.0, 1.0
    return s


def _largest_fraction(n: int, r: float) -> float:
    """Largest zone size on a unit side of n zones graded by r."""
    if abs(math.log(r)) < 1e-12:
        return 1.0 / n
    g = r if r > 1.0 else 1.0 / r
    # largest = (g - 1) g^(n-1) / (g^n - 1) = (1 - 1/g) / (1 - g^-n)
    return (1.0 - 1.0 / g) / (-math.expm1(-n * math.log(g)))


def _n_for_size(length: float, h: float, r: float, nmin: int, key) -> int:
    """Smallest number of zones >= nmin whose largest zone on a side of this length is <= h."""
    g = max(r, 1.0 / r)
    floor = length * (1.0 - 1.0 / g)
    if floor >= h * (1.0 - 1e-12) and abs(math.log(g)) >= 1e-12:
        gmax = 1.0 / (1.0 - h / length) if h < length else math.inf
        raise MeshError(f"with grading {r:g} the largest zone of a side {length:.6g} m long is at "
                        f"least {floor:.6g} m, above the size {h:g} m: give a larger size, a "
                        f"grading between {1.0 / gmax:.6g} and {gmax:.6g}, or the number of zones",
                        key=key)
    n = max(nmin, math.ceil(length / h * (1.0 - 1e-12)))
    while length * _largest_fraction(n, r) > h * (1.0 + 1e-12):
        n += 1
    return n


def _grow(n: int, excess: float, r: float) -> int:
    """Next count when the largest zone is ``excess`` times the size: in proportion when uniform
    (the sizes scale as 1/n), by 10 % when graded (they tend to a limit)."""
    if abs(math.log(r)) < 1e-12:
        return max(n + 1, math.ceil(n * excess))
    return n + max(1, n // 10)


def _n_sides(sides, h: float, r: float, nmin: int, key) -> int:
    """Smallest count (searched by :func:`_grow`) for which no zone along the sides is longer
    than h (arc length, which bounds the chord), the gridpoints snapped to their vertices."""
    n = n0 = max(_n_for_size(s.length, h, r, nmin, key) for s in sides)
    while True:
        worst = max(s.length * float(np.diff(s.fractions(n, r)).max()) for s in sides)
        if worst <= h * (1.0 + 1e-9):
            return n
        if n > 4 * n0 + 64:
            raise MeshError(f"with grading {r:g} the zones along a side with vertices stay larger "
                            f"than the size {h:g} m: give the number of zones, a larger size or a "
                            "grading closer to 1", key=key)
        n = _grow(n, worst / h, r)


class _Polyline:
    """A polyline side with its arc length."""

    def __init__(self, pts: np.ndarray) -> None:
        self.p = pts
        seg = np.hypot(*np.diff(pts, axis=0).T)
        self.cum = np.concatenate([[0.0], np.cumsum(seg)])
        self.length = float(self.cum[-1])
        self.nseg = len(pts) - 1

    def reversed(self) -> _Polyline:
        return _Polyline(self.p[::-1].copy())

    def at(self, f: np.ndarray) -> np.ndarray:
        s = np.asarray(f) * self.length
        out = np.empty((len(s), 2))
        out[:, 0] = np.interp(s, self.cum, self.p[:, 0])
        out[:, 1] = np.interp(s, self.cum, self.p[:, 1])
        # the vertices exactly (interp is exact at the knots, but keep the ends bit-exact)
        out[0], out[-1] = self.p[0], self.p[-1]
        return out

    def fractions(self, n: int, ratio: float) -> np.ndarray:
        """Graded fractions with a gridpoint at each vertex, the progression kept within each
        segment of the polyline (an affine map of it)."""
        s = graded_fractions(n, ratio)
        if self.nseg == 1:
            return s
        fv = self.cum / self.length
        m = self.nseg
        idx = [0]
        for k in range(1, m):
            near = int(np.argmin(np.abs(s - fv[k])))
            idx.append(min(max(near, idx[-1] + 1), n - (m - k)))
        idx.append(n)
        out = s.copy()
        for k in range(m):
            a, b = idx[k], idx[k + 1]
            out[a:b + 1] = fv[k] + (s[a:b + 1] - s[a]) / (s[b] - s[a]) * (fv[k + 1] - fv[k])
        return out


def _tfi(bottom: np.ndarray, right: np.ndarray, top: np.ndarray, left: np.ndarray,
         sb, sr, st, sl) -> np.ndarray:
    """Transfinite interpolation (Gordon & Hall (1973), linear blending) of the gridpoints
    of the four sides: bottom and top (nx+1 points, i direction), left and right (ny+1 points, j
    direction), all oriented from the c0 side; ``s*`` their fractions. Returns (ny+1, nx+1, 2)."""
    c0, c1, c2, c3 = bottom[0], bottom[-1], top[-1], top[0]
    ubar = 0.5 * (sb + st)                       # (nx+1,)
    vbar = 0.5 * (sl + sr)                       # (ny+1,)
    u = (1.0 - vbar)[:, None] * sb[None, :] + vbar[:, None] * st[None, :]
    v = (1.0 - ubar)[None, :] * sl[:, None] + ubar[None, :] * sr[:, None]
    u3, v3 = u[..., None], v[..., None]
    p = ((1.0 - v3) * bottom[None, :, :] + v3 * top[None, :, :]
         + (1.0 - u3) * left[:, None, :] + u3 * right[:, None, :]
         - ((1.0 - u3) * (1.0 - v3) * c0 + u3 * (1.0 - v3) * c1 + u3 * v3 * c2
            + (1.0 - u3) * v3 * c3))
    # the sides exactly
    p[0, :], p[-1, :], p[:, 0], p[:, -1] = bottom, top, left, right
    return p


def _grid_zones(nx: int, ny: int) -> np.ndarray:
    j, i = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
    g = (j * (nx + 1) + i).ravel()
    return np.stack([g, g + 1, g + nx + 2, g + nx + 1], axis=1).astype(np.int64)


def _grid_sides(nx: int, ny: int) -> list[np.ndarray]:
    """Chains of the four sides of a structured grid, counter-clockwise (bottom, right, top,
    left), each from its start corner."""
    idx = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    return [idx[0, :], idx[:, -1], idx[-1, ::-1], idx[::-1, 0]]


def _side_names(side_names, n: int, key) -> tuple[str, ...]:
    names = tuple(str(s) for s in side_names)
    if len(names) != n:
        raise MeshError(f"side_names must give {n} names", key=key)
    if len(set(names)) != n or any(not s or "." in s for s in names):
        raise MeshError("side_names must be distinct, non-empty and without '.'", key=key)
    return names


def _region_name(name, key=("name",)) -> str:
    name = str(name)
    if not name or "." in name:
        raise MeshError(f"region name {name!r} must be non-empty and without '.'", key=key)
    return name


def _mesh_quad(sides: list[np.ndarray], nx, ny, size, grading, name: str,
               side_names: tuple[str, ...], keys: Mapping[str, tuple]) -> Mesh:
    """Mesh a region bounded by four validated polylines (counter-clockwise, consecutive ends
    coinciding)."""
    bottom = _Polyline(sides[0])
    right = _Polyline(sides[1])
    top = _Polyline(sides[2]).reversed()      # c3 -> c2, the i direction
    left = _Polyline(sides[3]).reversed()     # c0 -> c3, the j direction
    rx, ry = grading
    segx = max(bottom.nseg, top.nseg)
    segy = max(left.nseg, right.nseg)
    if nx is not None and nx < segx:
        raise MeshError(f"nx = {nx} is fewer than the {segx} segments of the bottom or top side "
                        "(a gridpoint sits at every vertex)", key=keys["nx"])
    if ny is not None and ny < segy:
        raise MeshError(f"ny = {ny} is fewer than the {segy} segments of the left or right side "
                        "(a gridpoint sits at every vertex)", key=keys["ny"])
    auto_x, auto_y = nx is None, ny is None
    if auto_x or auto_y:
        if size is None:
            raise MeshError("give nx and ny, or a target zone size", key=keys["size"])
        hx, hy = size
        if auto_x:
            nx = _n_sides((bottom, top), hx, rx, segx, keys["size"])
        if auto_y:
            ny = _n_sides((left, right), hy, ry, segy, keys["size"])
    for _ in range(30):
        sb, st = bottom.fractions(nx, rx), top.fractions(nx, rx)
        sl, sr = left.fractions(ny, ry), right.fractions(ny, ry)
        p = _tfi(bottom.at(sb), right.at(sr), top.at(st), left.at(sl), sb, sr, st, sl)
        if not (auto_x or auto_y):
            break
        ex = np.hypot(*np.diff(p, axis=1).reshape(-1, 2).T).max()
        ey = np.hypot(*np.diff(p, axis=0).reshape(-1, 2).T).max()
        grow_x = auto_x and ex > hx * (1.0 + 1e-9)
        grow_y = auto_y and ey > hy * (1.0 + 1e-9)
        if not (grow_x or grow_y):
            break
        if grow_x:
            nx = _grow(nx, ex / hx, rx)
        if grow_y:
            ny = _grow(ny, ey / hy, ry)
    else:  # the interior edges stay longer than the size (a strongly distorted region)
        raise MeshError(f"region {name!r}: the interior zones stay larger than the size: give "
                        "the numbers of zones or a grading closer to 1", key=keys["size"])
    xy = p.reshape(-1, 2)
    zones = _grid_zones(nx, ny)
    bad = _bad_zones(xy, zones)
    if bad.size:
        raise MeshError(f"region {name!r}: {bad.size} of {len(zones)} zones come out inverted or "
                        "non-convex (the corners do not map to a convex quadrilateral): split the "
                        "region or choose other corners", key=keys["corners"])
    chains = _grid_sides(nx, ny)
    return Mesh(xy, zones, np.zeros(len(zones), dtype=np.int64), (name,),
                {f"{name}.{s}": c for s, c in zip(side_names, chains, strict=True)})


def _mesh_args(nx, ny, size, grading):
    nx = None if nx is None else _int_count(nx, ("nx",))
    ny = None if ny is None else _int_count(ny, ("ny",))
    size = None if size is None else _pair(size, ("size",), " [m]")
    grading = _pair(grading, ("grading",), "")
    return nx, ny, size, grading


_QUAD_KEYS = {"nx": ("nx",), "ny": ("ny",), "size": ("size",), "corners": ("sides",)}


def quad_region(bottom, right, top, left, *, nx: int | None = None, ny: int | None = None,
                size=None, grading=1.0, name: str = "region",
                side_names: Sequence[str] = SIDE_NAMES) -> Mesh:
    """Mesh a region bounded by four sides (polylines) by transfinite interpolation.

    Parameters
    ----------
    bottom, right, top, left : array_like
        The four sides, each a polyline of (x, y) points [m] (two points for a straight side),
        following the boundary counter-clockwise: ``bottom`` from c0 to c1, ``right`` from c1 to
        c2, ``top`` from c2 to c3, ``left`` from c3 back to c0. Each side ends where the next
        starts.
    nx, ny : int, optional
        Zones along the bottom and top (``nx``) and along the left and right (``ny``); at least
        the number of segments of those sides (a gridpoint sits at every vertex). A missing one
        comes from ``size``.
    size : float or (float, float), optional
        Target zone size [m] (one, or one per direction): the smallest numbers of zones such that
        no zone edge in that direction is longer.
    grading : float or (float, float)
        Ratio of successive zone sizes along i (bottom and top, from c0 and c3) and along j
        (left and right, from c0 and c1): > 1 grows away from c0, < 1 shrinks; 1 is uniform.
    name : str
        Region name (the prefix of its sides: ``"NAME.bottom"``).
    side_names : sequence of 4 str
        Names of the four sides, counter-clockwise from c0.

    Returns
    -------
    Mesh
        ``(nx + 1) (ny + 1)`` gridpoints and ``nx ny`` zones.

    Raises
    ------
    MeshError
        Bad counts, size or grading; sides that do not join or that cross; a region whose zones
        come out inverted (key ``("sides",)``).

    References
    ----------
    Gordon & Hall (1973) (transfinite interpolation with linear blending).
    """
    name = _region_name(name)
    side_names = _side_names(side_names, 4, ("side_names",))
    nx, ny, size, grading = _mesh_args(nx, ny, size, grading)
    sides = [_points(s, (k,), 2) for s, k in zip((bottom, right, top, left), SIDE_NAMES,
                                                   strict=True)]
    allp = np.concatenate(sides)
    scale = float(np.hypot(*(allp.max(0) - allp.min(0))))
    if scale == 0.0:
        raise MeshError("the sides have no extent", key=("bottom",))
    for k in range(4):
        end, start = sides[k][-1], sides[(k + 1) % 4][0]
        if math.dist(end, start) > _TOL * scale:
            raise MeshError(f"side {SIDE_NAMES[k]} ends at ({end[0]:.6g}, {end[1]:.6g}) but "
                            f"{SIDE_NAMES[(k + 1) % 4]} starts at ({start[0]:.6g}, "
                            f"{start[1]:.6g})", key=(SIDE_NAMES[(k + 1) % 4], 0))
        sides[(k + 1) % 4][0] = end
    ring = np.concatenate([s[:-1] for s in sides])
    _check_ring(ring, ("sides",), indexed=False)
    if _signed_area(ring) <= 0.0:
        raise MeshError("the sides must follow the boundary counter-clockwise (bottom, right, "
                        "top, left)", key=("sides",))
    return _mesh_quad(sides, nx, ny, size, grading, name, side_names, _QUAD_KEYS)


def rectangle(x0: float, y0: float, width: float, height: float, *, nx: int | None = None,
              ny: int | None = None, size=None, grading=1.0, name: str = "region",
              side_names: Sequence[str] = SIDE_NAMES) -> Mesh:
    """Mesh a rectangle ``[x0, x0 + width] x [y0, y0 + height]`` (corner c0 at ``(x0, y0)``).

    Parameters
    ----------
    x0, y0 : float
        Lower-left corner [m].
    width, height : float
        Sides [m] (> 0).
    nx, ny, size, grading, name, side_names
        As for :func:`quad_region`.

    Returns
    -------
    Mesh
        The structured mesh.
    """
    w = _positive(width, ("width",), " [m]")
    h = _positive(height, ("height",), " [m]")
    a, b = (x0, y0), (x0 + w, y0)
    c, d = (x0 + w, y0 + h), (x0, y0 + h)
    return quad_region([a, b], [b, c], [c, d], [d, a], nx=nx, ny=ny, size=size, grading=grading,
                       name=name, side_names=side_names)


# ------------------------------------------------------------------------------------ polygons


def _interior_angles_deg(p: np.ndarray) -> np.ndarray:
    """Interior angles [deg] of a counter-clockwise ring."""
    a = np.roll(p, 1, axis=0) - p
    b = np.roll(p, -1, axis=0) - p
    cross = b[:, 0] * a[:, 1] - b[:, 1] * a[:, 0]
    ang = np.degrees(np.arctan2(cross, np.sum(a * b, axis=1)))
    return np.where(ang < 0.0, ang + 360.0, ang)


def _ring_path(p: np.ndarray, i: int, j: int) -> np.ndarray:
    """Vertices of a ring from i to j (inclusive), forwards."""
    n = len(p)
    k = (j - i) % n
    return p[[(i + t) % n for t in range(k + 1)]]


def _auto_corners(p: np.ndarray) -> list[int]:
    """Four (or three) corner indices of a counter-clockwise ring: the convex vertices whose
    interior angles are furthest below 180 deg; ties at the last place are broken by the most
    balanced opposite sides."""
    from itertools import combinations

    ang = _interior_angles_deg(p)
    dev = np.where(ang < 180.0 - _CORNER_MIN_DEG, 180.0 - ang, -np.inf)
    cand = [int(i) for i in np.argsort(-dev, kind="stable") if np.isfinite(dev[i])]
    if len(cand) <= 4:
        return sorted(cand)
    fourth = dev[cand[3]]
    sure = [i for i in cand if dev[i] > fourth + 1e-9]
    tied = [i for i in cand if abs(dev[i] - fourth) <= 1e-9]
    if len(sure) + len(tied) == 4:
        return sorted(sure + tied)
    seg = np.hypot(*(np.roll(p, -1, axis=0) - p).T)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    n = len(p)

    def side_len(i, j):
        return (cum[j] - cum[i]) if j > i else (cum[n] - cum[i] + cum[j])

    best, best_score = None, math.inf
    for extra in combinations(tied, 4 - len(sure)):
        c = sorted(sure + list(extra))
        L = [side_len(c[k], c[(k + 1) % 4]) for k in range(4)]
        score = max(abs(L[0] - L[2]) / (L[0] + L[2]), abs(L[1] - L[3]) / (L[1] + L[3]))
        if score < best_score - 1e-12:
            best, best_score = c, score
    return best


def polygon_corners(vertices) -> tuple[int, ...]:
    """The corners :func:`polygon_region` picks on a polygon, as indices into ``vertices``.

    Parameters
    ----------
    vertices : array_like
        (n, 2) polygon vertices [m], n >= 3, in either orientation.

    Returns
    -------
    tuple of int
        Four indices (three for a polygon with only three vertices below 180 deg): the vertices
        whose interior angles are furthest below 180 deg (ties broken by the most balanced
        opposite sides), counter-clockwise from corner c0, the lowest of them (then the
        leftmost).
    """
    p, order = _polygon(vertices)
    corners = _auto_corners(p)
    return tuple(int(order[c]) for c in _start_low(p, corners))


def _start_low(p: np.ndarray, corners: list[int]) -> list[int]:
    """Rotate a counter-clockwise list of corners to start from the lowest, then leftmost."""
    k = min(range(len(corners)), key=lambda t: (p[corners[t], 1], p[corners[t], 0]))
    return corners[k:] + corners[:k]


def _polygon(vertices) -> tuple[np.ndarray, np.ndarray]:
    """Validated counter-clockwise ring and, for each of its vertices, the index in the input."""
    p = _points(vertices, ("vertices",), 3)
    _check_ring(p, ("vertices",))
    order = np.arange(len(p))
    a = _signed_area(p)
    if a < 0.0:
        p, order = p[::-1].copy(), order[::-1].copy()
    if abs(a) <= 1e-14 * float(np.sum((p.max(0) - p.min(0)) ** 2)):
        raise MeshError("the polygon has no area", key=("vertices",))
    return p, order


def polygon_region(vertices, *, corners: Sequence[int] | None = None, nx: int | None = None,
                   ny: int | None = None, size=None, grading=1.0, name: str = "region",
                   side_names: Sequence[str] | None = None) -> Mesh:
    """Mesh a polygon region: four of its vertices are the corners, the boundary between two
    corners is a side (a polyline), and the region is meshed by :func:`quad_region`.

    Parameters
    ----------
    vertices : array_like
        (n, 2) vertices [m], n >= 3, counter-clockwise or clockwise (normalised to
        counter-clockwise); no duplicated vertex, no self-intersection.
    corners : sequence of 4 (or 3) int, optional
        Indices into ``vertices`` of the four corners, the first being c0 (the start of the
        bottom side); the others follow counter-clockwise whatever their order here (three
        corners: the region is meshed as a triangle, below). Default:
        :func:`polygon_corners` (the four vertices whose interior angles are furthest from
        180 deg, c0 the lowest, then leftmost). A polygon with only three vertices below
        180 deg (a triangle) is meshed as three quadrilaterals meeting at its centroid, with
        ``max(nx, ny)`` zones along each half side.
    nx, ny, size, grading
        As for :func:`quad_region` (a three-cornered region takes no grading: its three
        quadrilaterals must conform along the lines from the mid-sides to the centroid).
    name : str
        Region name.
    side_names : sequence of str, optional
        Names of the sides counter-clockwise from c0; default ``("bottom", "right", "top",
        "left")``, or ``("bottom", "right", "left")`` for three corners.

    Returns
    -------
    Mesh
        The mesh of the region.

    Raises
    ------
    MeshError
        Fewer than 3 vertices, duplicated vertices, self-intersection (key ``("vertices", i)`` or
        ``("vertices",)``), bad corners (``("corners",)``), bad counts, size or grading, or zones
        that come out inverted (``("corners",)``).

    References
    ----------
    Gordon & Hall (1973) (transfinite interpolation).
    """
    name = _region_name(name)
    nx, ny, size, grading = _mesh_args(nx, ny, size, grading)
    p, order = _polygon(vertices)
    n = len(p)
    if corners is None:
        c = _start_low(p, _auto_corners(p))
    else:
        try:
            given = [int(k) for k in corners]
        except (TypeError, ValueError):
            raise MeshError("corners must be 4 vertex indices", key=("corners",)) from None
        if len(given) not in (3, 4) or len(set(given)) != len(given) or any(
                not 0 <= k < n for k in given):
            raise MeshError(f"corners must be 4 (or 3) distinct vertex indices in 0..{n - 1}",
                            key=("corners",))
        pos = {int(order[i]): i for i in range(n)}      # input index -> ring index
        ring = [pos[k] for k in given]
        c0 = ring[0]
        c = sorted(ring, key=lambda i: (i - c0) % n)
        ang = _interior_angles_deg(p)
        for i in c:
            if ang[i] >= 180.0 - _CORNER_MIN_DEG:
                raise MeshError(f"corner vertex {int(order[i])} has an interior angle of "
                                f"{ang[i]:.6g} deg: a corner must be below 180 deg",
                                key=("corners",))
    if len(c) == 4:
        names = _side_names(side_names or SIDE_NAMES, 4, ("side_names",))
        sides = [_ring_path(p, c[k], c[(k + 1) % 4]) for k in range(4)]
        keys = {"nx": ("nx",), "ny": ("ny",), "size": ("size",), "corners": ("corners",)}
        return _mesh_quad(sides, nx, ny, size, grading, name, names, keys)
    names = _side_names(side_names or TRIANGLE_SIDE_NAMES, 3, ("side_names",))
    if grading != (1.0, 1.0):
        raise MeshError("a three-cornered region is meshed as three quadrilaterals: it takes no "
                        "grading", key=("grading",))
    counts = [k for k in (nx, ny) if k is not None]
    return _triangle(p, c, max(counts) if counts else None, size, name, names)


def _triangle(p: np.ndarray, c: list[int], n, size, name: str, names) -> Mesh:
    """Three-cornered region: three quadrilaterals (corner, mid-side, centroid, mid-side)."""
    sides = [_Polyline(_ring_path(p, c[k], c[(k + 1) % 3])) for k in range(3)]
    mids = [s.at(np.array([0.0, 0.5, 1.0]))[1] for s in sides]
    g = p[c].mean(axis=0)
    halves = []                  # for corner k: (second half of side k-1, first half of side k)
    for k in range(3):
        s, sp = sides[k], sides[k - 1]
        first = np.vstack([s.p[s.cum < 0.5 * s.length], [mids[k]]])
        second = np.vstack([[mids[k - 1]], sp.p[sp.cum > 0.5 * sp.length]])
        halves.append((second, first))
    quads = []
    for k in range(3):
        second, first = halves[k]
        quads.append([first, np.array([mids[k], g]), np.array([g, mids[k - 1]]), second])
    keys = {"nx": ("nx",), "ny": ("nx",), "size": ("size",), "corners": ("vertices",)}
    h = None if size is None else min(size)
    if n is None:
        if h is None:
            raise MeshError("give nx or a target zone size", key=("size",))
        n = max(max(_n_for_size(_Polyline(s).length, h, 1.0, _Polyline(s).nseg, ("size",))
                    for s in q) for q in quads)
    for _ in range(200):
        parts = [_mesh_quad(q, n, n, None, (1.0, 1.0), f"{name}{k}", SIDE_NAMES, keys)
                 for k, q in enumerate(quads)]
        if h is None or max(m.edge_lengths().max() for m in parts) <= h * (1.0 + 1e-9):
            break
        n += 1
    m = merge(parts)
    out_sides = {f"{name}.{names[k]}": _chain_on(m, sides[k].p) for k in range(3)}
    return Mesh(m.xy, m.zones, np.zeros(m.n_zones, dtype=np.int64), (name,), out_sides)


def _chain_on(mesh: Mesh, poly: np.ndarray) -> np.ndarray:
    """Boundary gridpoints on a polyline, ordered along it."""
    pl = _Polyline(poly)
    tol = _TOL * 10.0 * max(mesh.size, 1e-300)
    b = mesh.boundary_gridpoints()
    xy = mesh.xy[b]
    best_d = np.full(len(b), np.inf)
    best_s = np.zeros(len(b))
    for k in range(pl.nseg):
        a, d = pl.p[k], pl.p[k + 1] - pl.p[k]
        L2 = float(d @ d)
        t = np.clip((xy - a) @ d / L2, 0.0, 1.0)
        dist = np.hypot(*(xy - a - t[:, None] * d).T)
        better = dist < best_d
        best_d = np.where(better, dist, best_d)
        best_s = np.where(better, pl.cum[k] + t * math.sqrt(L2), best_s)
    on = best_d <= tol
    return b[on][np.argsort(best_s[on], kind="stable")]


# ------------------------------------------------------------------------------------- merging


def merge(meshes: Sequence[Mesh], *, tol: float = _TOL) -> Mesh:
    """Merge meshes that share sides into one conforming mesh.

    Gridpoints closer than ``tol`` times the model size (the diagonal of the bounding box of all
    gridpoints) become one. The regions keep their names (which must differ) and their sides.

    Parameters
    ----------
    meshes : sequence of Mesh
        The meshes (each one or more regions).
    tol : float
        Relative tolerance of coincident gridpoints (> 0, default 1e-9).

    Returns
    -------
    Mesh
        The merged mesh: regions numbered in the order given.

    Raises
    ------
    MeshError
        Duplicated region names (key ``("meshes", i)``); sides that touch without conforming: a
        gridpoint of one lies inside a boundary edge of another (different numbers of zones or
        gradings along a shared side); overlapping zones; zones that collapse.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    meshes = list(meshes)
    if not meshes:
        raise MeshError("nothing to merge", key=("meshes",))
    tol = _positive(tol, ("tol",))
    names: list[str] = []
    owner: dict[str, int] = {}
    for i, m in enumerate(meshes):
        if not isinstance(m, Mesh):
            raise MeshError(f"meshes[{i}] is not a Mesh", key=("meshes", i))
        for n in m.region_names:
            if n in owner:
                raise MeshError(f"region name {n!r} appears twice (meshes {owner[n]} and {i})",
                                key=("meshes", i))
            owner[n] = i
            names.append(n)
    xy = np.concatenate([m.xy for m in meshes])
    offs = np.cumsum([0] + [m.n_gridpoints for m in meshes])
    scale = float(np.hypot(*(xy.max(0) - xy.min(0))))
    atol = tol * scale
    # coincident gridpoints: connected components of the pairs closer than atol
    pairs = cKDTree(xy).query_pairs(atol, output_type="ndarray")
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])),
                       shape=(len(xy), len(xy)))
    _, label = connected_components(graph, directed=False)
    first = np.full(label.max() + 1, len(xy))
    np.minimum.at(first, label, np.arange(len(xy)))
    roots = first[label]                      # each point -> the first point of its group
    keep, new = np.unique(roots, return_inverse=True)
    xy_new = xy[keep]
    zones = np.concatenate([new[m.zones + offs[i]] for i, m in enumerate(meshes)])
    roff = np.cumsum([0] + [len(m.region_names) for m in meshes])
    region = np.concatenate([m.region + roff[i] for i, m in enumerate(meshes)])
    zsrc = np.repeat(np.arange(len(meshes)), [m.n_zones for m in meshes])
    srt = np.sort(zones, axis=1)
    coll = np.nonzero((np.diff(srt, axis=1) == 0).any(1))[0]
    if coll.size:
        raise MeshError(f"zones of {names[region[coll[0]]]!r} collapse when merging: tol "
                        f"{tol:g} is too large for their size", key=("meshes", int(zsrc[coll[0]])))
    # each edge at most twice, in opposite directions
    e = _zone_edges(zones)
    ez = np.repeat(np.arange(len(zones)), 4)
    inv, cnt = _edge_groups(e, len(xy_new))
    over = np.nonzero(cnt[inv] > 2)[0]
    two = np.nonzero(cnt[inv] == 2)[0]
    two = two[np.argsort(inv[two], kind="stable")]          # the two uses of an edge, together
    same = two[0::2][e[two[0::2], 0] == e[two[1::2], 0]]     # both uses in the same direction
    if over.size or same.size:
        z = ez[int(over[0]) if over.size else int(same[0])]
        raise MeshError(f"region {names[region[z]]!r} overlaps another region",
                        key=("meshes", int(zsrc[z])))
    # conformity: no boundary gridpoint inside a boundary edge
    be = e[cnt[inv] == 1]
    bz = ez[cnt[inv] == 1]
    bp = np.unique(be)
    a, b = xy_new[be[:, 0]], xy_new[be[:, 1]]
    d = b - a
    L2 = np.sum(d * d, axis=1)
    for start in range(0, len(bp), 256):
        q = xy_new[bp[start:start + 256]]                      # (k, 2)
        t = np.einsum("kij,ij->ki", q[:, None, :] - a[None], d) / L2[None]
        inside = (t > 1e-9) & (t < 1.0 - 1e-9)
        foot = a[None] + t[..., None] * d[None]
        dist = np.hypot(*(q[:, None, :] - foot).transpose(2, 0, 1))
        hit = inside & (dist <= max(10.0 * atol, 1e-300))
        if hit.any():
            qi, ei = (int(v[0]) for v in np.nonzero(hit))
            g = bp[start + qi]
            zq = np.nonzero((zones == g).any(1))[0][0]
            ra, rb = names[region[zq]], names[region[bz[ei]]]
            x, y = xy_new[g]
            raise MeshError(f"regions {ra!r} and {rb!r} touch without conforming: gridpoint "
                            f"({x:.6g}, {y:.6g}) of {ra!r} lies inside an edge of {rb!r} (give "
                            "the shared side the same zones and grading)",
                            key=("meshes", int(zsrc[zq])))
    sides = {}
    for i, m in enumerate(meshes):
        for n, c in m.sides.items():
            if n in sides:
                raise MeshError(f"side {n!r} appears twice", key=("meshes", i))
            sides[n] = new[c + offs[i]]
    return Mesh(xy_new, zones, region, tuple(names), sides)


# ------------------------------------------------------------------------------- generators


def annulus(inner_radius: float, outer_radius: float, nr: int, ntheta: int, *,
            theta0_deg: float = 0.0, theta1_deg: float = 90.0, grading: float = 1.0,
            center=(0.0, 0.0), name: str = "ground") -> Mesh:
    """Mesh an annular sector around a cylindrical hole (the verification problem of a hole in
    a Mohr-Coulomb medium), gridpoints on the two circles.

    Parameters
    ----------
    inner_radius, outer_radius : float
        Radius ``a`` of the hole and outer radius ``b > a`` [m].
    nr, ntheta : int
        Zones along a radius and around the sector.
    theta0_deg, theta1_deg : float
        Start and end angles of the sector [deg], counter-clockwise from the x axis (default a
        quarter, 0 to 90); a sector of 360 deg is the full annulus (no start and end rays).
    grading : float
        Ratio of successive radial zone sizes, outwards (> 0). ``(b / a) ** (1 / nr)`` gives
        radii in geometric progression (zones of constant aspect ratio).
    center : (float, float)
        Centre of the hole [m].
    name : str
        Region name; its sides are ``start`` (the ray at ``theta0``, outwards), ``outer``
        (counter-clockwise), ``end`` (the ray at ``theta1``, inwards) and ``inner`` (clockwise),
        following the boundary counter-clockwise; the full annulus has ``inner`` and ``outer``.

    Returns
    -------
    Mesh
        ``nr ntheta`` zones; gridpoint ``(i, j)`` at radius ``r_i`` and angle ``theta_j``. The
        zone areas sum to the polygonal area ``ntheta sin(dtheta) (b² - a²) / 2`` with
        ``dtheta`` the angle of a zone (the chords of the circles).
    """
    name = _region_name(name)
    a = _positive(inner_radius, ("inner_radius",), " [m]")
    b = _positive(outer_radius, ("outer_radius",), " [m]")
    if b <= a:
        raise MeshError(f"outer_radius = {b} must exceed inner_radius = {a}",
                        key=("outer_radius",))
    nr = _int_count(nr, ("nr",))
    ntheta = _int_count(ntheta, ("ntheta",))
    r = _positive(grading, ("grading",))
    span = float(theta1_deg) - float(theta0_deg)
    if not (0.0 < span <= 360.0):
        raise MeshError(f"theta1_deg - theta0_deg = {span} must be in (0, 360]",
                        key=("theta1_deg",))
    full = span == 360.0
    if full and ntheta < 3:
        raise MeshError("the full annulus needs ntheta >= 3", key=("ntheta",))
    if span / ntheta >= 180.0:
        raise MeshError(f"ntheta = {ntheta} gives zones spanning {span / ntheta:g} deg (must be "
                        "below 180)", key=("ntheta",))
    cx, cy = (float(v) for v in center)
    rad = a + (b - a) * graded_fractions(nr, r)
    nt = ntheta if full else ntheta + 1
    th = np.radians(float(theta0_deg) + span * np.arange(nt) / ntheta)
    R, T = np.meshgrid(rad, th)                 # (nt, nr+1)
    xy = np.stack([cx + R * np.cos(T), cy + R * np.sin(T)], axis=-1).reshape(-1, 2)
    idx = np.arange(nt * (nr + 1)).reshape(nt, nr + 1)
    jn = (np.arange(ntheta) + 1) % nt
    j, i = np.meshgrid(np.arange(ntheta), np.arange(nr), indexing="ij")
    zones = np.stack([idx[j, i], idx[j, i + 1], idx[jn[j], i + 1], idx[jn[j], i]],
                     axis=-1).reshape(-1, 4)
    if full:
        outer = np.append(idx[:, -1], idx[0, -1])
        inner = np.append(idx[0, 0], idx[::-1, 0])
        sides = {f"{name}.outer": outer, f"{name}.inner": inner}
    else:
        sides = {f"{name}.start": idx[0, :], f"{name}.outer": idx[:, -1],
                 f"{name}.end": idx[-1, ::-1], f"{name}.inner": idx[::-1, 0]}
    return Mesh(xy, zones.astype(np.int64), np.zeros(len(zones), dtype=np.int64), (name,), sides)


def _n_progression(length: float, h0: float, q: float) -> int:
    """Number of zones, first of size ~h0 growing by q, that fills a length."""
    if abs(q - 1.0) < 1e-12:
        return max(1, round(length / h0))
    return max(1, round(math.log1p(length * (q - 1.0) / h0) / math.log(q)))


def strip_footing(half_width: float, depth: float, width: float, *, n_footing: int = 8,
                  grading: float = 1.1, full: bool = False, name: str = "soil") -> Mesh:
    """Mesh the ground under a strip footing on its surface (the verification problem of
    Prandtl's bearing capacity), refined towards the footing.

    The ground surface is ``y = 0``, the footing covers ``|x| <= B`` with ``B = half_width``,
    the ground goes down to ``y = -depth`` and out to ``x = width`` (and ``-width`` for the full
    model); the half model has its axis of symmetry at ``x = 0``. Under the footing the zones are
    uniform, ``B / n_footing`` wide; beside it and below the surface they grow by ``grading``
    away from the footing edge and from the surface (the numbers of zones are chosen so that the
    first zone is about ``B / n_footing``; the ratio is exact).

    Parameters
    ----------
    half_width : float
        Half-width ``B`` of the footing [m].
    depth : float
        Depth of the model [m].
    width : float
        Extent of the model from the axis [m] (> B).
    n_footing : int
        Zones across the half-width of the footing.
    grading : float
        Ratio of successive zone sizes away from the footing (>= 1).
    full : bool
        Model both sides of the axis (default: the half model ``0 <= x <= width``).
    name : str
        Prefix of the regions (``NAME_under``, ``NAME_side``, and ``NAME_left`` for the full
        model).

    Returns
    -------
    Mesh
        The mesh, with the chains ``footing`` (the surface gridpoints under the footing, from
        left to right), ``base`` (``y = -depth``, left to right) and, for the half model,
        ``surface`` (the free surface beside the footing, outwards), ``far`` (``x = width``,
        upwards) and ``axis`` (``x = 0``, upwards); for the full model ``surface_left``,
        ``surface_right`` (left to right) and ``far_left``, ``far_right`` (upwards).
    """
    name = _region_name(name)
    B = _positive(half_width, ("half_width",), " [m]")
    D = _positive(depth, ("depth",), " [m]")
    W = _positive(width, ("width",), " [m]")
    if W <= B:
        raise MeshError(f"width = {W} must exceed half_width = {B}", key=("width",))
    nf = _int_count(n_footing, ("n_footing",))
    q = _positive(grading, ("grading",))
    if q < 1.0:
        raise MeshError(f"grading = {q} must be >= 1 (zones grow away from the footing)",
                        key=("grading",))
    h0 = B / nf
    ny = _n_progression(D, h0, q)
    nside = _n_progression(W - B, h0, q)
    under = rectangle(-B if full else 0.0, -D, 2 * B if full else B, D,
                      nx=2 * nf if full else nf, ny=ny, grading=(1.0, 1.0 / q),
                      name=f"{name}_under")
    side = rectangle(B, -D, W - B, D, nx=nside, ny=ny, grading=(q, 1.0 / q), name=f"{name}_side")
    parts = [under, side]
    if full:
        parts.insert(0, rectangle(-W, -D, W - B, D, nx=nside, ny=ny, grading=(1.0 / q, 1.0 / q),
                                  name=f"{name}_left"))
    m = merge(parts)
    foot = m.side(f"{name}_under.top")[::-1]
    bottoms = [m.side(f"{p.region_names[0]}.bottom") for p in parts]
    extra = {"footing": foot,
             "base": np.concatenate([bottoms[0]] + [c[1:] for c in bottoms[1:]])}
    if full:
        extra["surface_left"] = m.side(f"{name}_left.top")[::-1]
        extra["surface_right"] = m.side(f"{name}_side.top")[::-1]
        extra["far_left"] = m.side(f"{name}_left.left")[::-1]
        extra["far_right"] = m.side(f"{name}_side.right")
    else:
        extra["surface"] = m.side(f"{name}_side.top")[::-1]
        extra["far"] = m.side(f"{name}_side.right")
        extra["axis"] = m.side(f"{name}_under.left")[::-1]
    sides = dict(m.sides)
    sides.update(extra)
    return Mesh(m.xy, m.zones, m.region, m.region_names, sides)


# ----------------------------------------------------------------------------- case files

#: Keys of one region for :func:`mesh_regions` (the arguments of :func:`polygon_region`).
REGION_KEYS = ("vertices", "corners", "nx", "ny", "size", "grading", "name", "side_names")


def mesh_regions(regions: Sequence[Mapping], *, table: str = "zones", tol: float = _TOL) -> Mesh:
    """Mesh polygon regions and merge them into one conforming mesh: the layer under the
    ``[[zones]]`` tables of a case file.

    Parameters
    ----------
    regions : sequence of mapping
        One mapping per region with the keys of :func:`polygon_region` (``vertices`` [m],
        optional ``corners``, ``nx``, ``ny``, ``size`` [m], ``grading``, ``name``,
        ``side_names``); other keys (a material) are ignored. ``name`` defaults to
        ``"{table}{i}"``.
    table : str
        Name of the table, the first element of the key path of an error.
    tol : float
        Relative tolerance of coincident gridpoints (:func:`merge`).

    Returns
    -------
    Mesh
        The merged mesh; region ``i`` (``Mesh.region == i``) is ``regions[i]``.

    Raises
    ------
    MeshError
        With the key path prefixed by ``(table, i)``: ``("zones", 2, "vertices", 3)`` for a
        duplicated vertex of the third region, ``("zones", 1)`` for a region whose side does not
        conform to another's.
    """
    meshes = []
    for i, spec in enumerate(regions):
        if not isinstance(spec, Mapping):
            raise MeshError(f"{table}[{i}] must be a table", key=(table, i))
        if "vertices" not in spec:
            raise MeshError(f"{table}[{i}] has no vertices", key=(table, i, "vertices"))
        kw = {k: spec[k] for k in REGION_KEYS if k in spec and k != "vertices"}
        kw.setdefault("name", f"{table}{i}")
        try:
            meshes.append(polygon_region(spec["vertices"], **kw))
        except MeshError as e:
            raise MeshError(str(e), key=(table, i, *e.key)) from None
    if not meshes:
        raise MeshError(f"no {table} regions", key=(table,))
    try:
        return merge(meshes, tol=tol) if len(meshes) > 1 else meshes[0]
    except MeshError as e:
        k = e.key[1:] if e.key[:1] == ("meshes",) else e.key
        raise MeshError(str(e), key=(table, *k)) from None
