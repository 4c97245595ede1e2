"""Figure of a collapse mechanism (matplotlib imported lazily): ``plot_mechanism(result,
ax=None) -> Axes``; lengths in m."""

from __future__ import annotations

import numpy as np


def displaced_polygons(result, scale: float) -> list:
    """The polygons of ``result.assembly`` moved by ``scale`` [s] times the mechanism's
    velocities (small-rotation kinematics: each block rotates about its centroid by
    ``scale x omega`` and translates by ``scale x (u, v)``)."""
    asm = result.assembly
    out = []
    for v, b in zip(asm.polygons, asm.body, strict=True):
        u, w, om = scale * result.mechanism[b]
        c = asm.centroid[b]
        co, si = np.cos(om), np.sin(om)
        r = v - c
        out.append(c + np.column_stack([co * r[:, 0] - si * r[:, 1],
                                        si * r[:, 0] + co * r[:, 1]]) + (u, w))
    return out


def plot_mechanism(result, ax=None, scale=None):
    """Draw the blocks of a :class:`murus.limit.LimitResult` at rest (outlined, light) and
    displaced by the collapse mechanism (filled; supports dark grey).

    Parameters
    ----------
    result : LimitResult
        A solved assembly.
    ax : matplotlib.axes.Axes, optional
        Where to draw (a new figure by default).
    scale : float, optional
        Displacement [m] drawn for a unit velocity of the mechanism (default: 10 % of the
        height of the assembly).

    Returns
    -------
    matplotlib.axes.Axes
    """
    from matplotlib.collections import PolyCollection

    if ax is None:
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6.4, 4.8), layout="constrained")
    asm = result.assembly
    allv = np.concatenate(asm.polygons)
    if scale is None:
        scale = 0.1 * float(np.ptp(allv[:, 1]) or np.ptp(allv[:, 0]) or 1.0)
    sup = asm.support[asm.body]
    moved = displaced_polygons(result, scale)
    ax.add_collection(PolyCollection(asm.polygons, facecolors="none", edgecolors="0.7",
                                     linewidths=0.5))
    colors = np.where(sup, "0.35", "tan")
    ax.add_collection(PolyCollection(moved, facecolors=list(colors), edgecolors="k",
                                     linewidths=0.5, alpha=0.9))
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    what = (f"tilt {result.angle_deg:.3f} deg" if result.load == "tilt"
            else f"load factor {result.load_factor:.4g}")
    ax.set_title(f"collapse mechanism ({what}, {result.friction} friction)")
    return ax
