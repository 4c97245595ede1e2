"""Verification cases of the rigid-block limit analysis (closed forms, the minimum thickness of a
semicircular arch, the pseudo-static resistance of a dry-stone retaining wall), shared by
``tests/test_limit.py`` and ``murus verify limit``.

Each case function returns a list of rows ``dict(case, expected, obtained, error, tolerance,
passed)``; ``error`` is relative unless the case name says ``abs``. Non-associative friction
(the default of :func:`murus.limit.analyse`) unless a row says otherwise.

Sources: a block on a base topples at ``lambda = b / h`` and slides at ``tan(phi)``; a stack of
blocks topples about the edge of its governing joint at ``lambda = lever / height`` of the
centroid of the blocks above that joint (statics of the rigid part above it); a semicircular
arch under self-weight stands down to ``t/R = 0.1075`` (Milankovitch 1907, reported by
Ochsendorf 2002 and Makris & Alexakis 2013; Heyman's approximation 0.106); the pseudo-static
resistance ``A_pseudo`` of the dry-stone retaining wall DSRW1 by the Coulomb-wedge joint checks of
:mod:`murus.retaining.pseudostatic` (1.588 m/s², Savalle et al. (2022), Table 8: 1.58); a wall panel
with an opening (two piers and a lintel) under an overburden on the lintel or a live point load at
its level, by the virtual work of its sway mechanism.

No published collapse load factor of a wall with an opening could be checked offline: the rows of
the panel with an opening are closed forms, not a published benchmark (tests/data/limit/README.md).
"""

from __future__ import annotations

import math

import numpy as np

from murus.limit.model import Assembly
from murus.limit.solve import LimitError, PointLoad, analyse

RHO = 2000.0


def _row(case, expected, obtained, tolerance, relative=True):
    err = abs(obtained - expected) / abs(expected) if relative else abs(obtained - expected)
    return {"case": case, "expected": float(expected), "obtained": float(obtained),
            "error": float(err), "tolerance": float(tolerance),
            "passed": bool(np.isfinite(err) and err <= tolerance)}


def _rect(x0, y0, w, h):
    return [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]


# ---------------------------------------------------------------------- builders
def block_on_base(b=0.25, h=1.0, friction_deg=40.0) -> Assembly:
    """A ``b x h`` [m] block on a fixed base whose top is y = 0 (block 1; the base is 0)."""
    return Assembly.from_polygons([_rect(-2.0, -0.2, 4.0, 0.2), _rect(-b / 2, 0.0, b, h)],
                                  supports=[0], density=RHO, friction_deg=friction_deg)


def stack(widths, heights, offsets=None, friction_deg=40.0) -> Assembly:
    """Rectangles stacked on a fixed base (top at y = 0), bottom first, centred on
    ``offsets`` [m] (default 0)."""
    offsets = np.zeros(len(widths)) if offsets is None else offsets
    polys = [_rect(-3.0, -0.2, 6.0, 0.2)]
    y = 0.0
    for w, h, x in zip(widths, heights, offsets, strict=True):
        polys.append(_rect(x - w / 2, y, w, h))
        y += h
    return Assembly.from_polygons(polys, supports=[0], density=RHO, friction_deg=friction_deg)


def stack_toppling(widths, heights, offsets=None, direction=1) -> float:
    """Closed form: the smallest over the joints of ``lever / height`` of the centroid of the
    blocks above the joint (equal density), the lever measured from the edge of the joint on
    the side of the load (statics of the rigid part above one joint)."""
    w = np.asarray(widths, float)
    h = np.asarray(heights, float)
    x = np.zeros(len(w)) if offsets is None else np.asarray(offsets, float)
    yb = np.concatenate([[0.0], np.cumsum(h)[:-1]])
    A = w * h
    best = math.inf
    for j in range(len(w)):
        xb = (A[j:] * x[j:]).sum() / A[j:].sum()
        yc = (A[j:] * (yb[j:] + h[j:] / 2)).sum() / A[j:].sum()
        if j == 0:
            lo, hi = x[0] - w[0] / 2, x[0] + w[0] / 2
        else:
            lo = max(x[j] - w[j] / 2, x[j - 1] - w[j - 1] / 2)
            hi = min(x[j] + w[j] / 2, x[j - 1] + w[j - 1] / 2)
        lever = (hi - xb) if direction > 0 else (xb - lo)
        best = min(best, lever / (yc - yb[j]))
    return best


