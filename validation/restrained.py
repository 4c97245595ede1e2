"""Validation of the restrained rocking wall of EURODYN (2020) (issue 4, item 5): damped free
vibration (Figures 7-9), the tie's filtering of the response (Figure 2), and the resonance
frequencies of eqs. 8-9 against the simulator.

Run through ``make validate`` or ``python validation/restrained.py``; writes PNGs under
``docs/figures/restrained/`` and returns the Markdown section.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from murus import G
from murus.rocking import (
    Constant,
    Damper,
    RockingModel,
    SpringBed,
    Tie,
    restrained_wall_block,
    simulate,
)
from murus.rocking.design import reference_damping, resonance_frequencies, tie_design

ROOT = Path(__file__).resolve().parents[1]
FIG = ROOT / "docs" / "figures" / "restrained"
K_BED = 4.5e8  # N/m/m, EURODYN (2020), §4.2 (eq. 10 with E_x = 1.5e9, t = 0.3 m, L_eff = 1 m)
FRACTIONS = (0.0, 0.001, 0.01, 0.05)  # c / c_d of Figures 7-8


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def block1_model(c: float = 0.0, K: float = 0.0, sides: str = "one", e: float = 1.0):
    """Block1 of EURODYN (2020) with a damper ``c`` [N s/m] and a tie ``K`` [N/m] at the top,
    transverse walls K' = 4.5e8 N/m/m over the full height when one-sided."""
    b = restrained_wall_block("block1")
    return RockingModel(
        b, Constant(e),
        tie=Tie(K, b.height) if K > 0 else None,
        damper=Damper(c, b.height) if c > 0 else None,
        transverse_walls=SpringBed(K_BED, b.height) if sides == "one" else None,
        motion_sides=sides,
    )


def reduction_after_first_impact(c: float, K: float) -> float:
    """1 - (first positive peak after release) / (theta0 = 0.9 alpha), one-sided, e = 1."""
    r = simulate(block1_model(c, K), theta0_over_alpha=0.9, duration=8.0, out_dt=0.01)
    pk = r.peaks[r.peaks[:, 1] > 0]
    return 1.0 - pk[0, 1] / (0.9 * r.alpha)


def calibrate_delta_t(target: float = 0.82) -> float:
    """The characteristic time of eq. 13 (not given by the paper) for which c = 1 % c_d reduces
    the free-standing one-sided block by ``target`` after the first impact (Figure 9)."""
    from scipy.optimize import brentq

    b = restrained_wall_block("block1")

    def f(dt):
        return reduction_after_first_impact(0.01 * reference_damping(b, dt), 0.0) - target

    return brentq(f, 1.0, 30.0, xtol=1e-4)


def figures_7_8_9(fig_dir: Path, delta_t: float, Kd: float) -> tuple[list[str], list[str]]:
    plt = _plt()
    b = restrained_wall_block("block1")
    cd = reference_damping(b, delta_t)
    fig, axes = plt.subplots(3, 1, figsize=(8, 8.5), layout="constrained", sharex=True)
    rows = ["| configuration | c / c_d | 1st peak after release (theta/alpha) | reduction [%] | "
            "impacts in 10 s |", "|---|---|---|---|---|"]
    for ax, (sides, K, title) in zip(axes, (
            ("two", 0.0, "(a) free-standing, two-sided (Figure 7a)"),
            ("one", 0.0, "(b) free-standing, one-sided, K' = 4.5e8 N/m/m (Figure 7b)"),
            ("one", Kd, f"(c) restrained K = K_d = {Kd:.4g} N/m, one-sided (Figure 8)")),
            strict=True):
        for fr in FRACTIONS:
            r = simulate(block1_model(fr * cd, K, sides), theta0_over_alpha=0.9, duration=10.0,
                         out_dt=0.002)
            ax.plot(r.t, r.theta / r.alpha, lw=0.8, label=f"c = {100 * fr:g} % c_d")
            pk = r.peaks[r.peaks[:, 1] > 0] if sides == "one" else r.peaks
            first = abs(pk[0, 1]) / r.alpha if len(pk) else float("nan")
            rows.append(f"| {title[4:].split(' (')[0]} | {100 * fr:g} % | {first:.4f} | "
                        f"{100 * (1 - first / 0.9):.1f} | {r.n_impacts} |")
        ax.set_title(title, fontsize=9)
        ax.set_ylabel("theta/alpha")
        ax.legend(fontsize=7, ncol=4)
    axes[-1].set_xlabel("time [s]")
    fig.savefig(fig_dir / "eurodyn2020_fig7_fig8.png", dpi=110)
    plt.close(fig)
    # Figure 9: c = 1 % c_d, free-standing vs restrained, one-sided
    fig, ax = plt.subplots(figsize=(8, 3.2), layout="constrained")
    for K, lab in ((0.0, "free-standing"), (Kd, "restrained, K = K_d")):
        r = simulate(block1_model(0.01 * cd, K), theta0_over_alpha=0.9, duration=6.0,
                     out_dt=0.002)
        ax.plot(r.t, r.theta / r.alpha, lw=0.9, label=lab)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("theta/alpha")
    ax.set_title("Figure 9: block1, c = 1 % c_d, one-sided, e = 1", fontsize=9)
    ax.legend(fontsize=8)
    fig.savefig(fig_dir / "eurodyn2020_fig9.png", dpi=110)
    plt.close(fig)
    return rows, ["eurodyn2020_fig7_fig8.png", "eurodyn2020_fig9.png"]


