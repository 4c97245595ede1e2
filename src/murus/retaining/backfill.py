"""Fully discrete granular backfill behind the DEM retaining wall (issue 6 item 2a; Savalle et al.
(2022), §2, §4.1, Figures 9-10).

Savalle et al. (2022) models the backfill of a dry-stone retaining wall as a
Mohr-Coulomb continuum (UDEC), ``W`` = 5 m wide behind the wall with a free-field boundary at
its far end, and checks (Figure 10) that ``2W`` gives the same crest response. Here the backfill
is a disc assembly in :mod:`murus.dem`, behind the stones of
:func:`murus.retaining.dem_wall.build_wall` (built with ``backstop=False``).

When to use it, against the equivalent thrust (:class:`~murus.retaining.dem_wall.EquivalentThrust`)
---------------------------------------------------------------------------------------------------
- The equivalent thrust is one EN 1998-5 Annex E force updated from the instantaneous base
  acceleration: cheap (the wall alone, about a hundred bodies, a DSRW1 S2 run in about a
  minute), but it has no memory: when the wall rocks or slides out of the slope and comes back,
  the thrust is the same as before, and the soil never fills the gap behind a wall that has
  moved out. It also fixes the shape of the pressure (triangle or uniform) and the wall friction.
- The discrete backfill captures what the thrust cannot: the grains fall into the gap that
  opens behind a rocking wall at each cycle and wedge it (ratcheting: the permanent
  displacement accumulates), the pressure distribution and the mobilised wall friction follow
  from the contacts, the soil's own inertia and its arching are in the model, and the failure
  surface in the backfill is an outcome. It costs a few thousand extra bodies (DSRW1, W = 5 m:
  about 2,000 discs, i.e. 20 times the stones, and a settling stage), and its friction angle is a
  calibrated property of the disc assembly (:mod:`murus.dem.biaxial`), not an input.
  Use the thrust for sweeps and behaviour-factor tables, the discrete backfill to check one
  case, the ratcheting mechanism, the pressure distribution, or the influence of ``W``.

Geometry (frame of :mod:`murus.retaining.geometry`: x into the backfill, z up, toe at the
origin). The backfill fills the region between the back face of the wall ``x = B - lambda_m z``
(from the heel up, extended above the crest for a sloping backfill), a horizontal floor at the
level of the heel, the vertical lateral boundary at ``x = x_heel + W`` and the backfill surface,
a plane rising at ``beta`` (``backfill_slope_deg``) from the top of the back face. The floor
is a kinematic ``"base"`` slab (it moves with the base motion), starting ``floor_gap`` behind
the heel (no contact with the heel stone; the gap is far smaller than a disc).

Discs. Radii uniform in ``r_mean (1 -+ spread)`` (default spread 0.2: ``r_max / r_min = 1.5``,
the size ratio of the biaxial calibration). Default ``r_mean = 0.016 H`` (0.04 m for the 2.5 m
walls of Savalle et al. (2022)): the backfill of a full-scale wall, ``5 m x 2.6 m``, then holds
about 2,000 discs (4,000 for 2W), which keeps a DSRW1 collapse run within minutes on one core.
The price:
a disc diameter of 0.08 m against 0.1 m courses gives one or two disc contacts per stone on the
back face where the paper asks for at least six sub-contacts per unit (§2); the thrust resultant
and its height are reproduced, its course-by-course distribution is coarse. Pass ``radius``
for finer discs (the count grows as ``1 / r²`` and the time step shrinks as ``r``).

Generation (:func:`generate_packing`; the generic tools, lattice, overlap check, solid fraction,
absorbing boundary and wall thrust, are in :mod:`murus.dem.packing` and :mod:`murus.dem.boundary`
and re-exported here): discs on a hexagonal grid of pitch ``2 r_max (1 + gap)``
(no initial overlap: :func:`check_overlap` raises :class:`BackfillError` otherwise), in the
region stretched upwards by ``fill`` (the loose grid has a solid fraction near 0.6 and
compacts to about 0.8), inside a rigid box (the back face, the floor and the lateral
boundary as fixed plates); settled under 8 g with light local damping (pre-compaction, as in
``benchmarks/bench_dem.py``), then under 1 g; the discs whose centre is above the backfill
surface are removed. The settled positions are the packing put behind the real wall.

Materials. Disc-disc contacts (and disc-floor): ``kn = ks = 1e9 Pa/m``, friction 30 deg and
the rolling resistance ``mu_r`` of the biaxial calibration (:func:`rolling_for`: 0.167 gives a
peak friction angle of 37.97 deg, the 37.7 deg of Savalle et al. (2022), Table 6; 0.347 gives 45.1
deg, the 45 deg of the mock-ups, Table 1). Wall-backfill interface: Savalle et al. (2022), Table 6
(Table 1 for the mock-ups), ``kn = ks = 2.9e10`` (3.0e10) Pa/m times the wall's ``stiffness_scale``,
friction ``wall.interface_friction_deg``. The lateral boundary is frictionless. Disc density
``rho_s = gamma / (g phi)`` with ``phi`` the solid (area) fraction of the settled packing,
measured in an interior window away from the walls and the surface (:func:`solid_fraction`),
so that the bulk unit weight of the settled assembly is the wall's ``backfill_unit_weight``
(14.9 kN/m³, Table 6); :attr:`DiscreteBackfill.unit_weight` reports the value measured in the
final, settled model.

Lateral boundary at ``x = x_heel + W``:

- ``"container"``: a rigid kinematic plate moving with the base (a shaking-table box);
- ``"absorbing"``: Lysmer-Kuhlemeyer viscous boundary. The model is settled against the
  container plate; the static force of the plate on each disc touching it is recorded, the
  plate is moved out of reach, and those discs (the last layer) receive, through the engine's
  external-force hook, the recorded static force plus the dashpot tractions ``-rho Vp (v_x -
  v_bx)`` and ``-rho Vs (v_y - v_by)`` [Pa] times their tributary length along the boundary
  (half the distance to their neighbours above and below, the ends extended to the floor and to
  the surface) and the thickness: :class:`AbsorbingBoundary`. The velocities are relative to
  the base motion, so the boundary does not resist the rigid motion of the model with the
  ground (the far field moves with the base, as UDEC's free-field column at low frequency).
  Wave speeds: from the elastic constants that Savalle et al. (2022) gives the continuum backfill,
  Table 6 for the full-scale walls (``E = 92.7 MPa``, ``nu = 0.22``: ``Vp = 264 m/s``, ``Vs = 158
  m/s`` with ``rho = 14.9e3 / g``) and Table 1 for the mock-ups (10 MPa, 0.3: 93 and 50 m/s),
  ``Vp = sqrt(E (1 - nu) / ((1 + nu)(1 - 2 nu) rho))``, ``Vs = sqrt(E / (2 (1 + nu) rho))``;
  pass ``wave_speeds=(vp, vs)`` to match the disc assembly instead (its affine estimate with
  ``kn = 1e9 Pa/m`` and 0.04 m discs is about half of those speeds: the boundary then
  reflects about a third of a normally incident wave's amplitude). The dashpot force is
  explicit and constant between hook calls: the hook runs every
  :meth:`AbsorbingBoundary.interval` steps, ``c dt_hook / m <= 0.5`` on every disc.

Settling (:meth:`DiscreteBackfill.settle`): the packing is put behind the wall with its radii
relieved of the elastic overlaps (stress-free: the 8 g pre-compaction would otherwise come back
as locked-in, over-consolidated lateral stresses, K ~ 0.6), settled under 1 g with local
damping, then relaxed dynamically without base motion (:meth:`DiscreteBackfill._relax`): the
wall leans on the soil and tilts slowly (DSRW1 with the joints at 1e-3 of Table 6: 2.3 cm at
the crest, 0.5 deg, in about 0.9 s), which the local damping of ``settle`` brakes.

Measured (DSRW1, W = 5 m, 2,053 discs; ``validation/retaining_backfill.py``): bulk unit
weight 14.98 kN/m³ in the interior window (target 14.9), 14.78 over the whole region (the
layers along the wall, floor and surface are looser); at-rest horizontal thrust on the wall
``K = 2 E_h / (gamma h²)`` = 0.32 after settling and 0.36 after the relaxation, with a
mobilised wall friction of 16-23 deg, i.e. between the Rankine active value at the peak
friction angle (0.24) and Jaky's ``1 - sin(phi)`` (0.39 at 37.7 deg, 0.56 at the disc
assembly's critical-state angle of about 26 deg): about 1.6 times the Coulomb active thrust
of the pseudo-static analysis (``delta = 2/3 phi``). The thrust of the disc backfill on a wall
that yields by a few centimetres is thus well above the active value that ``A_pseudo`` and the
equivalent thrust assume (the disc assembly is softer than the paper's continuum, E = 92.7 MPa,
and mobilises its peak strength only at larger strains), and the wall creeps out from the
start of the S2 ramp: DSRW1 at 5 Hz collapses at A_col = 3.65 m/s² (Savalle et al. (2022), Table 7:
5.38; the equivalent thrust: 8.47) by toppling, in about 3 minutes on two cores (W = 5 m;
``benchmarks/bench_retaining.py``).

Mock-ups (Savalle et al. (2022), §3): the default radius ``0.016 H`` is 0.7 mm for the 44 mm wall,
the time step 5.7e-6 s, and the generation, settling and relaxation take about 3 minutes on one
core; with the absorbing boundary the dashpot hook runs at every step (its explicit dashpots
need it on such light discs), which makes a run several times slower than with the container
(``boundary="container"``, the shaking-table box of the experiments, the CLI's default for the
mock-ups). Not validated against Savalle et al. (2022), Table 3: VALIDATION.md uses the equivalent
thrust for the mock-ups.

Units: SI (m, kg, s, N, Pa; ``*_deg`` in degrees).
"""

