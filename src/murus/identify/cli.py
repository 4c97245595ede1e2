"""``murus lab`` commands: shaking-table test processing (issue 8, items 2-4, 7, 8).

Thin layer over :mod:`murus.identify`: ``frf`` (white-noise identification of one test file),
``sequence`` (frequency and damping evolution, classification, compressive lengths and one
Markdown report for a sequence folder) and ``synthesize`` (a virtual sequence in the
documented format). Bad input exits with code 2 and a one-line ``error:`` message on stderr,
and nothing is written: outputs are produced in a temporary folder and moved into place only
when every step has succeeded. The library (scipy, matplotlib) is imported inside the commands.
"""

from __future__ import annotations

from pathlib import Path

import typer

from murus.cliutil import dumps, fail
from murus.identify.pipeline import DENSITY, MODULUS, THICKNESS

app = typer.Typer(
    rich_markup_mode=None,
    name="lab",
    help="Shaking-table tests (Mordant et al. (SERIES), §2): white-noise FRF and modal "
         "parameters, evolution "
         "along a sequence, response classification, compressive length; virtual sequences.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _errors():
    from murus.identify.classify import ClassifyError
    from murus.identify.compressive import CompressiveError
    from murus.identify.modal import ModalError
    from murus.identify.testdata import TestDataError

    return (TestDataError, ModalError, CompressiveError, ClassifyError, ValueError)


def _save(fig, stem: Path) -> None:
    fig.savefig(stem.with_suffix(".png"), dpi=120)
    fig.savefig(stem.with_suffix(".svg"))


def _staged(out: Path, names=None):
    """:func:`murus.outputs.staged_dir`: a temporary folder whose files are published into
    ``out`` at the end (only files murus wrote there before are replaced)."""
    from murus.outputs import command_line, staged_dir

    return staged_dir(out, command_line(), names)


def _written(tmp: Path) -> list[str]:
    return sorted(p.relative_to(tmp).as_posix() for p in tmp.rglob("*") if p.is_file())


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _write_outputs(out: Path, figures: dict, files: dict[str, str]) -> None:
    """Save ``figures`` (stem -> Figure, PNG and SVG) and ``files`` (name -> text) in a
    temporary folder, then move them all into ``out``: nothing is written if a step fails."""
    from murus.outputs import OutputError

    plt = _pyplot()
    try:
        with _staged(out) as tmp:
            for stem, fig in figures.items():
                fig.tight_layout()
                _save(fig, tmp / stem)
                plt.close(fig)
            for name, text in files.items():
                (tmp / name).write_text(text, encoding="utf-8")
            written = _written(tmp)
    except OutputError as exc:
        fail(exc)
    for name in written:
        typer.echo(f"wrote {out / name}")


def _check_out(out: Path, names=None) -> None:
    """Refuse a bad ``--out`` before any computation (:func:`murus.outputs.check_dir`)."""
    from murus.outputs import OutputError, check_dir

    try:
        check_dir(out, names)
    except OutputError as exc:
        fail(exc)


_NPERSEG = typer.Option(None, "--nperseg", help="Welch segment length [samples] (default: "
                        "the power of two nearest to 1/8 of the record).")
_FMIN = typer.Option(0.0, "--f-min", help="Lowest frequency searched for peaks [Hz].")
_FMAX = typer.Option(None, "--f-max", help="Highest frequency searched for peaks [Hz] "
                     "(default 0.8 x Nyquist).")


@app.command()
def frf(
    test_file: Path = typer.Argument(..., help="Test file (CSV, murus.identify.testdata "
                                     "format)."),
    out: Path | None = typer.Option(None, "--out", help="Folder for frf.png/.svg, modes.md, "
                                    "modes.json (default: print only)."),
    n_modes: int | None = typer.Option(None, "--modes", min=1, help="Keep at most this many modes "
                                       "(lowest first)."),
    nperseg: int | None = _NPERSEG,
    f_min: float = _FMIN,
    f_max: float | None = _FMAX,
) -> None:
    """H1 frequency response (top / table acceleration) with coherence, natural frequencies
    by peak picking, damping by half-power and by a modal fit (reliability flags)."""
    from murus.identify.modal import identify
    from murus.identify.testdata import read_test

    if out is not None:
        _check_out(out, ["frf.png", "frf.svg", "modes.md", "modes.json"])
    try:
        test = read_test(test_file)
        res = identify(test, nperseg=nperseg, f_min=f_min, f_max=f_max, n_modes=n_modes)
    except _errors() as exc:
        fail(exc)
    table = res.table()
    typer.echo(f"{test.name}: {len(res.modes)} mode(s), df = {res.frf.df:.4g} Hz, "
               f"{res.frf.n_averages} averages")
    typer.echo(table)
    if out is None:
        return
    _pyplot()
    from murus.identify.modal import plot_frf

    d = res.to_dict()
    d["file"] = str(test_file)
    _write_outputs(out, {"frf": plot_frf(res)[0].figure},
                   {"modes.md": f"# {test.name}\n\n{table}\n", "modes.json": dumps(d)})


@app.command()
def sequence(
    sequence_dir: Path = typer.Argument(..., help="Sequence folder (sequence.toml or NN_*.csv "
                                        "files)."),
    out: Path = typer.Option(..., "--out", help="Output folder."),
    n_modes: int = typer.Option(1, "--modes", min=1, help="Modes followed along the sequence."),
    closure: float = typer.Option(0.0, "--closure", help="Closure of the base joint read as "
                                  "still in contact [m] (murus.identify.compressive)."),
    cantilever_below: float = typer.Option(0.3, "--cantilever-below", help="Classification: "
                                           "peak |rot_bottom| / |rot_top| below this: "
                                           "cantilever."),
    rocking_above: float = typer.Option(0.8, "--rocking-above", help="Classification: ratio "
                                        "at or above this: rocking."),
    min_rotation: float = typer.Option(1e-5, "--min-rotation", help="Classification: top "
                                       "rotation under this [rad] is a cantilever."),
    nperseg: int | None = _NPERSEG,
    f_min: float = _FMIN,
    f_max: float | None = _FMAX,
    modulus: float = typer.Option(MODULUS, "--modulus", help="Cantilever model: Young's modulus "
                                  "E [Pa] (default 1000 fk, EN 1996-1-1 §3.7.2, with the "
                                  "Mordant et al. (SERIES) measured fk = 5.6 MPa, printed '6.5' "
                                  "by the "
                                  "extraction); G = 0.4 E."),
    density: float = typer.Option(DENSITY, "--density", help="Cantilever model: masonry "
                                  "density [kg/m3]."),
    thickness: float = typer.Option(THICKNESS, "--thickness", help="Cantilever model: wall "
                                    "thickness [m]."),
) -> None:
    """Frequency and damping evolution (Mordant et al. (SERIES), Figures 3-4), classification (§2.3)
    with the rotations (Figures 6-7), compressive lengths (Table 2, Figure 5), lifted lengths
    (Figures 19-20), the Timoshenko cantilever model against the identified frequencies, and
    one Markdown report."""
    from murus.identify.classify import Criterion
    from murus.identify.pipeline import process_sequence

    _check_out(out, ["summary.json", "report.md"])
    try:
        crit = Criterion(cantilever_below=cantilever_below, rocking_above=rocking_above,
                         min_rotation=min_rotation)
        rep = process_sequence(sequence_dir, n_modes=n_modes, closure=closure, criterion=crit,
                               nperseg=nperseg, f_min=f_min, f_max=f_max, modulus=modulus,
                               density=density, thickness=thickness)
    except _errors() as exc:
        fail(exc)
    _pyplot()
    from murus.outputs import OutputError

    try:
        with _staged(out, ["summary.json", "report.md"]) as tmp:
            rep.write(tmp)
            written = _written(tmp)
    except OutputError as exc:
        fail(exc)
    for name in written:
        typer.echo(f"wrote {out / name}")


@app.command()
def synthesize(
    out_dir: Path = typer.Argument(..., help="Folder to create (must not exist or be empty)."),
    seed: int = typer.Option(0, "--seed", help="Random seed (the output is deterministic)."),
    levels: str = typer.Option(",".join(f"{a:g}" for a in (0.04, 0.08, 0.08, 0.16, 0.24, 0.32,
                                                            0.45)),
                               "--levels", help="Nominal PGAs of the seismic tests [g], "
                               "comma-separated."),
    wn_duration: float = typer.Option(120.0, "--wn-duration", help="Duration of each "
                                      "white-noise test [s]."),
    fs: float = typer.Option(100.0, "--fs", help="Sampling rate [Hz]."),
) -> None:
    """Write a virtual test sequence (cantilever + rigid rocking wall with sensor noise,
    murus.identify.synth) in the documented format, with sequence.toml and truth.json."""
    from murus.identify.synth import synthesize_sequence
    from murus.outputs import OutputError

    if out_dir.is_dir() and any(out_dir.iterdir()):
        # a sequence folder is read as a whole: never mix it with other files
        fail(f"{out_dir}: exists and is not an empty folder")
    _check_out(out_dir)
    try:
        lv = [float(x) for x in levels.split(",") if x.strip()]
    except ValueError:
        fail(f"--levels must be comma-separated numbers [g], got {levels!r}")
    try:
        with _staged(out_dir) as tmp:
            synthesize_sequence(tmp, seed=seed, levels=lv, wn_duration=wn_duration, fs=fs)
            moved = _written(tmp)
    except (*_errors(), OutputError) as exc:
        fail(exc)
    typer.echo(f"wrote {len(moved)} files to {out_dir}")


def _bounds(items: list[str]) -> dict[str, tuple[float, float]]:
    out = {}
    for it in items:
        name, _, rng = it.partition("=")
        lo, _, hi = rng.partition(":")
        try:
            out[name.strip()] = (float(lo), float(hi))
        except ValueError:
            raise ValueError(f"--bounds takes NAME=LOW:HIGH, got {it!r}") from None
    return out


@app.command()
def calibrate(
    test_files: list[Path] = typer.Argument(..., help="Seismic test files (CSV, "
                                            "murus.identify.testdata format) with a rotation "
                                            "channel."),
    params: str = typer.Option("k0,k1", "--params", help="Parameters to fit, comma-separated, "
                               "among k0, k1, k0_free, k1_free, A0 (Mordant et al. (SERIES), eqs. "
                               "14-18)."),
    start: list[str] = typer.Option([], "--start", help="Initial value NAME=VALUE (repeat); "
                                    "default 1 (A0: 2)."),
    bounds: list[str] = typer.Option([], "--bounds", help="NAME=LOW:HIGH (repeat); defaults "
                                     "in murus.identify.calibrate.PARAMETERS."),
    pivot: str = typer.Option("corner", "--pivot", help="'corner' (Housner) or "
                              "'compressive-length' (Mordant et al. (SERIES), eq. 11)."),
    channel: str = typer.Option("rot_bottom", "--channel", help="Rotation channel compared."),
    objective: str = typer.Option("peaks", "--objective", help="'peaks' or 'envelope'."),
    window: float = typer.Option(0.25, "--window", help="Time resolution of the comparison "
                                 "[s]."),
    starts: int = typer.Option(4, "--starts", min=1, help="Least-squares starts."),
    thickness: float = typer.Option(0.138, "--thickness", help="Wall thickness [m] (only with "
                                    "--density)."),
    density: float = typer.Option(0.0, "--density", help="Masonry density [kg/m3]; 0: the "
                                  "self-weight is neglected beside the top mass (Mordant et al. "
                                  "(SERIES) "
                                  "§3.1)."),
    out: Path | None = typer.Option(None, "--out", help="Folder for calibration.md, "
                                    "calibration.json and calibration.png/.svg."),
) -> None:
    """Fit the restitution laws of the modified rocking model (Mordant et al. (SERIES), §3.3) to
    measured rotation histories (murus.identify.calibrate): a rigid wall of the test file's length
    and height with its top mass, least squares on the rotation peaks, with bounds and several
    starts; prints the fitted values, their standard errors and sensitivities."""
    from murus.identify.calibrate import PARAMETERS, CalibrationError, measurement_from_test
    from murus.identify.calibrate import calibrate as fit
    from murus.identify.testdata import read_test
    from murus.rocking import RigidBlock, RockingModel
    from murus.rocking.body import BodyError
    from murus.rocking.restitution import AmplitudeDependent
    from murus.rocking.restraints import Pivot, RestraintError

    if out is not None:
        _check_out(out, ["calibration.png", "calibration.svg", "calibration.md",
                         "calibration.json"])
    names = [p.strip() for p in params.split(",") if p.strip()]
    try:
        init = {k: (2.0 if k == "A0" else 1.0) for k in names}
        for it in start:
            k, _, v = it.partition("=")
            try:
                init[k.strip()] = float(v)
            except ValueError:
                raise ValueError(f"--start takes NAME=VALUE, got {it!r}") from None
            if k.strip() not in names:
                raise ValueError(f"--start {k.strip()}: not among --params {params!r}")
        bnd = _bounds(bounds)
        for k in list(init) + list(bnd):
            if k not in PARAMETERS:
                raise ValueError(f"unknown parameter {k!r}; choose from {', '.join(PARAMETERS)}")
        if pivot not in ("corner", "compressive-length"):
            raise ValueError(f"--pivot must be 'corner' or 'compressive-length', got {pivot!r}")
        tests = [read_test(f) for f in test_files]
        ms = []
        for t in tests:
            if t.top_mass is None and density <= 0:
                raise ValueError(f"{t.name}: the test file gives no top_mass_kg and --density "
                                 "is 0: the wall has no mass")
            body = RigidBlock(width=t.wall_length, height=t.wall_height, thickness=thickness,
                              density=density, top_mass=t.top_mass or 0.0, name=t.name)
            kw = {} if pivot == "corner" else {"pivot": Pivot("compressive-length")}
            mdl = RockingModel(body, AmplitudeDependent(k0=1.0, k1=0.0), **kw)
            ms.append(measurement_from_test(t, channel, model=mdl))
        from murus.progress import LazyProgress

        with LazyProgress("lab calibrate", unit="evaluations") as bar:
            res = fit(ms[0].model, ms, init, bounds=bnd or None, objective=objective,
                      window=window, starts=starts, progress=bar.update)
    except (*_errors(), CalibrationError, BodyError, RestraintError) as exc:
        error = exc
    else:
        error = None
    if error is not None:
        fail(error)
    table = res.table()
    typer.echo(f"calibrated {', '.join(names)} on {len(ms)} test(s), objective "
               f"'{res.objective}', {res.n_residuals} residuals, cost {res.cost:.4g}")
    typer.echo(table)
    if out is None:
        return
    plt = _pyplot()
    from murus.identify.calibrate import plot_calibration

    fig, axes = plt.subplots(len(ms), 1, figsize=(8, 2.6 * len(ms)), squeeze=False)
    for m, ax in zip(ms, axes[:, 0], strict=True):
        plot_calibration(m.model, m, res.params, ax=ax)
    d = {"params": res.params, "std_error": res.std_error, "sensitivity": res.sensitivity,
         "rms": res.rms, "cost": res.cost, "objective": res.objective, "pivot": pivot,
         "starts": res.starts, "files": [str(f) for f in test_files]}
    _write_outputs(out, {"calibration": fig}, {
        "calibration.md": f"# Calibration ({', '.join(t.name for t in tests)})\n\n{table}\n",
        "calibration.json": dumps(d)})