def figure_2(fig_dir: Path) -> tuple[list[str], str]:
    """FFT of the horizontal displacement at the restraint level (the top), free vibration,
    free-standing vs a bidirectional elastic tie K = 1e6 N/m (EURODYN (2020), Figure 2)."""
    plt = _plt()
    b = restrained_wall_block("block1")
    e = b.housner_restitution()
    dt = 0.002
    out = {}
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.2), layout="constrained")
    for ax, (lab, tie) in zip(axes, (("(a) free-standing", None),
                                     ("(b) restrained, K = 1e6 N/m", Tie(1e6, b.height,
                                                                         tension_only=False))),
                              strict=True):
        mdl = RockingModel(b, Constant(e), tie=tie)
        r = simulate(mdl, theta0_over_alpha=0.9, duration=20.0, out_dt=dt)
        s = np.where(r.pivot < 0, -1.0, 1.0)
        x0 = -s * 0.5 * b.width
        u = x0 * (np.cos(r.theta) - 1) + b.height * np.sin(r.theta)  # top, mid-thickness
        spec = np.abs(np.fft.rfft(u - u.mean())) * dt
        f = np.fft.rfftfreq(u.size, dt)
        cum = np.cumsum(spec**2)
        cum /= cum[-1]
        f05, f50, f95 = (f[np.searchsorted(cum, q)] for q in (0.05, 0.5, 0.95))
        out[lab] = (f05, f50, f95)
        ax.semilogy(f, spec / spec.max(), lw=0.8)
        ax.set_xlim(0, 10)
        ax.set_xlabel("frequency [Hz]")
        ax.set_title(f"{lab}: 90 % of the energy in {f05:.2f}-{f95:.2f} Hz", fontsize=8)
    axes[0].set_ylabel("|FFT| / max")
    fig.savefig(fig_dir / "eurodyn2020_fig2.png", dpi=110)
    plt.close(fig)
    rows = ["| configuration | 5 % [Hz] | median [Hz] | 95 % [Hz] | band 5-95 % [Hz] | "
            "band / median |", "|---|---|---|---|---|---|"]
    for lab, (a, m, c) in out.items():
        rows.append(f"| {lab[4:]} | {a:.2f} | {m:.2f} | {c:.2f} | {c - a:.2f} | "
                    f"{(c - a) / m:.2f} |")
    w = resonance_frequencies(b, K=1e6).omega_plus / (2 * math.pi)
    rows += ["", f"Eq. 8 for K = 1e6 N/m: omega_r+ / 2 pi = {w:.2f} Hz."]
    return rows, "eurodyn2020_fig2.png"


def resonance_table() -> list[str]:
    """Eq. 8 against the simulator: small free oscillation (theta0 = 0.3 alpha, e = 1) of each
    block with a bidirectional tie K = K_d at the top."""
    rows = ["| block | K_d [N/m] | omega simulated [rad/s] | piecewise-linear closed form "
            "[rad/s] | difference [%] | linearised [rad/s] | eq. 8 [rad/s] |",
            "|---|---|---|---|---|---|---|"]
    for k in range(1, 7):
        b = restrained_wall_block(f"block{k}")
        Kd = tie_design(b).K_d
        res = resonance_frequencies(b, K=Kd)
        mdl = RockingModel(b, Constant(1.0), tie=Tie(Kd, b.height, tension_only=False))
        w_lin = res.omega_plus_lin
        r = simulate(mdl, theta0_over_alpha=0.3, duration=12 * 2 * math.pi / w_lin,
                     out_dt=1e-3, rtol=1e-10)
        pk = r.peaks[r.peaks[:, 1] > 0, 0]
        w_sim = 2 * math.pi / np.diff(pk).mean()
        w_pl = piecewise_linear_frequency(b, Kd, 0.3 * b.alpha)
        rows.append(f"| block{k} | {Kd:.4g} | {w_sim:.4f} | {w_pl:.4f} | "
                    f"{100 * (w_pl / w_sim - 1):+.3f} | {w_lin:.4f} | {res.omega_plus:.4f} |")
    return rows


def piecewise_linear_frequency(b, K: float, amplitude: float) -> float:
    """Frequency [rad/s] of the linearised restrained block with elastic impacts: on each side
    theta'' = -omega^2 (|theta| + delta) with delta = m g (b/2) / K_theta, so a quarter period
    is arccos(delta / (A + delta)) / omega for the amplitude A."""
    kth = K * b.height**2 - b.mass * G * b.z_G
    w = math.sqrt(kth / b.I_O)
    delta = b.mass * G * 0.5 * b.width / kth
    return w * 0.5 * math.pi / math.acos(delta / (amplitude + delta))


