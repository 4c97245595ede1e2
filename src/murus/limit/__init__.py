"""Rigid-block limit analysis (Livesley 1978; Gilbert, Casapulla and Ahmed 2006): the collapse
load factor, mechanism and joint forces of an assembly of rigid blocks, e.g. of a DEM case file.

>>> from murus.limit import Assembly, analyse
>>> base = [(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)]
>>> block = [(0, 0), (0.25, 0), (0.25, 1), (0, 1)]
>>> r = analyse(Assembly.from_polygons([base, block], supports=[0], friction_deg=40))
>>> round(r.load_factor, 6)
0.25

References
----------
Livesley, R. K. (1978). Limit analysis of structures formed from rigid blocks. Int. J. Numer.
Meth. Eng. 12(12), 1853-1871. doi:10.1002/nme.1620121207

Gilbert, M., Casapulla, C., Ahmed, H. M. (2006). Limit analysis of masonry block structures
with non-associative frictional joints using linear programming. Computers & Structures
84(13-14), 873-887. doi:10.1016/j.compstruc.2006.02.005
"""

from murus.limit.model import Assembly, Interfaces, LimitModelError, find_interfaces, from_case
from murus.limit.solve import LimitError, LimitResult, PointLoad, analyse

__all__ = ["Assembly", "Interfaces", "LimitError", "LimitModelError", "LimitResult", "PointLoad",
           "analyse", "find_interfaces", "from_case", "plot_mechanism"]


def plot_mechanism(result, ax=None, scale=None):
    """See :func:`murus.limit.plots.plot_mechanism` (imports matplotlib when called)."""
    from murus.limit.plots import plot_mechanism as _plot

    return _plot(result, ax=ax, scale=scale)
