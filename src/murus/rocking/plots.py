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


def plot_response(result, axes=None):
    """Ground acceleration, rocking criterion RC (Mordant et al. (SERIES), eq. 9) and theta/alpha
    against time.

    ``axes``: three Axes, or ``None`` for a new figure. Returns the Axes."""
    ax = _axes(axes, 3)
    t = result.t
    ax[0].plot(t, result.ag / G, lw=0.8, color="0.3")
    ax[0].set_ylabel("a_g [g]")
    rc = result.rocking_criterion
    ax[1].plot(t, rc, lw=0.8, color="tab:blue")
    ax[1].axhline(1.0, color="tab:red", lw=0.8, ls="--", label="RC = 1 (uplift)")
    ax[1].set_ylabel("RC [-]")
    ax[1].legend(loc="upper right", fontsize=8)
    ax[2].plot(t, result.theta / result.alpha, lw=0.9, color="k")
    for name, v in LIMIT_STATES.items():
        for sgn in (1, -1):
            ax[2].axhline(sgn * v, color="tab:orange" if name == "limited" else "tab:red", lw=0.6,
                          ls=":", label=f"theta/alpha = {v} ({name})" if sgn == 1 else None)
    if result.overturned:
        ax[2].axvline(result.t_overturn, color="tab:red", lw=1.0, label="overturning")
    ax[2].set_ylabel("theta/alpha [-]")
    ax[2].set_xlabel("time [s]")
    ax[2].legend(loc="upper right", fontsize=7, ncol=2)
    title = (f"{result.meta.get('model', {}).get('body', {}).get('name', '')}: "
             f"max theta/alpha = {result.theta_max_over_alpha:.3f}, impacts = {result.n_impacts}"
             + (", overturned" if result.overturned else ""))
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
    ax.set_xlabel("theta/alpha")
    ax.set_ylabel("theta'/(p alpha)")
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
    ax[1].set_ylabel("theta/alpha [-]")
    ax[2].plot(t, result.contact_length, lw=0.8, label="contact length")
    ax[2].plot(t, result.lifted_length, lw=0.8, label="lifted length")
    ax[2].set_ylabel("length [m]")
    ax[2].set_xlabel("time [s]")
    ax[2].legend(loc="upper right", fontsize=7)
    name = result.meta.get("body", {}).get("name", "") if isinstance(result.meta, dict) else ""
    ax[0].set_title(f"{name} on an elastic layer: max theta/alpha = "
                    f"{result.theta_max_over_alpha:.3f}"
                    + (", overturned" if result.overturned else ""), fontsize=9)
    return ax
