"""A Mohr-Coulomb continuum backfill behind the DEM retaining wall, the model of Savalle et al.
(2022), §2 (issue 18, first part): the stones are blocks, the backfill zones
(:mod:`murus.continuum`), the wall-backfill interface the zone-block interface, all advanced in
one time loop by the blocks' engine (:class:`murus.continuum.coupled.CoupledModel`).

Geometry: the backfill region of the discrete backfill (:func:`murus.retaining.backfill.
region_polygon`: heel, floor end at ``x_heel + W``, surface end, top of the back face), meshed
into quadrilateral zones of about ``size`` (default ``H / 12``, 0.2 m for the 2.5 m walls of
Savalle et al. (2022)); the mesh follows the wall's inclined back and a sloped surface.

Material (Savalle et al. (2022), Table 6, full scale; Table 1 for the mock-ups): unit weight
``wall.backfill_unit_weight``, E and nu of the table, friction ``wall.backfill_friction_deg``,
zero cohesion and dilation, no tension, except the zones of the top row, which take the
strength of a layer of 2 kPa over 17 mm ("an artificial thin cohesive layer ... cohesion of only
2 kPa with a tiny depth", §2; scaled with H for other walls, ``crust_*``) so that the
unconfined surface zones do not flow. Interface (Table 6 / Table 1): ``kn = ks`` of the table
times ``stiffness_scale`` (the wall's joints take the same factor in
:func:`murus.retaining.dem_wall.build_wall`), friction ``wall.interface_friction_deg``, no
cohesion.

Boundaries: the bottom gridpoints move with the base (the paper's "velocity of the bottom
computational nodes ... fixed to match the dynamic solicitation"); the far side is on rollers
during the static stage, then (``boundary``) a free-field column (default, the paper's) or a
rigid side moving horizontally with the base (``"fixed"``) or a quiet side (``"quiet"``):
dashpots ``rho Cp``, ``rho Cs`` on the velocity relative to the base (on the absolute velocity
they would resist the rigid motion of the backfill with its base), the roller's reaction at the
end of the static stage kept as a constant force (FLAC's practice when a fixed boundary becomes
quiet). The free field is the paper's and the default; the quiet side absorbs the waves
leaving the model without a free-field column's own response; the fixed side reflects them.

Initial state: K0 stresses (``nu / (1 - nu)``), then the coupled settling, elastic first then
plastic (:meth:`~murus.continuum.coupled.CoupledModel.settle`), then the far side's dynamic
boundary.

Validated against Savalle et al. (2022), Tables 3, 7 and 8 and Figures 10, 11 and 14 in
VALIDATION.md (section *Dry-stone retaining walls on the continuum backfill*,
``validation/retaining_continuum.py``): every A_col there is the median of five runs with the
time step perturbed. Numerical choices, measured on DSRW1 at 5 Hz: the joint and interface
stiffness of the tables times 1e-2 (the collapse runs' default; A_col within 0.3 % of the
printed stiffness, 3.5 % lower at 1e-3), zones of H / 12 (a mesh twice as fine: the difference
in VALIDATION.md), the crust smeared over the top row (2 kPa over the whole 0.21 m row delayed
the collapse by 4 %). The mesh is Lagrangian (large strain): on meshes finer than about H / 24
a zone next to a course that slides out may turn inside out before the collapse threshold
(with 0.1 m zones and the damping of 10 % used before issue 18, at d_top = 0.38 m), which
stops the run with that message.

Units: SI (m, kg, s, N, Pa; ``*_deg`` in degrees).
"""

from __future__ import annotations

import math

import numpy as np

from murus import G
from murus.continuum import DEFAULT_CORNER_SHARE
from murus.errors import MurusError
from murus.retaining.geometry import RetainingWall

__all__ = ["ContinuumBackfillError", "ContinuumBackfill", "BOUNDARIES", "CRUST_COHESION",
           "CRUST_HEIGHT"]

