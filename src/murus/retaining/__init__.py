"""Dry-stone retaining walls (seed 001): geometry, earth thrust, pseudo-static limit equilibrium.

- :mod:`murus.retaining.geometry`: the cross-section, its bed joints, the walls DSRW1-4 of
  seed 001 Table 5 and the scaled-down mock-ups of its §3;
- :mod:`murus.retaining.wedge`: trial-wedge (Coulomb) thrust for planar or broken backfills;
- :mod:`murus.retaining.pseudostatic`: sliding and overturning above every bed joint, the
  pseudo-static resistance ``A_pseudo`` (seed 001 §4.4, Table 8) and the tilting-table
  equivalence;
- :mod:`murus.retaining.cli`: ``murus retaining pseudo-static`` and ``geometry``.

The EN 1998-5 Annex E earth pressure itself is in :mod:`murus.eurocode.ec8_5`. The names below
are imported on first use (PEP 562), so that the command line stays light.

>>> from murus.retaining import critical_acceleration, preset
>>> round(critical_acceleration(preset("DSRW1")).A_pseudo, 2)   # seed 001 Table 8: 1.58
1.59
"""

from importlib import import_module

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
    "WedgeError": "wedge",
    "WedgeResult": "wedge",
    "trial_wedge": "wedge",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        value = getattr(import_module(f"murus.retaining.{_EXPORTS[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'murus.retaining' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