def arch_polygons(t_over_R, n, R=1.0):
    """Voussoirs of a semicircular arch (centreline radius R [m], thickness t = t_over_R R,
    n radial joints apart by pi / n; chords between the joints' end points) and a fixed
    foundation (first polygon)."""
    t = t_over_R * R
    ri, ro = R - t / 2, R + t / 2
    polys = [_rect(-R - t - 0.5, -0.2, 2 * R + 2 * t + 1.0, 0.2)]
    for i in range(n):
        a0, a1 = math.pi * i / n, math.pi * (i + 1) / n
        c0, s0, c1, s1 = math.cos(a0), math.sin(a0), math.cos(a1), math.sin(a1)
        polys.append([(ro * c0, ro * s0), (ro * c1, ro * s1), (ri * c1, ri * s1),
                      (ri * c0, ri * s0)])
    return polys


def arch_stands(t_over_R, n, friction_deg=60.0) -> float:
    """Horizontal load factor of the arch (negative when it cannot stand under its own weight:
    the LP then has no equilibrium, reported as -1)."""
    asm = Assembly.from_polygons(arch_polygons(t_over_R, n), supports=[0], density=RHO,
                                 friction_deg=friction_deg)
    try:
        return analyse(asm).load_factor
    except LimitError:
        return -1.0


def arch_min_thickness(n, steps=30, lo=0.05, hi=0.2) -> float:
    """Minimum t/R of an n-voussoir semicircular arch by bisection on whether it stands under
    its own weight (horizontal load factor >= 0)."""
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        if arch_stands(mid, n) >= 0.0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def portal_panel(b=0.4, h_block=0.3, courses=5, opening=1.0, lintel_h=0.3,
                 friction_deg=40.0) -> Assembly:
    """A wall panel with an opening: two stack-bonded piers (``courses`` blocks ``b x h_block``
    [m] each) either side of an opening ``opening`` [m] wide, spanned by a lintel block
    ``(2 b + opening) x lintel_h``, on a fixed base."""
    polys = [_rect(-3.0, -0.2, 6.0 + 2 * b + opening, 0.2)]
    for x0 in (0.0, b + opening):
        for c in range(courses):
            polys.append(_rect(x0, c * h_block, b, h_block))
    polys.append(_rect(0.0, courses * h_block, 2 * b + opening, lintel_h))
    return Assembly.from_polygons(polys, supports=[0], density=RHO, friction_deg=friction_deg)


def coursed_wall(pattern, courses_width, unit=0.4, course=0.175, friction_coef=0.65,
                 density=1000.0) -> Assembly:
    """A wall of rectangular units laid in courses on a fixed base (block 0), described course by
    course from the bottom as in the pattern notation of HybriDFEM (Bouckaert et al., public
    repository thlgrs/HybriDFEM-3.1, ``add_wall``): each course is a list of lengths in units of
    ``unit`` [m] laid from x = 0, a negative length a gap (an opening).

    Parameters
    ----------
    pattern : sequence of sequence of float
        Courses, bottom first.
    courses_width : float
        Width of the base in units (the base spans ``0 .. courses_width * unit``, 1 course high).
    unit, course : float
        Unit length and course height [m].
    friction_coef : float
        Friction coefficient mu = tan(phi) of every joint [-].
    density : float
        [kg/m³].

    Returns
    -------
    Assembly
    """
    polys = [_rect(0.0, -course, courses_width * unit, course)]
    for j, line in enumerate(pattern):
        x = 0.0
        for n in line:
            w = abs(float(n)) * unit
            if n > 0:
                polys.append(_rect(x, j * course, w, course))
            x += w
    return Assembly.from_polygons(polys, supports=[0], density=density,
                                  friction_deg=math.degrees(math.atan(friction_coef)))


