"""Figures of ground motions and spectra (matplotlib imported lazily). ``plot_x(result, ax=None)
-> Axes``."""

from __future__ import annotations

import numpy as np


def _ax(ax):
    if ax is None:
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6.4, 4.0), layout="constrained")
    return ax


def plot_motion(motion, ax=None):
    """Acceleration history [m/s²] against time [s]."""
    ax = _ax(ax)
    ax.plot(motion.time, motion.acc, lw=0.7, label="horizontal")
    if motion.acc_v is not None:
        ax.plot(motion.time, motion.acc_v, lw=0.7, label="vertical")
        ax.legend()
    ax.set_xlabel("time [s]")
    ax.set_ylabel("acceleration [m/s²]")
    ax.set_title(motion.name)
    return ax


def plot_spectrum(spec, ax=None, label=None, what="psa"):
    """Pseudo-spectral acceleration [m/s²] against period [s]."""
    ax = _ax(ax)
    ax.plot(spec.period, getattr(spec, what), label=label or f"{spec.damping:.0%} damping")
    ax.set_xscale("log")
    ax.set_xlabel("period [s]")
    ax.set_ylabel(f"{what.upper()} [m/s²]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return ax


def plot_compatibility(report, ax=None, title="EN 1998-1 §3.2.3.1.2"):
    """Spectra of the records, their mean, the target and 90 % of the target in the range."""
    ax = _ax(ax)
    for s in report.spectra:
        ax.plot(report.periods, s, color="0.75", lw=0.6)
    ax.plot(report.periods, report.mean_psa, "k", lw=1.6, label="mean of records (5 %)")
    ax.plot(report.periods, report.target, "r", lw=1.4, label="EC8 elastic spectrum")
    ax.plot(report.periods, 0.9 * np.asarray(report.target), "r--", lw=1.0, label="90 % target")
    ax.set_xscale("log")
    ax.set_xlabel("period [s]")
    ax.set_ylabel("PSA [m/s²]")
    ax.set_title(f"{title}: {'PASS' if report.passed else 'FAIL'}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return ax