#: Far-side boundaries during the dynamic run.
BOUNDARIES = ("free-field", "fixed", "quiet")
#: Cohesion of the thin top layer [Pa] (Savalle et al. (2022), §2), for a wall of height
#: :data:`CRUST_HEIGHT`; scaled with the height for others (see :class:`ContinuumBackfill`).
CRUST_COHESION = 2.0e3
#: Height of the full-scale walls of Savalle et al. (2022) [m] (Table 5).
CRUST_HEIGHT = 2.5
#: Depth of the thin top layer [m] for a wall of height :data:`CRUST_HEIGHT`: "a tiny depth"
#: (Savalle et al. (2022), §2), taken as one element of the paper's full-scale mesh (17 mm, §4.1).
CRUST_DEPTH = 0.017
#: Default zone size as a fraction of the wall height.
SIZE_FRACTION = 1.0 / 12.0
#: Steps per stage of the settling at joint stiffness x 1e-2 and below (see ``settle_steps``).
SETTLE_STEPS = 200_000


class ContinuumBackfillError(MurusError, ValueError):
    """Invalid input to the continuum backfill (one-line message)."""


class ContinuumBackfill:
    """The continuum backfill of ``wall`` behind the DEM wall (module docstring).

    Use: ``bf = ContinuumBackfill(wall)``; ``dw = build_wall(wall, backstop=False, ...)``;
    ``bf.settle(dw)``; then run ``dw.model`` (the blocks' engine advances the zones too).

    Parameters
    ----------
    wall : RetainingWall
        The wall; it needs a backfill (``backfill_unit_weight > 0``) with a planar surface.
    W : float, optional
        Width of the backfill behind the heel [m]; default ``2 H``.
    size : float, optional
        Target zone size [m]; default ``H / 12``.
    boundary : str
        Far side during the run: ``"free-field"``, ``"fixed"`` or ``"quiet"``.
    stiffness_scale : float
        Factor on the interface stiffness of Savalle et al. (2022), Table 6 (Table 1 for the
        mock-ups) [-]; the wall's.
    crust_cohesion : float, optional
        Cohesion of the thin top layer [Pa]; default 2 kPa (the paper's, §2) times
        ``H / 2.5 m`` (at 1 g stresses scale with the size).
    crust_depth : float, optional
        Depth of that layer [m]; default 17 mm times ``H / 2.5 m`` ("a tiny depth", §2: one
        element of the paper's full-scale mesh, §4.1). The top row of zones, thicker than
        that, takes the cohesion ``crust_cohesion * min(1, crust_depth / t)`` with ``t`` its
        mean thickness: the same strength of the layer per metre of surface (cohesion times
        depth) whatever the mesh, so that the layer does not stiffen the backfill more on a
        coarser mesh (with the full 2 kPa on the 0.21 m top row of the default mesh, DSRW1 at
        5 Hz collapsed 4 % later than without any crust).
    E, nu : float, optional
        Elastic constants of the backfill [Pa, -]; default Table 6 (Table 1 for the mock-ups).
    settle_tol : float
        Unbalanced-force ratio of the settling [-].
    settle_steps : int, optional
        Largest number of steps of each stage of the settling; default 200 000 at joint
        stiffness x 1e-2 and below, times sqrt(``stiffness_scale`` / 1e-2) above it (2 000 000
        at the printed stiffness): the time step falls as the square root of the joints'
        stiffness while the backfill's slowest mode keeps its period, so the steps that
        settling needs grow alike (the H/B = 3.3 mock-up at x 1, subcycled: its elastic stage
        was still at the ratio 2.7e-4 after 200 000 steps).
    corner_share : {"follow", "shrink"}
        How a loaded stone corner's share of the backfill's face follows the coverage rule
        of the interface (:class:`murus.continuum.interface.Interface`): "shrink" (default:
        down only, no energy given to a rocking corner) or "follow" (up and down, the rule
        of earlier versions: a rocking corner gains energy, which made the printed joint
        stiffness creep; VALIDATION.md, *The corner rule*).

    Raises
    ------
    ContinuumBackfillError
        Unknown boundary, no or broken backfill, a size, scale or cohesion out of range.

    References
    ----------
    Savalle et al. (2022), §2, Tables 1 and 6; Itasca UDEC, Theory and Background.
    """

    def __init__(self, wall: RetainingWall, W: float | None = None, *,
                 size: float | None = None, boundary: str = "free-field",
                 stiffness_scale: float = 1e-2, crust_cohesion: float | None = None,
                 crust_depth: float | None = None,
                 E: float | None = None, nu: float | None = None, settle_tol: float = 1e-4,
                 settle_steps: int | None = None,
                 corner_share: str = DEFAULT_CORNER_SHARE) -> None:
        from murus.retaining.backfill import SEED_ELASTIC, SEED_INTERFACE_K, _is_mock

        b = str(boundary).strip().lower()
        if b not in BOUNDARIES:
            raise ContinuumBackfillError(f"boundary must be one of {', '.join(BOUNDARIES)}, "
                                         f"got {boundary!r}")
        if wall.backfill_unit_weight <= 0:
            raise ContinuumBackfillError(f"{wall.name}: backfill_unit_weight is 0 (no "
                                         "backfill)")
        if wall.backfill_profile is not None:
            raise ContinuumBackfillError(f"{wall.name}: a broken backfill_profile is not "
                                         "supported (planar surface at beta only)")
        for name, v in (("stiffness_scale", stiffness_scale), ("size", size), ("W", W)):
            if v is not None and not (math.isfinite(v) and v > 0):
                raise ContinuumBackfillError(f"{name} must be positive, got {v!r}")
        if crust_cohesion is None:
            crust_cohesion = CRUST_COHESION * wall.height / CRUST_HEIGHT
        if crust_depth is None:
            crust_depth = CRUST_DEPTH * wall.height / CRUST_HEIGHT
        if not (math.isfinite(crust_depth) and crust_depth >= 0):
            raise ContinuumBackfillError(f"crust_depth must be >= 0 [m], got {crust_depth!r}")
        if not (math.isfinite(crust_cohesion) and crust_cohesion >= 0):
            raise ContinuumBackfillError(f"crust_cohesion must be >= 0 [Pa], got "
                                         f"{crust_cohesion!r}")
        kind = "mockup" if _is_mock(wall) else "full"
        e0, n0 = SEED_ELASTIC[kind]
        self.wall = wall
        self.W = 2.0 * wall.height if W is None else float(W)
        self.size = SIZE_FRACTION * wall.height if size is None else float(size)
        self.boundary = b
        self.stiffness_scale = float(stiffness_scale)
        self.crust_cohesion = float(crust_cohesion)
        self.crust_depth = float(crust_depth)
        self.crust_row_cohesion = math.nan  # the top row's, set when built
        self.E = e0 if E is None else float(E)
        self.nu = n0 if nu is None else float(nu)
        self.k_interface = SEED_INTERFACE_K[kind] * self.stiffness_scale
        self.settle_tol = float(settle_tol)
        if settle_steps is None:
            settle_steps = math.ceil(SETTLE_STEPS * max(1.0, math.sqrt(
                self.stiffness_scale / 1e-2)))
        elif isinstance(settle_steps, bool) or not isinstance(settle_steps, (int, np.integer)) \
                or settle_steps < 1:
            raise ContinuumBackfillError(f"settle_steps must be a positive integer, got "
                                         f"{settle_steps!r}")
        self.settle_steps = int(settle_steps)
        from murus.continuum.interface import CORNER_SHARES

        if corner_share not in CORNER_SHARES:
            raise ContinuumBackfillError(f"corner_share must be one of "
                                         f"{', '.join(CORNER_SHARES)}, got {corner_share!r}")
        self.corner_share = corner_share
        self.mesh = None
        self.zones = None
        self.interface = None
        self.coupled = None
        self.settle_result = None

    def _build(self, dw) -> None:
        from murus.continuum import ContinuumModel, MohrCoulomb
        from murus.continuum.coupled import CoupledModel
        from murus.continuum.interface import Interface
        from murus.continuum.mesh import polygon_region
        from murus.dem import Joint
        from murus.retaining.backfill import region_polygon

        wall, m = self.wall, dw.model
        mesh = polygon_region(region_polygon(wall, self.W), corners=(0, 1, 2, 3),
                              size=self.size, name="backfill")
        rho = wall.backfill_unit_weight / G
        common = {"density": rho, "E": self.E, "nu": self.nu,
                  "friction_deg": wall.backfill_friction_deg, "dilation_deg": 0.0}
        soil = MohrCoulomb(cohesion=0.0, **common)
        # the top row of zones: the zones with a gridpoint on the surface; the crust's
        # strength per metre (cohesion x depth) smeared over the row's mean thickness
        top = np.zeros(mesh.xy.shape[0], bool)
        top[mesh.side("backfill.top")] = True
        row = top[mesh.zones].any(axis=1)
        zmat = np.where(row, 1, 0)
        q = mesh.xy[mesh.zones[row]]  # (n, 4, 2): the row's area over the surface's length
        area = 0.5 * np.abs((q[..., 0] * np.roll(q[..., 1], -1, axis=1)
                             - np.roll(q[..., 0], -1, axis=1) * q[..., 1]).sum(axis=1)).sum()
        surf = mesh.xy[mesh.side("backfill.top")]
        surf = surf[np.argsort(surf[:, 0])]
        t_row = float(area / np.hypot(*np.diff(surf, axis=0).T).sum())
        self.crust_row_cohesion = self.crust_cohesion * min(1.0, self.crust_depth / t_row)
        crust = MohrCoulomb(cohesion=self.crust_row_cohesion, **common)
        zm = ContinuumModel(mesh.xy, mesh.zones, [soil, crust], zmat, gravity=m.gravity)
        # the far side on rollers for the static stage (its dynamic boundary comes after);
        # the bottom, its corners included, moves with the base
        zm.fix(mesh.side("backfill.right"), x=True, y=False)
        zm.set_base(mesh.side("backfill.bottom"))
        joint = Joint(kn=self.k_interface, ks=self.k_interface,
                      friction_deg=wall.interface_friction_deg)
        back = mesh.side("backfill.left")
        iface = Interface(zm, mesh.edges_of(back), m, joint, corner_share=self.corner_share)
        self.mesh, self.zones, self.interface = mesh, zm, iface
        self.coupled = CoupledModel(m, zm, iface)

    def settle(self, dw, external=None, built=None):
        """Build the zones and the interface on the wall ``dw``
        (:class:`~murus.retaining.dem_wall.DemWall`, built with ``backstop=False``), set the
        K0 stresses, settle blocks and zones (elastic, then plastic), then put the far side's
        dynamic boundary.

        Parameters
        ----------
        dw : murus.retaining.dem_wall.DemWall
            The wall.
        external : callable, optional
            The blocks' external-force hook during the settling (the collapse protocol's zero
            thrust, for its probes).
        built : callable, optional
            Called with this backfill once built, before the settling (a check of the
            caller's that needs the model, e.g. the subcycle's limit).

        Returns
        -------
        murus.dem.engine.SettleResult
        """
        self._build(dw)
        if built is not None:
            built(self)
        zm = self.zones
        zm.initial_stress_k0()
        st = self.coupled.settle(elastic_first=True, tol=self.settle_tol,
                                 max_steps=self.settle_steps, external=external)
        self.settle_result = st
        # the plastic state reported after the run is the one of the shaking: the settling's
        # yield (K0 to the active state at the wall, the crust) is forgotten (reporting only)
        from murus.continuum import kernels as K

        zm.zstate[:] &= K.ST_SHEAR_NOW | K.ST_TENSION_NOW
        right = self.mesh.side("backfill.right")
        side = right[zm.gfix[right, 1] == 0]  # the far side above the base corner
        if self.boundary == "free-field":
            zm.add_free_field([right])
        elif self.boundary == "quiet":  # dashpots on the velocity relative to the base
            zm.add_quiet(self.mesh.edges_of(right), frame="base", static=True)
        else:  # "fixed": a rigid side moving with the base
            zm.set_base(side, x=True, y=False)
        return st

    def thrust(self) -> tuple[float, float]:
        """The interface's force on the wall now: normal (horizontal for a vertical back) and
        shear sums [N per metre of wall].

        Returns
        -------
        tuple of float
        """
        return self.interface.normal_force(), self.interface.shear_force()

    def summary(self) -> dict:
        """JSON-ready description and measured values."""
        zm = self.zones
        out = {"model": "continuum", "W": self.W, "size": self.size,
               "boundary": self.boundary, "n_zones": None if zm is None else int(zm.nz),
               "E": self.E, "nu": self.nu, "crust_cohesion": self.crust_cohesion,
               "crust_depth": self.crust_depth, "crust_row_cohesion": self.crust_row_cohesion,
               "k_interface": self.k_interface,
               "settle": None if self.settle_result is None else self.settle_result.message}
        out["corner_share"] = self.corner_share
        return out