from __future__ import annotations

import math
import time as _time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from murus import G
from murus.dem.boundary import AbsorbingBoundary, contact_forces_from, wall_thrust
from murus.dem.packing import GRID_GAP, PackingError, check_overlap, disc_grid, solid_fraction
from murus.retaining.geometry import RetainingWall

__all__ = ["BackfillError", "Packing", "DiscreteBackfill", "AbsorbingBoundary",
           "CALIBRATION", "DISC_JOINT", "default_width", "rolling_for", "wave_speeds",
           "check_overlap", "generate_packing", "solid_fraction", "region_polygon", "wall_thrust"]

#: Biaxial calibration (:func:`murus.dem.biaxial.calibrate_rolling`, disc friction 30 deg,
#: kn = ks = 1e9 Pa/m, radii ratio 1.5): (peak friction angle [deg], rolling coefficient mu_r).
CALIBRATION = ((37.97, 0.167), (45.1, 0.347))
#: Disc-disc contact of the backfill (the biaxial calibration's).
DISC_JOINT = {"kn": 1.0e9, "ks": 1.0e9, "friction_deg": 30.0}
#: Elastic constants of the continuum backfill of Savalle et al. (2022) (E [Pa], nu): Table 6 (full
#: scale) and Table 1 (mock-ups); used for the dashpots of the absorbing boundary.
SEED_ELASTIC = {"full": (92.7e6, 0.22), "mockup": (10.0e6, 0.30)}
#: Wall-backfill interface stiffness [Pa/m]: Savalle et al. (2022), Table 6 (full scale) and Table
#: 1.
SEED_INTERFACE_K = {"full": 2.9e10, "mockup": 3.0e10}

