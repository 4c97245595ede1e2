"""``murus study`` commands: run a study file, plot a result, show the state of a study folder.

Thin layer over :mod:`murus.studies`. Bad input exits with code 2 and a one-line message naming
the file, line and key; a bad study writes nothing (every grid node is resolved before the
first chunk runs). A run stores each finished chunk, so running the same command again after an
interruption computes only what is missing.
"""

from __future__ import annotations

from pathlib import Path

import typer

from murus.cliutil import fail as _fail
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


def _progress_bar():
    """A rich progress bar (chunks, ETA) and its callback."""
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    prog = Progress(TextColumn("[bold]{task.description}"), BarColumn(), MofNCompleteColumn(),
                    TextColumn("chunks"), TextColumn("{task.fields[failed]}"),
                    TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn(),
                    transient=False)
    state = {"task": None}

    def callback(done: int, total: int, failed: int) -> None:
        extra = f"[red]{failed} failed" if failed else ""
        if state["task"] is None:
            state["task"] = prog.add_task("study", total=total, completed=done, failed=extra)
        else:
            prog.update(state["task"], completed=done, failed=extra)

    return prog, callback


@app.command()
def run(
    study: Path = typer.Argument(..., help="Study file (TOML)."),
    out: Path | None = typer.Option(None, "--out", "-o",
                                    help="Study folder (default: [output] folder, or the "
                                    "study file's name next to it)."),
    scheduler: str | None = typer.Option(None, "--scheduler",
                                         help="Dask scheduler address, tcp://HOST:PORT."),
    dask: str | None = typer.Option(None, "--dask", help="'local': start a local Dask cluster."),
    workers: int | None = typer.Option(None, "--workers", "-w", min=1,
                                       help="Worker processes (default: the cores)."),
    serial: bool = typer.Option(False, "--serial", help="Run in this process (no pool)."),
    retries: int | None = typer.Option(None, "--retries", min=0,
                                       help="Retries of a failing chunk (default [study])."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress bar."),
) -> None:
    """Run a study: writes OUT/study.json, OUT/chunks/*.npz, OUT/result.nc (resumable)."""
    if sum(x is not None and x is not False for x in (scheduler, dask, serial or None)) > 1:
        _fail("give only one of --scheduler, --dask, --serial")
    if dask is not None and dask != "local":
        _fail(f"--dask takes 'local' (got {dask!r}); use --scheduler tcp://HOST:PORT for a "
              "running cluster")
    kind = "dask" if (scheduler or dask) else "serial" if serial else "process"
    with _guard():
        from murus.studies.study import load_study
        from murus.studies.sweep import run_plan

        st = load_study(study)
        if retries is not None:
            st.retries = retries
        plan = st.plan()
        folder = out if out is not None else Path(st.output) if st.output else \
            study.parent / study.stem
    typer.echo(f"{st.name}: {plan.n_histories:,} histories ({len(plan.points)} grid nodes x "
               f"{plan.n_records} records) in {len(plan.chunks())} chunks -> {folder}")
    with _guard():
        from murus.studies.executors import open_executor

        handle = open_executor(kind, workers, scheduler or ("local" if dask else None))
    try:
        with _guard():
            if quiet:
                ds = run_plan(plan, handle, out=folder, retries=st.retries)
            else:
                prog, cb = _progress_bar()
                with prog:
                    ds = run_plan(plan, handle, out=folder, retries=st.retries, progress=cb)
    finally:
        handle.close()
    n_failed = int(ds.attrs.get("n_failed_chunks", 0))
    if st.figure:
        with _guard():
            _plot(ds, folder / st.figure, None)
    typer.echo(f"result: {folder / 'result.nc'}")
    if n_failed:
        typer.echo(f"warning: {n_failed} chunks failed (their cases are NaN; errors in "
                   f"{folder / 'failures.json'}); run the same command again to retry them",
                   err=True)
        raise typer.Exit(1)


def _plot(ds, png: Path, record: str | None) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if "im" in ds.dims:
        from murus.studies.fragility import plot_fragility

        ax = plot_fragility(ds)
    else:
        from murus.studies.spectrum import plot_rocking_spectrum

        if record is not None and record not in [str(r) for r in ds["record"].values]:
            raise ValueError(f"record {record!r} is not in the result")
        ax = plot_rocking_spectrum(ds, record=record)
    png.parent.mkdir(parents=True, exist_ok=True)
    tmp = png.with_name(f".{png.stem}.tmp{png.suffix or '.png'}")
    ax.figure.savefig(tmp, dpi=120)
    plt.close(ax.figure)
    tmp.replace(png)
    return png


@app.command()
def plot(
    result: Path = typer.Argument(..., help="result.nc of a study (or its folder)."),
    out: Path | None = typer.Option(None, "--out", "-o", help="PNG file (default: next to "
                                    "the result)."),
    record: str | None = typer.Option(None, "--record", help="One record of a spectrum."),
) -> None:
    """Plot a result: a rocking spectrum, or fragility curves when the sweep has 'im'."""
    with _guard():
        from murus.studies.sweep import open_result

        path = result / "result.nc" if result.is_dir() else result
        ds = open_result(path)
        png = out if out is not None else path.with_suffix(".png")
        _plot(ds, png, record)
    typer.echo(f"figure: {png}")


@app.command()
def status(
    folder: Path = typer.Argument(..., help="Study folder (holding study.json)."),
) -> None:
    """Chunks done, missing and failed in a study folder."""
    with _guard():
        from murus.studies.sweep import study_status

        s = study_status(folder)
    typer.echo(f"{s['name']} ({s['digest']}): {len(s['done'])}/{s['total']} chunks done, "
               f"{len(s['missing'])} missing, {len(s['failed'])} failed"
               f"{', result.nc written' if s['result'] else ''}")
    for i, f in sorted(s["failed"].items()):
        typer.echo(f"  failed chunk {i}: {f.get('error')} (attempts: {f.get('attempts')})")
    if s["missing"]:
        m = s["missing"]
        typer.echo(f"  missing: {', '.join(map(str, m[:20]))}{' ...' if len(m) > 20 else ''}")