def section(fig_dir: Path | None = None) -> str:
    fig_dir = FIG if fig_dir is None else Path(fig_dir)
    fig_dir.mkdir(parents=True, exist_ok=True)
    rel = fig_dir.relative_to(ROOT) if fig_dir.is_relative_to(ROOT) else fig_dir
    b = restrained_wall_block("block1")
    td = tie_design(b)
    delta_t = calibrate_delta_t()
    cd = reference_damping(b, delta_t)
    red_free = reduction_after_first_impact(0.01 * cd, 0.0)
    red_tie = reduction_after_first_impact(0.01 * cd, td.K_d)
    out = ["## Restrained rocking walls: tie, damper, transverse walls (EURODYN (2020))", ""]
    out += [
        "Block1 of EURODYN (2020) (b = 0.3 m, h = 3 m, unit length, 21 kN/m³), free vibration from "
        "theta0/alpha = 0.9 with elastic impacts (e = 1, EURODYN (2020), §4.2). Tie and damper at "
        "the "
        "top, mid-thickness; transverse walls K' = 4.5e8 N/m/m over the full height, on the "
        "geometry of EURODYN (2020), eq. 6.",
        "",
        f"Design tie (eq. 12, S275, mu = 0.2, 10 m rod): T_d = {td.T_d:.1f} N, "
        f"phi = {1e3 * td.phi_d:.3f} mm, K_d = {td.K_d:.5g} N/m "
        "(`murus design tie --block block1`).",
        "",
        "### Figure 9: the damper's effect, free-standing against restrained",
        "",
        "EURODYN (2020) does not give the characteristic time delta_t of eq. 13 "
        "(c_d = 2 m g delta_t / h). One number was calibrated, the other predicted: "
        f"delta_t = **{delta_t:.3f} s** (c_d = {cd:.4g} N s/m) makes c = 1 % c_d reduce the "
        "free-standing one-sided block by 82 % after the first impact, as the paper reports; "
        "with that same delta_t the restrained block (K = K_d) is reduced by "
        f"**{100 * red_tie:.1f} %**, against the paper's **27 %**.",
        "",
        "| block1, c = 1 % c_d, one-sided | EURODYN (2020), §4.2 | murus |",
        "|---|---|---|",
        f"| free-standing: reduction after the first impact | 82 % | {100 * red_free:.1f} % "
        "(calibrated) |",
        f"| restrained K = K_d: reduction after the first impact | 27 % | "
        f"{100 * red_tie:.1f} % (predicted) |",
        "",
    ]
    rows, figs = figures_7_8_9(fig_dir, delta_t, td.K_d)
    out += [f"![Figure 9]({rel}/{figs[1]})", "",
            "### Figures 7 and 8: damping c = 0, 0.1, 1 and 5 % of c_d", "",
            *rows, "", f"![Figures 7-8]({rel}/{figs[0]})", "",
            "As in the paper: the damper lowers the successive peaks and delays the impacts of "
            "the free-standing block (Figure 7); the tie re-centres the block, shortens the "
            "time to the first impact and raises the rocking frequency, and for the same c the "
            "restrained block keeps larger rotations (Figure 8).", ""]
    rows, fig = figure_2(fig_dir)
    out += ["### Figure 2: the tie filters the response", "",
            "Fourier amplitude of the horizontal displacement of the top in free vibration from "
            "theta0/alpha = 0.9 (Housner's e), free-standing and with a bidirectional elastic "
            "tie K = 1e6 N/m. The free-standing block's frequency grows as its amplitude decays, "
            "spreading the spectrum; the tie concentrates it near omega_r+.", "", *rows, "",
            f"![Figure 2]({rel}/{fig})", ""]
    out += ["### Eq. 8 against the simulator, six blocks with K = K_d", "",
            "Small free oscillation (theta0 = 0.3 alpha, e = 1, bidirectional tie at the top): "
            "the frequency of the simulated motion; the closed form of the piecewise-linear "
            "oscillator that keeps the constant part m g b/2 of the gravity moment (a static "
            "offset delta = m g (b/2) / K_theta on each side); the linearised value "
            "sqrt((K h² - m g z_G) / I_O) and EURODYN (2020), eq. 8 (R_t and m g R), which both "
            "drop "
            "that offset and so underestimate the frequency of a small oscillation when the "
            "tie is soft (block1: delta / theta0 = 16 %). With a stiff tie (K = 1e7 N/m, "
            "delta / theta0 = 0.3 %) the tests find the linearised value and eq. 8 within 2 % "
            "(tests/rocking/test_restraints.py).", "",
            *resonance_table(), ""]
    return "\n".join(out) + "\n"


def main(argv=None) -> None:
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    import runcache

    runcache.emit(section(), args.out)


if __name__ == "__main__":
    main()