BOUNDARIES = ("container", "absorbing")

# Packing defaults (module docstring, "Discs" and "Generation"), shared by
# :func:`generate_packing` and :class:`DiscreteBackfill`:
#: Default mean disc radius as a fraction of the wall height: 0.04 m for the 2.5 m walls of
#: Savalle et al. (2022), about 2,000 discs for W = 5 m (a collapse run within minutes).
RADIUS_FRACTION = 0.016
#: Radii uniform in ``r_mean (1 -+ SPREAD)``: ``r_max / r_min = 1.5``, the size ratio of the
#: biaxial calibration (:data:`CALIBRATION`).
SPREAD = 0.2
#: The lattice fills the region stretched upwards by this factor (a loose lattice, solid
#: fraction near 0.6, compacts to about 0.8 and fills the region after settling).
FILL = 1.45
#: Gravity multiple of the pre-compaction stage (as in ``benchmarks/bench_dem.py``).
PRECOMPACT_G = 8.0
#: Largest numbers of steps of the two settling stages of the generation (pre-compaction,
#: then 1 g): enough for the unbalanced-force ratio :data:`SETTLE_TOL` on the walls of
#: Savalle et al. (2022) Table 5 with the default radius.
PACKING_STEPS = (6000, 30000)
#: Unbalanced-force ratio that ends a settling stage (the engine's ``settle``).
SETTLE_TOL = 1e-2
#: Largest number of steps of the settling behind the real wall (:meth:`DiscreteBackfill.settle`).
SETTLE_STEPS = 20000
#: Disc density during the generation [kg/m³] (the packing does not depend on it: the real
#: density follows from the backfill unit weight and the solid fraction).
GENERATION_DENSITY = 1800.0


BackfillError = PackingError
"""Invalid input to the discrete backfill (one-line message): the error of the disc packings of
:mod:`murus.dem.packing` (one class, so that the generic tools moved there raise what the
backfill always raised)."""


def _is_mock(wall: RetainingWall) -> bool:
    return wall.name.lower().startswith("mockup")


def default_width(wall: RetainingWall) -> float:
    """Default backfill width [m]: ``2 H``, the ratio of Savalle et al. (2022) (W = 5 m behind its
    2.5 m walls, §4.1; Figure 10 shows that 2W changes nothing), so that a mock-up gets a backfill
    of its own scale."""
    return 2.0 * wall.height


def rolling_for(phi_deg: float) -> float:
    """Rolling coefficient ``mu_r`` giving the peak friction angle ``phi_deg`` [deg] of the disc
    assembly: linear between the two calibrated points of :data:`CALIBRATION`, within
    [36, 47] deg (outside: run :func:`murus.dem.biaxial.calibrate_rolling` and pass
    ``rolling``)."""
    phi = float(phi_deg)
    if not 36.0 <= phi <= 47.0:
        raise BackfillError(f"backfill friction {phi:g} deg is outside the calibrated range "
                            "36-47 deg: calibrate the rolling resistance "
                            "(murus.dem.biaxial.calibrate_rolling) and pass rolling=...")
    (p0, m0), (p1, m1) = CALIBRATION
    return float(m0 + (phi - p0) * (m1 - m0) / (p1 - p0))


def wave_speeds(wall: RetainingWall) -> tuple[float, float]:
    """P and S wave speeds [m/s] of the paper's continuum backfill (module docstring)."""
    E, nu = SEED_ELASTIC["mockup" if _is_mock(wall) else "full"]
    rho = wall.backfill_unit_weight / G
    vp = math.sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho))
    vs = math.sqrt(E / (2 * (1 + nu) * rho))
    return vp, vs


# ------------------------------------------------------------------------ geometry
def _frame(wall: RetainingWall, W: float):
    """Heel, floor level, end of the backfill, back-face and surface functions."""
    xh, zh = wall.heel
    xb, zb = wall.back_top
    lm = wall.internal_batter
    tb = math.tan(wall.beta)

    def back_x(z):
        return wall.base_width - lm * np.asarray(z, float)

    def surf_z(x):
        return zb + (np.asarray(x, float) - xb) * tb

    return xh, zh, xh + W, back_x, surf_z