#: The wall with one window of the Ferris and Tin-Loi (2001) set as HybriDFEM rebuilds it
#: (``Examples/Refactored_Legacy/FTL_Walls/Pushover_FTL_Wall3.py``): 11 courses of 0.4 x 0.175 m
#: units on a 1.6 m base, a window 0.4 m wide through courses 4 to 8 (x = 0.6 .. 1.0 m).
FTL_WALL3_PATTERN = (
    [1, 1, 1, 1], [.5, 1, 1, 1, .5], [1, 1, 1, 1],
    [.5, 1, -1, 1, .5], [1, .5, -1, .5, 1], [.5, 1, -1, 1, .5], [1, .5, -1, .5, 1],
    [.5, 1, -1, 1, .5],
    [1, 1, 1, 1], [.5, 1, 1, 1, .5], [1, 1, 1, 1])


def portal_sway(b, h, W_piers, W_lintel, Q=0.0, P=0.0) -> float:
    """Closed form of the sway mechanism of :func:`portal_panel` (virtual work): both piers
    (width ``b``, height ``h`` [m], total weight ``W_piers`` [N]) rotate by theta about the toes
    of their bases, the lintel (weight ``W_lintel``) translates with their tops by
    ``theta (h, b)``. With a dead vertical load ``Q`` [N] on the lintel and a live horizontal
    load ``P`` [N] at its level, besides the horizontal body force ``lambda W`` on every block:

        lambda (W_piers h / 2 + W_lintel h + P h) = b (W_piers / 2 + W_lintel + Q)

    (each pier's centroid rises by ``theta b / 2`` and moves by ``theta h / 2``; the lintel and
    ``Q`` rise by ``theta b``). For one pier's weight ``W_p = W_piers / 2``:
    ``lambda = (b / h) (W_p + W_lintel + Q) / (W_p + W_lintel + P)``.

    The sway about the base governs the sway about any higher bed joint of the piers: with
    ``h'`` the height above the joint, ``(a h' + c) / (h' (a h' + d))`` (a = W_p / h,
    c = W_lintel + Q, d = W_lintel, P = 0) decreases with ``h'``. Sliding of the lintel needs
    ``lambda >= mu (W_lintel + Q) / (W_lintel + P)``, of the whole panel on its base
    ``lambda >= mu (W + Q) / (W + P)``: above the sway for the parameters of
    :func:`case_opening` (mu = tan 40 deg); that the associative LP, a minimum over all
    mechanisms, returns the sway value confirms that no other mechanism is lower."""
    Wp = 0.5 * W_piers
    return b / h * (Wp + W_lintel + Q) / (Wp + W_lintel + P)


# ---------------------------------------------------------------------- cases
def case_block(quick=False):
    """A 0.25 x 1 m block on a base: toppling lambda = b/h (1e-6), tilt atan(b/h); with 10 deg
    of friction it slides at tan(phi) (non-associative and associative)."""
    rows = []
    r = analyse(block_on_base())
    rows.append(_row("block 0.25 x 1 m topples: lambda = b/h", 0.25, r.load_factor, 1e-6))
    r = analyse(block_on_base(), load="tilt")
    rows.append(_row("block 0.25 x 1 m, tilt: atan(b/h) [deg]", math.degrees(math.atan(0.25)),
                     r.angle_deg, 1e-6))
    r = analyse(block_on_base(), direction=-1)
    rows.append(_row("block 0.25 x 1 m, load along -x: lambda = b/h", 0.25, r.load_factor,
                     1e-6))
    for fr in ("non-associative", "associative"):
        r = analyse(block_on_base(1.0, 0.5, friction_deg=10.0), friction=fr)
        rows.append(_row(f"block 1 x 0.5 m slides, phi = 10 deg ({fr}): lambda = tan(phi)",
                         math.tan(math.radians(10.0)), r.load_factor, 1e-6))
    return rows


