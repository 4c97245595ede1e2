"""``murus study`` commands: run a study file, plot a result, show the state of a study folder.

Thin layer over :mod:`murus.studies`. Bad input exits with code 2 and a one-line message naming
the file, line and key; a bad study writes nothing (every grid node is resolved before the
first chunk runs). A run stores each finished chunk, so running the same command again after an
interruption computes only what is missing.
"""

from __future__ import annotations

from pathlib import Path

import typer

from murus.cliutil import guard

app = typer.Typer(
    rich_markup_mode=None,
    name="study",
    help="Parameter sweeps over record suites: rocking spectra, fragility (Dask or processes).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _guard():
    from murus.config import CaseError

    return guard(CaseError, ValueError, ImportError, OSError, first_line=True)


def progress_bar(unit: str = "chunks", description: str = "study", quiet: bool = False,
                 poll=None):
    """A progress display (:func:`murus.progress.progress`: a bar in a terminal, a line every
    10 s on stderr otherwise) and its callback ``callback(done, total, failed)`` (the
    ``progress`` of :func:`~murus.studies.sweep.run_tasks`); ``unit`` names the tasks
    ("chunks", "cases"); ``poll() -> str`` adds what the tasks running are doing."""
    from murus.progress import progress

    p = progress(None, description, unit=unit, quiet=quiet, poll=poll)

    def callback(done: int, total: int, failed: int) -> None:
        p.update(done, total=total, info=f"{failed} failed" if failed else "")

    return p, callback


def interrupted(folder: Path, command: str) -> None:
    """Say on stderr what an interrupted study kept and how to resume it, then exit 130 (the
    exit code of a command stopped by SIGINT)."""
    import sys

    from murus.studies.sweep import StudyError, study_status

    try:
        s = study_status(folder)
        kept = f"after {len(s['done'])} of {s['total']} {s['unit']} (kept in {folder})"
    except (StudyError, OSError, ValueError, KeyError):
        kept = "before anything was stored"
    print(f"\ninterrupted {kept}; resume with: {command}", file=sys.stderr, flush=True)
    raise typer.Exit(130)


def resume_command(*words) -> str:
    """``murus WORD ...`` quoted for a POSIX shell."""
    import shlex

    return shlex.join(["murus", *[str(w) for w in words]])


EXECUTOR_HELP = ("Executor: serial, process (a local pool of --workers) or dask (--scheduler; "
                 "default a local cluster). Default: the case file's [executor] table where "
                 "it has one, else process.")

#: The executor options shared by the commands that run studies (``murus study run``,
#: ``murus retaining behaviour-factor``): the defaults of their parameters, one definition
#: each, read by :func:`executor_choice`.
EXECUTOR_OPTION = typer.Option(None, "--executor", help=EXECUTOR_HELP)
WORKERS_OPTION = typer.Option(None, "--workers", "-w", min=1, help="Worker processes (default: "
                              "the case file's [executor] workers where it has them, else the "
                              "cores).")
SCHEDULER_OPTION = typer.Option(None, "--scheduler",
                                help="Dask scheduler address, tcp://HOST:PORT.")
DASK_OPTION = typer.Option(None, "--dask", help="'local': start a local Dask cluster.")
SERIAL_OPTION = typer.Option(False, "--serial", help="Run in this process (no pool).")


def executor_choice(executor: str | None, serial: bool, dask: str | None,
                    scheduler: str | None, default: tuple[str, str | None] = ("process", None)
                    ) -> tuple[str, str | None]:
    """The executor kind and Dask scheduler from the options shared by the commands that run
    studies: ``--executor serial|process|dask``, or the shortcuts ``--serial``, ``--dask
    local`` and ``--scheduler tcp://HOST:PORT`` (a Dask cluster); ``default`` when none is
    given (``--executor dask`` without a scheduler starts a local cluster). Conflicting
    options raise ``ValueError`` (one line)."""
    from murus.studies.executors import EXECUTOR_KINDS

    if executor is not None and executor not in EXECUTOR_KINDS:
        raise ValueError(f"--executor must be one of {', '.join(EXECUTOR_KINDS)}, got "
                         f"{executor!r}")
    if dask is not None and dask != "local":
        raise ValueError(f"--dask takes 'local' (got {dask!r}); use --scheduler "
                         "tcp://HOST:PORT for a running cluster")
    short = [k for k, on in (("serial", serial), ("dask", bool(scheduler or dask))) if on]
    if (scheduler and dask) or len(short) > 1:
        raise ValueError("give only one of --scheduler, --dask, --serial")
    if executor is not None and short and short[0] != executor:
        raise ValueError(f"--executor {executor} conflicts with "
                         f"{'--serial' if serial else '--scheduler/--dask'}")
    if executor is None and not short:
        return default
    kind = executor or short[0]
    return kind, (scheduler or ("local" if dask else None)) if kind == "dask" else None


@app.command()
def run(
    study: Path = typer.Argument(..., help="Study file (TOML)."),
    out: Path | None = typer.Option(None, "--out", "-o",
                                    help="Study folder (default: [output] folder, or the "
                                    "study file's name next to it)."),
    executor: str | None = EXECUTOR_OPTION,
    workers: int | None = WORKERS_OPTION,
    scheduler: str | None = SCHEDULER_OPTION,
    dask: str | None = DASK_OPTION,
    serial: bool = SERIAL_OPTION,
    retries: int | None = typer.Option(None, "--retries", min=0,
                                       help="Retries of a failing chunk (default [study])."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress bar."),
) -> None:
    """Run a study: writes OUT/study.json, OUT/chunks/*.npz, OUT/result.nc (resumable)."""
    with _guard():
        kind, scheduler = executor_choice(executor, serial, dask, scheduler)
    try:
        with _guard():
            from murus.studies.study import load_study
            from murus.studies.sweep import run_plan

            st = load_study(study)
            if retries is not None:
                st.retries = retries
            plan = st.plan()
            folder = out if out is not None else Path(st.output) if st.output else \
                study.parent / study.stem
            from murus.outputs import check_dir, check_file

            check_dir(folder)  # not a file, under a file, the current folder, unwritable
            if st.figure:
                check_file(folder / st.figure, _FIGURES, label="[output] figure")
    except KeyboardInterrupt:
        typer.echo("\ninterrupted while reading the study; nothing was written", err=True)
        raise typer.Exit(130) from None
    typer.echo(f"{st.name}: {plan.n_histories:,} histories ({len(plan.points)} grid nodes x "
               f"{plan.n_records} records) in {len(plan.chunks())} chunks -> {folder}")
    resume = resume_command("study", "run", study, "--out", folder)
    try:
        with _guard():
            from murus.studies.executors import open_executor

            handle = open_executor(kind, workers, scheduler)
        try:
            with _guard():
                prog, cb = progress_bar("chunks", st.name, quiet=quiet)
                with prog:
                    ds = run_plan(plan, handle, out=folder, retries=st.retries, progress=cb)
        finally:
            handle.close()
    except KeyboardInterrupt:
        interrupted(folder, resume)
    n_failed = int(ds.attrs.get("n_failed_chunks", 0))
    if st.figure:
        try:
            with _guard():
                _plot(ds, folder / st.figure, None)
        except KeyboardInterrupt:
            typer.echo(f"\ninterrupted while drawing the figure; the result is complete in "
                       f"{folder / 'result.nc'}; draw it with: "
                       f"{resume_command('study', 'plot', folder, '--out', folder / st.figure)}",
                       err=True)
            raise typer.Exit(130) from None
    typer.echo(f"result: {folder / 'result.nc'}")
    n_early, n_all = stopped_early(ds)
    if n_early:
        typer.echo(f"error: {n_early} of {n_all} histories stopped before the end of the "
                   f"analysis (variable 'status' of {folder / 'result.nc'}: 1 step size "
                   "underflow, 2 step budget exhausted); their results are truncated", err=True)
    if n_early and not n_failed:
        raise typer.Exit(1)
    if n_failed:
        typer.echo(f"warning: {n_failed} chunks failed (their cases are NaN; errors in "
                   f"{folder / 'failures.json'}); run the same command again to retry them",
                   err=True)
        raise typer.Exit(1)


_FIGURES = (".png", ".svg", ".pdf")


def stopped_early(ds) -> tuple[int, int]:
    """(histories whose solver stopped before the end, all histories) of a study result: the
    cases with a ``status`` other than 0 (NaN, a case of a failed chunk, is counted apart)."""
    import numpy as np

    if "status" not in ds:
        return 0, 0
    st = np.asarray(ds["status"].values, dtype=float)
    return int(np.sum(np.isfinite(st) & (st != 0.0))), int(st.size)


def _plot(ds, png: Path, record: str | None, p=None) -> Path:
    def stage(text, done=None, total=None):
        if p is None:
            return
        if done is None:
            p.stage(text)
        else:
            p.update(done, total=total, info=text)

    stage("loading matplotlib (its first use builds a font cache)")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if "im" in ds.dims:
        from murus.studies.fragility import plot_fragility

        def fits(done, total):
            stage("fitting the fragility curves (each with a bootstrap of 200 fits)", done,
                  total)

        ax = plot_fragility(ds, progress=fits)
    else:
        stage("drawing the rocking spectrum")
        from murus.studies.spectrum import plot_rocking_spectrum

        if record is not None and record not in [str(r) for r in ds["record"].values]:
            raise ValueError(f"record {record!r} is not in the result")
        ax = plot_rocking_spectrum(ds, record=record)
    from murus.outputs import write_file

    stage(f"writing {png}")
    try:
        write_file(png, lambda tmp: ax.figure.savefig(tmp, dpi=120), record=True)
    finally:
        plt.close(ax.figure)
    stage(f"wrote {png}")
    return png


@app.command()
def plot(
    result: Path = typer.Argument(..., help="result.nc of a study (or its folder)."),
    out: Path | None = typer.Option(None, "--out", "-o", help="PNG file (default: next to "
                                    "the result)."),
    record: str | None = typer.Option(None, "--record", help="One record of a spectrum."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress."),
) -> None:
    """Plot a result: a rocking spectrum, or fragility curves when the sweep has 'im'."""
    from murus.progress import progress

    try:
        with _guard(), progress(None, "study plot", quiet=quiet) as p:
            from murus.outputs import check_file
            from murus.studies.sweep import open_result

            path = result / "result.nc" if result.is_dir() else result
            png = out if out is not None else path.with_suffix(".png")
            check_file(png, _FIGURES)
            p.stage(f"reading {result}")
            ds = open_result(path)
            _plot(ds, png, record, p)
    except KeyboardInterrupt:
        typer.echo("\ninterrupted; no figure written", err=True)
        raise typer.Exit(130) from None
    typer.echo(f"figure: {png}")


@app.command()
def status(
    folder: Path = typer.Argument(..., help="Study folder (holding study.json)."),
) -> None:
    """Chunks (or cases) done, missing and failed in a study folder."""
    with _guard():
        from murus.studies.sweep import study_status

        s = study_status(folder)
    unit = s.get("unit", "chunks")
    one = unit.removesuffix("s")
    typer.echo(f"{s['name']} ({s['digest']}): {len(s['done'])}/{s['total']} {unit} done, "
               f"{len(s['missing'])} missing, {len(s['damaged'])} damaged, "
               f"{len(s['failed'])} failed"
               f"{', ' + s.get('result_file', 'result.nc') + ' written' if s['result'] else ''}")
    for i, why in sorted(s["damaged"].items()):
        typer.echo(f"  damaged {one} {i} ({s['paths'][i]}): {why}")
    for i, f in sorted(s["failed"].items()):
        typer.echo(f"  failed {one} {i}: {f.get('error')} (attempts: "
                   f"{f.get('attempts')})")
    if s["missing"]:
        m = s["missing"]
        typer.echo(f"  missing: {', '.join(map(str, m[:20]))}{' ...' if len(m) > 20 else ''}")
    if s["damaged"] or s["missing"] or s["failed"]:
        typer.echo("  run the study again with the same --out to compute the others "
                   "(damaged ones included)")
