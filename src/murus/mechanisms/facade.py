"""Mechanisms of a façade of one or several storeys: every hinge level of the simple overturning,
the vertical flexure of a storey (hinge height minimising alpha0), and the governing result.
"""

from __future__ import annotations

import math

import numpy as np

from murus.mechanisms.checks import MechanismResult, Seismic, analyse
from murus.mechanisms.kinematics import (
    Floor,
    MechanismError,
    SimpleOverturning,
    Storey,
    VerticalFlexure,
    alpha,
)

__all__ = ["overturning", "vertical_flexure", "flexure_of_storey", "governing",
           "plot_capacity"]


def overturning(storeys, floors, seismic: Seismic, n: int = 101,
                ties_in_curve: bool = False, slices: int = 1,
                verdict: str = "code") -> list[MechanismResult]:
    """Simple overturning with the hinge at the base of each storey in turn (the storeys above
    it move as one block); one result per hinge level, bottom first.

    Parameters
    ----------
    storeys : sequence of Storey
        Bottom to top.
    floors : sequence of Floor
    seismic : Seismic
    n : int
        Points of each capacity curve.
    ties_in_curve : bool
        Keep the ties in the capacity curves (:func:`murus.mechanisms.checks.analyse`).
    slices : int
        Horizontal slices per storey (:class:`murus.mechanisms.kinematics.SimpleOverturning`).
    verdict : str
        ``"code"`` or ``"all"`` (:func:`murus.mechanisms.checks.analyse`).

    Returns
    -------
    list of MechanismResult
        The governing one is :func:`governing` of the list.
    """
    storeys = [s if isinstance(s, Storey) else Storey(**s) for s in storeys]
    floors = [f if isinstance(f, Floor) else Floor(**f) for f in floors]
    out = []
    for k in range(len(storeys)):
        out.append(analyse(SimpleOverturning(storeys, floors, hinge=k, slices=slices), seismic,
                           n, ties_in_curve, verdict))
    return out


def _flexure_alpha0(base: dict, h1: float) -> float:
    return alpha(VerticalFlexure(h1=h1, **base), 0.0)


def vertical_flexure(height: float, thickness: float, weight: float, seismic: Seismic,
                     top_load: float = 0.0, top_load_x: float | None = None,
                     top_inertial: bool = False, z0: float = 0.0, n: int = 101,
                     grid: int = 199, verdict: str = "code") -> MechanismResult:
    """Vertical flexure of a wall restrained at top and bottom, with the intermediate hinge at
    the height that minimises alpha0 (a grid of ``grid`` heights refined by golden section).

    Parameters
    ----------
    height, thickness : float
        Wall height and thickness [m].
    weight : float
        Wall weight [N].
    seismic : Seismic
    top_load, top_load_x, top_inertial, z0
        As for :class:`murus.mechanisms.kinematics.VerticalFlexure`.
    n : int
        Points of the capacity curve.
    grid : int
        Hinge heights of the first search.
    verdict : str
        ``"code"`` or ``"all"`` (:func:`murus.mechanisms.checks.analyse`).

    Returns
    -------
    MechanismResult
        ``info["h1"]`` is the hinge height [m].
    """
    base = {"height": height, "thickness": thickness, "weight": weight, "top_load": top_load,
            "top_load_x": top_load_x, "top_inertial": top_inertial, "z0": z0}
    VerticalFlexure(h1=0.5 * height, **base)  # validates
    hs = np.linspace(0.0, height, grid + 2)[1:-1]
    vals = np.array([_flexure_alpha0(base, float(h)) for h in hs])
    i = int(np.argmin(vals))
    lo, hi = hs[max(i - 1, 0)], hs[min(i + 1, len(hs) - 1)]
    g = (math.sqrt(5) - 1) / 2
    for _ in range(40):
        c, d = hi - g * (hi - lo), lo + g * (hi - lo)
        if _flexure_alpha0(base, c) < _flexure_alpha0(base, d):
            hi = d
        else:
            lo = c
    h1 = 0.5 * (lo + hi)
    res = analyse(VerticalFlexure(h1=h1, **base), seismic, n, verdict=verdict)
    res.info["h1"] = h1
    return res


