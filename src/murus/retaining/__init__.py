"""Dry-stone retaining walls (Savalle et al. (2022)): geometry, earth thrust, pseudo-static limit
equilibrium.

- :mod:`murus.retaining.geometry`: the cross-section, its bed joints, the walls DSRW1-4 of
  Savalle et al. (2022), Table 5 and the scaled-down mock-ups of its §3;
- :mod:`murus.retaining.wedge`: trial-wedge (Coulomb) thrust for planar or broken backfills;
- :mod:`murus.retaining.pseudostatic`: sliding and overturning above every bed joint, the
  pseudo-static resistance ``A_pseudo`` (Savalle et al. (2022), §4.4, Table 8) and the tilting-table
  equivalence;
- :mod:`murus.retaining.dem_wall`: the distinct-element model of the wall (stones in running
  bond on the inclined beds) with the equivalent EN 1998-5 Annex E thrust;
- :mod:`murus.retaining.backfill`: the fully discrete granular backfill (discs) behind the DEM
  wall, with a container or an absorbing lateral boundary;
- :mod:`murus.retaining.collapse`: the collapse protocol (S2 ramps, ``A_col``, S1 checks) and
  the behaviour factor ``r`` (Savalle et al. (2022), §4.2-4.4, Tables 7-8);
- :mod:`murus.retaining.cli`: ``murus retaining pseudo-static``, ``geometry``, ``collapse``,
  ``behaviour-factor``.

The EN 1998-5 Annex E earth pressure itself is in :mod:`murus.eurocode.ec8_5`. The names below
are imported on first use (PEP 562), so that the command line stays light.

>>> from murus.retaining import critical_acceleration, preset
>>> round(critical_acceleration(preset("DSRW1")).A_pseudo, 2)   # Savalle et al. (2022): 1.58
1.59
"""

from murus._lazy import lazy_exports

_EXPORTS = {
    "MOCKUP_SLENDERNESS": "geometry",
    "PRESETS": "geometry",
    "BedJoint": "geometry",
    "GeometryError": "geometry",
    "RetainingWall": "geometry",
    "WallPart": "geometry",
    "mockup": "geometry",
    "preset": "geometry",
    "Assumptions": "pseudostatic",
    "JointCheck": "pseudostatic",
    "PseudoStaticError": "pseudostatic",
    "PseudoStaticResult": "pseudostatic",
    "check_joint": "pseudostatic",
    "check_joints": "pseudostatic",
    "critical_acceleration": "pseudostatic",
    "critical_tilt": "pseudostatic",
    "safety_curves": "pseudostatic",
    "tilt_coefficients": "pseudostatic",
    "tilt_from_coefficients": "pseudostatic",
    "DemWall": "dem_wall",
    "EquivalentThrust": "dem_wall",
    "build_wall": "dem_wall",
    "BackfillError": "backfill",
    "DiscreteBackfill": "backfill",
    "AbsorbingBoundary": "backfill",
    "generate_packing": "backfill",
    "BehaviourTable": "collapse",
    "CollapseResult": "collapse",
    "behaviour_factor": "collapse",
    "collapse_run": "collapse",
    "peak_ratio_check": "collapse",
    "WedgeError": "wedge",
    "WedgeResult": "wedge",
    "trial_wedge": "wedge",
}

__all__ = sorted(_EXPORTS)


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
