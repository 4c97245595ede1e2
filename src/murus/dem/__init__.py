"""2D distinct elements (UDEC-like) for block masonry: rigid convex polygons, clumps and discs,
Mohr-Coulomb joints with rounded corners, explicit central differences (Savalle et al. (2022), eqs.
2-4), local and mass-proportional damping, kinematic bases driven by ground motions, monitors,
energy balance and checkpoints; disc packings (:mod:`murus.dem.packing`), absorbing
boundaries and boundary forces (:mod:`murus.dem.boundary`).

Conventions (details in :mod:`murus.dem.model`, :mod:`murus.dem.kernels`,
:mod:`murus.dem.engine`): SI units; x horizontal, y up, gravity -y; angles counter-clockwise;
per unit out-of-plane thickness unless ``Model(thickness=...)``.

The names below are imported on first use (PEP 562), so that ``murus --help`` does not load
numba.
"""

from murus._lazy import lazy_exports

_EXPORTS = {
    "Joint": "materials",
    "JointError": "materials",
    "Model": "model",
    "ModelError": "model",
    "polygon_properties": "model",
    "Probe": "engine",
    "RunResult": "engine",
    "SettleResult": "engine",
    "body_probe": "engine",
    "relative_probe": "engine",
    "tilt_probe": "engine",
    "stop_when": "engine",
    "run_verification": "verify",
    "PackingError": "packing",
    "disc_grid": "packing",
    "check_overlap": "packing",
    "solid_fraction": "packing",
    "AbsorbingBoundary": "boundary",
    "wall_thrust": "boundary",
    "contact_forces_from": "boundary",
}

__all__ = sorted(_EXPORTS)


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
