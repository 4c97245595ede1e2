"""Validation of the studies layer against EURODYN (2020), §4.1 (issue 7, item 7): rocking spectra
of block2 against the tie stiffness (Figures 3-4) and fragility curves of a free-standing, a tied
and a damped wall over the FEMA P695 far-field set.

Run through ``make validate`` or ``python validation/studies.py [--out FILE]``; writes PNGs
under ``docs/figures/studies/`` and returns the Markdown section.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FIG = ROOT / "docs" / "figures" / "studies"

#: FEMA P695 far-field records standing in for the paper's (not in FEMA P695): Duzce 1999 at
#: Bolu (Turkey, as Dinar 1995; Duzce 1999 is itself in EURODYN (2020), Table 2) and Friuli 1976 at
#: Tolmezzo (Italy, Mw 6.5 as Norcia 2016).
STAND_INS = {
    "Dinar 1995 (Mw 6.2, Figure 3)": ("farfield_03a", "farfield_03b"),
    "Norcia 2016 (Mw 6.5, Figure 4)": ("farfield_22a", "farfield_22b"),
}
DELTA_T = 10.186  # s, eq. 13 characteristic time calibrated in validation/restrained.py


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def n_peaks(y: np.ndarray) -> int:
    """Interior local maxima of a curve (a measure of its non-monotonic trend)."""
    return int(np.sum((y[1:-1] > y[:-2]) & (y[1:-1] > y[2:])))


def spectra(fig_dir: Path) -> tuple[list[str], str]:
    from murus.rocking import restrained_wall_block
    from murus.studies import RecordSet, plot_rocking_spectrum, rocking_spectrum

    plt = _plt()
    names = tuple(n for pair in STAND_INS.values() for n in pair)
    ds = rocking_spectrum(restrained_wall_block("block2"), RecordSet(kind="suite", select=names),
                          executor="serial")
    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5), layout="constrained", sharex=True)
    rows = ["| seed record | FEMA P695 stand-in | free-standing theta/alpha | max over K > 0 "
            "(at K/K_d) | min over K > 0 | K values above free-standing | K values above 0.4 | "
            "local maxima |", "|---|---|---|---|---|---|---|---|"]
    for (seed_rec, pair), axrow in zip(STAND_INS.items(), axes, strict=True):
        for name, ax in zip(pair, axrow, strict=True):
            plot_rocking_spectrum(ds, ax=ax, record=name)
            i = list(ds["record"].values).index(name)
            ev = f"{ds['event'].values[i]}, {ds['station'].values[i]}, " \
                 f"{ds['component'].values[i]}"
            ax.set_title(f"block2 - {ev}\n(stand-in for {seed_rec.split(' (')[0]})", fontsize=8)
            y = ds["theta_max_over_alpha"].isel(record=i).values
            ov = ds["overturned"].isel(record=i).values > 0.5
            k = ds["K_over_Kd"].values
            free = float(ds["free_standing"].isel(record=i))
            yk, kk = y[1:], k[1:]
            j = int(np.nanargmax(np.where(ov[1:], np.inf, yk)))
            rows.append(
                f"| {seed_rec} | {name} ({ev}) | {free:.3f}"
                f"{' (overturns)' if ov[0] else ''} | {yk[j]:.3f} ({kk[j]:.2f})"
                f"{' overturns' if ov[1:].any() else ''} | {np.nanmin(yk):.3f} | "
                f"{int(np.sum(yk > free))} of {yk.size} | {int(np.sum(yk >= 0.4))} of "
                f"{yk.size} | {n_peaks(y)} |")
    fig.savefig(fig_dir / "eurodyn2020_fig3_fig4_standins.png", dpi=110)
    plt.close(fig)
    return rows, "eurodyn2020_fig3_fig4_standins.png"


def fragility_figure(fig_dir: Path) -> tuple[list[str], str]:
    from murus.rocking import restrained_wall_block
    from murus.studies import fragility, plot_fragility, restraint_configs

    plt = _plt()
    b = restrained_wall_block("block2")
    models = restraint_configs(b, delta_t=DELTA_T, c_over_cd=0.10)
    levels = np.array([0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0])
    ds = fragility(models, "farfield", im="PGA", levels=levels, executor="serial", n_boot=200)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.0), layout="constrained", sharey=True)
    for ax, ls in zip(axes, ds["limit_state"].values, strict=True):
        plot_fragility(ds, ax=ax, limit_state=str(ls))
        ax.set_title(f"block2, {ls}", fontsize=9)
    fig.savefig(fig_dir / "eurodyn2020_fragility_block2.png", dpi=110)
    plt.close(fig)
    rows = ["| configuration | limit state | median PGA [g] (90 % CI) | beta (90 % CI) | fit |",
            "|---|---|---|---|---|"]
    for c in ds["config"].values:
        for ls in ds["limit_state"].values:
            s = {"config": c, "limit_state": ls}
            m = float(ds["fragility_median"].sel(s))
            rows.append(
                f"| {c} | {ls} | {m:.3f} ({float(ds['fragility_median_lo'].sel(s)):.3f}-"
                f"{float(ds['fragility_median_hi'].sel(s)):.3f}) | "
                f"{float(ds['fragility_beta'].sel(s)):.2f} "
                f"({float(ds['fragility_beta_lo'].sel(s)):.2f}-"
                f"{float(ds['fragility_beta_hi'].sel(s)):.2f}) | "
                f"{ds['fragility_status'].sel(s).item()} |")
    return rows, "eurodyn2020_fragility_block2.png"


def section(fig_dir: Path | None = None) -> str:
    fig_dir = FIG if fig_dir is None else Path(fig_dir)
    fig_dir.mkdir(parents=True, exist_ok=True)
    rel = fig_dir.relative_to(ROOT) if fig_dir.is_relative_to(ROOT) else fig_dir
    rows, fig = spectra(fig_dir)
    out = [
        "## Rocking spectra and fragility (EURODYN (2020), §4.1)", "",
        "Rocking spectra (`murus.studies.rocking_spectrum`) of block2 (lambda = 10, s = 0.6 m): "
        "theta_max/alpha for 50 values 0 <= K <= K_d of a tension-only tie at the top (K_d "
        "from eq. 12), one-sided motion against transverse walls whose stiffness follows the "
        "tie by eq. 11 (K = 0: no tie, no walls, the free-standing wall), Housner's e, limit "
        "states 0.1 and 0.4 (dashed) and the free-standing value (dotted).", "",
        "The seed's records, Dinar 1995 (Figure 3) and Norcia 2016 (Figure 4), are not in the "
        "FEMA P695 sets that murus ships, so the curves cannot be compared number for number. "
        "The stand-ins are the two far-field records closest to them: Duzce 1999 at Bolu "
        "(Turkey; Duzce 1999 is itself one of the paper's events, Table 2) and Friuli 1976 at "
        "Tolmezzo (Italy, Mw 6.5 like Norcia), both horizontal components. The comparison is "
        "qualitative: does the response vary non-monotonically with K, with peaks that "
        "exceed the free-standing response (the paper's \"amplifications ... where beats and "
        "resonant effects develop\")?", "",
        *rows, "",
        f"![Rocking spectra]({rel}/{fig})", "",
        "As in Figures 3-4, the spectra are far from monotonic in K (several local maxima, "
        "last column). Under Friuli the restrained wall rotates more than the free-standing "
        "one for most stiffnesses (the paper's Figure 4 reading: amplified responses, sometimes "
        "above the free-standing peak). Under Duzce-Bolu, stronger (PGA 0.73 g), the "
        "free-standing wall overturns and every tie keeps the wall up, but the softest ties "
        "(K < 0.1 K_d) let it rotate beyond alpha, and the response rises again with K in "
        "bands (near K = 0.2 and 0.35 K_d, and towards K_d): the paper's Figure 3 reading "
        "(\"even low values of stiffness result in an amplification\"). A tie is not "
        "stabilising for every K: the spectrum, not a single stiffness, is what a design "
        "should check (the paper's conclusion).", "",
    ]
    rows, fig = fragility_figure(fig_dir)
    out += [
        "### Fragility: free-standing, tied and damped block2", "",
        "Multiple-stripe analysis (`murus.studies.fragility`): the 44 FEMA P695 far-field "
        "components scaled to 10 PGA levels (0.05-1.0 g), maximum-likelihood lognormal fit "
        "per limit state (binomial likelihood, Baker 2015), 90 % bands by bootstrap over the "
        "records (200 resamples). Tied: K = K_d at the top with eq. 11 transverse walls; "
        f"damped: the same with a damper c = 10 % c_d (eq. 13, delta_t = {DELTA_T} s, the "
        "value calibrated on Figure 9), the paper's design value for limited rocking. "
        "Markers are the observed fractions.", "",
        *rows, "",
        f"![Fragility]({rel}/{fig})", "",
        "The one-sided walls (tied, damped) cannot overturn inward and the tie holds them "
        "outward within the PGA range run, so their overturning fragility is not defined "
        "(\"none exceeded\" when no case overturns). The damper shifts the rocking limit "
        "states to higher PGA.", "",
    ]
    return "\n".join(out) + "\n"


def main(argv=None) -> None:
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None, help="Markdown file (default: standard output).")
    ap.add_argument("--fig-dir", default=None)
    args = ap.parse_args(argv)
    import runcache

    runcache.emit(section(args.fig_dir), args.out)


if __name__ == "__main__":
    main()
