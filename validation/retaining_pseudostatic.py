"""Validation of the pseudo-static resistance of dry-stone retaining walls against
Savalle et al. (2022), §4.4 (Table 8), with the sensitivity to every assumption the seed leaves open
(issue 6, item 3).

Run through ``make validate`` or ``python validation/retaining_pseudostatic.py [--out FILE]``;
writes PNGs under ``docs/figures/retaining/`` and returns the Markdown section.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from murus import G
from murus.retaining import (
    MOCKUP_SLENDERNESS,
    Assumptions,
    PseudoStaticError,
    critical_acceleration,
    critical_tilt,
    mockup,
    preset,
    safety_curves,
)

ROOT = Path(__file__).resolve().parents[1]
FIG = ROOT / "docs" / "figures" / "retaining"
DATA = ROOT / "tests" / "data" / "retaining"
WALLS = ("DSRW1", "DSRW2", "DSRW3", "DSRW4")
PHI = 37.7

#: (label, preset overrides, assumptions, signs) of the sensitivity study; the first is the default
VARIANTS = [
    ("**default**: delta = 2/3 phi = 25.1 deg, static and dynamic thrust at h/3 "
     "(§7.3.2.3(5)), base parallel to the beds, worse kv sign", {}, Assumptions(), None),
    ("delta = phi = 37.7 deg (Table 6 wall-backfill interface)", {},
     Assumptions(delta_ratio=None), None),
    ("delta = 0 (smooth back)", {}, Assumptions(delta_deg=0.0), None),
    ("dynamic increment at h/2 (§7.3.2.3(4))", {}, Assumptions(dynamic_point=0.5), None),
    ("delta = phi and dynamic increment at h/2 (EN 1998-5 defaults, Table 6 literally)", {},
     Assumptions(delta_ratio=None, dynamic_point=0.5), None),
    ("delta = phi and dynamic increment at 0.6 h (Seed and Whitman 1970)", {},
     Assumptions(delta_ratio=None, dynamic_point=0.6), None),
    ("horizontal base (beds inclined above it)", {"base": "horizontal"}, Assumptions(), None),
    ("horizontal base, delta = phi, dynamic at h/2 (the REFERENCE.md reconstruction)",
     {"base": "horizontal"}, Assumptions(delta_ratio=None, dynamic_point=0.5), None),
    ("thrust down to the level of the joint's front edge only", {},
     Assumptions(back_height="front"), None),
    ("base excluded (first course fixed, as the DEM's bottom units)", {},
     Assumptions(joints="above-base"), None),
    ("kv downwards only", {}, Assumptions(), (-1,)),
    ("tan theta = kh (kv only in the factor 1 - kv; not EN 1998-5 (E.6))", {},
     Assumptions(seismic_angle="kh-only"), None),
    ("wall unit weight 18 kN/m3 (10 % voids; Table 6 gives 20)",
     {"wall_unit_weight": 18.0e3}, Assumptions(), None),
    ("trial-wedge thrust instead of (E.2)", {}, Assumptions(thrust="wedge"), None),
]


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _rows(name: str) -> list[dict]:
    with open(DATA / name) as fh:
        return list(csv.DictReader(ln for ln in fh if not ln.startswith("#")))


def _a(wall: str, ratio: float, over: dict | None = None, asm: Assumptions | None = None,
       signs=None):
    try:
        return critical_acceleration(preset(wall, **(over or {})), ratio, asm, signs)
    except PseudoStaticError:
        return None


def _peak(r: dict) -> float:
    """A_peak as printed in Table 8 (DSRW1), else 0.6 A_col of Table 7."""
    return float(r["A_peak_m_s2"]) if r["A_peak_m_s2"] else 0.6 * float(r["A_col_m_s2"])


def table8() -> tuple[list[str], dict]:
    rows = _rows("savalle2022_table8.csv")
    out = ["| case | wall | f [Hz] | vertical | A_col [m/s²] (Table 7) | A_peak [m/s²] | "
           "A_pseudo, seed [m/s²] | A_pseudo, murus [m/s²] | difference | r, seed | r, murus | "
           "governing |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    res = {}
    for r in rows:
        key = (r["wall"], float(r["kv_ratio"]))
        if key not in res:
            res[key] = critical_acceleration(preset(r["wall"]), key[1])
        m = res[key]
        peak = _peak(r)
        seed = r["A_pseudo_m_s2"]
        diff = f"{100 * (m.A_pseudo / float(seed) - 1):+.1f} %" if seed else "—"
        out.append(f"| {r['case']} | {r['wall']} | {r['frequency_Hz']} | {r['vertical']} | "
                   f"{float(r['A_col_m_s2']):.2f} | {peak:.2f}{'' if r['A_peak_m_s2'] else ' *'} "
                   f"| {seed or '— (not printed)'} | {m.A_pseudo:.3f} | {diff} | "
                   f"{r['r'] or '—'} | {peak / m.A_pseudo:.2f} | joint {m.joint}, {m.mode} |")
    return out, r_stats({}, Assumptions(), None)


def r_stats(over: dict, asm: Assumptions, signs) -> dict | None:
    """Behaviour factors r = A_peak / A_pseudo of the eight cases for one set of assumptions:
    mean and minimum (seed: 2.08 and 1.83), and the sum and minimum over DSRW2-4 (the cases
    Table 8 does not print: the paper's mean and its five printed r imply a sum of 6.27 +- 0.05,
    and each at least 1.83)."""
    rs, rest = [], []
    for r in _rows("savalle2022_table8.csv"):
        m = _a(r["wall"], float(r["kv_ratio"]), over, asm, signs)
        if m is None:
            return None
        rs.append(_peak(r) / m.A_pseudo)
        if not r["A_pseudo_m_s2"]:
            rest.append(rs[-1])
    return {"mean": sum(rs) / len(rs), "min": min(rs), "sum_rest": sum(rest),
            "min_rest": min(rest)}


def sensitivity() -> tuple[list[str], list[dict]]:
    out = ["| assumption (one change from the default) | A_pseudo, kv = 0 [m/s²] (seed 1.58) | "
           "A_pseudo, kv = 0.5 kh [m/s²] (seed 1.50) | ratio (seed 0.949) | governing | "
           "mean r, 8 cases (seed 2.08) | min r (seed 1.83) | r of DSRW2-4: sum (implied "
           "6.27 +- 0.05), min (>= 1.83) |",
           "|---|---|---|---|---|---|---|---|"]
    stats = []
    for label, over, asm, signs in VARIANTS:
        a0 = _a("DSRW1", 0.0, over, asm, None)
        a5 = _a("DSRW1", 0.5, over, asm, signs)
        st = r_stats(over, asm, signs)
        stats.append({"a0": a0.A_pseudo if a0 else None, "a5": a5.A_pseudo if a5 else None,
                      **(st or {})})

        def cell(x, seed):
            if x is None:
                return "—"
            return f"{x.A_pseudo:.3f} ({100 * (x.A_pseudo / seed - 1):+.1f} %)"

        ratio = f"{a5.A_pseudo / a0.A_pseudo:.3f}" if a0 and a5 else "—"
        gov = f"joint {a0.joint}, {a0.mode}" if a0 else "—"
        if st is None:
            rcells = "— | — | —"
        else:
            rcells = (f"{st['mean']:.2f} | {st['min']:.2f} | {st['sum_rest']:.2f}, "
                      f"{st['min_rest']:.2f}")
        out.append(f"| {label} | {cell(a0, 1.58)} | {cell(a5, 1.50)} | {ratio} | {gov} | "
                   f"{rcells} |")
    return out, stats


def mockups() -> list[str]:
    rows = {float(r["slenderness"]): r for r in _rows("savalle2022_table3.csv")}
    out = ["| H/B | A_pseudo, murus [m/s²] | mode, murus | A_fail exp. [m/s²] | mode exp. | "
           "A_fail UDEC [m/s²] | mode UDEC | exp. / pseudo-static |",
           "|---|---|---|---|---|---|---|---|"]
    for s in MOCKUP_SLENDERNESS:
        m = critical_acceleration(mockup(s))
        r = rows[s]
        out.append(f"| {s:g} | {m.A_pseudo:.2f} | {'S' if m.mode == 'sliding' else 'T'} | "
                   f"{r['exp_A_fail_m_s2']} | {r['exp_mode']} | {r['num_A_fail_m_s2']} | "
                   f"{r['num_mode']} | {float(r['exp_A_fail_m_s2']) / m.A_pseudo:.2f} |")
    return out


def figure(fig_dir: Path) -> str:
    plt = _plt()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    w = preset("DSRW1")
    res = critical_acceleration(w)
    kh = np.linspace(0.0, 0.3, 61)
    cur = safety_curves(w, kh)
    cmap = plt.get_cmap("viridis")
    n = len(cur["joint_height"])
    for j in range(0, n, 4):
        c = cmap(j / max(n - 1, 1))
        z = cur["joint_height"][j]
        ax1.plot(kh, cur["overturning"][j], color=c, lw=1.2, label=f"joint at {z:.1f} m")
        ax1.plot(kh, cur["sliding"][j], color=c, lw=1.0, ls="--")
    ax1.axhline(1.0, color="k", lw=0.6)
    ax1.axvline(res.kh, color="r", lw=0.6)
    ax1.set_ylim(0, 4)
    ax1.set_xlabel("kh [-]")
    ax1.set_ylabel("safety factor")
    ax1.set_title(f"DSRW1, kv = 0: overturning (solid), sliding (dashed); kh_c = {res.kh:.4f}",
                  fontsize=8)
    ax1.legend(fontsize=7)
    ratios = np.linspace(0.0, 1.0, 11)
    for name, c in zip(WALLS, ("C0", "C1", "C2", "C3"), strict=True):
        up, down = [], []
        for r in ratios:
            m = critical_acceleration(preset(name), r, signs=(1, -1) if r > 0 else (1,))
            up.append(m.by_sign[1][0] * G)
            down.append(m.by_sign.get(-1, m.by_sign[1])[0] * G)
        ax2.plot(ratios, up, color=c, label=f"{name}, kv upwards")
        ax2.plot(ratios, down, color=c, ls="--", label=f"{name}, kv downwards")
    ax2.plot([0, 0.5], [1.58, 1.50], "k*", ms=9, label="Savalle et al. (2022), Table 8 (DSRW1)")
    ax2.set_xlabel("kv / kh [-]")
    ax2.set_ylabel("A_pseudo (horizontal) [m/s²]")
    ax2.set_title("A_pseudo against the vertical component", fontsize=8)
    ax2.legend(fontsize=6, ncol=2)
    name = "savalle2022_pseudostatic.png"
    fig.savefig(fig_dir / name, dpi=110)
    plt.close(fig)
    return name


def _pct(value: float | None, seed: float) -> str:
    return "—" if value is None else f"{value:.3f} m/s² ({100 * (value / seed - 1):+.1f} %)"


def section(fig_dir: Path | None = None) -> str:
    fig_dir = FIG if fig_dir is None else Path(fig_dir)
    fig_dir.mkdir(parents=True, exist_ok=True)
    rel = fig_dir.relative_to(ROOT) if fig_dir.is_relative_to(ROOT) else fig_dir
    t8, stats = table8()
    sens, st = sensitivity()
    d1 = critical_acceleration(preset("DSRW1"))
    d5 = critical_acceleration(preset("DSRW1"), 0.5)
    tilt, _, _ = critical_tilt(preset("DSRW1"))
    out = ["## Dry-stone retaining walls: pseudo-static resistance (Savalle et al. (2022), §4.4)",
           ""]
    out += [
        "Savalle et al. (2022) computes the pseudo-static resistance A_pseudo of its walls "
        "\"using an "
        "analytical approach based on the limit-equilibrium of a Coulomb's wedge of soil\" with "
        "the properties of Tables 5 and 6 and perfect stones, and gives no equations. murus "
        "(`murus.retaining.pseudostatic`, `murus retaining pseudo-static`) takes the wall above "
        "each bed joint as a rigid block under its weight, the inertia kh W (out of the slope) "
        "and kv W (positive upwards), and the EN 1998-5 Annex E thrust on its back face "
        "(static part 1/2 gamma K_A h², dynamic increment 1/2 gamma (1 - kv) K h² - static, eqs "
        "(E.1)-(E.3) with theta of (E.6), `murus.eurocode.ec8_5`), and checks sliding along the "
        "joint (friction 25 deg, inclined 9.1 deg into the slope) and overturning about its "
        "front edge. A_pseudo = kh g where the smallest safety factor over the 25 joints and "
        "both mechanisms is 1; kv = +-0.5 kh, the worse sign reported.",
        "",
        "### Table 8", "",
        *t8, "",
        f"DSRW1: **{d1.A_pseudo:.3f} m/s²** against 1.58 ({100 * (d1.A_pseudo / 1.58 - 1):+.1f} "
        f"%) with horizontal action, **{d5.A_pseudo:.3f} m/s²** against 1.50 "
        f"({100 * (d5.A_pseudo / 1.50 - 1):+.1f} %) with kv = 0.5 kh upwards (the worse sign, "
        "as in the DEM where the opposite-phase case was critical); overturning of the whole "
        "wall about its toe governs. The text of the seed prints Table 8 for DSRW1 only (* : "
        "A_peak = 0.6 A_col computed from Table 7); it states a mean behaviour factor r = 2.08 "
        "over the eight cases and a minimum of 1.83, so that the three r it does not print "
        "(DSRW2-4) must sum to 6.27 +- 0.05 (16.64 - 10.37, with the rounding), each at least "
        f"1.83. With the murus A_pseudo: mean **{stats['mean']:.2f}**, minimum "
        f"**{stats['min']:.2f}**, DSRW2-4 sum **{stats['sum_rest']:.2f}**, minimum "
        f"**{stats['min_rest']:.2f}**: the values the paper does not print are consistent with "
        "what it states.",
        "",
        "### Assumptions the seed leaves open, and their effect", "",
        "Each row changes one assumption from the default, for DSRW1 and for the behaviour "
        "factors of all eight cases of Tables 7-8 (computed as above).", "",
        *sens, "",
        "Reading the table:",
        "",
        "- The level is set by the wall friction delta and the point of application of the "
        "dynamic increment. The default (delta = 2/3 phi, static and dynamic thrust at h/3, "
        "base parallel to the beds) is the only combination found that meets both Table 8 "
        "values within 5 % *and* the r the seed states for the cases it does not print. It is "
        "defensible: delta = 2/3 phi is the customary wall friction of gravity-wall design; EN "
        "1998-5 §7.3.2.3(5) lets the dynamic force act at the static point for walls free to "
        "rotate about their toe, the governing mechanism here; a pseudo-static Coulomb wedge "
        "(the paper's wording) has a triangular pressure, i.e. acts at h/3, and so does a "
        "tilting table (the equivalence below), the seed authors' earlier tool [18].",
        f"- Taking Table 6 literally (delta = phi = 37.7 deg) with the EN 1998-5 mid-height "
        f"increment gives {_pct(st[4]['a0'], 1.58)} and {_pct(st[4]['a5'], 1.50)}; with a "
        f"horizontal base (the REFERENCE.md reconstruction) {_pct(st[7]['a0'], 1.58)} and "
        f"{_pct(st[7]['a5'], 1.50)}, with the best kv ratio, but DSRW2-4 then give r summing "
        f"to {st[7]['sum_rest']:.2f} with a minimum of {st[7]['min_rest']:.2f}, against 6.27 "
        "and 1.83. delta = phi with the increment at 0.6 h (Seed and Whitman) gives "
        f"{_pct(st[5]['a0'], 1.58)} and {_pct(st[5]['a5'], 1.50)} but an r sum of "
        f"{st[5]['sum_rest']:.2f} for DSRW2-4.",
        f"- With the default, the kv case is {_pct(d5.A_pseudo, 1.50)} (ratio "
        f"{d5.A_pseudo / d1.A_pseudo:.3f} against 1.50 / 1.58 = 0.949). Taking tan theta = kh "
        f"(kv only scaling the thrust and the weight) gives {st[11]['a5']:.3f} m/s², the "
        "printed value; it is not EN 1998-5 (E.6) and breaks the tilting equivalence, so murus "
        "keeps (E.6) and reports the difference.",
        "- The sign of kv: upwards (less effective gravity) is the worse for every wall.",
        "- The joints: the base governs every wall; excluding it (first course fixed to the "
        f"foundation, as the DEM does with its bottom units) gives {_pct(st[9]['a0'], 1.58)} "
        f"and {_pct(st[9]['a5'], 1.50)}. A horizontal base under inclined beds makes sliding "
        f"on the base govern ({_pct(st[6]['a0'], 1.58)}).",
        "",
        "### Scaled-down mock-ups (Savalle et al. (2022), §3, Table 3)", "",
        "Vertical walls, level sand, the materials of Table 1 (delta = 2/3 x 45 = 30 deg); only "
        "the base joint (course heights not given). The pseudo-static resistance depends on "
        "H/B only (friction has no length scale), so the paper's inconsistent width (34 mm "
        "printed, 38-42 mm implied by the 50-140 mm heights) does not matter here. The "
        "experimental accelerations are dynamic (10 Hz ramp, failure at 5 % of H) and not "
        "pseudo-static limits; the mechanisms agree: sliding for the squat walls, toppling for "
        "the slender ones, the change between H/B = 2.3 and 2.7 as observed.", "",
        *mockups(), "",
        "### Tilting-table equivalence", "",
        "A tilt t of the wall and its backfill is kh = sin t, kv = 1 - cos t (upwards): the "
        "effective gravity keeps its magnitude and turns by t = theta of (E.6), so the safety "
        "factors are those of kh = tan t with kv = 0 (asserted in the tests). DSRW1 topples "
        f"at a tilt of **{math.degrees(tilt):.2f} deg** (tan t = {math.tan(tilt):.4f} = kh_c "
        "with kv = 0).", "",
    ]
    name = figure(fig_dir)
    out += [f"![DSRW1 safety factors and A_pseudo against kv]({rel}/{name})", ""]
    return "\n".join(out) + "\n"


def main(argv=None) -> None:
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None, help="Markdown file (default: standard output).")
    ap.add_argument("--fig-dir", default=None, help=f"Figure folder (default {FIG}).")
    args = ap.parse_args(argv)
    import runcache

    runcache.emit(section(args.fig_dir), args.out)


if __name__ == "__main__":
    main()
