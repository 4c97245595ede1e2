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
    units = {"sd": "m", "sv": "m/s", "psv": "m/s"}.get(what, "m/s²")
    ax.set_ylabel(f"{what.upper()} [{units}] ({spec.damping:.0%} damping)")
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


def plot_histories(motion, axes=None, corrected: bool = True):
    """Acceleration [m/s²], velocity [m/s] and displacement [m] against time [s] (three Axes,
    shared time axis), the peaks marked. Velocity and displacement are integrated from rest,
    after the end correction of :data:`murus.motion.measures.BASELINE` when ``corrected``
    (the PGV and PGD that ``murus motion info`` and ``plot`` report)."""
    if axes is None:
        import matplotlib

        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        _, axes = plt.subplots(3, 1, sharex=True, figsize=(6.4, 6.0), layout="constrained")
    t = motion.time
    if corrected:
        from murus.motion.processing import end_correction

        c = end_correction(motion)
        v, d = c.velocity(), c.displacement()
    else:
        v, d = motion.velocity(), motion.displacement()
    tag = "\n(end-corrected)" if corrected else "\n(uncorrected)"
    for ax, y, lab in zip(axes, (motion.acc, v, d), ("acceleration [m/s²]",
                                                     "velocity [m/s]" + tag,
                                                     "displacement [m]" + tag), strict=True):
        ax.plot(t, y, lw=0.7, color="k")
        i = int(np.argmax(np.abs(y)))
        ax.plot(t[i], y[i], "o", ms=4, color="tab:red")
        ax.annotate(f"{abs(y[i]):.3g}", (t[i], y[i]), xytext=(4, 4),
                    textcoords="offset points", fontsize=8, color="tab:red")
        ax.set_ylabel(lab)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    return axes


def plot_husid(motion, ax=None):
    """Husid plot: the normalised Arias intensity [-] against time [s], with the 5-95 %
    significant duration D5-95 shaded."""
    from murus.motion.measures import arias, d5_95, husid

    ax = _ax(ax)
    h = husid(motion)
    t = motion.time
    ax.plot(t, h, color="k", lw=1.0)
    t5 = float(np.interp(0.05, h, t))
    d = d5_95(motion)
    ax.axvspan(t5, t5 + d, color="tab:blue", alpha=0.15, label=f"D5-95 = {d:.2f} s")
    ax.axhline(0.05, color="0.6", lw=0.6, ls="--")
    ax.axhline(0.95, color="0.6", lw=0.6, ls="--")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("normalised Arias intensity [-]")
    ax.set_title(f"Husid plot (I_A = {arias(motion):.3g} m/s)")
    ax.legend(loc="lower right")
    ax.grid(True, alpha=0.3)
    return ax


def plot_fourier(motion, ax=None):
    """Fourier amplitude spectrum of the acceleration [m/s] against frequency [Hz] (log-log)."""
    from murus.motion.measures import fourier_amplitude

    ax = _ax(ax)
    f, c = fourier_amplitude(motion)
    ax.loglog(f[1:], c[1:], lw=0.6, color="k")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("Fourier amplitude [m/s]")
    ax.set_title("Fourier amplitude spectrum")
    ax.grid(True, which="both", alpha=0.3)
    return ax


def plot_damped_spectra(spectra, ax=None):
    """Pseudo-spectral acceleration [m/s²] against period [s] for several dampings, one line
    each, labelled with its damping (``spectra``: ResponseSpectrum objects)."""
    ax = _ax(ax)
    for sp in spectra:
        ax.plot(sp.period, sp.psa, lw=1.0, label=f"{sp.damping:.0%} damping")
    ax.set_xscale("log")
    ax.set_xlabel("period [s]")
    ax.set_ylabel("PSA [m/s²]")
    ax.set_title("Response spectra (pseudo-acceleration)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return ax


def plot_record(motion, spectra, measures: dict | None = None):
    """One figure of a record: acceleration, velocity and displacement histories (left), the
    Husid plot, the Fourier amplitude spectrum and the response spectra at several dampings
    (right), the intensity measures (:data:`murus.motion.measures.MEASURES`; PGV and PGD after
    the end correction, as the histories) in the title block. Returns the Figure."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from murus.motion.measures import MEASURES

    fig = plt.figure(figsize=(12.0, 8.5), layout="constrained")
    gs = fig.add_gridspec(3, 2)
    left = [fig.add_subplot(gs[0, 0])]
    left += [fig.add_subplot(gs[i, 0], sharex=left[0]) for i in (1, 2)]
    plot_histories(motion, left)
    plot_husid(motion, fig.add_subplot(gs[0, 1]))
    plot_fourier(motion, fig.add_subplot(gs[1, 1]))
    plot_damped_spectra(spectra, fig.add_subplot(gs[2, 1]))
    title = motion.name or "record"
    if measures:
        parts = [f"{MEASURES[k][0].split(' (')[0]} {v:.3g} {MEASURES[k][1]}"
                 for k, v in measures.items() if k in MEASURES]
        half = (len(parts) + 1) // 2
        title += "\n" + ",  ".join(parts[:half]) + "\n" + ",  ".join(parts[half:])
    fig.suptitle(title, fontsize=10)
    return fig


def plot_rotd(spec, psa_a=None, psa_b=None, ax=None, names=("a", "b")):
    """RotD50 and RotD100 [m/s²] against period [s] (a :class:`murus.motion.components.
    RotDSpectrum`), with the spectra of the two components when given (same periods)."""
    ax = _ax(ax)
    T = spec.period
    if psa_a is not None:
        ax.plot(T, psa_a, lw=0.7, color="0.6", label=f"component a ({names[0]})")
    if psa_b is not None:
        ax.plot(T, psa_b, lw=0.7, color="0.6", ls="--", label=f"component b ({names[1]})")
    ax.plot(T, spec[50], lw=1.4, color="C0", label="RotD50")
    ax.plot(T, spec[100], lw=1.4, color="C3", label="RotD100")
    ax.set_xscale("log")
    ax.set_xlabel("period [s]")
    ax.set_ylabel(f"PSA [m/s²] ({spec.damping:.0%} damping)")
    ax.set_title("RotDnn spectra (Boore 2010)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return ax
