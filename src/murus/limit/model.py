"""Rigid-block assemblies for limit analysis: blocks, supports and the interfaces between them.

Conventions: SI units (m, kg, N, Pa); x horizontal to the right, y up; polygons
counter-clockwise; masses per out-of-plane ``thickness`` [m]. A block is one rigid body made of
one or more convex polygons (a DEM clump); blocks with ``kinematic = "fixed"`` or ``"base"`` are
supports (they do not move in a mechanism).

An **interface** is a stretch of two collinear, overlapping, opposite edges of two blocks (the
gap or overlap across it and the overlap length within ``tol``); it is represented by its two end
points ``p1``, ``p2`` (the standard representation of Livesley (1978) and Gilbert et al. (2006):
normal forces at the two ends, a shear force along it). Its unit normal points from block ``a``
into block ``b``; its tangent is the normal turned by +90 deg. A corner touching a face (a point
contact) is not an interface.

References
----------
Livesley, R. K. (1978). Limit analysis of structures formed from rigid blocks. International
Journal for Numerical Methods in Engineering 12(12), 1853-1871. doi:10.1002/nme.1620121207
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from murus import G
from murus.errors import MurusError

__all__ = ["Assembly", "Interfaces", "LimitModelError", "from_case", "find_interfaces"]


class LimitModelError(MurusError, ValueError):
    """A model that limit analysis cannot take (one line, naming the block)."""


@dataclass
class Interfaces:
    """The interfaces of an assembly (arrays over interfaces, see the module docstring).

    Attributes
    ----------
    a, b : numpy.ndarray
        Blocks on either side (int); the normal points from ``a`` into ``b``.
    p1, p2 : numpy.ndarray
        End points ``(k, 2)`` [m].
    normal : numpy.ndarray
        Unit normals ``(k, 2)``, from ``a`` into ``b``.
    friction : numpy.ndarray
        Friction coefficient mu = tan(phi) [-].
    cohesion, tensile : numpy.ndarray
        Cohesion c and tensile strength t [Pa].
    """

    a: np.ndarray
    b: np.ndarray
    p1: np.ndarray
    p2: np.ndarray
    normal: np.ndarray
    friction: np.ndarray
    cohesion: np.ndarray
    tensile: np.ndarray

    def __len__(self) -> int:
        return len(self.a)

    @property
    def tangent(self) -> np.ndarray:
        """Unit tangents ``(k, 2)``: the normals turned by +90 deg."""
        return np.column_stack([-self.normal[:, 1], self.normal[:, 0]])

    @property
    def length(self) -> np.ndarray:
        """Lengths [m]."""
        return np.hypot(*(self.p2 - self.p1).T)

    @property
    def midpoint(self) -> np.ndarray:
        """Mid points ``(k, 2)`` [m]."""
        return 0.5 * (self.p1 + self.p2)


@dataclass
class Assembly:
    """Rigid blocks for limit analysis.

    Parameters
    ----------
    polygons : list of numpy.ndarray
        Convex polygons ``(k, 2)`` [m], counter-clockwise.
    body : numpy.ndarray
        Block of each polygon (int).
    support : numpy.ndarray
        Per block: True for a support (fixed or base block).
    density : numpy.ndarray
        Per block [kg/m³].
    names : list of str
        Per block, for messages (``"[[blocks]] 3"``).
    joint : callable
        ``joint(i, j) -> (friction_deg, cohesion [Pa], tensile [Pa])`` of the joint between
        blocks i and j.
    thickness : float
        Out-of-plane thickness [m].
    gravity : float
        Acceleration of gravity [m/s²].
    tol : float
        Geometric tolerance [m] of the interface search and of the overlap check.
    keys : list of tuple
        Per block, its key path in the case file (for :class:`murus.errors.MurusError`).
    """

    polygons: list
    body: np.ndarray
    support: np.ndarray
    density: np.ndarray
    names: list
    joint: object
    thickness: float = 1.0
    gravity: float = G
    tol: float = 1e-5
    keys: list = field(default_factory=list)
    source: object = None

    def __post_init__(self) -> None:
        self.body = np.asarray(self.body, dtype=int)
        self.support = np.asarray(self.support, dtype=bool)
        self.density = np.asarray(self.density, dtype=float)
        nb = len(self.support)
        area = np.zeros(nb)
        first = np.zeros((nb, 2))
        for v, b in zip(self.polygons, self.body, strict=True):
            A, c = _area_centroid(v)
            area[b] += A
            first[b] += A * c
        self.area = area
        self.centroid = first / np.where(area > 0, area, 1.0)[:, None]
        self.mass = area * self.density * self.thickness
        if not self.keys:
            self.keys = [() for _ in range(nb)]

    @property
    def nblock(self) -> int:
        return len(self.support)

    def error(self, block: int, msg: str) -> LimitModelError:
        """A :class:`LimitModelError` about ``block``, carrying its key path."""
        return LimitModelError(f"{self.names[block]}: {msg}", key=self.keys[block],
                               source=self.source)

    @classmethod
    def from_polygons(cls, polygons, supports=(), density=2000.0, friction_deg=30.0,
                      cohesion=0.0, tensile=0.0, thickness=1.0, gravity=G, tol=1e-5):
        """An assembly of one block per polygon, with one joint material everywhere.

        Parameters
        ----------
        polygons : sequence of array_like
            Convex polygons ``(k, 2)`` [m] (either orientation).
        supports : iterable of int
            Indices of the support blocks.
        density : float
            [kg/m³].
        friction_deg, cohesion, tensile : float
            Joint friction angle [deg], cohesion and tensile strength [Pa].
        thickness, gravity, tol : float
            [m], [m/s²], [m].
        """
        polys = [_ccw(np.asarray(p, dtype=float)) for p in polygons]
        n = len(polys)
        sup = np.zeros(n, dtype=bool)
        sup[list(supports)] = True
        mat = (float(friction_deg), float(cohesion), float(tensile))
        return cls(polys, np.arange(n), sup, np.full(n, float(density)),
                   [f"block {i}" for i in range(n)], lambda i, j: mat, thickness, gravity,
                   tol)


def _ccw(v: np.ndarray) -> np.ndarray:
    A, _ = _area_centroid(v)
    return v[::-1].copy() if A < 0 else v


def _area_centroid(v: np.ndarray) -> tuple[float, np.ndarray]:
    x, y = v[:, 0], v[:, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cr = x * y1 - x1 * y
    A = 0.5 * cr.sum()
    if A == 0:
        return 0.0, v.mean(0)
    return float(A), np.array([((x + x1) * cr).sum(), ((y + y1) * cr).sum()]) / (6 * A)


# ---------------------------------------------------------------------- interfaces
def find_interfaces(asm: Assembly) -> Interfaces:
    """The interfaces of ``asm`` (module docstring), found between the polygons of different
    blocks whose bounding boxes touch within ``asm.tol``; none between two supports.

    Parameters
    ----------
    asm : Assembly

    Returns
    -------
    Interfaces
    """
    tol = asm.tol
    polys = asm.polygons
    box = np.array([np.concatenate([v.min(0), v.max(0)]) for v in polys])
    body = asm.body
    sup = asm.support[body]
    # candidate pairs: bounding boxes within tol, different blocks, not two supports
    order = np.argsort(box[:, 0])
    out = {k: [] for k in ("a", "b", "p1", "p2", "n")}
    edges = []
    for v in polys:
        e = np.roll(v, -1, axis=0) - v
        L = np.hypot(e[:, 0], e[:, 1])
        edges.append((v, e / L[:, None], L))
    xs = box[order, 0]
    for ii, i in enumerate(order):
        hi = np.searchsorted(xs, box[i, 2] + tol, side="right")
        cand = order[ii + 1:hi]
        if not len(cand):
            continue
        bj = box[cand]
        ok = ((bj[:, 1] <= box[i, 3] + tol) & (bj[:, 3] >= box[i, 1] - tol)
              & (body[cand] != body[i]) & ~(sup[cand] & sup[i]))
        for j in cand[ok]:
            p, q = (i, j) if i < j else (j, i)
            _edge_pairs(edges[p], edges[q], body[p], body[q], tol, out)
    k = len(out["a"])
    a = np.asarray(out["a"], dtype=int)
    b = np.asarray(out["b"], dtype=int)
    fr = np.empty(k)
    co = np.empty(k)
    te = np.empty(k)
    cache = {}
    for m in range(k):
        key = (a[m], b[m])
        if key not in cache:
            cache[key] = asm.joint(int(a[m]), int(b[m]))
        f, c, t = cache[key]
        fr[m] = math.tan(math.radians(f))
        co[m] = c
        te[m] = t
    shape = (k, 2)
    return Interfaces(a, b, np.asarray(out["p1"], float).reshape(shape),
                      np.asarray(out["p2"], float).reshape(shape),
                      np.asarray(out["n"], float).reshape(shape), fr, co, te)


def _edge_pairs(P, Q, bp, bq, tol, out) -> None:
    """Append the interfaces between the edges of polygons P and Q (each ``(vertices, unit
    tangents, lengths)``)."""
    vp, tp, Lp = P
    vq, tq, Lq = Q
    npo = np.column_stack([tp[:, 1], -tp[:, 0]])  # outward normals of P (counter-clockwise)
    anti = (tp @ tq.T) < -(1.0 - 1e-6)  # opposite edges
    if not anti.any():
        return
    ip, iq = np.nonzero(anti)
    d0 = vq[iq] - vp[ip]
    d1 = vq[(iq + 1) % len(vq)] - vp[ip]
    n = npo[ip]
    t = tp[ip]
    gap0 = (d0 * n).sum(1)
    gap1 = (d1 * n).sum(1)
    s0 = (d0 * t).sum(1)
    s1 = (d1 * t).sum(1)
    lo = np.maximum(np.minimum(s0, s1), 0.0)
    hi = np.minimum(np.maximum(s0, s1), Lp[ip])
    hit = (np.abs(gap0) <= tol) & (np.abs(gap1) <= tol) & (hi - lo > tol)
    for m in np.nonzero(hit)[0]:
        base = vp[ip[m]]
        out["a"].append(bp)
        out["b"].append(bq)
        out["p1"].append(base + lo[m] * t[m])
        out["p2"].append(base + hi[m] * t[m])
        out["n"].append(n[m])


def check(asm: Assembly, itf: Interfaces) -> None:
    """Refuse an assembly that limit analysis cannot take: overlapping blocks (by more than
    ``asm.tol``), no interface at all, no support, or a block without a path of interfaces to
    a support. The message names the block.

    Raises
    ------
    LimitModelError
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    from murus.dem.case import check_overlaps

    nb = asm.nblock
    if not asm.support.any():
        raise LimitModelError("the model has no support: mark a block kinematic = 'fixed' or "
                              "'base'", key=("blocks",), source=asm.source)
    if asm.support.all():
        raise LimitModelError("the model has no free block (all are supports)",
                              key=("blocks",), source=asm.source)
    shapes = [[] for _ in range(nb)]
    for v, b in zip(asm.polygons, asm.body, strict=True):
        shapes[b].append(("poly", v))
    hit = check_overlaps(shapes, asm.tol)
    if hit is not None:
        i, j, depth = hit
        raise asm.error(j, f"overlaps {asm.names[i]} by {depth:.3g} m (> {asm.tol:g} m)")
    if len(itf) == 0:
        free = int(np.nonzero(~asm.support)[0][0])
        raise asm.error(free, "no interface found between the blocks (no two edges of "
                        "different blocks are collinear and overlapping)")
    g = coo_matrix((np.ones(len(itf)), (itf.a, itf.b)), shape=(nb, nb))
    _, lab = connected_components(g, directed=False)
    held = np.zeros(nb, dtype=bool)
    held[np.isin(lab, lab[asm.support])] = True
    loose = np.nonzero(~held)[0]
    if len(loose):
        raise asm.error(int(loose[0]), "the block has no path of interfaces to a support "
                        "(it floats or touches others only at corners)")