def flexure_of_storey(storeys, floors, index: int, seismic: Seismic, n: int = 101,
                      verdict: str = "code"):
    """Vertical flexure of the storey ``index`` (0-based) of a façade: the top load is the weight
    of the storeys above (at the middle of the storey above) and the loads of the floors at its
    top level and above, without horizontal inertia (the floor above restrains the top).

    Parameters
    ----------
    storeys : sequence of Storey
    floors : sequence of Floor
    index : int
        The storey (0-based).
    seismic : Seismic
    n : int
        Points of the capacity curve.
    verdict : str
        ``"code"`` or ``"all"`` (:func:`murus.mechanisms.checks.analyse`).

    Returns
    -------
    MechanismResult
    """
    storeys = [s if isinstance(s, Storey) else Storey(**s) for s in storeys]
    floors = [f if isinstance(f, Floor) else Floor(**f) for f in floors]
    if not 0 <= index < len(storeys):
        raise MechanismError(f"storey must be in 1..{len(storeys)}", key=("storey",))
    s = storeys[index]
    load, moment = 0.0, 0.0
    for above in storeys[index + 1:]:
        load += above.W
        moment += above.W * 0.5 * min(above.thickness, s.thickness)
    for f in floors:
        if f.level >= index + 1 and f.load > 0:
            x = 0.5 * storeys[f.level - 1].thickness if f.x is None else f.x
            load += f.load
            moment += f.load * min(x, s.thickness)
    x = moment / load if load > 0 else None
    z0 = float(sum(t.height for t in storeys[:index]))
    res = vertical_flexure(s.height, s.thickness, s.W, seismic, top_load=load, top_load_x=x,
                           z0=z0, n=n, verdict=verdict)
    res.name = f"vertical flexure of storey {index + 1}"
    return res


def governing(results) -> MechanismResult:
    """The result with the smallest capacity / demand ratio.

    Parameters
    ----------
    results : sequence of MechanismResult

    Returns
    -------
    MechanismResult
    """
    return min(results, key=lambda r: r.ratio)


def plot_capacity(result: MechanismResult, ax=None, seismic: Seismic | None = None):
    """Capacity curve a*(d*) of ``result`` with the displacement capacities and demands of its
    nonlinear checks (vertical lines) and the linear activation demand (horizontal lines).

    Parameters
    ----------
    result : MechanismResult
    ax : matplotlib.axes.Axes, optional
    seismic : Seismic, optional
        The seismic input of the checks: adds the SLV demand spectrum in the acceleration-
        displacement plane (ground spectrum, or the floor spectrum of §C7.2.3 at the height of
        the mechanism, damping 8 %) and the secant line at T_SLV.

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(6, 4))
    c = result.curve
    ax.plot(np.asarray(c["d_star"]) * 1e3, c["a_star"], "k-", label="capacity a*(d*)")
    colors = {"SLD": "tab:green", "SLV": "tab:orange", "SLC": "tab:red"}
    for ch in result.checks:
        col = colors.get(ch.limit_state, "tab:blue")
        if ch.method == "linear":
            ax.axhline(ch.demand, color=col, ls=":", lw=1,
                       label=f"{ch.limit_state} linear demand {ch.demand:.2f} m/s2")
        else:
            ax.axvline(ch.capacity * 1e3, color=col, ls="-", lw=1,
                       label=f"d_{ch.limit_state} = {ch.capacity * 1e3:.1f} mm")
            ax.axvline(ch.demand * 1e3, color=col, ls="--", lw=1,
                       label=f"{ch.limit_state} demand {ch.demand * 1e3:.1f} mm")
    nl = [ch for ch in result.checks if ch.method == "nonlinear" and ch.limit_state == "SLV"]
    if seismic is not None and nl:
        from murus.mechanisms.demand import floor_spectrum

        sp = seismic.spectra["SLV"]
        T = np.linspace(0.05, 4.0, 200)
        xi = nl[0].details["damping"]
        if result.z > 0 and seismic.building is not None:
            a = np.maximum(floor_spectrum(sp, seismic.building, result.z, T, xi), sp.Se(T, xi))
        else:
            a = np.asarray(sp.Se(T, xi))
        d = a * T ** 2 / (4 * math.pi ** 2)
        dmax = 1.5 * max(float(np.max(c["d_star"])), nl[0].demand)
        keep = d <= dmax
        ax.plot(d[keep] * 1e3, a[keep], color="tab:orange", lw=1, alpha=0.7,
                label=f"SLV demand spectrum, xi = {100 * xi:g} %")
        Ts = nl[0].details["T"]
        dd = np.array([0.0, nl[0].demand])
        ax.plot(dd * 1e3, dd * 4 * math.pi ** 2 / Ts ** 2, color="tab:gray", lw=0.8,
                ls="-.", label=f"T_SLV = {Ts:.2f} s")
    ax.set_xlabel("d* [mm]")
    ax.set_ylabel("a* [m/s2]")
    ax.set_xlim(left=0)
    lin = [ch.demand for ch in result.checks if ch.method == "linear"]
    ax.set_ylim(0, max([2.0 * float(np.max(c["a_star"]))] + [1.3 * x for x in lin]))
    ax.set_title(f"{result.name}: ratio {result.ratio:.2f} "
                 f"({'PASS' if result.passed else 'FAIL'})")
    ax.legend(fontsize=7)
    return ax