def region_polygon(wall: RetainingWall, W: float) -> np.ndarray:
    """The backfill region (counter-clockwise vertices [m]): heel, floor end, surface end, top
    of the back face."""
    xh, zh, xe, _, surf = _frame(wall, W)
    xb, zb = wall.back_top
    return np.array([[xh, zh], [xe, zh], [xe, float(surf(xe))], [xb, zb]])


def _window(wall: RetainingWall, W: float, rmax: float, margin: float = 5.0):
    """Interior window: ``margin`` largest radii away from the walls, floor and surface."""
    xh, zh, xe, back_x, surf = _frame(wall, W)
    d = margin * rmax
    x0 = float(max(back_x(zh), back_x(surf(xh)))) + d
    x1 = xe - d
    z1 = float(min(surf(xh), surf(xe))) - d
    return (x0, x1, zh + d, z1)


# ------------------------------------------------------------------------ generation
@dataclass
class Packing:
    """Settled disc packing of the backfill region: ``centres (n, 2)`` [m], ``radii`` [m],
    ``phi`` the solid fraction in the interior window, ``phi_region`` over the whole region
    ``area`` [m²]; ``info`` the generation log (counts, steps, wall time)."""

    wall: str
    W: float
    centres: np.ndarray
    radii: np.ndarray
    phi: float
    phi_region: float
    area: float
    info: dict = field(default_factory=dict)

    @property
    def n(self) -> int:
        return int(self.radii.size)


def _grid(wall, W, rmean, spread, gap, fill, seed):
    """The hexagonal lattice of the region stretched upwards by ``fill``
    (:func:`murus.dem.packing.disc_grid`); returns centres, radii and the top of the lattice."""
    xh, zh, xe, back_x, surf = _frame(wall, W)
    rmax = rmean * (1 + spread)
    ztop = zh + fill * (float(max(surf(xh), surf(xe))) - zh)
    c, r, _ = disc_grid((rmean * (1 - spread), rmax), seed=seed, gap=gap, lattice="hex",
                        floor=zh, top=ztop, left=back_x, right=xe,
                        ceiling=lambda x: zh + fill * (float(surf(x)) - zh))
    if len(c) < 10:
        raise BackfillError(f"the backfill region ({W:g} m wide) holds only {len(c)} discs "
                            f"of radius {rmean:g} m: lower radius or raise W")
    return c, r, ztop


def _relieve(c, r, wall, W, clear: float = 1e-9) -> np.ndarray:
    """Radii shrunk by the elastic overlap of each disc with its neighbours and the box
    (a few 1e-4 of the radius under 1 g): the packing is put behind the wall stress-free, so
    that the settling there, under 1 g, sets the stresses (the locked-in stresses of the 8 g
    pre-compaction, an over-consolidation, would otherwise come back through the overlaps)."""
    from scipy.spatial import cKDTree

    xh, zh, xe, back_x, _ = _frame(wall, W)
    lm = wall.internal_batter
    dback = (c[:, 0] - back_x(c[:, 1])) / math.sqrt(1.0 + lm * lm)
    ov = np.maximum.reduce([r - dback, r - (c[:, 1] - zh), r - (xe - c[:, 0]),
                            np.zeros_like(r)])
    pairs = cKDTree(c).query_pairs(2.0 * float(r.max()), output_type="ndarray")
    if pairs.size:
        d = np.hypot(*(c[pairs[:, 0]] - c[pairs[:, 1]]).T)
        o = np.maximum(r[pairs[:, 0]] + r[pairs[:, 1]] - d, 0.0)
        np.maximum.at(ov, pairs[:, 0], o)
        np.maximum.at(ov, pairs[:, 1], o)
    return r - ov - clear


def _disc_joint(rolling, kn=None):
    from murus.dem import Joint

    k = DISC_JOINT["kn"] if kn is None else float(kn)
    return Joint(kn=k, ks=k, friction_deg=DISC_JOINT["friction_deg"], rolling=rolling)


def _interface_joint(wall, stiffness_scale):
    from murus.dem import Joint

    k = SEED_INTERFACE_K["mockup" if _is_mock(wall) else "full"] * stiffness_scale
    return Joint(kn=k, ks=k, friction_deg=wall.interface_friction_deg)


