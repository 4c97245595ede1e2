"""DEM contact damping against the rocking engine (issue 19, item 5): restitution per impact
of a free-rocking DEM block for several contact_damping values, and its free decay against
murus.rocking with the same e; writes docs/figures/dem/rocking_damping.png and prints the
table of VALIDATION.md.

    PYTHONPATH=src python validation/dem_rocking_damping.py
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from murus.dem import rocking_damping as RD  # noqa: E402
from murus.rocking import RigidBlock, simulate  # noqa: E402

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures" / "dem" / "rocking_damping.png"


def main():
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    print("| block | zeta | Housner e | DEM e (impacts 1-5) | peaks 1-5 vs murus.rocking |")
    print("|---|---|---|---|---|")
    for ax, (b, h) in zip(axes, ((0.25, 1.0), (0.2, 1.2)), strict=True):
        alpha = math.atan(b / h)
        eh = 1 - 1.5 * math.sin(alpha) ** 2
        for z in (0.0, 0.15, 1.0):
            r = RD.free_rocking(b, h, z, n_impacts=5)
            e = float(np.mean(r.e[:5]))
            rr = simulate(RigidBlock(b, h, density=2000.0), theta0_over_alpha=0.5,
                          restitution=e, duration=r.t[-1], out_dt=1e-3)
            th = np.abs(rr.theta)
            cut = np.nonzero(np.sign(rr.theta[1:]) != np.sign(rr.theta[:-1]))[0]
            ref = np.array([th[a:c].max() for a, c in zip(np.r_[0, cut + 1],
                                                          np.r_[cut + 1, th.size],
                                                          strict=True)])
            n = min(6, r.peaks.size, ref.size)
            dev = np.abs(r.peaks[1:n] / ref[1:n] - 1)
            print(f"| {b} x {h} | {z} | {eh:.4f} | {np.array2string(r.e[:5], precision=4)} | "
                  f"max dev {100 * dev.max():.2f} % |")
            ax.plot(r.t, r.theta / alpha, lw=1, label=f"DEM zeta={z} (e={e:.3f})")
            ax.plot(rr.t, rr.theta / alpha, "k--", lw=0.7)
        ax.set_title(f"{b} x {h} m block, Housner e = {eh:.3f} (dashed: murus.rocking, same e)")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("theta / alpha")
        ax.legend(fontsize=7)
    fig.tight_layout()
    OUT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUT, dpi=120)
    print(f"figure: {OUT}")


if __name__ == "__main__":
    main()
