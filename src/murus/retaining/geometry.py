"""Cross-section of a dry-stone retaining wall (DSRW), its bed joints, and the walls of
Savalle et al. (2022).

Savalle et al. (2022): Savalle, Vincens, Hans, Lourenço, "Dynamic numerical simulations of dry-stone
retaining walls: identification of the seismic behaviour factor", Geosciences 12 (2022) 252.
Table 5 (geometry of DSRW1-4 and of the original "C3s" wall of Colas et al. [16]), Table 6
(materials of the full-scale walls), §3.1 and Table 1 (the scaled-down mock-ups of [33]).

Frame and sign conventions (written once, here): plane strain, one metre of wall; ``x``
horizontal, positive into the backfill; ``z`` vertical, upwards; the toe of the wall (front
edge of the base) at the origin. Then

- the front face is ``x = lambda_v z`` (external batter ``lambda_v`` = horizontal over
  vertical, 0.06 for the 6 % of Table 5: the face leans back into the slope);
- the back face is ``x = B - lambda_m z`` (internal batter ``lambda_m``; positive when the wall
  widens downwards on its back, so that the soil rests on the back face: the back makes
  ``psi = pi/2 - atan(lambda_m)`` with the horizontal, measured on the wall side as in EN
  1998-5 Annex E);
- ``B`` is the horizontal width at the level of the toe, ``b = B - H (lambda_v + lambda_m)``
  the width of the horizontal crest at ``z = H``;
- the beds (course joints) are inclined by ``alpha`` (``bed_inclination_deg``) towards the
  backfill: they go down into the slope, ``z = z_f - tan(alpha) (x - x_f)`` from a point
  ``(x_f, z_f)`` of the front face. Successive joints are one stone height apart measured
  perpendicular to the beds (0.1 m in Savalle et al. (2022), §4.1);
- the base is a bed joint through the toe (``base="inclined"``: the wall is founded on a
  surface with the counter-slope of its beds, so that the heel is ``B tan(alpha)`` below the
  toe) or horizontal (``base="horizontal"``). Savalle et al. (2022) does not say which (Figure 9 is
  not in the text); the inclined base is the default, the other is a documented option.

Units: lengths in m, unit weights in N/m³, weights in N per metre of wall, angles ``*_deg``
in degrees (properties in radians).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

from murus.errors import MurusError

__all__ = [
    "GeometryError", "RetainingWall", "BedJoint", "WallPart", "PRESETS", "MOCKUP_SLENDERNESS",
    "preset", "mockup", "polygon_area_centroid", "clip_above",
]


class GeometryError(MurusError, ValueError):
    """Invalid wall geometry or material (one-line message)."""


def polygon_area_centroid(points) -> tuple[float, float, float]:
    """Area [m²] and centroid (x, z) [m] of a simple polygon (shoelace formula).

    The area is positive for counter-clockwise vertices; the absolute value is returned.
    """
    n = len(points)
    if n < 3:
        return 0.0, float("nan"), float("nan")
    a = cx = cz = 0.0
    for i in range(n):
        x0, z0 = points[i]
        x1, z1 = points[(i + 1) % n]
        c = x0 * z1 - x1 * z0
        a += c
        cx += (x0 + x1) * c
        cz += (z0 + z1) * c
    a *= 0.5
    if abs(a) < 1e-300:
        return 0.0, float("nan"), float("nan")
    return abs(a), cx / (6.0 * a), cz / (6.0 * a)


def clip_above(points, p0, normal) -> list[tuple[float, float]]:
    """The part of a polygon on the side ``(p - p0) . normal >= 0`` of a line
    (Sutherland-Hodgman against one half-plane)."""
    def side(p):
        return (p[0] - p0[0]) * normal[0] + (p[1] - p0[1]) * normal[1]

    out: list[tuple[float, float]] = []
    n = len(points)
    for i in range(n):
        a, b = points[i], points[(i + 1) % n]
        sa, sb = side(a), side(b)
        if sa >= 0:
            out.append(a)
        if (sa >= 0) != (sb >= 0):
            t = sa / (sa - sb)
            out.append((a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])))
    # drop repeated vertices
    clean: list[tuple[float, float]] = []
    for p in out:
        if not clean or math.hypot(p[0] - clean[-1][0], p[1] - clean[-1][1]) > 1e-12:
            clean.append(p)
    if len(clean) > 1 and math.hypot(clean[0][0] - clean[-1][0],
                                     clean[0][1] - clean[-1][1]) <= 1e-12:
        clean.pop()
    return clean


@dataclass(frozen=True)
class BedJoint:
    """A bed joint: the straight line where it cuts the wall, front to back.

    ``front`` is on the front face (the edge about which the wall above overturns), ``back``
    where the joint leaves the section (on the back face, or on the base for a horizontal
    base). ``angle`` [rad] is the inclination towards the backfill (the joint goes down into
    the slope). ``index`` 0 is the base.

    Attributes
    ----------
    index : int
        0 for the base.
    front, back : tuple of float
        Ends ``(x, z)`` [m].
    angle : float
        Inclination towards the backfill [rad].
    """

    index: int
    front: tuple[float, float]
    back: tuple[float, float]
    angle: float

    @property
    def height(self) -> float:
        """Height of the front (downhill) edge above the toe [m]."""
        return self.front[1]

    @property
    def normal(self) -> tuple[float, float]:
        """Unit normal pointing up into the part above the joint."""
        return (math.sin(self.angle), math.cos(self.angle))

    @property
    def tangent_out(self) -> tuple[float, float]:
        """Unit tangent pointing out of the slope (towards the front): the sliding direction."""
        return (-math.cos(self.angle), math.sin(self.angle))


@dataclass(frozen=True)
class WallPart:
    """The wall above one bed joint: a rigid block in the limit analysis.

    ``polygon`` vertices (counter-clockwise), ``area`` [m²], ``centroid`` (x, z) [m],
    ``weight`` [N/m]; ``back_bottom`` and ``back_top`` the ends of its back face in contact
    with the backfill, ``back_height`` their vertical distance [m].

    Attributes
    ----------
    joint : BedJoint
    polygon : tuple
        Vertices ``(x, z)`` [m], counter-clockwise.
    area : float
        [m²].
    centroid : tuple of float
        [m].
    weight : float
        [N/m].
    back_bottom, back_top : tuple of float
        Ends of the back face in contact with the backfill [m].
    """

    joint: BedJoint
    polygon: tuple[tuple[float, float], ...]
    area: float
    centroid: tuple[float, float]
    weight: float
    back_bottom: tuple[float, float]
    back_top: tuple[float, float]

    @property
    def back_height(self) -> float:
        """Vertical height of the back face of the part [m] (H of EN 1998-5 (E.1))."""
        return self.back_top[1] - self.back_bottom[1]

    def back_point(self, fraction: float) -> tuple[float, float]:
        """The point of the back face at ``fraction`` of its height above its bottom."""
        (x0, z0), (x1, z1) = self.back_bottom, self.back_top
        return (x0 + fraction * (x1 - x0), z0 + fraction * (z1 - z0))


def _num(name: str, value, lo: float | None = None, lo_open: bool = False,
         hi: float | None = None, hi_open: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise GeometryError(f"{name} must be a number, got {value!r}", key=(name,)) from None
    if not math.isfinite(v):
        raise GeometryError(f"{name} must be finite, got {value!r}", key=(name,))
    if lo is not None and (v < lo or (lo_open and v == lo)):
        raise GeometryError(f"{name} must be {'>' if lo_open else '>='} {lo:g}, got {v:g}",
                            key=(name,))
    if hi is not None and (v > hi or (hi_open and v == hi)):
        raise GeometryError(f"{name} must be {'<' if hi_open else '<='} {hi:g}, got {v:g}",
                            key=(name,))
    return v


@dataclass(frozen=True)
class RetainingWall:
    """A dry-stone retaining wall cross-section with its backfill (module docstring: frame).

    Parameters
    ----------
    height : ``H`` [m], from the toe to the crest.
    base_width : ``B`` [m], horizontal width at the level of the toe.
    top_width : ``b`` [m]; ``None`` computes ``B - H (lambda_v + lambda_m)``, a value that
        differs from it by more than 1 mm is an error.
    external_batter, internal_batter : ``lambda_v``, ``lambda_m`` [-] (0.06 = 6 %).
    bed_inclination_deg : ``alpha`` [deg], beds inclined towards the backfill.
    backfill_slope_deg : ``beta`` [deg], planar backfill rising from the crest.
    stone_height, stone_length : [m] (0.1 and 0.35 in Savalle et al. (2022), §4.1);
        ``stone_height=None`` when the courses are unknown: only the base joint is then checked.
    wall_unit_weight, backfill_unit_weight : [N/m³].
    backfill_friction_deg : ``phi`` of the backfill [deg].
    joint_friction_deg : friction angle of the stone-stone bed joints [deg].
    interface_friction_deg : friction of the wall-backfill interface [deg] (the pseudo-static
        analysis uses it as ``delta`` with ``Assumptions(delta_ratio=None)``; its default is
        ``delta = 2/3 phi``).
    base : ``"inclined"`` (base parallel to the beds, through the toe) or ``"horizontal"``.
    backfill_profile : optional broken backfill surface: points ``(dx, dz)`` [m] relative to
        the top of the back face, ``dx`` increasing; the last segment is extended to infinity.
        ``None``: a plane at ``beta``. Used by the trial-wedge thrust
        (:mod:`murus.retaining.wedge`).
    """

    height: float
    base_width: float
    top_width: float | None = None
    external_batter: float = 0.0
    internal_batter: float = 0.0
    bed_inclination_deg: float = 0.0
    backfill_slope_deg: float = 0.0
    stone_height: float | None = 0.1
    stone_length: float = 0.35
    wall_unit_weight: float = 20.0e3
    backfill_unit_weight: float = 14.9e3
    backfill_friction_deg: float = 37.7
    joint_friction_deg: float = 25.0
    interface_friction_deg: float = 37.7
    base: str = "inclined"
    backfill_profile: tuple[tuple[float, float], ...] | None = None
    name: str = field(default="wall", compare=False)

    #: Declared parameters, units and validity limits (GUIDE §3).
    PARAMS = {
        "height": ("m", "> 0"),
        "base_width": ("m", "> 0"),
        "top_width": ("m", "> 0, = B - H (lambda_v + lambda_m) within 1 mm"),
        "external_batter": ("-", "0 <= lambda_v < 1"),
        "internal_batter": ("-", "-1 < lambda_m < 1"),
        "bed_inclination_deg": ("deg", "0 <= alpha < 45"),
        "backfill_slope_deg": ("deg", "-45 < beta < phi"),
        "stone_height": ("m", "> 0 or None"),
        "stone_length": ("m", "> 0"),
        "wall_unit_weight": ("N/m3", "> 0"),
        "backfill_unit_weight": ("N/m3", ">= 0 (0: no backfill)"),
        "backfill_friction_deg": ("deg", "0 < phi < 60"),
        "joint_friction_deg": ("deg", "0 <= phi_j < 60"),
        "interface_friction_deg": ("deg", "0 <= delta <= phi"),
        "base": ("-", "'inclined' or 'horizontal'"),
    }

    def __post_init__(self) -> None:
        s = object.__setattr__
        s(self, "height", _num("height", self.height, 0.0, True))
        s(self, "base_width", _num("base_width", self.base_width, 0.0, True))
        s(self, "external_batter", _num("external_batter", self.external_batter, 0.0, False,
                                         1.0, True))
        s(self, "internal_batter", _num("internal_batter", self.internal_batter, -1.0, True,
                                         1.0, True))
        s(self, "bed_inclination_deg", _num("bed_inclination_deg", self.bed_inclination_deg,
                                             0.0, False, 45.0, True))
        s(self, "backfill_friction_deg", _num("backfill_friction_deg",
                                               self.backfill_friction_deg, 0.0, True, 60.0, True))
        s(self, "backfill_slope_deg", _num("backfill_slope_deg", self.backfill_slope_deg,
                                            -45.0, True, self.backfill_friction_deg, True))
        if self.stone_height is not None:
            s(self, "stone_height", _num("stone_height", self.stone_height, 0.0, True))
        s(self, "stone_length", _num("stone_length", self.stone_length, 0.0, True))
        s(self, "wall_unit_weight", _num("wall_unit_weight", self.wall_unit_weight, 0.0, True))
        s(self, "backfill_unit_weight", _num("backfill_unit_weight", self.backfill_unit_weight,
                                              0.0))
        s(self, "joint_friction_deg", _num("joint_friction_deg", self.joint_friction_deg, 0.0,
                                            False, 60.0, True))
        s(self, "interface_friction_deg", _num("interface_friction_deg",
                                                self.interface_friction_deg, 0.0, False,
                                                self.backfill_friction_deg))
        if self.base not in ("inclined", "horizontal"):
            raise GeometryError(f"base must be 'inclined' or 'horizontal', got {self.base!r}",
                                key=("base",))
        b_calc = self.base_width - self.height * (self.external_batter + self.internal_batter)
        if self.top_width is None:
            s(self, "top_width", b_calc)
        else:
            s(self, "top_width", _num("top_width", self.top_width, 0.0, True))
            if abs(self.top_width - b_calc) > 1e-3:
                raise GeometryError(
                    f"top_width {self.top_width:g} m is inconsistent with B - H (lambda_v + "
                    f"lambda_m) = {b_calc:.4f} m", key=("top_width",))
        if self.top_width <= 0.0:
            raise GeometryError(f"the batters close the section below the crest (b = "
                                f"{self.top_width:.4f} m)")
        if self.backfill_profile is not None:
            prof = tuple((float(dx), float(dz)) for dx, dz in self.backfill_profile)
            xs = [0.0] + [p[0] for p in prof]
            if any(x1 <= x0 for x0, x1 in zip(xs, xs[1:], strict=False)) or not all(
                    math.isfinite(v) for p in prof for v in p):
                raise GeometryError("backfill_profile must be finite (dx, dz) points with dx "
                                    "strictly increasing from 0", key=("backfill_profile",))
            s(self, "backfill_profile", prof)

    # -- angles -----------------------------------------------------------------------------
    @property
    def alpha(self) -> float:
        """Bed inclination [rad]."""
        return math.radians(self.bed_inclination_deg)

    @property
    def beta(self) -> float:
        """Backfill slope [rad]."""
        return math.radians(self.backfill_slope_deg)

    @property
    def psi(self) -> float:
        """Inclination of the back face to the horizontal, wall side [rad] (EN 1998-5 psi)."""
        return 0.5 * math.pi - math.atan(self.internal_batter)

    @property
    def slenderness(self) -> float:
        """``H / B`` [-]."""
        return self.height / self.base_width

    # -- section ----------------------------------------------------------------------------
    @cached_property
    def polygon(self) -> tuple[tuple[float, float], ...]:
        """Vertices (counter-clockwise): toe, heel, back top, front top [m]."""
        H, B, lv, lm = self.height, self.base_width, self.external_batter, self.internal_batter
        t = math.tan(self.alpha) if self.base == "inclined" else 0.0
        xh = B / (1.0 - lm * t) if t else B
        heel = (xh, -t * xh)
        return ((0.0, 0.0), heel, (B - lm * H, H), (lv * H, H))

    @property
    def heel(self) -> tuple[float, float]:
        return self.polygon[1]

    @property
    def back_top(self) -> tuple[float, float]:
        return self.polygon[2]

    @cached_property
    def _props(self) -> tuple[float, float, float]:
        return polygon_area_centroid(self.polygon)

    @property
    def area(self) -> float:
        """Area of the section [m²]."""
        return self._props[0]

    @property
    def centroid(self) -> tuple[float, float]:
        """Centroid (x, z) of the section [m]."""
        return self._props[1], self._props[2]

    @property
    def weight(self) -> float:
        """Weight of the wall per metre [N/m]."""
        return self.wall_unit_weight * self.area

    # -- joints -----------------------------------------------------------------------------
    def _joint_from_front(self, index: int, zf: float, angle: float) -> BedJoint:
        xf = self.external_batter * zf
        n = (math.sin(angle), math.cos(angle))
        part = clip_above(self.polygon, (xf, zf), n)
        # the back end: the point of the clipped polygon on the joint line farthest from front
        on_line = [p for p in part
                   if abs((p[0] - xf) * n[0] + (p[1] - zf) * n[1]) < 1e-9]
        back = max(on_line, key=lambda p: p[0]) if on_line else (xf, zf)
        return BedJoint(index, (xf, zf), back, angle)

    @cached_property
    def joints(self) -> tuple[BedJoint, ...]:
        """The bed joints, base first (index 0), one stone height apart perpendicular to the
        beds; their front edges are on the front face below the crest."""
        a = self.alpha
        base_angle = a if self.base == "inclined" else 0.0
        out = [self._joint_from_front(0, 0.0, base_angle)]
        if self.stone_height is None:
            return tuple(out)
        t = math.tan(a)
        k = 1
        while True:
            # lines z + t x = c, one stone height apart perpendicular to the beds
            c = k * self.stone_height / math.cos(a)
            zf = c / (1.0 + t * self.external_batter)
            if zf >= self.height - 1e-9:
                break
            out.append(self._joint_from_front(k, zf, a))
            k += 1
        return tuple(out)

    def part_above(self, joint: BedJoint) -> WallPart:
        """The rigid block of wall above ``joint`` (its weight, centroid and back face)."""
        poly = clip_above(self.polygon, joint.front, joint.normal)
        area, cx, cz = polygon_area_centroid(poly)
        if area <= 0.0:
            raise GeometryError(f"joint {joint.index} leaves no wall above it")
        top = self.back_top
        # the back face of the part: from where the joint (or the heel) meets the back face
        heel = self.heel
        jb = joint.back
        on_back = abs(jb[0] - (self.base_width - self.internal_batter * jb[1])) < 1e-9
        bottom = jb if on_back else heel
        if bottom[1] > top[1]:
            bottom = top
        return WallPart(joint, tuple(poly), area, (cx, cz), self.wall_unit_weight * area,
                        bottom, top)

    def with_(self, **changes) -> RetainingWall:
        """A copy with some parameters changed (validated again)."""
        return replace(self, **changes)

    def summary(self) -> dict:
        """Geometry and materials as a JSON-ready dict (SI units, angles in degrees)."""
        return {
            "name": self.name, "H_m": self.height, "B_m": self.base_width,
            "b_m": self.top_width, "external_batter": self.external_batter,
            "internal_batter": self.internal_batter,
            "bed_inclination_deg": self.bed_inclination_deg,
            "backfill_slope_deg": self.backfill_slope_deg, "base": self.base,
            "stone_height_m": self.stone_height, "stone_length_m": self.stone_length,
            "wall_unit_weight_N_m3": self.wall_unit_weight,
            "backfill_unit_weight_N_m3": self.backfill_unit_weight,
            "backfill_friction_deg": self.backfill_friction_deg,
            "joint_friction_deg": self.joint_friction_deg,
            "interface_friction_deg": self.interface_friction_deg,
            "area_m2": self.area, "weight_N_m": self.weight, "n_joints": len(self.joints),
        }


# -- Savalle et al. (2022) walls -------------------------------------------------------------------
#: Savalle et al. (2022), Table 6 (full-scale walls): units 20.0 kN/m³; backfill 14.9 kN/m³, phi =
#: 37.7 deg; friction of the unit-unit interfaces 25.0 deg, of the wall-backfill interface 37.7 deg.
_TABLE6 = dict(wall_unit_weight=20.0e3, backfill_unit_weight=14.9e3, backfill_friction_deg=37.7,
               joint_friction_deg=25.0, interface_friction_deg=37.7, stone_height=0.1,
               stone_length=0.35)

#: Savalle et al. (2022), Table 5: H, B, b [m], internal batter lambda_m, external batter lambda_v
#: [-], bed inclination alpha and backfill slope beta [deg]. "C3s" (Colas et al. [16]) is DSRW2
#: (Figure 9 caption). Stones 0.1 m high and 0.35 m long (§4.1).
_TABLE5 = {
    "C3s": (2.5, 0.7, 0.55, 0.0, 0.06, 9.1, 32.6),
    "DSRW1": (2.5, 0.7, 0.55, 0.0, 0.06, 9.1, 0.0),
    "DSRW2": (2.5, 0.7, 0.55, 0.0, 0.06, 9.1, 32.6),
    "DSRW3": (2.5, 0.7, 0.55, 0.0, 0.06, 3.4, 0.0),
    "DSRW4": (2.5, 0.7, 0.70, 0.0, 0.00, 0.0, 0.0),
}

#: Savalle et al. (2022), §3.1, Table 3: slenderness H/B of the scaled-down mock-ups of [33].
MOCKUP_SLENDERNESS = (1.3, 1.7, 2.3, 2.7, 3.0, 3.3)

#: Savalle et al. (2022), §3.1: "400 mm long, 34 mm wide" [m].
MOCKUP_WIDTH = 0.034

#: Savalle et al. (2022), Table 1 (mock-ups): units 14.4 kN/m³; sand 15.4 kN/m³, phi = 45 deg;
#: friction unit-unit and wall-backfill 32 deg.
_TABLE1 = dict(wall_unit_weight=14.4e3, backfill_unit_weight=15.4e3, backfill_friction_deg=45.0,
               joint_friction_deg=32.0, interface_friction_deg=32.0)


def mockup(slenderness: float, width: float = MOCKUP_WIDTH, **overrides) -> RetainingWall:
    """A scaled-down mock-up of Savalle et al. (2022), §3 (experiments of [33]) with ``H =
    slenderness B``.

    What the paper gives: vertical walls of constant width (34 mm printed) and heights giving
    H/B = 1.3-3.3, H the height free to move above the fixed first course, level sand
    backfill, the materials of Table 1. What it does not give: the brick (course) height and
    length, hence the positions of the bed joints (``stone_height=None``: only the base joint
    above the fixed course is checked, which governs a rectangular wall since the thrust grows
    as h² and the weight as h), and any batter or bed inclination (taken as zero). Note that
    "between 50 mm and 140 mm high" with H/B = 1.3-3.3 implies B = 38-42 mm rather than 34 mm
    (the printed heights may include the fixed course): pass ``width`` to test it.

    Parameters
    ----------
    slenderness : float
        ``H / B`` [-].
    width : float
        ``B`` [m].
    **overrides
        Any parameter of :class:`RetainingWall`.

    Returns
    -------
    RetainingWall

    References
    ----------
    Savalle et al. (2022), §3.1, Tables 1 and 3.
    """
    r = _num("slenderness", slenderness, 0.0, True)
    w = _num("width", width, 0.0, True)
    kw = dict(height=r * w, base_width=w, top_width=w, stone_height=None, stone_length=w,
              name=f"mockup H/B={r:g}", **_TABLE1)
    kw.update(overrides)
    return RetainingWall(**kw)


def preset(name: str, **overrides) -> RetainingWall:
    """Savalle et al. (2022) walls: ``DSRW1``-``DSRW4`` and ``C3s`` (Tables 5 and 6), or
    ``mockup-<H/B>`` for the scaled-down walls of §3 (``mockup-2.7``). ``overrides`` change any
    parameter.

    Parameters
    ----------
    name : str
        ``"DSRW1"`` ... ``"DSRW4"``, ``"C3s"`` or ``"mockup-<H/B>"`` (case-insensitive).
    **overrides
        Any parameter of :class:`RetainingWall`.

    Returns
    -------
    RetainingWall

    References
    ----------
    Savalle et al. (2022), Tables 1, 5 and 6.
    """
    key = str(name).strip()
    up = key.upper()
    if up.startswith("MOCKUP-"):
        try:
            r = float(key.split("-", 1)[1])
        except ValueError:
            raise GeometryError(f"unknown mock-up {name!r}; expected mockup-<H/B>, e.g. "
                                "mockup-2.7") from None
        return mockup(r, **overrides)
    canon = {k.upper(): k for k in _TABLE5}
    if up not in canon:
        raise GeometryError(f"unknown preset {name!r}; expected one of "
                            f"{', '.join(PRESETS)} or mockup-<H/B>")
    H, B, b, lm, lv, a, beta = _TABLE5[canon[up]]
    kw = dict(height=H, base_width=B, top_width=b, internal_batter=lm, external_batter=lv,
              bed_inclination_deg=a, backfill_slope_deg=beta, name=canon[up], **_TABLE6)
    kw.update(overrides)
    return RetainingWall(**kw)


#: Names accepted by :func:`preset` (besides ``mockup-<H/B>``).
PRESETS = tuple(_TABLE5)
