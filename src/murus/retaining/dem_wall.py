"""Distinct-element model of a dry-stone retaining wall cross-section, with the backfill replaced
by an equivalent earth thrust (Savalle et al. (2022), §4, Tables 5-6; issue 6 items 1 and 2b).

Savalle et al. (2022) models the wall block by block in UDEC with a continuum
backfill. Here the wall is built block by block in :mod:`murus.dem` and the backfill is
replaced by the EN 1998-5 Annex E (Mononobe-Okabe) active thrust on the back face, updated with
the instantaneous base acceleration: the "equivalent thrust" model.

Wall (:func:`build_wall`). The frame of :mod:`murus.retaining.geometry` (x into the backfill,
the model's y = z upwards, toe at the origin). The courses are the bands between successive bed
joints of :attr:`RetainingWall.joints` (inclined by ``alpha``, one stone height apart measured
perpendicular to the beds, 0.1 m in Savalle et al. (2022), §4.1); the top course is the band between
the last joint and the horizontal crest. Each course is cut into stones of length ``L`` (0.35 m,
Savalle et al. (2022), §4.1) by head joints perpendicular to the beds, in running bond: the cuts of
odd courses are offset by ``L/2`` from the front face, so that odd courses start with a half stone
at the front; the end pieces at the faces are whatever fits the batters, and an end piece
shorter than ``min_piece L`` is merged with its neighbour (no slivers). ``bond_phase = 1``
shifts the even courses instead (the other stretcher section of the same wall), and the
courses listed in ``headers`` are single through-stones from face to face (Savalle et al. (2022),
§3.2, Figure 3: the cross-sections of one wall differ by the position of their headers). Every
stone is the course polygon clipped by two half-planes: a convex polygon, and the stones tile
the section exactly (their total weight is :attr:`RetainingWall.weight`). The wall stands on a
kinematic foundation slab (``kinematic="base"``, moved by the base motion) below the base
joint, whose top face is the base joint line extended in front of the toe and behind the heel;
the base joint is then a stone-foundation joint with the stone-stone properties.

Materials: Savalle et al. (2022), Table 6 (full-scale walls): units 20.0 kN/m³ (density ``20e3 / g``
kg/m³, taken from ``wall.wall_unit_weight``), unit-unit interface kn = ks = 2.8e12 Pa/m and
friction 25.0 deg (from ``wall.joint_friction_deg``); Table 1 for the mock-ups (2.6e12 Pa/m,
32 deg). ``stiffness_scale`` scales kn and ks (the time step grows as its inverse square
root; the "perfect stones" of the paper make the walls nearly rigid, so a softer joint changes the
collapse acceleration little while making the run cheaper: used by the tests and stated in the
results).

Equivalent thrust (:class:`EquivalentThrust`). With ``a_x(t)``, ``a_y(t)`` the base
acceleration [m/s²] (x into the backfill, y upwards), the seismic coefficients are
``kh = a_x / g`` (the inertia ``-m a_x`` of the wall and of the soil wedge acts out of the
slope when ``a_x > 0``) and ``kv = -a_y / g`` (positive upwards, the effective weight is
``(1 - kv) W``: the convention of :mod:`murus.retaining.pseudostatic`). The thrust on the back
face of vertical height ``h`` (from the heel to the crest) is that of
:func:`murus.retaining.pseudostatic.earth_thrust`: static ``E_s = 1/2 gamma K_A h²`` and
dynamic increment ``dE = 1/2 gamma (1 - kv) K h² - E_s`` (EN 1998-5 (E.1)-(E.3), theta of
(E.6)), with the wall friction ``delta`` and the points of application of the same
:class:`~murus.retaining.pseudostatic.Assumptions` as the pseudo-static resistance ``A_pseudo``
(default: ``delta = 2/3 phi``, both parts at ``h/3``). Each part is distributed over the back
face as a linear pressure (per unit vertical height) whose resultant acts at the assumed height:
a triangle (zero at the crest) for ``1/3``, uniform for ``1/2`` (``q(s) = (4 - 6 f) + (12 f -
6) s`` for a resultant at fraction ``f``, ``s`` the height fraction above the heel). The
pressure on each back-face stone is integrated over its back edge and applied at the centroid
of that pressure, inclined by ``delta`` to the normal of the back face (downwards on the wall:
``(-sin(psi - delta), -cos(psi - delta))``). Choices where the standard is silent: for
``kh < 0`` (inertia into the slope) the active thrust is taken at ``kh = 0`` (EN 1998-5 (E.6)
needs ``theta >= 0``; the soil does not pull the wall), with ``kv`` kept; ``kh`` is capped
just below the value at which (E.2) breaks (``psi - theta - delta = 0``). The force keeps its
direction and the application points move with the stones (the backfill follows the wall,
Savalle et al. (2022), Figure 11); it is sampled every ``update_dt`` seconds (default 1 ms) through
the engine's external-force hook (``Model.bext``).

Units: SI (m, kg, s, N, rad; ``*_deg`` in degrees).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from murus import G
from murus.errors import MurusError
from murus.retaining.geometry import RetainingWall, clip_above, polygon_area_centroid

__all__ = ["DemWallError", "DemWall", "BackSegment", "build_wall", "stones_of_wall",
           "EquivalentThrust", "pressure_weights", "TABLE6_JOINT", "TABLE1_JOINT"]

#: Savalle et al. (2022), Table 6, unit-unit interface of the full-scale walls: kn = ks = 2.8e12
#: Pa/m (the friction angle, 25.0 deg, is the wall's ``joint_friction_deg``).
TABLE6_JOINT = {"kn": 2.8e12, "ks": 2.8e12}
#: Savalle et al. (2022), Table 1, unit-unit interface of the mock-ups: kn = ks = 2.6e12 Pa/m (32
#: deg).
TABLE1_JOINT = {"kn": 2.6e12, "ks": 2.6e12}


class DemWallError(MurusError, ValueError):
    """Invalid input to the DEM wall builder (one-line message)."""


@dataclass(frozen=True)
class BackSegment:
    """The part of the back face carried by one stone: body index, end points in the body
    frame relative to the centroid at angle 0 (``p0`` lower, ``p1`` upper) [m], and their
    height fractions ``s0 < s1`` on the back face (0 at the heel, 1 at the crest)."""

    body: int
    p0: tuple[float, float]
    p1: tuple[float, float]
    s0: float
    s1: float


@dataclass
class DemWall:
    """A built wall: the :class:`murus.dem.Model`, the wall, the stones.

    ``stones`` body indices (course by course, front to back), ``courses`` the same grouped by
    course (bottom first), ``polygons`` the initial stone polygons, ``foundation`` the
    kinematic base body, ``top`` the stone whose horizontal displacement relative to the base
    is d_top (the front stone of the top course), ``back`` the back-face segments,
    ``back_height`` the vertical height of the back face [m], ``joint`` the stone joint used.

    Attributes
    ----------
    model : murus.dem.Model
    wall : RetainingWall
    stones : list of int
    courses : list of list of int
    polygons : list of numpy.ndarray
        [m].
    foundation, top : int
    back : list
    back_height : float
        [m].
    joint : murus.dem.Joint
    options : dict
    """

    model: object
    wall: RetainingWall
    stones: list[int]
    courses: list[list[int]]
    polygons: list[np.ndarray]
    foundation: int
    top: int
    back: list[BackSegment]
    back_height: float
    joint: object
    options: dict = field(default_factory=dict)

    @property
    def stone_weight(self) -> float:
        """Total weight of the stones [N per metre of wall]."""
        m = self.model
        m.build()
        return float(np.sum(m.bmass[self.stones]) * m.gravity / m.thickness)

    def d_top(self) -> float:
        """Horizontal displacement of the top stone relative to the base [m], positive out of
        the slope (towards the front face, ``-x``): the collapse indicator of Savalle et al. (2022),
        §4.2."""
        m = self.model
        return -float((m.bpos[self.top, 0] - m.bref[self.top, 0])
                      - (m.bpos[self.foundation, 0] - m.bref[self.foundation, 0]))


def _band(section, lower, upper):
    poly = clip_above(section, lower.front, lower.normal)
    if upper is not None:
        n = upper.normal
        poly = clip_above(poly, upper.front, (-n[0], -n[1]))
    return poly


def stones_of_wall(wall: RetainingWall, stone_length: float | None = None,
                   min_piece: float = 0.4, headers: Sequence[int] = (),
                   bond_phase: int = 0) -> list[list[list[tuple[float, float]]]]:
    """The stone polygons of ``wall`` (module docstring), course by course (bottom first), each
    course front to back; vertices counter-clockwise [m].

    headers : indices of the courses (0: the lowest course, on the base joint) laid as one
        through-stone (a header, from the front face to the back face of the section); seed
        001 §3.2 and Figure 3: the position of the headers in the height differs from one
        cross-section of a wall to the next and changes its response.
    bond_phase : 0 (default) or 1: which courses start with a half stone at the front, the odd
        (0) or the even ones (1): the two stretcher cross-sections of a running bond.
    """
    if bond_phase not in (0, 1):
        raise DemWallError(f"bond_phase must be 0 or 1, got {bond_phase!r}")
    if wall.stone_height is None:
        raise DemWallError(f"{wall.name}: the courses are unknown (stone_height=None): give "
                           "stone_height", key=("stone_height",))
    L = wall.stone_length if stone_length is None else float(stone_length)
    if not (L > 0 and math.isfinite(L)):
        raise DemWallError(f"stone_length must be positive [m], got {stone_length!r}")
    if not 0.0 <= min_piece < 1.0:
        raise DemWallError(f"min_piece must be in [0, 1), got {min_piece!r}")
    section = list(wall.polygon)
    joints = wall.joints
    heads = set()
    for h in headers:
        if isinstance(h, bool) or not isinstance(h, int | np.integer) or not \
                0 <= h < len(joints):
            raise DemWallError(f"headers: course {h!r} is not a course index of {wall.name} "
                               f"(0 to {len(joints) - 1}, the lowest first)")
        heads.add(int(h))
    out = []
    for k, jt in enumerate(joints):
        upper = joints[k + 1] if k + 1 < len(joints) else None
        band = _band(section, jt, upper)
        a, _, _ = polygon_area_centroid(band)
        if a <= 1e-12:
            continue
        t = (math.cos(jt.angle), -math.sin(jt.angle))  # along the bed, into the slope
        s_of = [(p[0] - jt.front[0]) * t[0] + (p[1] - jt.front[1]) * t[1] for p in band]
        smin, smax = min(s_of), max(s_of)
        offset = 0.5 * L if (k + bond_phase) % 2 == 1 else 0.0
        cuts = []
        c = offset if offset > 0 else L
        while c < smax - 1e-9 and k not in heads:
            if c > smin + 1e-9:
                cuts.append(c)
            c += L
        # merge short end pieces with their neighbours
        while cuts and cuts[0] - smin < min_piece * L:
            cuts.pop(0)
        while cuts and smax - cuts[-1] < min_piece * L:
            cuts.pop()
        edges = [smin - 1.0, *cuts, smax + 1.0]
        course = []
        for s0, s1 in zip(edges[:-1], edges[1:], strict=True):
            p0 = (jt.front[0] + s0 * t[0], jt.front[1] + s0 * t[1])
            p1 = (jt.front[0] + s1 * t[0], jt.front[1] + s1 * t[1])
            piece = clip_above(band, p0, t)
            piece = clip_above(piece, p1, (-t[0], -t[1]))
            if polygon_area_centroid(piece)[0] > 1e-12:
                course.append(piece)
        out.append(course)
    return out


def build_wall(wall: RetainingWall, *, stone_length: float | None = None,
               min_piece: float = 0.4, kn: float | None = None, ks: float | None = None,
               stiffness_scale: float = 1.0, foundation_depth: float | None = None,
               foundation_front: float | None = None, safety: float = 0.2,
               rounding: float | None = None, top: str = "front",
               backstop: bool = True, backstop_joint: dict | None = None,
               add_bodies: Callable | None = None, headers: Sequence[int] = (),
               bond_phase: int = 0) -> DemWall:
    """The DEM model of the cross-section of ``wall`` (module docstring), one metre thick.

    Parameters
    ----------
    kn, ks : stone-stone joint stiffness [Pa/m] (default: Savalle et al. (2022), Table 6, 2.8e12, or
        Table 1 for a mock-up, 2.6e12), both multiplied by ``stiffness_scale``;
    foundation_depth : thickness of the kinematic foundation slab [m] (default one stone
        height); foundation_front : its extension in front of the toe [m] (default H / 2, where
        the falling stones land);
    headers, bond_phase : the bond pattern (:func:`stones_of_wall`);
    safety, rounding : passed to :class:`murus.dem.Model`;
    top : the d_top stone in the top course, ``"front"`` (default) or ``"back"``;
    backstop : a kinematic plate moving with the base along the back face, from the heel to
        above the crest (the backfill cannot be entered: without it the stones slide down the
        inclined beds into the slope during the half cycles whose inertia points into the
        slope, Savalle et al. (2022) has a continuum backfill there); its joint is the wall-backfill
        interface of Savalle et al. (2022), Table 6 (kn = ks = 2.9e10 Pa/m times
        ``stiffness_scale``, friction ``wall.interface_friction_deg``) unless ``backstop_joint``
        (Joint keyword arguments) is given. It only pushes: the active thrust stays the applied
        force.
    add_bodies : ``add_bodies(model)`` called after the stones and before the model is built,
        to add more bodies and joints (the discrete backfill of
        :mod:`murus.retaining.backfill`); the stones keep their body indices.
    """
    from murus.dem import Joint, Model

    if not (stiffness_scale > 0 and math.isfinite(stiffness_scale)):
        raise DemWallError(f"stiffness_scale must be positive, got {stiffness_scale!r}")
    if top not in ("front", "back"):
        raise DemWallError(f"top must be 'front' or 'back', got {top!r}")
    mock = wall.name.lower().startswith("mockup")
    base_k = TABLE1_JOINT if mock else TABLE6_JOINT
    kn = (base_k["kn"] if kn is None else float(kn)) * stiffness_scale
    ks = (base_k["ks"] if ks is None else float(ks)) * stiffness_scale
    joint = Joint(kn=kn, ks=ks, friction_deg=wall.joint_friction_deg)
    courses_poly = stones_of_wall(wall, stone_length, min_piece, headers, bond_phase)
    density = wall.wall_unit_weight / G
    m = Model(thickness=1.0, gravity=G, joint=joint, rounding=rounding, safety=safety)
    # foundation slab under the base joint
    j0 = wall.joints[0]
    t = (math.cos(j0.angle), -math.sin(j0.angle))
    n = j0.normal
    depth = wall.stone_height if foundation_depth is None else float(foundation_depth)
    front = 0.5 * wall.height if foundation_front is None else float(foundation_front)
    if not (depth > 0 and front >= 0):
        raise DemWallError("foundation_depth must be > 0 and foundation_front >= 0 [m]")
    heel_s = (wall.heel[0] - j0.front[0]) * t[0] + (wall.heel[1] - j0.front[1]) * t[1]
    s_a, s_b = -front, heel_s + max(0.5 * wall.base_width, 0.1)
    pa = (j0.front[0] + s_a * t[0], j0.front[1] + s_a * t[1])
    pb = (j0.front[0] + s_b * t[0], j0.front[1] + s_b * t[1])
    slab = [(pa[0] - depth * n[0], pa[1] - depth * n[1]),
            (pb[0] - depth * n[0], pb[1] - depth * n[1]), pb, pa]
    foundation = m.add_polygon(slab, density=density, kinematic="base", group="foundation")
    m.set_joint(joint, "foundation", "stones")
    stones, courses, polys = [], [], []
    for course in courses_poly:
        ids = []
        for p in course:
            b = m.add_polygon(p, density=density, group="stones")
            ids.append(b)
            polys.append(np.asarray(p, float))
        stones += ids
        courses.append(ids)
    m.set_joint(joint, "stones", "stones")
    plate = None
    if backstop:
        bk = dict(kn=2.9e10 * stiffness_scale, ks=2.9e10 * stiffness_scale,
                  friction_deg=wall.interface_friction_deg)
        bk.update(backstop_joint or {})
        part0 = wall.part_above(j0)
        (x0, z0), (x1, z1) = part0.back_bottom, part0.back_top
        ext = 0.25 * wall.height
        lam = (z1 - z0) and (x1 - x0) / (z1 - z0)
        xt, zt = x1 + lam * ext, z1 + ext
        wpl = max(0.2 * wall.base_width, 0.01)
        plate = m.add_polygon([(x0, z0), (x0 + wpl, z0), (xt + wpl, zt), (xt, zt)],
                              density=density, kinematic="base", group="backfill")
        m.set_joint(Joint(**bk), "backfill", "stones")
    if add_bodies is not None:
        add_bodies(m)
    m.build()
    # back face: x = B - lambda_m z from the heel to the crest
    part = wall.part_above(j0)
    bot, tp = part.back_bottom, part.back_top
    hb = tp[1] - bot[1]

    def on_back(p):
        return abs(p[0] - (wall.base_width - wall.internal_batter * p[1])) < 1e-7

    back = []
    for b, p in zip(stones, polys, strict=True):
        on = [tuple(q) for q in p if on_back(q)]
        if len(on) < 2:
            continue
        lo = min(on, key=lambda q: q[1])
        hi = max(on, key=lambda q: q[1])
        if hi[1] - lo[1] <= 1e-9:
            continue
        c = m.bpos[b]
        back.append(BackSegment(b, (lo[0] - c[0], lo[1] - c[1]), (hi[0] - c[0], hi[1] - c[1]),
                                (lo[1] - bot[1]) / hb, (hi[1] - bot[1]) / hb))
    top_course = courses[-1]
    top_b = top_course[0] if top == "front" else top_course[-1]
    opts = dict(stone_length=wall.stone_length if stone_length is None else stone_length,
                min_piece=min_piece, kn=kn, ks=ks, stiffness_scale=stiffness_scale,
                backstop=plate is not None,
                foundation_depth=depth, foundation_front=front, safety=safety)
    return DemWall(m, wall, stones, courses, polys, foundation, top_b, back, hb, joint, opts)


def pressure_weights(s0, s1, f: float):
    """Share of a resultant and the height fraction of its point of application carried by the
    back-face segment ``[s0, s1]`` (height fractions above the heel) for the linear pressure
    ``q(s) = (4 - 6 f) + (12 f - 6) s`` (unit integral over [0, 1], resultant at ``f``)."""
    s0 = np.asarray(s0, float)
    s1 = np.asarray(s1, float)
    c0, c1 = 4.0 - 6.0 * f, 12.0 * f - 6.0
    w = c0 * (s1 - s0) + 0.5 * c1 * (s1**2 - s0**2)
    mom = 0.5 * c0 * (s1**2 - s0**2) + c1 * (s1**3 - s0**3) / 3.0
    with np.errstate(divide="ignore", invalid="ignore"):
        sp = np.where(np.abs(w) > 1e-300, mom / w, 0.5 * (s0 + s1))
    return w, sp


class EquivalentThrust:
    """The equivalent earth thrust on the back-face stones (module docstring), as the
    ``external`` callback of :func:`murus.dem.engine.run`.

    ``acc(t) -> (a_x, a_y)`` the base acceleration [m/s²] at model time ``t`` [s] (vectorised
    or scalar); ``assumptions`` those of the pseudo-static resistance (default
    :class:`~murus.retaining.pseudostatic.Assumptions`); ``scale`` multiplies the thrust (0:
    no backfill). ``last`` keeps the latest ``(t, kh, kv, E_s, dE)``.

    Parameters
    ----------
    dw : DemWall
        The wall.
    acc : callable, optional
        ``acc(t) -> (a_x, a_y)`` [m/s²].
    assumptions : Assumptions, optional
        Those of the pseudo-static resistance.
    scale : float
        Factor on the thrust [-].

    References
    ----------
    EN 1998-5 Annex E; Savalle et al. (2022), §4.
    """

    def __init__(self, dw: DemWall, acc: Callable | None = None, assumptions=None,
                 scale: float = 1.0) -> None:
        from murus.retaining.pseudostatic import Assumptions

        self.dw = dw
        self.acc = acc
        self.asm = assumptions or Assumptions()
        self.scale = float(scale)
        wall = dw.wall
        self.delta = self.asm.delta(wall)
        psi = wall.psi
        self.u = (-math.sin(psi - self.delta), -math.cos(psi - self.delta))
        self.kh_cap = math.tan(max(psi - self.delta - 1e-3, 0.0))
        segs = dw.back
        self.bodies = np.array([s.body for s in segs], np.int64)
        s0 = np.array([s.s0 for s in segs])
        s1 = np.array([s.s1 for s in segs])
        self.ws, self.ss = pressure_weights(s0, s1, self.asm.static_point)
        self.wd, self.sd = pressure_weights(s0, s1, self.asm.dynamic_point)
        self.p0 = np.array([s.p0 for s in segs]).reshape(-1, 2)
        self.p1 = np.array([s.p1 for s in segs]).reshape(-1, 2)
        self.last = (math.nan, 0.0, 0.0, 0.0, 0.0)

    def coefficients(self, t: float) -> tuple[float, float]:
        """``(kh, kv)`` at time ``t`` from the base acceleration (module docstring)."""
        if self.acc is None:
            return 0.0, 0.0
        a = self.acc(t)
        ax, ay = (float(a[0]), float(a[1])) if isinstance(a, tuple | list | np.ndarray) and \
            np.ndim(a) == 1 else (float(a), 0.0)
        return ax / G, -ay / G

    def thrust(self, kh: float, kv: float) -> tuple[float, float]:
        """``(E_s, dE)`` [N/m] for the coefficients (``kh < 0`` taken as 0, capped)."""
        from murus.retaining.pseudostatic import earth_thrust

        if self.scale == 0.0:
            return 0.0, 0.0
        khc = min(max(kh, 0.0), self.kh_cap * (1.0 - kv))
        Es, dE = earth_thrust(self.dw.wall, self.dw.back_height, khc, kv, self.delta,
                              self.asm.thrust, self.asm.seismic_angle)
        return self.scale * Es, self.scale * dE

    def forces(self, Es: float, dE: float, model) -> np.ndarray:
        """Force (Fx, Fy) [N] and moment [N m] on each back-face stone (rows of ``bodies``)."""
        th = model.thickness
        b = self.bodies
        ang = model.bang[b]
        c, s = np.cos(ang), np.sin(ang)
        out = np.zeros((b.size, 3))
        for E, w, sp in ((Es, self.ws, self.ss), (dE, self.wd, self.sd)):
            if E == 0.0:
                continue
            F = E * th * w
            # point at fraction sp of the back face, on the stone's segment [s0, s1]
            seg = self.dw.back
            s0 = np.array([q.s0 for q in seg])
            s1 = np.array([q.s1 for q in seg])
            lam = np.where(s1 > s0, (sp - s0) / (s1 - s0), 0.5)[:, None]
            r = self.p0 + lam * (self.p1 - self.p0)
            rx = c * r[:, 0] - s * r[:, 1]
            ry = s * r[:, 0] + c * r[:, 1]
            fx = F * self.u[0]
            fy = F * self.u[1]
            out[:, 0] += fx
            out[:, 1] += fy
            out[:, 2] += rx * fy - ry * fx
        return out

    def __call__(self, model) -> None:
        t = model.time
        kh, kv = self.coefficients(t)
        Es, dE = self.thrust(kh, kv)
        self.last = (t, kh, kv, Es, dE)
        model.bext[:, :] = 0.0
        if self.bodies.size:
            model.bext[self.bodies] = self.forces(Es, dE, model)

    def resultant(self, model) -> tuple[float, float, float]:
        """Sum of the applied forces (Fx, Fy) [N] and their moment about the origin [N m]
        (checks)."""
        f = model.bext[self.bodies]
        pos = model.bpos[self.bodies]
        M = float(np.sum(f[:, 2] + pos[:, 0] * f[:, 1] - pos[:, 1] * f[:, 0]))
        return float(f[:, 0].sum()), float(f[:, 1].sum()), M
