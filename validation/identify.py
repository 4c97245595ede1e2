"""Validation of the shaking-table processing chain (murus.identify, issue 8).

No public shaking-table data of Mordant et al. (SERIES) ships offline, so each step is validated
where the answer is known: modal identification of base-excited systems of known frequencies and
damping ratios, the Timoshenko cantilever against the exact solution of its equations, the
calibration of the restitution laws against histories synthesised with known parameters, and the
whole chain on a virtual test sequence (``murus lab synthesize``).

``section(fig_dir)`` returns the Markdown section and writes figures; ``python
validation/identify.py`` prints it.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FIG = ROOT / "docs" / "figures" / "identify"
sys.path.insert(0, str(ROOT / "tests" / "identify"))


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def modal_rows() -> list[str]:
    """SDOF (2 % and 5 %) and 2-DOF systems under band-limited white noise with 5 % noise on
    both channels (the synthetic set of tests/identify/test_modal.py)."""
    import test_modal as tm

    from murus.identify.modal import identify

    lines = ["| system | mode | f true [Hz] | f identified [Hz] | error | zeta true [%] | "
             "zeta fit [%] | zeta half-power [%] |", "|---|---|---|---|---|---|---|---|"]
    _, _, f2, _, r2 = tm.two_dof()
    cases = [("SDOF 2 %", [(5.0, 0.02, 1.0)], 1, 2), ("SDOF 5 %", [(5.0, 0.05, 1.0)], 1, 2),
             ("2-DOF", [(f2[0], 0.02, r2[0]), (f2[1], 0.05, r2[1])], 3, 4)]
    for name, modes, s_in, s_meas in cases:
        x, y = tm._simulate(modes, seed=s_in)
        xm, ym = tm._measure(x, y, seed=s_meas)
        res = identify((xm, ym), tm.FS, nperseg=4096, f_max=30.0)
        for k, (f, z, _) in enumerate(modes):
            m = res.modes[k]
            lines.append(f"| {name} | {k + 1} | {f:.4f} | {m.frequency:.4f} | "
                         f"{(m.frequency / f - 1) * 100:+.2f} % | {100 * z:.1f} | "
                         f"{100 * m.damping:.2f} | {100 * m.damping_half_power:.2f} |")
    return lines


def cantilever_rows() -> list[str]:
    import test_cantilever as tc

    from murus.identify.cantilever import Cantilever

    lines = ["| model | exact f1, f2 [Hz] | 8 elements | 16 | 32 | 40 (default) |",
             "|---|---|---|---|---|---|"]
    for label, tip in (("short wall, 5 t on top", dict(tip_mass=5000.0)),
                       ("short wall alone", {})):
        ref = tc.exact_timoshenko(Cantilever(**tc.WALL, **tip), 400.0)[:2]
        cells = []
        for n in (8, 16, 32, 40):
            f = Cantilever(**tc.WALL, **tip, elements=n).frequencies(2)
            err = np.abs(f / ref - 1)
            cells.append(f"{err[0]:.1e}, {err[1]:.1e}")
        lines.append(f"| {label} | {ref[0]:.3f}, {ref[1]:.3f} | " + " | ".join(cells) + " |")
    return lines


def calibration_rows() -> list[str]:
    import test_calibrate as tk

    from murus.identify.calibrate import calibrate
    from murus.rocking import RockingModel
    from murus.rocking.body import series_clay_wall
    from murus.rocking.restitution import AmplitudeDependent

    lines = ["| data | noise | fitted | true | std. error |", "|---|---|---|---|---|"]
    for noise, seed in ((0.0, 1), (0.02, 1), (0.02, 2), (0.02, 3)):
        ms = tk.synthetic(AmplitudeDependent(**tk.TRUE), noise=noise, seed=seed)
        res = calibrate(ms[0].model, ms, {"k0": 1.0, "k1": 1.0})
        p, se = res.params, res.std_error
        lines.append(f"| short wall, 2 sine pulses (seed {seed}) | {100 * noise:.0f} % | "
                     f"k0 = {p['k0']:.3f}, k1 = {p['k1']:.3f} | 1.5, 0.8 | "
                     f"{se['k0']:.2g}, {se['k1']:.2g} |")
    ms = tk.synthetic(AmplitudeDependent(**tk.TRUE, A0=2.0), kinds=("short", "long"), noise=0.02)
    base = RockingModel(series_clay_wall("short"), AmplitudeDependent(**tk.TRUE))
    res = calibrate(base, ms, {"A0": 4.0}, bounds={"A0": (0.5, 10.0)})
    lines.append(f"| short + long walls (A0 of eq. 18) | 2 % | A0 = {res.params['A0']:.3f} | "
                 f"2.0 | {res.std_error['A0']:.2g} |")
    return lines


def virtual_sequence(fig_dir: Path) -> list[str]:
    from murus.identify.classify import classify_sequence
    from murus.identify.modal import evolution, plot_frequency_evolution
    from murus.identify.synth import synthesize_sequence
    from murus.identify.testdata import read_sequence

    plt = _plt()
    with tempfile.TemporaryDirectory() as td:
        folder = synthesize_sequence(Path(td) / "seq", seed=0, wn_duration=60.0)
        truth = json.loads((folder / "truth.json").read_text())["tests"]
        seq = read_sequence(folder)
        evo = evolution(seq)
        classes = classify_sequence(seq)
    wn = [t for t in truth if t["kind"] == "white_noise"]
    lines = ["| white-noise test | f true [Hz] | f identified [Hz] | zeta true [%] | "
             "zeta identified [%] |", "|---|---|---|---|---|"]
    for k, t in enumerate(wn):
        lines.append(f"| {t['test']} | {t['frequency_hz']:.3f} | {evo.frequency[k, 0]:.3f} | "
                     f"{100 * t['damping']:.2f} | {100 * evo.damping[k, 0]:.2f} |")
    ax = plot_frequency_evolution(evo)
    ax.figure.tight_layout()
    fig_dir.mkdir(parents=True, exist_ok=True)
    ax.figure.savefig(fig_dir / "virtual_sequence_frequency.png", dpi=110)
    plt.close(ax.figure)
    seis = [t for t in truth if t["kind"] == "seismic"]
    cl = ", ".join(f"{c.name} {c.label}" + (" (rocked)" if s["rocked"] else "")
                   for c, s in zip(classes, seis, strict=True))
    return lines + ["", f"Classification of the seismic tests: {cl}.", "",
                    "![virtual sequence](docs/figures/identify/virtual_sequence_frequency.png)"]


def section(fig_dir: Path | None = None) -> str:
    fig_dir = fig_dir or FIG
    parts = ["## Shaking-table processing and calibration (murus.identify)", "",
             "No shaking-table data of Mordant et al. (SERIES) are available offline; each step "
             "is checked "
             "where the answer is known.", "",
             "### White-noise identification (H1 FRF, modal fit)", "",
             "600 s of band-limited (0.5-40 Hz) white noise at 100 Hz, exact discrete-time "
             "response, 5 % Gaussian noise on the table and top channels (the issue's "
             "tolerances: 2 % on the frequency, 15 % on the damping).", "",
             *modal_rows(), "",
             "### Timoshenko cantilever against the exact solution", "",
             "Mordant et al. (SERIES) short wall (0.72 x 1.80 x 0.138 m, E = 5.6 GPa, G = 0.4 E, "
             "1800 "
             "kg/m3); exact frequencies from the transfer matrix of the Timoshenko equations "
             "with the tip mass; relative error of the finite elements (f1, f2), converging as "
             "h^2 from above:", "", *cantilever_rows(), "",
             "### Calibration of the restitution laws (Mordant et al. (SERIES), eqs. 14-18)", "",
             "Histories of the Mordant et al. (SERIES) walls under two 3-cycle sine pulses "
             "synthesised with "
             "k0 = 1.5, k1 = 0.8 (and A0 = 2), then fitted (`murus.identify.calibrate`, peaks "
             "objective, 4 starts from a 40-point Latin-hypercube screen):", "",
             *calibration_rows(), "",
             "Without noise the parameters are recovered exactly. With 2 % noise the sum k0 + "
             "k1 (the coefficient of the largest half-cycle) is fixed within a few per cent, "
             "the split between them less well; the Gauss-Newton standard errors understate "
             "the scatter (the residuals of a rocking history are not independent). A0 is "
             "identifiable only from walls of different aspect ratios fitted together.", "",
             "### A virtual test sequence through the whole chain", "",
             "`murus lab synthesize --seed 0` (cantilever wall of 8 Hz degrading along the "
             "sequence, rigid rocking above uplift, sensor noise) read back and identified "
             "(`murus lab sequence`):", "", *virtual_sequence(fig_dir), ""]
    return "\n".join(parts)


if __name__ == "__main__":
    print(section())
