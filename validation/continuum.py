"""Validation of the continuum zones (issue 17, item 7): every case of
:mod:`murus.continuum.verify` in its full form (closed forms: the shaken layer, the quiet base,
the free field, Salençon's hole, Prandtl's footing, Rankine's thrust, Coulomb's and
Mononobe-Okabe's on a rough wall of blocks, the oedometer under a pressure and under a block,
the energy balances), a figure of the hole's stresses against Salençon (1969) and of the
footing's load against Prandtl-Reissner, and one of the rough wall's thrust as it rotates away.

Run through ``make validate`` or ``python validation/continuum.py [--out FILE]``; writes PNGs
under ``docs/figures/continuum/`` and returns the Markdown section (1 to 3 minutes).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FIG = ROOT / "docs" / "figures" / "continuum"


def _fmt(x: float) -> str:
    return "" if not np.isfinite(x) else f"{x:.4g}"


def _figure(path: Path) -> str:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from murus.continuum import closed_forms as cf
    from murus.continuum import verify as V

    rows, m, r, sr, st = V.hole_solution(quick=False)
    a, p0, c, ph = 1.0, 30e6, 3.45e6, math.radians(30.0)
    rr = np.linspace(a, 5 * a, 400)
    srx, stx = cf.hole_stresses(rr, a, p0, 0.0, c, ph)
    near = r <= 5 * a
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    ax[0].plot(rr, srx / 1e6, color="C0", label="radial, Salençon (1969)")
    ax[0].plot(rr, stx / 1e6, color="C3", label="tangential, Salençon (1969)")
    ax[0].plot(r[near], sr[near] / 1e6, ".", ms=3, color="C0", label="radial, murus zones")
    ax[0].plot(r[near], st[near] / 1e6, ".", ms=3, color="C3", label="tangential, murus zones")
    r0 = cf.hole_plastic_radius(a, p0, 0.0, c, ph)
    ax[0].axvline(r0, color="0.5", lw=0.8, ls="--")
    ax[0].text(r0, 2, " R0", color="0.4")
    ax[0].set_xlabel("r / a")
    ax[0].set_ylabel("stress [MPa], compression positive")
    ax[0].set_title("cylindrical hole in Mohr-Coulomb, 60 x 24 zones")
    ax[0].legend(fontsize=8)
    for phi, nf, gc, s in ((0.0, 24, 1000.0, 0.025), (30.0, 16, 5000.0, 0.05)):
        want = cf.strip_footing_capacity(1.0, math.radians(phi))
        _, q, mm = V.footing_limit_pressure(phi, nf, psi_deg=phi, G_over_c=gc, settlement=s)
        x = np.linspace(0.0, s, q.size)
        ax[1].plot(x, q / want, label=f"phi = psi = {phi:g} deg ({nf} zones "
                           "under the half-width)")
    ax[1].axhline(1.0, color="0.3", lw=0.8, ls="--", label="Prandtl (phi = 0), "
                  "Prandtl-Reissner (phi = 30)")
    ax[1].set_xlabel("settlement / half-width B")
    ax[1].set_ylabel("footing pressure / q_u")
    ax[1].set_title("smooth strip footing, weightless soil")
    ax[1].set_ylim(0, 1.3)
    ax[1].legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path.relative_to(ROOT).as_posix()


def _wall_figure(path: Path) -> str:
    """The settled thrust on the rough wall of blocks as it rotates away, against Coulomb and
    Mononobe-Okabe (the full model of the verification rows)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from murus.continuum import closed_forms as cf
    from murus.continuum import verify as V

    fig, ax = plt.subplots(figsize=(6.5, 4))
    d = math.radians(20.0)
    tilt = math.degrees(math.atan(0.2))
    for t, lab, col in ((0.0, "static: / Coulomb P_A cos(delta)", "C0"),
                        (tilt, "kh = 0.2 (tilted gravity): / Mononobe-Okabe", "C3")):
        _, hist, cm = V.wall_thrust(20.0, t, quick=False)
        th = math.radians(t)
        want = cf.active_thrust(18e3, 4.0, math.radians(30.0), d, kh=math.sin(th),
                                kv=1.0 - math.cos(th)) * math.cos(d)
        x = 100 * 0.0005 * np.arange(hist.size)
        ax.plot(x, hist / want, "o-", color=col, ms=4, label=lab)
    ax.axhline(1.0, color="0.3", lw=0.8, ls="--")
    ax.axhspan(0.9, 1.1, color="0.9", zorder=0, label="tolerance 10 %")
    ax.set_xlabel("movement of the top of the wall / H [%] (rotation about the heel)")
    ax.set_ylabel("settled horizontal thrust / closed form")
    ax.set_title(f"rough wall of blocks (delta = 20 deg), sand backfill, {cm.zones.nz} zones",
                 fontsize=10)
    ax.set_ylim(0.8, 1.8)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path.relative_to(ROOT).as_posix()


