"""The processing of a shaking-table sequence, as one library function (the pipeline behind
``murus lab sequence``).

:func:`process_sequence` reads a sequence folder (:func:`~murus.identify.testdata.read_sequence`)
and runs, in order: the evolution of the natural frequencies and damping ratios along the
white-noise tests (:func:`~murus.identify.modal.evolution`; Mordant et al. (SERIES), Figures
3-4), the cantilever / hybrid / rocking classification of the seismic tests
(:func:`~murus.identify.classify.classify_sequence`; §2.3, Figures 6-7), the compressive lengths
from the base transducers (:func:`~murus.identify.compressive.compressive_table`; Table 2,
Figure 5) and the Timoshenko cantilever against the identified first frequencies
(:mod:`murus.identify.cantilever`). The :class:`SequenceReport` it returns holds the results,
their JSON summary and Markdown report, and writes them with the figures into a folder
(:meth:`SequenceReport.write`); the CLI publishes that folder atomically
(:mod:`murus.outputs`).

>>> from murus.identify import process_sequence           # doctest: +SKIP
>>> rep = process_sequence("tests/data/sequence", n_modes=1)  # doctest: +SKIP
>>> rep.summary()["evolution"]                              # doctest: +SKIP

Units: SI (m, kg, s, Pa, rad; frequencies in Hz).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

__all__ = ["SequenceReport", "process_sequence", "MODULUS", "DENSITY", "THICKNESS"]

#: Young's modulus of the cantilever model [Pa]: ``E = 1000 f_k`` (EN 1996-1-1 §3.7.2) with the
#: measured ``f_k = 5.6 MPa`` of Mordant et al. (SERIES) (printed "6.5" by the extraction);
#: ``G = 0.4 E``.
MODULUS = 5.6e9
#: Masonry density of the cantilever model [kg/m³] (clay masonry, Mordant et al. (SERIES)).
DENSITY = 1800.0
#: Wall thickness of the cantilever model [m] (the 138 mm walls of Mordant et al. (SERIES)).
THICKNESS = 0.138


@dataclass
class SequenceReport:
    """Results of :func:`process_sequence`.

    Attributes
    ----------
    sequence : TestSequence
        The sequence read.
    folder : str
        The sequence folder as given.
    evolution : Evolution
        Frequencies and damping along the white-noise tests.
    classifications : list of Classification
        One per seismic test with both rotation channels.
    compressive : CompressiveTable or None
        Compressive lengths (None: no seismic test has base transducers).
    criterion : Criterion
        Thresholds of the classification.
    closure : float
        Closure of the base joint read as still in contact [m].
    cantilever : dict or None
        The Timoshenko cantilever against the identified first frequencies (None: empty
        sequence).
    """

    sequence: object
    folder: str
    evolution: object
    classifications: list
    compressive: object | None
    criterion: object
    closure: float
    cantilever: dict | None

    def summary(self) -> dict:
        """The content of ``summary.json`` (JSON-safe dictionary)."""
        crit = self.criterion
        return {"sequence": self.sequence.name, "folder": self.folder,
                "table1": self.sequence.table1(), "evolution": self.evolution.rows(),
                "classification": [c.to_dict() for c in self.classifications],
                "compressive_length": (self.compressive.rows if self.compressive is not None
                                       else None),
                "criterion": {"cantilever_below": crit.cantilever_below,
                              "rocking_above": crit.rocking_above,
                              "min_rotation_rad": crit.min_rotation},
                "closure_m": self.closure, "cantilever": self.cantilever}

    def markdown(self, figures: list[str] | None = None) -> str:
        """The content of ``report.md``; ``figures`` the figure files written (as
        :meth:`write` returns them)."""
        return (_report(self.sequence, self.evolution, self.classifications, self.compressive,
                        self.criterion, self.closure, figures or [])
                + _cantilever_report(self.cantilever))

    def write(self, folder) -> list[str]:
        """Write the figures (PNG and SVG), ``compressive_length.csv``, ``summary.json`` and
        ``report.md`` into the existing folder ``folder`` (not atomic: the CLI writes into a
        staged folder, :func:`murus.outputs.staged_dir`). Needs matplotlib. Returns the
        figures listed in the report."""
        import matplotlib.pyplot as plt

        from murus.cliutil import dumps
        from murus.identify.classify import plot_lifted_length, plot_rotations
        from murus.identify.compressive import plot_contact_length
        from murus.identify.modal import plot_damping_evolution, plot_frequency_evolution

        tmp = Path(folder)
        seq, comp = self.sequence, self.compressive
        figs = []
        for stem, fn in (("frequency", plot_frequency_evolution),
                         ("damping", plot_damping_evolution)):
            ax = fn(self.evolution)
            ax.figure.tight_layout()
            _save(ax.figure, tmp / stem)
            figs.append(f"{stem}.png")
            plt.close(ax.figure)
        if comp is not None:
            ax = plot_contact_length(comp)
            ax.figure.tight_layout()
            _save(ax.figure, tmp / "compressive_length")
            figs.append("compressive_length.png")
            plt.close(ax.figure)
            (tmp / "compressive_length.csv").write_text(comp.to_csv(), encoding="utf-8")
        by_label = {e.label: e for e in seq.seismic}
        for c in self.classifications:
            ax = plot_rotations(by_label[c.name].test, classification=c)
            ax.figure.tight_layout()
            _save(ax.figure, tmp / f"rotations_{c.name}")
            plt.close(ax.figure)
        for e in seq.seismic:
            if e.test.has_lvdt:
                ax = plot_lifted_length(e.test, closure=self.closure)
                ax.figure.tight_layout()
                _save(ax.figure, tmp / f"lifted_{e.label}")
                plt.close(ax.figure)
        (tmp / "summary.json").write_text(dumps(self.summary()), encoding="utf-8")
        (tmp / "report.md").write_text(self.markdown(figs), encoding="utf-8")
        return figs


def process_sequence(sequence_dir, *, n_modes: int = 1, closure: float = 0.0,
                     criterion=None, nperseg: int | None = None, f_min: float = 0.0,
                     f_max: float | None = None, modulus: float = MODULUS,
                     density: float = DENSITY, thickness: float = THICKNESS) -> SequenceReport:
    """Process a shaking-table sequence: modal evolution, classification, compressive lengths
    and the cantilever model (module docstring).

    Parameters
    ----------
    sequence_dir : path-like
        Sequence folder (``sequence.toml`` or ``NN_*.csv`` files,
        :func:`~murus.identify.testdata.read_sequence`).
    n_modes : int
        Modes followed along the sequence.
    closure : float
        Closure of the base joint read as still in contact [m]
        (:mod:`murus.identify.compressive`).
    criterion : Criterion, optional
        Thresholds of the classification (default ``Criterion()``).
    nperseg : int, optional
        Welch segment length [samples] (default: the power of two nearest to 1/8 of the
        record).
    f_min, f_max : float
        Frequency band searched for peaks [Hz] (``f_max`` default 0.8 x Nyquist).
    modulus : float
        Young's modulus of the cantilever model [Pa] (:data:`MODULUS`).
    density : float
        Masonry density of the cantilever model [kg/m³] (:data:`DENSITY`).
    thickness : float
        Wall thickness of the cantilever model [m] (:data:`THICKNESS`).

    Returns
    -------
    SequenceReport

    Raises
    ------
    TestDataError, ModalError, CompressiveError, ClassifyError, ValueError
        Bad input (one-line messages).

    References
    ----------
    Mordant, Dietz & Degée (SERIES shaking-table tests), §2, Figures 3-7 and 19-20, Table 2.
    """
    from murus.identify.classify import Criterion, classify_sequence
    from murus.identify.compressive import compressive_table
    from murus.identify.modal import evolution
    from murus.identify.testdata import read_sequence

    crit = Criterion() if criterion is None else criterion
    seq = read_sequence(sequence_dir)
    evo = evolution(seq, n_modes=n_modes, nperseg=nperseg, f_min=f_min, f_max=f_max)
    classes = classify_sequence(seq, crit)
    comp = None
    if any(e.test.has_lvdt for e in seq.seismic):
        comp = compressive_table(seq, closure=closure)
    cant = _cantilever_rows(seq, evo, modulus, density, thickness)
    return SequenceReport(seq, str(sequence_dir), evo, classes, comp, crit, closure, cant)


def _save(fig, stem: Path) -> None:
    fig.savefig(stem.with_suffix(".png"), dpi=120)
    fig.savefig(stem.with_suffix(".svg"))


def _cantilever_rows(seq, evo, modulus, density, thickness) -> dict | None:
    """The Timoshenko cantilever of the sequence's wall (length, height and top mass of its
    first test) against the identified first frequencies: model f1 and E_eff per test."""
    import numpy as np

    from murus.cliutil import json_safe
    from murus.identify.cantilever import Cantilever, equivalent_moduli

    if not len(seq):
        return None
    t0 = seq.entries[0].test
    c = Cantilever(height=t0.wall_height, length=t0.wall_length, thickness=thickness,
                   modulus=modulus, density=density, tip_mass=t0.top_mass or 0.0)
    f = evo.frequency[:, 0] if evo.frequency.size else np.zeros(0)
    E = equivalent_moduli(c, f)
    return {"modulus_pa": modulus, "density": density, "thickness_m": thickness,
            "length_m": c.length, "height_m": c.height, "top_mass_kg": c.tip_mass,
            "f1_model_hz": float(c.frequencies(1)[0]),
            "tests": [{"test": lab, "f1_hz": json_safe(float(fi)),
                       "E_eff_pa": json_safe(float(e))}
                      for lab, fi, e in zip(evo.labels, f, E, strict=True)]}


def _cantilever_report(cant: dict | None) -> str:
    if cant is None:
        return ""
    lines = ["", "## Cantilever model (low-amplitude regime)", "",
             f"Timoshenko cantilever (murus.identify.cantilever): L = {cant['length_m']:g} m, "
             f"H = {cant['height_m']:g} m, t = {cant['thickness_m']:g} m, E = "
             f"{cant['modulus_pa'] / 1e9:.3g} GPa, G = 0.4 E, {cant['density']:g} kg/m3, top "
             f"mass {cant['top_mass_kg']:g} kg: f1 = {cant['f1_model_hz']:.3f} Hz. E_eff is the "
             "modulus that gives each identified f1 (E_eff / E = (f1 / f1,model)^2).", "",
             "| test | f1 identified [Hz] | f1 / f1,model | E_eff [GPa] |", "|---|---|---|---|"]
    for r in cant["tests"]:
        f1 = r["f1_hz"]
        if f1 is None:
            lines.append(f"| {r['test']} | / | / | / |")
            continue
        lines.append(f"| {r['test']} | {f1:.3f} | {f1 / cant['f1_model_hz']:.3f} | "
                     f"{r['E_eff_pa'] / 1e9:.3f} |")
    return "\n".join(lines) + "\n"


def _report(seq, evo, classes, comp, crit, closure, figs) -> str:
    lines = [f"# Shaking-table sequence: {seq.name}", "",
             f"Folder `{seq.folder}`, {len(seq)} tests ({len(seq.seismic)} seismic, "
             f"{len(seq.white_noise)} white noise).", "", "## Seismic tests (Mordant et al. "
                                                          "(SERIES), Table 1)",
             "", "| No | Test | PGA nominal [g] | PGA measured [g] |", "|---|---|---|---|"]
    for r in seq.table1():
        nom = "/" if r["pga_nominal_g"] is None else f"{r['pga_nominal_g']:.4f}"
        lines.append(f"| {r['no']} | {r['test']} | {nom} | {r['pga_measured_g']:.4f} |")
    lines += ["", "## Natural frequencies and damping (white-noise tests, Mordant et al. "
                  "(SERIES), Figures 3-4)",
              "", "H1 FRF of top over table acceleration; frequency and damping from a modal "
              "fit of the base-excitation transmissibility near each peak; (?) marks an "
              "unreliable estimate (see summary.json for the reasons).", "", evo.table(), "",
              "![frequency](frequency.png)", "", "![damping](damping.png)", "",
              "## Classification (Mordant et al. (SERIES), §2.3)", "",
              f"ratio = max|rot_bottom| / max|rot_top|: cantilever below "
              f"{crit.cantilever_below}, rocking at or above {crit.rocking_above}, hybrid in "
              f"between; cantilever when max|rot_top| < {crit.min_rotation:g} rad.", ""]
    if classes:
        lines += ["| Test | Class | Ratio | max rot bottom [mrad] | max rot top [mrad] |",
                  "|---|---|---|---|---|"]
        for c in classes:
            ratio = "/" if not math.isfinite(c.ratio) else f"{c.ratio:.3f}"
            lines.append(f"| {c.name} | {c.label} | {ratio} | {1e3 * c.peak_bottom:.4f} | "
                         f"{1e3 * c.peak_top:.4f} |")
    else:
        lines.append("No seismic test has both rotation channels.")
    lines += ["", "## Compressive length (Mordant et al. (SERIES), Table 2, Figure 5)", ""]
    if comp is not None:
        lines += [f"Plane base section fitted to the base transducers; contact where the "
                  f"opening is at most {closure:g} m. Eurocode 6 assessments: equivalent "
                  "static load 2.5 x level x m g at the top (murus.eurocode.ec6).", "",
                  comp.to_markdown(), "", "![compressive length](compressive_length.png)", "",
                  "Lifted length L - Lc against time (Mordant et al. (SERIES), Figures 19-20): "
                  "`lifted_<test>.png`; bottom and top rotations (Figures 6-7): "
                  "`rotations_<test>.png`."]
    else:
        lines.append("No seismic test has base transducers.")
    return "\n".join(lines) + "\n"
