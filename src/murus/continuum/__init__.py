"""A 2D plane-strain continuum of quadrilateral zones next to the blocks (FLAC/UDEC style):
mixed discretisation (Marti & Cundall (1982)), Mohr-Coulomb plasticity with FLAC's return,
explicit central differences, local and mass-proportional damping, fixed, roller and
base-driven gridpoints, boundary pressures, gravity and K0 initial stresses.

- :class:`ContinuumModel` (:mod:`murus.continuum.model`): the model, from plain arrays of
  gridpoints and zones;
- :class:`Elastic`, :class:`MohrCoulomb` (:mod:`murus.continuum.materials`);
- :func:`settle`, :func:`run` (:mod:`murus.continuum.engine`);
- free-field sides (:mod:`murus.continuum.freefield`), zone-block interfaces
  (:class:`Interface`, :mod:`murus.continuum.interface`) and blocks and zones in one time loop
  (:class:`CoupledModel`, :mod:`murus.continuum.coupled`);
- meshing (:mod:`murus.continuum.mesh`), case files (:mod:`murus.continuum.case`), closed forms
  and verification (:mod:`murus.continuum.closed_forms`, :mod:`murus.continuum.verify`), VTK
  and figures (:mod:`murus.continuum.vtk`, :mod:`murus.continuum.plots`);
- the kernels: :mod:`murus.continuum.kernels`.

The names below are imported on first use (PEP 562), so that ``murus --help`` does not load
numba.
"""

from murus._lazy import lazy_exports

#: The interface's default corner rule (``corner_share`` of :class:`Interface`: "shrink", a
#: loaded corner's share of a stone's face follows the coverage rule down only), also the
#: default of the continuum backfill (:mod:`murus.retaining.continuum_backfill`) and the rule
#: :func:`murus.retaining.collapse.subcycle_refused` assumes: one constant, here where none of
#: them loads numba to read it.
DEFAULT_CORNER_SHARE = "shrink"

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
    "Interface": "interface",
    "CoupledModel": "coupled",
    "build_free_field": "freefield",
}

__all__ = sorted(_EXPORTS)

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals(),
                                    submodules=("mesh", "closed_forms", "vtk", "plots", "freefield",
                                                "interface", "coupled", "case", "verify"))
