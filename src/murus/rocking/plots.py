"""Figures of rocking results: functions ``plot_x(result, ax=None) -> Axes`` (GUIDE §1)."""

from __future__ import annotations

import numpy as np

from murus import G
from murus.rocking.summary import LIMIT_STATES


def _axes(ax, n=1):
    import matplotlib.pyplot as plt

    if ax is not None:
        return ax
    fig, axes = plt.subplots(n, 1, figsize=(8, 2.2 * n + 0.6), sharex=True, squeeze=False)
    fig.set_layout_engine("constrained")
    return axes[:, 0] if n > 1 else axes[0, 0]


def _free(result) -> bool:
    """A run without ground motion (free vibration from an initial rotation)."""
    av = getattr(result, "av", None)
    return not np.any(result.ag) and (av is None or not np.any(av))


#: Axis labels that say what the symbols are.
THETA_LABEL = "θ/α [-]\n(rotation / slenderness α)"
RC_LABEL = "RC [-]\n(|a_g| z_G / ((g + a_v) b/2))"
OVERTURNED_NOTE = "overturned: θmax/α reported as π/(2α)"


def plot_response(result, axes=None):
    """Ground acceleration, rocking criterion RC (Mordant et al. (SERIES), eq. 9) and theta/alpha
    against time; a free vibration (no ground motion) draws theta/alpha alone.

    ``axes``: three Axes (one for a free vibration), or ``None`` for a new figure. Returns the
    Axes (a list of one for a free vibration)."""
    t = result.t
    if _free(result):
        ax = [axes[0] if axes is not None and np.ndim(axes) else (axes or _axes(None, 1))]
        th_ax = ax[0]
    else:
        ax = _axes(axes, 3)
        ax[0].plot(t, result.ag / G, lw=0.8, color="0.3")
        ax[0].set_ylabel("ground acceleration\na_g [g]")
        rc = result.rocking_criterion
        ax[1].plot(t, rc, lw=0.8, color="tab:blue")
        ax[1].axhline(1.0, color="tab:red", lw=0.8, ls="--", label="RC = 1: uplift of a "
                      "free-standing body")
        ax[1].set_ylabel(RC_LABEL)
        ax[1].legend(loc="upper right", fontsize=8)
        th_ax = ax[2]
    th_ax.plot(t, result.theta / result.alpha, lw=0.9, color="k")
    for name, v in LIMIT_STATES.items():
        for sgn in (1, -1):
            th_ax.axhline(sgn * v, color="tab:orange" if name == "limited" else "tab:red",
                          lw=0.6, ls=":",
                          label=f"θ/α = ±{v} ({name} rocking)" if sgn == 1 else None)
    if result.overturned:
        th_ax.axvline(result.t_overturn, color="tab:red", lw=1.0, label="overturning")
    th_ax.set_ylabel(THETA_LABEL)
    th_ax.set_xlabel("time [s]")
    th_ax.legend(loc="upper right", fontsize=8, ncol=2)
    name = result.meta.get("model", {}).get("body", {}).get("name", "")
    kind = ""
    if _free(result):
        th0 = result.meta.get("solver", {}).get("theta0")
        kind = ("free vibration" + (f" from θ0/α = {th0 / result.alpha:.3g}"
                                    if th0 is not None else "") + ", ")
    title = (f"{name}: {kind}max θ/α = {result.theta_max_over_alpha:.3f}, impacts = "
             f"{result.n_impacts}" + (f" ({OVERTURNED_NOTE})" if result.overturned else ""))
    ax[0].set_title(title, fontsize=9)
    return ax


def plot_energy(result, ax=None):
    """Kinetic, potential and dissipated energy [J] against time."""
    ax = _axes(ax)
    ax.plot(result.t, result.kinetic_energy, label="kinetic", lw=0.8)
    ax.plot(result.t, result.potential_energy, label="potential", lw=0.8)
    ax.plot(result.t, result.dissipated_energy, label="dissipated at impacts", lw=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("energy [J]")
    ax.legend(fontsize=8)
    return ax


def plot_phase(result, ax=None):
    """Phase portrait theta/alpha against theta'/p alpha."""
    ax = _axes(ax)
    ax.plot(result.theta / result.alpha, np.nan_to_num(result.omega) / (result.p * result.alpha),
            lw=0.6)
    ax.set_xlabel("θ/α [-] (rotation / slenderness α)")
    ax.set_ylabel("θ'/(p α) [-] (p = √(m g R / I_O))")
    return ax


def plot_winkler(result, axes=None):
    """A body on an elastic layer: ground acceleration, theta/alpha, and the contact length
    with the lifted length (Mordant et al. (SERIES), Figures 19-20) against time. Returns the
    Axes."""
    ax = _axes(axes, 3)
    t = result.t
    ax[0].plot(t, result.ag / G, lw=0.8, color="0.3")
    ax[0].set_ylabel("a_g [g]")
    ax[1].plot(t, result.theta / result.alpha, lw=0.9, color="k")
    ax[1].set_ylabel(THETA_LABEL)
    ax[2].plot(t, result.contact_length, lw=0.8, label="contact length")
    ax[2].plot(t, result.lifted_length, lw=0.8, label="lifted length")
    ax[2].set_ylabel("length [m]")
    ax[2].set_xlabel("time [s]")
    ax[2].legend(loc="upper right", fontsize=7)
    name = result.meta.get("body", {}).get("name", "") if isinstance(result.meta, dict) else ""
    ax[0].set_title(f"{name} on an elastic layer: max θ/α = "
                    f"{result.theta_max_over_alpha:.3f}"
                    + (f" ({OVERTURNED_NOTE})" if result.overturned else ""), fontsize=9)
    return ax