def case_stack(quick=False):
    """Stacks: a tapering stack (widths 0.8, 0.5, 0.3 m, heights 0.4, 0.9, 0.3 m) that topples
    about the joint above the bottom block (closed form 0.25 / 0.55 = 0.4545, the other joints
    0.596 and 1.0), and a stack that slides at its base (tan phi)."""
    rows = []
    w, h = [0.8, 0.5, 0.3], [0.4, 0.9, 0.3]
    exp = stack_toppling(w, h)
    r = analyse(stack(w, h))
    rows.append(_row("tapering stack of 3 topples: lever / height of the part above", exp,
                     r.load_factor, 1e-6))
    w, h = [1.0, 1.0, 1.0], [0.2, 0.2, 0.2]
    r = analyse(stack(w, h, friction_deg=20.0))
    rows.append(_row("stack of 3 (1 x 0.2 m) slides at phi = 20 deg: lambda = tan(phi)",
                     math.tan(math.radians(20.0)), r.load_factor, 1e-6))
    return rows


def case_leaning(quick=False):
    """A leaning stack (each block shifted by 0.05 m to the right): toppling either way, closed
    form by statics of the part above the governing joint."""
    rows = []
    w, h, x = [0.4] * 4, [0.3] * 4, [0.0, 0.05, 0.10, 0.15]
    for d, name in ((1, "+x"), (-1, "-x")):
        exp = stack_toppling(w, h, x, direction=d)
        r = analyse(stack(w, h, x), direction=d)
        rows.append(_row(f"leaning stack of 4, load along {name}: statics", exp,
                         r.load_factor, 1e-6))
    return rows


#: Milankovitch's minimum thickness of a semicircular arch under self-weight [-].
T_MILANKOVITCH = 0.1075


def case_arch(quick=False):
    """Minimum thickness of a semicircular arch of n voussoirs (radial joints, friction 60 deg)
    by bisection on whether it stands under its own weight (horizontal load factor >= 0).
    Discrete hinges can form only at the joints, so the n-voussoir value lies at or below the
    continuous 0.1075 and tends to it as n grows (measured: n = 20 gives 0.10735, -0.14 %;
    n = 40 gives 0.10743, -0.07 %): tolerances 1 % (n = 20) and 0.5 % (n = 40), and a row
    checking that the gap shrinks from n = 20 to n = 40. No published table of discrete
    voussoir values was found; the convergence to 0.1075 is the check."""
    steps = 18 if quick else 30
    t40 = arch_min_thickness(40, steps)
    t20 = arch_min_thickness(20, steps)
    rows = [_row("semicircular arch, 40 voussoirs: t_min/R vs 0.1075 (continuous)",
                 T_MILANKOVITCH, t40, 0.005),
            _row("semicircular arch, 20 voussoirs: t_min/R vs 0.1075 (continuous)",
                 T_MILANKOVITCH, t20, 0.01)]
    conv = abs(T_MILANKOVITCH - t40) <= abs(T_MILANKOVITCH - t20) + 1e-4
    rows.append({"case": "arch: |0.1075 - t_min(40)| <= |0.1075 - t_min(20)| (abs)",
                 "expected": abs(T_MILANKOVITCH - t20), "obtained": abs(T_MILANKOVITCH - t40),
                 "error": 0.0 if conv else abs(T_MILANKOVITCH - t40),
                 "tolerance": 1e-4, "passed": bool(conv)})
    return rows


def case_panel(quick=False):
    """A wall panel with an opening (two stack-bonded piers 0.4 x 1.5 m and a lintel over a
    1 m opening): the sway mechanism (piers rotating about their base corners, the lintel
    translating with their tops) gives lambda = b / h_pier whatever the lintel (virtual work:
    every block rises by b/h of its horizontal displacement). No published wall benchmark
    with its full geometry was found (Ferris & Tin-Loi 2001 and Gilbert et al. 2006 print
    their walls in figures only), so this closed-form panel stands in."""
    r = analyse(portal_panel())
    return [_row("panel with an opening (piers 0.4 x 1.5 m, lintel): lambda = b/h", 0.4 / 1.5,
                 r.load_factor, 1e-6)]


