"""Figures of continuum zones from plain arrays (matplotlib imported lazily, Agg by default).

``plot_x(..., ax=None) -> Axes`` as everywhere in murus; lengths in m. The zones are drawn as
one ``PolyCollection`` (one quadrilateral per zone, in the order of ``zones``), either coloured
by a per-zone field on a continuous scale with a colour bar (:func:`plot_zones`, e.g. a stress
component) or by the plastic state with a categorical legend as FLAC shows its plasticity
indicators (:func:`plot_plastic_state`). Both draw the deformed mesh ``xy + magnification *
displacement`` when a displacement is given (optionally over the undeformed mesh in grey
lines), and blocks beside the zones (a list of polygons, light grey, as
:func:`murus.dem.plots.plot_blocks` draws them without values).

References
----------
Itasca. FLAC manual, plots of zone plasticity indicators ("shear-n", "shear-p", "tension-n",
"tension-p") and of the deformed grid with a magnification factor.
"""

from __future__ import annotations

import numpy as np

from murus.continuum.vtk import STATE_BITS, _as_mesh

__all__ = ["plot_plastic_state", "plot_zones", "state_label"]

#: Colour of elastic zones (state 0) and of the blocks.
_ELASTIC = "white"
_BLOCKS = "0.75"
#: One colour per "now" / "past" category, as in FLAC's plasticity plots: red shades for yield
#: now, blue/green for past only.
_STATE_COLOURS = {1: "tab:red", 2: "tab:orange", 3: "tab:pink", 4: "tab:green",
                  8: "tab:blue", 12: "tab:cyan", 5: "firebrick", 6: "gold", 7: "salmon",
                  9: "darkorange", 10: "orangered", 11: "coral", 13: "crimson", 14: "khaki",
                  15: "peru"}


def _ax(ax):
    if ax is None:
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6.4, 4.8), layout="constrained")
    return ax


def state_label(state: int) -> str:
    """Name of a plastic-state value as FLAC lists it, e.g. ``"shear-n shear-p"``, or
    ``"elastic"`` for 0.

    Parameters
    ----------
    state : int
        Bit field (1 shear now, 2 tension now, 4 shear past, 8 tension past), 0..15.

    Returns
    -------
    str
        The label.

    References
    ----------
    Itasca, FLAC manual (zone state indicators).
    """
    s = int(state)
    if not 0 <= s <= 15:
        raise ValueError(f"state must be in 0..15, got {state!r}")
    names = [name for name, bit in STATE_BITS.items() if s & bit]
    return " ".join(names) if names else "elastic"


def _positions(xy, zones, displacement, magnification):
    p, z = _as_mesh(xy, zones)
    if displacement is None:
        return p, p, z
    d = np.asarray(displacement, dtype=np.float64)
    if d.shape != p.shape:
        raise ValueError(f"displacement has shape {d.shape}; expected {p.shape}, one (ux, uy) "
                         "per gridpoint")
    if not np.all(np.isfinite(d)):
        raise ValueError("displacement has non-finite values")
    m = float(magnification)
    if not np.isfinite(m):
        raise ValueError(f"magnification must be finite, got {magnification!r}")
    return p, p + m * d, z


def _blocks(blocks) -> list[np.ndarray]:
    out = []
    for i, b in enumerate(blocks or []):
        a = np.asarray(b, dtype=np.float64)
        if a.ndim != 2 or a.shape[1] != 2 or len(a) < 3 or not np.all(np.isfinite(a)):
            raise ValueError(f"block {i} must be a (k >= 3, 2) array of finite x, y [m]")
        out.append(a)
    return out


def _draw(ax, p0, p, z, blocks, show_edges, show_original):
    from matplotlib.collections import LineCollection, PolyCollection

    if show_original:
        ring = p0[np.concatenate([z, z[:, :1]], axis=1)]
        ax.add_collection(LineCollection(ring, colors="0.4", linewidths=0.5, linestyles="--",
                                         label="undeformed", zorder=3), autolim=True)
    edge = dict(edgecolor="k", linewidth=0.4) if show_edges else dict(edgecolor="face")
    zc = PolyCollection(p[z], closed=True, **edge)
    ax.add_collection(zc, autolim=True)
    bc = None
    if blocks:
        bc = PolyCollection(blocks, closed=True, facecolor=_BLOCKS, edgecolor="k", linewidth=0.6)
        ax.add_collection(bc, autolim=True)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    return zc, bc