# ---------------------------------------------------------------------- case files
def from_case(path) -> Assembly:
    """The assembly of a DEM case file (:mod:`murus.dem.case`): its ``[[blocks]]``
    (rectangles, polygons, clumps of polygons) and ``[[walls]]``, the densities of their
    materials and the joint material of each pair of groups as the DEM assigns it
    (``[[joints]]``, else ``[dem] joint``, else the only material); ``[dem] thickness``,
    ``gravity`` and ``overlap_tolerance`` (the geometric tolerance). The ``[motion]``,
    monitors and run options are ignored.

    Parameters
    ----------
    path : path-like
        The case file.

    Returns
    -------
    Assembly

    Raises
    ------
    murus.config.CaseError
        Bad input, one line naming file, line and key (discs are refused: limit analysis
        takes polygon blocks).
    """
    from murus.dem.case import (
        _convex_parts,
        _material,
        _shape_list,
        default_joint,
        fail_at,
        load_case,
    )

    case, path, text = load_case(path)
    d = case.dem
    default = default_joint(case, path, text)
    pair = {}
    for i, j in enumerate(case.joints):
        if j.material not in case.materials:
            raise fail_at(path, text, ("joints", i, "material"), f"unknown material "
                          f"'{j.material}' (defined: {', '.join(case.materials)})")
        pair[frozenset((j.a, j.b))] = j.material
    polys, body, sup, rho, names, groups, keys = [], [], [], [], [], [], []
    for k, (where, name, parts, kin, mat, grp, _, _) in enumerate(_shape_list(case)):
        mname = _material(case, mat, where, path, text)
        if any(p[0] == "disc" for p in parts):
            raise fail_at(path, text, where, f"{name}: limit analysis takes polygon blocks "
                          "(a disc has no interface)")
        key = "parts" if where[0] == "blocks" and case.blocks[where[1]].kind == "clump" \
            else "vertices"
        for p in _convex_parts(parts, where, key, path, text):
            polys.append(p[1])
            body.append(k)
        sup.append(kin is not None)
        rho.append(case.materials[mname].density)
        names.append(name)
        groups.append(grp or mname)
        keys.append(where)
    known = set(groups)
    for i, j in enumerate(case.joints):
        for key in ("a", "b"):
            if getattr(j, key) not in known:
                raise fail_at(path, text, ("joints", i, key), f"unknown group "
                              f"'{getattr(j, key)}' (groups: {', '.join(sorted(known))})")
    mats = {n: (m.friction_deg, m.cohesion, m.tensile) for n, m in case.materials.items()}

    def joint(i, j):
        return mats[pair.get(frozenset((groups[i], groups[j])), default)]

    asm = Assembly(polys, np.asarray(body), np.asarray(sup), np.asarray(rho), names, joint,
                   d.thickness, d.gravity, max(d.overlap_tolerance, 1e-9), keys, path)
    return asm