def generate_packing(wall: RetainingWall, W: float | None = None, *, radius: float | None = None,
                     spread: float = SPREAD, seed: int = 0, fill: float = FILL,
                     gap: float = GRID_GAP, rolling: float | None = None,
                     precompact_g: float = PRECOMPACT_G,
                     steps: tuple[int, int] = PACKING_STEPS, tol: float = SETTLE_TOL,
                     density: float = GENERATION_DENSITY) -> Packing:
    """Settled disc packing of the backfill of ``wall`` (module docstring, "Generation").

    Discs on a hexagonal lattice in a rigid box (back face, floor, lateral plate), settled
    under ``precompact_g`` g then under 1 g; the discs above the backfill surface are removed
    and the radii relieved of the elastic overlaps.

    Parameters
    ----------
    wall : RetainingWall
        The wall whose backfill region is filled.
    W : float, optional
        Width of the backfill behind the heel [m]; default ``2 H`` (:func:`default_width`:
        the 5 m of Savalle et al. (2022), §4.1, for its 2.5 m walls). At least four disc
        diameters.
    radius : float, optional
        Mean disc radius [m]; default ``0.016 H``.
    spread : float
        Radii uniform in ``radius (1 -+ spread)`` [-], in [0, 1).
    seed : int
        Seed of the random radii.
    fill : float
        The lattice fills the region stretched upwards by this factor [-], >= 1.
    gap : float
        Clearance of the lattice [fraction of r_max].
    rolling : float, optional
        Rolling-resistance coefficient mu_r [-]; default from the wall's backfill friction
        angle (:func:`rolling_for`).
    precompact_g : float
        Gravity multiple of the first settling stage [-] (1: no pre-compaction).
    steps : tuple of int
        Largest numbers of steps of the two settling stages.
    tol : float
        Unbalanced-force ratio that ends a settling stage [-].
    density : float
        Disc density during the generation [kg/m³] (the packing does not depend on it).

    Returns
    -------
    Packing
        ``centres`` (n, 2) [m] and ``radii`` (n,) [m] of the settled discs, the solid
        fraction ``phi`` [-] in an interior window and ``phi_region`` [-] over the whole region
        of ``area`` [m²], and ``info``, the generation log (counts, settling messages, steps,
        time step [s], wall time [s]).

    Raises
    ------
    BackfillError
        If ``W``, ``radius``, ``spread`` or ``fill`` is out of range, ``W`` is narrower than
        four disc diameters, or the lattice overlaps.

    References
    ----------
    Savalle et al. (2022), §2 and §4.1, Tables 1 and 6 (the backfill); Cundall & Strack
    (1979) (the disc assembly).
    """
    from murus.dem import Joint, Model

    t0 = _time.perf_counter()
    W = default_width(wall) if W is None else float(W)
    if not (W > 0 and math.isfinite(W)):
        raise BackfillError(f"backfill width W must be positive [m], got {W!r}")
    rmean = RADIUS_FRACTION * wall.height if radius is None else float(radius)
    if not (rmean > 0 and math.isfinite(rmean)):
        raise BackfillError(f"radius must be positive [m], got {radius!r}")
    if not 0 <= spread < 1:
        raise BackfillError(f"spread must be in [0, 1), got {spread!r}")
    if not fill >= 1:
        raise BackfillError(f"fill must be >= 1, got {fill!r}")
    if W < 8 * rmean:
        raise BackfillError(f"W = {W:g} m is narrower than 4 disc diameters (radius "
                            f"{rmean:g} m)")
    mu = rolling_for(wall.backfill_friction_deg) if rolling is None else float(rolling)
    c, r, ztop = _grid(wall, W, rmean, spread, gap, fill, seed)
    check_overlap(c, r)
    xh, zh, xe, back_x, surf = _frame(wall, W)
    m = Model(gravity=G, joint=_disc_joint(mu))
    big = 2.0 * (ztop - zh) + 1.0
    th = max(0.2, 10 * rmean)
    z_lo, z_hi = zh - th, ztop + 1.0
    xl, xu = float(back_x(z_lo)), float(back_x(z_hi))
    m.add_polygon([(xl - th, z_lo), (xl, z_lo), (xu, z_hi), (xu - th, z_hi)],
                  kinematic="fixed", group="back")
    m.add_polygon([(min(xl, xu) - th, zh - th), (xe + th, zh - th), (xe + th, zh),
                   (min(xl, xu) - th, zh)], kinematic="fixed", group="bfloor")
    m.add_polygon([(xe, zh - th), (xe + th, zh - th), (xe + th, zh + big), (xe, zh + big)],
                  kinematic="fixed", group="container")
    for ci, ri in zip(c, r, strict=True):
        m.add_disc(ci, ri, density=density, group="fill")
    m.set_joint(_disc_joint(mu), "fill", "fill")
    m.set_joint(_disc_joint(mu), "fill", "bfloor")
    # the back plate: the interface friction with the discs' stiffness (small overlaps to
    # relieve, :func:`_relieve`); the settling behind the wall sets the interface stresses
    m.set_joint(Joint(kn=DISC_JOINT["kn"], ks=DISC_JOINT["ks"],
                      friction_deg=wall.interface_friction_deg), "fill", "back")
    m.set_joint(Joint(kn=DISC_JOINT["kn"], ks=DISC_JOINT["ks"], friction_deg=0.0), "fill",
                "container")
    m.build()
    s1 = None
    if precompact_g > 1:
        m.gravity = precompact_g * G
        s1 = m.settle(tol=tol, alpha=0.2, max_steps=int(steps[0]))
        m.gravity = G
    s2 = m.settle(tol=tol, alpha=0.7, max_steps=int(steps[1]))
    cs, rs = m.discs()
    keep = cs[:, 1] <= surf(cs[:, 0])
    inside = (cs[:, 0] <= xe) & (cs[:, 0] >= back_x(cs[:, 1])) & (cs[:, 1] >= zh)
    keep &= inside
    cs, rs = cs[keep], rs[keep]
    rs = _relieve(cs, rs, wall, W)
    poly = region_polygon(wall, W)
    from murus.dem import polygon_properties

    area = polygon_properties(poly)[0]
    phi_region = float(np.sum(np.pi * rs**2) / area)
    phi = solid_fraction(cs, rs, _window(wall, W, rmean * (1 + spread)))
    info = dict(n_grid=int(len(c)), n=int(keep.sum()), radius=rmean, spread=spread, seed=seed,
                rolling=mu, fill=fill, precompact_g=precompact_g,
                settle_8g=None if s1 is None else s1.message, settle_1g=s2.message,
                steps=(0 if s1 is None else s1.steps) + s2.steps, dt=m.dt,
                wall_time=_time.perf_counter() - t0)
    return Packing(wall.name, W, cs, rs, phi, phi_region, area, info)


