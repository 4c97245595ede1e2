"""Rigid-block limit analysis (Livesley 1978; Gilbert, Casapulla and Ahmed 2006): the collapse
load factor, mechanism and joint forces of an assembly of rigid blocks, e.g. of a DEM case file
(:func:`analyse`, :func:`plot_mechanism`; ``murus limit CASE.toml`` on the command line).

>>> from murus.limit import Assembly, analyse
>>> base = [(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)]
>>> block = [(0, 0), (0.25, 0), (0.25, 1), (0, 1)]
>>> r = analyse(Assembly.from_polygons([base, block], supports=[0], friction_deg=40))
>>> round(r.load_factor, 6)
0.25

The names below are imported on first use (PEP 562), so that ``murus --help`` stays fast.

References
----------
Livesley, R. K. (1978). Limit analysis of structures formed from rigid blocks. Int. J. Numer.
Meth. Eng. 12(12), 1853-1871. doi:10.1002/nme.1620121207

Gilbert, M., Casapulla, C., Ahmed, H. M. (2006). Limit analysis of masonry block structures
with non-associative frictional joints using linear programming. Computers & Structures
84(13-14), 873-887. doi:10.1016/j.compstruc.2006.02.005
"""

from murus._lazy import lazy_exports

_EXPORTS = {
    "Assembly": "model",
    "Interfaces": "model",
    "LimitModelError": "model",
    "find_interfaces": "model",
    "from_case": "model",
    "LimitError": "solve",
    "LimitResult": "solve",
    "PointLoad": "solve",
    "analyse": "solve",
    "plot_mechanism": "plots",
    "retaining_limit": "retaining",
    "run_verification": "verify",
}

__all__ = sorted(_EXPORTS)

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