def plot_zones(xy, zones, values=None, ax=None, displacement=None, magnification: float = 1.0,
               blocks=None, cmap: str = "viridis", label: str = "", show_edges: bool = True,
               show_original: bool = False):
    """Draw the zones, optionally coloured by a per-zone field and deformed.

    Parameters
    ----------
    xy : array (ng, 2)
        Gridpoint coordinates [m].
    zones : array (nz, 4) of int
        Gridpoint indices of each zone, counter-clockwise.
    values : array (nz,), optional
        Per-zone field (e.g. ``syy`` [Pa]) drawn through ``cmap`` from its minimum to its
        maximum with a colour bar labelled ``label`` (``NaN``: drawn as missing). Without it
        the zones are white with their edges.
    ax : matplotlib Axes, optional
        Axes to draw on (a new figure when ``None``).
    displacement : array (ng, 2), optional
        Gridpoint displacements [m]; the mesh is drawn at ``xy + magnification * displacement``.
    magnification : float
        Factor on the displacement [-] (FLAC's "magnification").
    blocks : list of (k, 2) arrays, optional
        Block polygons x, y [m] drawn beside the zones in light grey.
    cmap : str
        Colour map.
    label : str
        Colour-bar label, with units (e.g. ``"syy [Pa]"``).
    show_edges : bool
        Draw the zone edges.
    show_original : bool
        Draw the undeformed mesh in dashed grey lines over the deformed one.

    Returns
    -------
    matplotlib.axes.Axes
        The Axes; the zones are ``ax.collections`` entry returned first after the optional
        undeformed lines, and the colour bar is ``collection.colorbar``.

    References
    ----------
    Itasca, FLAC manual (contour plots of zone fields on the deformed grid).
    """
    from matplotlib.colors import Normalize

    p0, p, z = _positions(xy, zones, displacement, magnification)
    blk = _blocks(blocks)
    if values is not None:
        v = np.asarray(values, dtype=np.float64)
        if v.shape != (len(z),):
            raise ValueError(f"values have shape {v.shape}; expected ({len(z)},), one per zone")
    ax = _ax(ax)
    zc, _ = _draw(ax, p0, p, z, blk, show_edges, show_original)
    if values is None:
        zc.set_facecolor(_ELASTIC)
        return ax
    finite = v[np.isfinite(v)]
    lo, hi = (finite.min(), finite.max()) if len(finite) else (0.0, 1.0)
    zc.set_array(np.ma.masked_invalid(v))
    zc.set_cmap(cmap)
    zc.set_norm(Normalize(vmin=lo, vmax=hi))
    ax.figure.colorbar(zc, ax=ax, label=label)
    return ax


def plot_plastic_state(xy, zones, state, ax=None, displacement=None,
                       magnification: float = 1.0, blocks=None, show_edges: bool = True,
                       show_original: bool = False, legend: bool = True):
    """Draw the zones coloured by their plastic state, with a categorical legend (as FLAC).

    One colour and one legend entry per distinct state present (e.g. ``elastic``,
    ``shear-n shear-p``, ``tension-p``; :func:`state_label`), ordered by state value.

    Parameters
    ----------
    xy : array (ng, 2)
        Gridpoint coordinates [m].
    zones : array (nz, 4) of int
        Gridpoint indices, counter-clockwise.
    state : array (nz,) of int
        Plastic-state bit field: 1 shear now, 2 tension now, 4 shear past, 8 tension past.
    ax : matplotlib Axes, optional
        Axes to draw on.
    displacement : array (ng, 2), optional
        Gridpoint displacements [m] for the deformed mesh.
    magnification : float
        Factor on the displacement [-].
    blocks : list of (k, 2) arrays, optional
        Block polygons [m] drawn beside the zones.
    show_edges : bool
        Draw the zone edges.
    show_original : bool
        Draw the undeformed mesh in dashed grey.
    legend : bool
        Add the legend of the states present.

    Returns
    -------
    matplotlib.axes.Axes
        The Axes.

    References
    ----------
    Itasca, FLAC manual (plasticity indicators).
    """
    from matplotlib.patches import Patch

    p0, p, z = _positions(xy, zones, displacement, magnification)
    blk = _blocks(blocks)
    s = np.asarray(state)
    if s.shape != (len(z),) or s.dtype.kind not in "iu":
        raise ValueError(f"state must be ({len(z)},) integers, got {s.dtype} {s.shape}")
    if np.any((s < 0) | (s > 15)):
        raise ValueError("state values must be in 0..15 (bits 1, 2, 4, 8)")
    ax = _ax(ax)
    zc, _ = _draw(ax, p0, p, z, blk, show_edges, show_original)
    colours = {0: _ELASTIC, **_STATE_COLOURS}
    zc.set_facecolor([colours[int(v)] for v in s])
    if legend:
        present = sorted({int(v) for v in s})
        handles = [Patch(facecolor=colours[v], edgecolor="k", label=state_label(v))
                   for v in present]
        if blk:
            handles.append(Patch(facecolor=_BLOCKS, edgecolor="k", label="blocks"))
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0),
                  fontsize="small", title="plastic state")
    return ax
