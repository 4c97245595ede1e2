"""Figures of a 2D distinct-element model from plain arrays (matplotlib imported lazily).
``plot_x(..., ax=None) -> Axes``; lengths in m, times in s."""

from __future__ import annotations

import numpy as np

from murus.dem.vtk import _as_discs, _as_polygons


def _ax(ax):
    if ax is None:
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6.4, 4.8), layout="constrained")
    return ax


def plot_blocks(
    polygons,
    discs=None,
    values=None,
    ax=None,
    cmap="viridis",
    label="displacement [m]",
    show_edges=True,
):
    """Draw blocks: polygons ((k, 2) vertex arrays x, y [m]) as a ``PolyCollection`` and discs
    (``(centres (n, 2) [m], radii (n,) [m])``) as a ``PatchCollection`` of circles.

    ``values`` (one per polygon, then one per disc, in that order, as for
    :func:`murus.dem.vtk.write_vtp`) colour the blocks through ``cmap`` on one shared scale from
    their minimum to their maximum, with a colour bar labelled ``label``; without ``values``
    the blocks are light grey and there is no colour bar. Equal aspect; returns the Axes. The
    colour bar, when drawn, is reachable as ``ax.collections[0].colorbar``.
    """
    from matplotlib.collections import PatchCollection, PolyCollection
    from matplotlib.colors import Normalize
    from matplotlib.patches import Circle

    polys = _as_polygons(polygons)
    centres, radii = _as_discs(discs)
    n = len(polys) + len(centres)
    if values is not None:
        values = np.asarray(values, dtype=np.float64)
        if values.ndim != 1 or len(values) != n:
            raise ValueError(
                f"values have shape {values.shape}; expected ({n},): one per block "
                f"({len(polys)} polygons, then {len(centres)} discs)"
            )
    ax = _ax(ax)
    edge = dict(edgecolor="k", linewidth=0.5) if show_edges else dict(edgecolor="face")
    face = {} if values is not None else dict(facecolor="0.8")
    norm = None
    if values is not None:
        finite = values[np.isfinite(values)]
        lo, hi = (finite.min(), finite.max()) if len(finite) else (0.0, 1.0)
        norm = Normalize(vmin=lo, vmax=hi)
    cols = []
    if polys:
        pc = PolyCollection(polys, closed=True, **edge, **face)
        cols.append((pc, slice(0, len(polys))))
    if len(centres):
        circles = [Circle((float(x), float(y)), float(r)) for (x, y), r in zip(centres, radii,
                                                                               strict=True)]
        dc = PatchCollection(circles, match_original=False, **edge, **face)
        cols.append((dc, slice(len(polys), n)))
    for col, part in cols:
        if values is not None:
            col.set_array(values[part])
            col.set_cmap(cmap)
            col.set_norm(norm)
        ax.add_collection(col, autolim=True)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if values is not None and cols:
        ax.figure.colorbar(cols[0][0], ax=ax, label=label, shrink=0.8)
    return ax


def plot_history(t, series, ax=None):
    """Plot histories against time ``t`` [s]: ``series`` maps a label (with its unit, e.g.
    ``"top displacement [m]"``) to an array of ``len(t)`` values. One line per entry; with a
    single entry its label names the y axis. Returns the Axes."""
    t = np.asarray(t, dtype=np.float64)
    if t.ndim != 1:
        raise ValueError(f"t has shape {t.shape}; expected (n,)")
    if not series:
        raise ValueError("series is empty; give at least one {label: values}")
    data = {}
    for name, y in series.items():
        y = np.asarray(y, dtype=np.float64)
        if y.shape != t.shape:
            raise ValueError(f"series {name!r} has shape {y.shape} for {len(t)} times")
        data[name] = y
    ax = _ax(ax)
    for name, y in data.items():
        ax.plot(t, y, lw=0.9, label=str(name))
    ax.set_xlabel("time [s]")
    if len(data) == 1:
        ax.set_ylabel(str(next(iter(data))))
    else:
        ax.legend()
    ax.grid(True, alpha=0.3)
    return ax