# ------------------------------------------------------------------------ backfill
class DiscreteBackfill:
    """The discrete backfill of ``wall`` behind the DEM wall (module docstring).

    Use: ``bf = DiscreteBackfill(wall, W)``; ``dw = build_wall(wall, backstop=False,
    add_bodies=bf.add_to, ...)``; ``bf.settle(dw)``; then run with ``external=bf`` (or
    :meth:`external` to chain with another hook) every :meth:`interval` steps.

    Parameters
    ----------
    wall : RetainingWall
        The wall; it needs a backfill (``backfill_unit_weight > 0``) with a planar surface
        (no ``backfill_profile``).
    W : float, optional
        Width of the backfill behind the heel [m]; default ``2 H`` (:func:`default_width`).
    boundary : str
        Lateral boundary at ``x_heel + W``: ``"container"`` (a rigid plate moving with the
        base) or ``"absorbing"`` (Lysmer-Kuhlemeyer dashpots, :class:`AbsorbingBoundary`).
    radius : float, optional
        Mean disc radius [m]; default ``0.016 H`` (:func:`generate_packing`).
    spread : float
        Radii uniform in ``radius (1 -+ spread)`` [-].
    seed : int
        Seed of the random radii.
    fill : float
        Vertical stretch of the generation lattice [-].
    precompact_g : float
        Gravity multiple of the pre-compaction stage of the generation [-].
    packing_steps : tuple of int
        Largest numbers of steps of the two settling stages of the generation.
    packing : Packing, optional
        A ready packing of the same ``W``, used instead of generating one.
    rolling : float, optional
        Rolling-resistance coefficient mu_r [-]; default from the wall's backfill friction
        angle (:func:`rolling_for`).
    stiffness_scale : float
        Factor on the wall-backfill interface stiffness of Savalle et al. (2022), Table 6
        (Table 1 for the mock-ups) [-]; the wall's.
    wave_speeds : tuple of float, optional
        ``(Vp, Vs)`` of the dashpots of the absorbing boundary [m/s]; default
        :func:`wave_speeds`.
    floor_gap : float, optional
        Gap between the heel and the floor slab [m], in [0, r_min); default a fifth of the
        smallest radius.
    settle_tol : float
        Unbalanced-force ratio that ends the settling of the final model [-].
    settle_steps : int
        Largest number of steps of that settling.
    relax_max : float, optional
        Longest dynamic relaxation after the settling [s]; default ``3 sqrt(H / 2.5 m)`` s.
    relax_vtol : float, optional
        The relaxation ends when the largest speed of the stones and discs is below this twice
        in a row [m/s]; default ``2e-3 sqrt(H / 2.5 m)`` m/s.
    relax_xi : float
        Mass-proportional damping ratio of the relaxation [-], at 5 Hz for a 2.5 m wall
        (Froude-scaled).

    Attributes
    ----------
    density : float
        Disc density [kg/m³], ``gamma / (g phi)``, so that the bulk unit weight of the packing
        is the wall's ``backfill_unit_weight``.
    vp, vs : float
        Wave speeds of the absorbing boundary [m/s].
    unit_weight, unit_weight_region : float
        Bulk unit weight of the settled assembly [N/m³], in the interior window and over the
        whole region (NaN before :meth:`settle`).
    relax_time : float
        Duration of the dynamic relaxation [s].
    absorbing : AbsorbingBoundary or None
        The boundary, after :meth:`settle` with ``boundary="absorbing"``.

    Raises
    ------
    BackfillError
        If ``boundary`` is unknown, the wall has no or a broken backfill, a scale, speed,
        rolling coefficient or gap is out of range, or the packing's width differs from ``W``.

    References
    ----------
    Savalle et al. (2022), §2, §4.1, Tables 1 and 6, Figures 9-10; Lysmer & Kuhlemeyer
    (1969) (absorbing boundary); Cundall & Strack (1979).
    """

    def __init__(self, wall: RetainingWall, W: float | None = None,
                 boundary: str = "container", *,
                 radius: float | None = None, spread: float = SPREAD, seed: int = 0,
                 fill: float = FILL, precompact_g: float = PRECOMPACT_G,
                 packing_steps: tuple[int, int] = PACKING_STEPS, packing: Packing | None = None,
                 rolling: float | None = None, stiffness_scale: float = 1e-3,
                 wave_speeds: tuple[float, float] | None = None,
                 floor_gap: float | None = None, settle_tol: float = SETTLE_TOL,
                 settle_steps: int = SETTLE_STEPS, relax_max: float | None = None,
                 relax_vtol: float | None = None, relax_xi: float = 0.1) -> None:
        b = str(boundary).strip().lower()
        if b not in BOUNDARIES:
            raise BackfillError(f"boundary must be one of {', '.join(BOUNDARIES)}, got "
                                f"{boundary!r}")
        if wall.backfill_unit_weight <= 0:
            raise BackfillError(f"{wall.name}: backfill_unit_weight is 0 (no backfill)")
        if wall.backfill_profile is not None:
            raise BackfillError(f"{wall.name}: a broken backfill_profile is not supported by "
                                "the discrete backfill (planar surface at beta only)")
        if not (stiffness_scale > 0 and math.isfinite(stiffness_scale)):
            raise BackfillError(f"stiffness_scale must be positive, got {stiffness_scale!r}")
        self.wall = wall
        self.W = default_width(wall) if W is None else float(W)
        self.boundary = b
        self.stiffness_scale = float(stiffness_scale)
        self.rolling = (rolling_for(wall.backfill_friction_deg) if rolling is None
                        else float(rolling))
        if self.rolling < 0:
            raise BackfillError(f"rolling must be >= 0, got {rolling!r}")
        if packing is None:
            packing = generate_packing(wall, W, radius=radius, spread=spread, seed=seed,
                                       fill=fill, rolling=self.rolling,
                                       precompact_g=precompact_g, steps=packing_steps)
        elif abs(packing.W - self.W) > 1e-9:
            raise BackfillError(f"the packing is {packing.W:g} m wide, W = {self.W:g} m")
        check_overlap(packing.centres, packing.radii, tol=0.05 * float(packing.radii.min()))
        self.packing = packing
        self.density = wall.backfill_unit_weight / (G * packing.phi)
        vp_vs = globals()["wave_speeds"](wall) if wave_speeds is None else wave_speeds
        self.vp, self.vs = (float(v) for v in vp_vs)
        if not (self.vp > 0 and self.vs > 0):
            raise BackfillError(f"wave speeds must be positive, got {wave_speeds!r}")
        rmin = float(packing.radii.min())
        self.floor_gap = 0.2 * rmin if floor_gap is None else float(floor_gap)
        if not 0 <= self.floor_gap < rmin:
            raise BackfillError(f"floor_gap must be in [0, r_min = {rmin:g}) m")
        # Froude scaling from the 2.5 m walls of Savalle et al. (2022) (times and velocities ~
        # sqrt(H)): at most 3 s of relaxation by chunks of 0.05 s, damping at 5 Hz, 2 mm/s at full
        # scale
        self.relax_scale = math.sqrt(wall.height / 2.5)
        self.relax_max = 3.0 * self.relax_scale if relax_max is None else float(relax_max)
        self.relax_vtol = (2e-3 * self.relax_scale if relax_vtol is None
                           else float(relax_vtol))
        self.relax_xi = float(relax_xi)
        self.relax_time = 0.0
        self.settle_tol = float(settle_tol)
        self.settle_steps = int(settle_steps)
        self.discs: np.ndarray = np.zeros(0, np.int64)
        self.floor = self.container = -1
        self.absorbing: AbsorbingBoundary | None = None
        self.unit_weight = math.nan
        self.unit_weight_region = math.nan
        self.settle_result = None
        self.model = None

    # -- building
    def add_to(self, m) -> None:
        """Add the floor, the lateral plate and the discs to the model ``m`` (before it is
        built; :func:`~murus.retaining.dem_wall.build_wall`'s ``add_bodies``)."""
        from murus.dem import Joint

        wall = self.wall
        xh, zh, xe, back_x, surf = _frame(wall, self.W)
        th = max(0.2, 10 * float(self.packing.radii.mean()))
        top = float(max(surf(xh), surf(xe))) + 1.0
        x0 = xh + self.floor_gap
        self.floor = m.add_polygon([(x0, zh - th), (xe + th, zh - th), (xe + th, zh),
                                    (x0, zh)], density=self.density, kinematic="base",
                                   group="bfloor")
        self.container = m.add_polygon([(xe, zh), (xe + th, zh), (xe + th, top), (xe, top)],
                                       density=self.density, kinematic="base",
                                       group="container")
        ids = [m.add_disc(c, r, density=self.density, group="fill")
               for c, r in zip(self.packing.centres, self.packing.radii, strict=True)]
        self.discs = np.array(ids, np.int64)
        dj = _disc_joint(self.rolling)
        m.set_joint(dj, "fill", "fill")
        m.set_joint(dj, "fill", "bfloor")
        m.set_joint(dj, "fill", "foundation")
        m.set_joint(_interface_joint(wall, self.stiffness_scale), "fill", "stones")
        m.set_joint(Joint(kn=DISC_JOINT["kn"], ks=DISC_JOINT["ks"], friction_deg=0.0), "fill",
                    "container")
        self.model = m

    def settle(self, dw, external: Callable | None = None):
        """Settle the wall and the backfill under gravity (``external`` an extra hook, e.g.
        the zero thrust); for the absorbing boundary, record the static forces of the plate,
        move it out of reach and settle again with them. Sets :attr:`unit_weight`. Returns
        the engine's SettleResult."""
        m = dw.model
        st = m.settle(tol=self.settle_tol, max_steps=self.settle_steps, external=external)
        if self.boundary == "absorbing":
            forces = contact_forces_from(m, self.container, self.discs)
            bodies = np.array(sorted(forces, key=lambda b: m.bpos[b, 1]), np.int64)
            static = np.array([forces[b] for b in bodies]).reshape(-1, 3)
            _, zh, xe, _, surf = _frame(self.wall, self.W)
            y = m.bpos[bodies, 1]
            mids = 0.5 * (y[1:] + y[:-1])
            edges = np.concatenate([[zh], mids, [float(surf(xe))]])
            lengths = np.diff(edges)
            self.absorbing = AbsorbingBoundary(bodies, lengths, static,
                                               self.wall.backfill_unit_weight / G, self.vp,
                                               self.vs, m.thickness)
            # the plate out of reach (it keeps moving with the base, far away)
            m.bpos[self.container, 0] += 10.0 * self.W + 10.0
            self.absorbing.dashpots = False

            def hook(model):
                if external is not None:
                    external(model)
                self.absorbing(model)

            st = m.settle(tol=self.settle_tol, max_steps=self.settle_steps, external=hook)
            self.absorbing.dashpots = True
        self.relax_time = self._relax(m, external)
        self.settle_result = st
        self.unit_weight, self.unit_weight_region = self.measure_unit_weight(m)
        return st

    def _relax(self, m, external: Callable | None) -> float:
        """Dynamic relaxation after the settling: the wall leans on the backfill slowly (the
        local damping of ``settle`` brakes a quasi-static creep of the wall with the soil),
        so the model runs without base motion, with ``relax_xi`` mass-proportional damping at
        5 Hz, by chunks of 0.05 s until the largest velocity of the stones and discs is below
        ``relax_vtol`` twice in a row (at most ``relax_max`` s); the frequency, the chunk and
        the defaults of ``relax_max`` (3 s) and ``relax_vtol`` (2 mm/s) are those of a 2.5 m
        wall, scaled by Froude similitude (times and velocities as ``sqrt(H / 2.5 m)``), so
        that a mock-up relaxes in proportion (0.4 s at most for H = 44 mm). The model time is
        then set back (as ``settle`` does), the velocities zeroed and the state taken as
        reference. Returns the relaxation time [s]."""
        from murus.dem import kernels as K
        from murus.dem.engine import detect

        if self.relax_max <= 0:
            return 0.0
        hook = self.external(external)
        toff, soff, step0 = m.time_offset, m.step_offset, int(m.C[K.C_STEP])
        dyn = m.bkin == 0
        ok = 0
        t = 0.0
        probes = dict(m.probes)
        m.probes.clear()
        chunk = 0.05 * self.relax_scale
        while t < self.relax_max - 1e-12:
            m.run(chunk, xi=self.relax_xi, freq=5.0 / self.relax_scale, sample_dt=chunk,
                  external=hook,
                  external_every=min(self.interval(m), max(1, int(round(1e-3 / m.dt)))))
            t += chunk
            v = float(np.max(np.hypot(m.bvel[dyn, 0], m.bvel[dyn, 1])))
            ok = ok + 1 if v < self.relax_vtol else 0
            if ok >= 2:
                break
        m.history.clear()
        m.probes.update(probes)
        m.time_offset = toff
        m.step_offset = soff + int(m.C[K.C_STEP]) - step0
        m.bvel[:] = 0.0
        m.bomg[:] = 0.0
        detect(m)
        m.snapshot()
        m.reset_reference()
        return t

    def measure_unit_weight(self, m) -> tuple[float, float]:
        """Bulk unit weight [N/m³] of the settled assembly: in the interior window (as the
        density was set) and over the whole region (wall, floor and surface layers
        included)."""
        c = m.bpos[self.discs]
        r = np.sqrt(m.bmass[self.discs] / (np.pi * self.density * m.thickness))
        phi = solid_fraction(c, r, _window(self.wall, self.W, float(r.max())))
        poly = region_polygon(self.wall, self.W)
        from murus.dem import polygon_properties

        area = polygon_properties(poly)[0]
        wreg = float(np.sum(m.bmass[self.discs])) * m.gravity / m.thickness / area
        return self.density * m.gravity * phi, wreg

    # -- running
    def interval(self, model) -> int:
        """Steps between calls of the hook (1 for the container: the hook does nothing)."""
        if self.absorbing is None:
            return 10**9
        return self.absorbing.interval(model)

    def __call__(self, model) -> None:
        if self.absorbing is not None:
            self.absorbing(model)

    def external(self, other: Callable | None = None) -> Callable:
        """A hook calling ``other`` (which may reset ``model.bext``) then this boundary."""
        def hook(model):
            if other is not None:
                other(model)
            self(model)
        return hook

    def summary(self) -> dict:
        """JSON-ready description and measured values."""
        p = self.packing
        return {"W": self.W, "boundary": self.boundary, "n_discs": int(p.n),
                "radius_mean": float(p.radii.mean()), "radius_min": float(p.radii.min()),
                "radius_max": float(p.radii.max()), "rolling": self.rolling,
                "disc_friction_deg": DISC_JOINT["friction_deg"], "disc_kn": DISC_JOINT["kn"],
                "density": self.density, "phi_packing": p.phi,
                "unit_weight_target": self.wall.backfill_unit_weight,
                "unit_weight": self.unit_weight, "unit_weight_region": self.unit_weight_region,
                "vp": self.vp, "vs": self.vs,
                "n_boundary": 0 if self.absorbing is None else int(self.absorbing.bodies.size),
                "packing_wall_time": p.info.get("wall_time", math.nan),
                "packing_steps": p.info.get("steps", 0),
                "settle": None if self.settle_result is None else self.settle_result.message,
                "relax_time": self.relax_time}