def section() -> str:
    """The Markdown section of VALIDATION.md (runs the full verification, about 1 minute)."""
    from murus.continuum.verify import CASES

    lines = ["## Continuum zones against closed forms (issue 17)", "",
             "`murus verify continuum` (the full cases of `murus.continuum.verify`; the test "
             "suite runs the quick forms with the same tolerances). The rough wall, the block on "
             "the layer and the second energy balance couple distinct-element blocks with the "
             "zones through the zone-block interface in one time loop "
             "(`murus.continuum.coupled.CoupledModel`).", "",
             "| case | expected | murus | error | tolerance | result |",
             "|---|---|---|---|---|---|"]
    n_fail = 0
    for fn in CASES.values():
        for r in fn(False):
            if r["passed"] is None:
                res = "n/a"
            else:
                res = "pass" if r["passed"] else "**FAIL**"
                n_fail += not r["passed"]
            case = r["case"].replace("|", "\\|")  # a table cell: escape the bars of |x|
            lines.append(f"| {case} | {_fmt(r['expected'])} | {_fmt(r['obtained'])} | "
                         f"{_fmt(r['error'])} | {r['tolerance']:g} | {res} |")
    fig = _figure(FIG / "hole_and_footing.png")
    wall_fig = _wall_figure(FIG / "rough_wall.png")
    lines += ["", f"![Hole and footing]({fig})", "",
              "Left: the zones' stresses around the hole against Salençon's closed form; the "
              "tangential stress has a kink at the plastic radius R0, which a zone straddling "
              "it averages (the row compares with the closed form averaged over each zone). "
              "Right: the footing pressure as the footing is pushed down at a constant slow "
              "rate with local damping; the limit load is the mean over the last 40 % of the "
              "settlement. The cohesive case converges from above as the mesh is refined "
              "(+5.0, +3.6, +2.7, +2.1, +1.7 % with 8, 12, 16, 24, 32 zones under the "
              "half-width, non-associated psi = 0 runs of the verification helper); the "
              "frictional case with associated flow gives 30.73 c (8 zones) and 28.90 c (16), "
              "within 10 % of N_c = 30.14 but not monotonic in the mesh, as the "
              "non-associated runs (28.65 c, 28.00 c); with associated flow the load "
              "overshoots (1.12 q_u near 1 % settlement) and oscillates about 0.96 q_u: the "
              "dilating soil needs a slower loading than the cohesive one for a quasi-static "
              "response, a limit of this check. Rankine's thrust grows slowly above "
              "the closed form as the mesh is refined (+0.8, +1.3, +2.0, +3.6 % from 16 x 8 "
              "to 48 x 24 zones with psi = 0): a shear band whose mobilised friction is below "
              "phi under non-associated flow.", "",
              f"![Rough wall]({wall_fig})", "",
              "The rough wall is a prescribed block that rotates away from the backfill about "
              "its heel in steps of 0.05 % H of its top, each followed by a settling; the "
              "active thrust is the smallest settled horizontal force of the interface on the "
              "block (at 0.05-0.1 % H; it then rises slowly, by 1 to 2 % at 0.4 % H). The "
              "base is rough: on a smooth base the backfill's horizontal equilibrium ties the "
              "wall's thrust to the far end's, which stays at Rankine's whatever the wall "
              "friction (+21 % on Coulomb's in a trial with 16 x 8 zones), and a wall that "
              "translates on a rough base tears the bottom zones off at the heel (-17 %). "
              "The Mononobe-Okabe wall is "
              "rough too (the same model with gravity tilted by atan 0.2 towards the wall), so "
              "that the two rows differ by the pseudo-static load only; a smooth wall gives "
              "1.027 of the smooth Mononobe-Okabe thrust, and without tilt 0.998 of Rankine's. "
              "The coupled energy balance is measured against the work put in by the base "
              "(the largest term of the blocks' balance is their potential energy from the "
              "datum, which would dilute the error); the row names the plastic work and the "
              "interface slip, both large shares of it.",
              "", f"{n_fail} failed rows.", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    text = section()
    if args.out:
        Path(args.out).write_text(text)
    else:
        print(text)