def case_retaining(quick=False):
    """DSRW1 (Savalle et al. 2022): the Coulomb-wedge pseudo-static resistance A_pseudo of
    :mod:`murus.retaining` (1.588 m/s²) against the limit analysis of the same wall cut into
    its courses (monolithic slices between the bed joints, as "perfect stones" of the
    pseudo-static check), the Mononobe-Okabe thrust of the same ``kh`` applied on each slice's
    back face as a dead load, and ``A = kh g`` where the load factor equals ``kh``
    (:func:`murus.limit.retaining.retaining_limit`). Both give 1.5884 m/s² (relative
    difference about 1e-10): the governing mechanism is the same, the whole wall overturning
    about its toe, and the two share the thrust model. The 1 % tolerance allows for the
    bisection and for a multi-joint mechanism, which only the limit analysis sees, governing
    another wall."""
    from murus.limit.retaining import retaining_limit
    from murus.retaining.collapse import pseudo_static_resistance
    from murus.retaining.geometry import preset

    wall = preset("DSRW1")
    ref = pseudo_static_resistance(wall)
    la = retaining_limit(wall).A
    rows = [_row("DSRW1 A_pseudo [m/s2]: Coulomb wedge (murus.retaining) vs published 1.588",
                 1.588, ref, 0.005),
            _row("DSRW1 A [m/s2]: limit analysis of the courses vs Coulomb wedge", ref, la,
                 0.01)]
    return rows


def case_opening(quick=False):
    """The panel with an opening of :func:`portal_panel` (piers 0.4 x 1.5 m of five 0.3 m
    courses, a 1 m opening, a 1.8 x 0.3 m lintel, friction 40 deg) loaded besides its weight:
    a dead vertical load on the lintel of once and three times the lintel's weight (an
    overburden raises the factor to 0.3930 and 0.6456) and a live horizontal point load at the
    lintel's level equal to its weight (0.1810), both senses, non-associative and associative
    friction (the sway mechanism does not slide: the two agree). Closed form
    :func:`portal_sway`; HiGHS solves the LP to about 1e-15, tolerance 1e-6.

    Not a published benchmark: no published collapse load factor of a wall with an opening,
    with its geometry, could be read offline (tests/data/limit/README.md)."""
    b, hb, nc, op, lh = 0.4, 0.3, 5, 1.0, 0.3
    asm = portal_panel(b, hb, nc, op, lh)
    g = asm.gravity
    lint = asm.nblock - 1
    W_l = asm.mass[lint] * g
    W_p = asm.mass[1:lint].sum() * g
    h = hb * nc
    xc = b + 0.5 * op
    rows = []
    for q in (1.0, 3.0):
        exp = portal_sway(b, h, W_p, W_l, Q=q * W_l)
        load = [PointLoad(lint, (0.0, -q * W_l), (xc, h + lh))]
        for fr in ("non-associative", "associative"):
            for d in (1, -1):
                r = analyse(asm, friction=fr, direction=d, point_loads=load)
                rows.append(_row(f"opening, lintel load {q:g} W_lintel, {fr}, dir {d:+d}: "
                                 "sway (b/h)(W_p+W_l+Q)/(W_p+W_l)", exp, r.load_factor, 1e-6))
    exp = portal_sway(b, h, W_p, W_l, P=W_l)
    for d in (1, -1):
        r = analyse(asm, direction=d,
                    point_loads=[PointLoad(lint, (d * W_l, 0.0), (xc, h + lh / 2), live=True)])
        rows.append(_row(f"opening, live point load W_lintel at the lintel, dir {d:+d}: "
                         "sway (b/h)(W_p+W_l)/(W_p+W_l+P)", exp, r.load_factor, 1e-6))
    return rows


CASES = {
    "block": case_block,
    "stack": case_stack,
    "leaning": case_leaning,
    "arch": case_arch,
    "panel": case_panel,
    "opening": case_opening,
    "retaining": case_retaining,
}


def run_verification(quick: bool = False) -> list[dict]:
    """Every row of every case.

    Parameters
    ----------
    quick : bool
        Fewer bisection steps for the arch (same tolerances).

    Returns
    -------
    list of dict
        Rows ``{case, expected, obtained, error, tolerance, passed}``.
    """
    rows = []
    for fn in CASES.values():
        rows += fn(quick)
    return rows


__all__ = ["CASES", "run_verification", "block_on_base", "stack", "stack_toppling",
           "arch_polygons", "arch_min_thickness", "portal_panel", "portal_sway", "coursed_wall",
           "FTL_WALL3_PATTERN", "PointLoad"]
