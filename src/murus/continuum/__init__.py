"""A 2D plane-strain continuum of quadrilateral zones next to the blocks (FLAC/UDEC style):
mixed discretisation (Marti & Cundall (1982)), Mohr-Coulomb plasticity with FLAC's return,
explicit central differences, local and mass-proportional damping, fixed, roller and
base-driven gridpoints, boundary pressures, gravity and K0 initial stresses.

- :class:`ContinuumModel` (:mod:`murus.continuum.model`): the model, from plain arrays of
  gridpoints and zones;
- :class:`Elastic`, :class:`MohrCoulomb` (:mod:`murus.continuum.materials`);
- :func:`settle`, :func:`run` (:mod:`murus.continuum.engine`);
- the kernels: :mod:`murus.continuum.kernels`.

The names below are imported on first use (PEP 562), so that ``murus --help`` does not load
numba.
"""

from murus._lazy import lazy_exports

_EXPORTS = {
    "ContinuumModel": "model",
    "ModelError": "model",
    "Elastic": "materials",
    "MohrCoulomb": "materials",
    "MaterialError": "materials",
    "elastic_constants": "materials",
    "settle": "engine",
    "run": "engine",
    "SettleResult": "engine",
    "RunResult": "engine",
    "RunError": "engine",
}

__all__ = sorted(_EXPORTS)

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals(),
                                    submodules=("mesh", "closed_forms", "vtk", "plots"))
