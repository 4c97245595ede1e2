"""The ``murus`` command line.

The CLI is thin: it parses, calls the library and writes outputs. Heavy imports stay inside the
commands so that ``murus --help`` is fast. Bad input exits with code 2 and a one-line message on
standard error, and leaves no output behind.
"""

from __future__ import annotations

from pathlib import Path

import typer
from typer.core import TyperGroup

from murus import cliutil
from murus.identify.cli import app as lab_app
from murus.limit.cli import limit as limit_cmd
from murus.mechanisms.cli import mechanism
from murus.motion.cli import app as motion_app
from murus.report.cli import report as report_cmd
from murus.retaining.cli import app as retaining_app
from murus.rocking.design_cli import app as design_app
from murus.studies.cli import app as study_app


class _Group(TyperGroup):
    """The top-level group: Ctrl-C anywhere in a command ends with one line, ``interrupted``,
    on standard error and exit code 130 (no traceback); outputs are published atomically by
    :mod:`murus.outputs`, so they are left as they were before the command."""

    def main(self, args=None, *rest, **kwargs):
        import sys

        from murus.outputs import set_command

        set_command(sys.argv[1:] if args is None else args)
        return super().main(args, *rest, **kwargs)

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt:
            typer.echo("interrupted", err=True)
            raise typer.Exit(code=130) from None
        except MemoryError as exc:  # an input asking for more memory than the machine has
            size = str(exc).split(":")[-1].strip() if str(exc) else ""
            cliutil.fail(f"the input asks for more memory than this machine has"
                         f"{' (' + size + ')' if size else ''}: check the sizes, the number "
                         "of steps, samples or grid points, and the durations; nothing was "
                         "written")


app = typer.Typer(
    cls=_Group,
    rich_markup_mode=None,
    name="murus",
    help="Seismic assessment of masonry walls: rocking, ground motions, Eurocode checks.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
app.add_typer(motion_app, name="motion")
app.add_typer(design_app, name="design")
app.add_typer(retaining_app, name="retaining")
app.add_typer(study_app, name="study")
app.add_typer(lab_app, name="lab")
app.command("mechanism")(mechanism)
app.command("limit")(limit_cmd)
app.command("report")(report_cmd)
# "studies" is accepted too (hidden), so that either spelling works
app.add_typer(study_app, name="studies", hidden=True)

verify_app = typer.Typer(rich_markup_mode=None, no_args_is_help=True,
                         help="Verification of the engines against closed forms and "
                         "published limits.")
app.add_typer(verify_app, name="verify")


fail = cliutil.fail
cliutil.warnings_as_notes()


def _version(value: bool) -> None:
    if value:
        from importlib.metadata import PackageNotFoundError, version

        try:
            v = version("murus")
        except PackageNotFoundError:  # pragma: no cover - running from a bare source tree
            import murus

            v = getattr(murus, "__version__", "unknown")
        typer.echo(f"murus {v}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", is_eager=True, callback=_version,
                                 help="Print the version and exit."),
) -> None:
    """Seismic assessment of masonry walls: rocking, ground motions, Eurocode checks."""


def _out_error(exc) -> None:
    fail(str(exc))


@app.command()
def run(
    case: Path = typer.Argument(..., help="Case file (TOML)."),
    out: Path = typer.Option(..., "--out", "-o", help="Output folder."),
    no_figure: bool = typer.Option(False, "--no-figure",
                                   help="Skip response.png (blocks.png for a DEM case)."),
    progress: bool = typer.Option(True, "--progress/--no-progress",
                                  help="Progress of a DEM run on stderr: a bar in a terminal, "
                                  "a line every 10 s otherwise."),
) -> None:
    """Run a case file: a rocking case writes summary.json, timeseries.csv and response.png;
    a distinct-element case ([dem] table) writes summary.json, histories.csv, blocks.png and
    an optional VTK series; a continuum case ([continuum]) zones.png instead of blocks.png; a
    case of blocks and zones ([dem] and [[zones]]) model.png and both VTK series."""
    from murus.continuum.case import is_continuum_case
    from murus.continuum.coupled_case import is_coupled_case
    from murus.dem.case import is_dem_case
    from murus.outputs import OutputError, check_dir

    if is_coupled_case(case):  # [dem] and [[zones]]: blocks and zones in one time loop
        _run_coupled(case, out, not no_figure, progress)
        return
    if is_continuum_case(case):
        _run_continuum(case, out, not no_figure, progress)
        return
    if is_dem_case(case):
        _run_dem(case, out, not no_figure, progress)
        return
    from murus.rocking.output import output_names

    try:
        check_dir(out, output_names(not no_figure))
    except OutputError as exc:
        _out_error(exc)
    from murus.config import CaseError
    from murus.rocking.case import build, load_case, run_case
    from murus.rocking.output import write_outputs

    try:
        cfg, path, text = load_case(case)
        model, motion, kwargs = build(cfg, path, text)
        result = run_case(model, motion, kwargs)
    except (CaseError, ValueError) as exc:
        fail(cliutil.error_line(exc))
    try:
        write_outputs(result, out, figure=not no_figure)
    except OutputError as exc:
        _out_error(exc)
    if not result.success:  # the outputs say so too (summary.json: status)
        cliutil.failed(f"{case}: {result.message}; partial results in {out}")
    typer.echo(f"{case.name}: {result.headline()} -> {out}")  # dispatch on the result class


def _run_dem(case: Path, out: Path, figure: bool, progress: bool) -> None:
    """The DEM branch of ``murus run``."""
    from murus.dem import case as module

    _run_blocks(case, out, figure, progress, module, coupled=False)


def _run_blocks(case: Path, out: Path, figure: bool, progress: bool, module,
                coupled: bool) -> None:
    """``murus run`` of a case run by the DEM engine: blocks (:mod:`murus.dem.case`) or blocks
    and zones (:mod:`murus.continuum.coupled_case`, ``coupled``); ``module`` gives
    ``load_case``, ``build``, ``output_names``, ``run_case``, ``summary_line`` and
    ``write_outputs``."""
    from murus.config import CaseError
    from murus.outputs import OutputError, check_dir

    try:
        check_dir(out)
        cfg, path, text = module.load_case(case)
        built = module.build(cfg, path, text)
        figure = figure and (cfg.dem.output.figure if coupled else built.figure)
        check_dir(out, module.output_names(figure))  # before the run
    except OutputError as exc:
        _out_error(exc)
    except CaseError as exc:
        fail(cliutil.error_line(exc))
    from murus.progress import LazyProgress

    settle = built.blocks.settle if coupled else built.settle
    error = None
    with LazyProgress(f"{case.name}", unit="steps", quiet=not progress) as bar:
        bar.update(0, info="settling" if settle is not None else "")
        try:
            res = module.run_case(built, progress=lambda d, t: bar.update(d, t, info="run"))
        except ValueError as exc:
            error = f"{case.name}: {str(exc).splitlines()[0]}"
    if error is not None:
        fail(error)
    if res.result.status == "unstable" and not coupled:
        fail(f"{case.name}: {res.result.message}")
    try:
        module.write_outputs(res, out, figure=figure)
    except OutputError as exc:
        _out_error(exc)
    typer.echo(f"{module.summary_line(case.name, res)} -> {out}")
    if res.result.status == "interrupted":
        cliutil.failed(f"{case.name}: {res.result.message}; the results up to then are in {out} "
                       "(summary.json status 'interrupted'); the run restarts from the "
                       "beginning: run the same command again", code=130)
    if not res.ok:
        # the job did not succeed: its outputs say so (summary.json "ok": false), exit 1
        typer.echo(f"error: {case.name}: {res.result.status}: {res.result.message}", err=True)
        raise typer.Exit(code=1)


def _run_continuum(case: Path, out: Path, figure: bool, progress: bool) -> None:
    """The continuum branch of ``murus run``."""
    from murus.config import CaseError
    from murus.continuum.case import (
        build,
        load_case,
        output_names,
        run_case,
        summary_line,
        write_outputs,
    )
    from murus.outputs import OutputError, check_dir

    try:
        check_dir(out)
        cfg, path, text = load_case(case)
        figure = figure and cfg.output.figure
        check_dir(out, output_names(figure))
        built = build(cfg, path, text)
    except OutputError as exc:
        _out_error(exc)
    except CaseError as exc:
        fail(cliutil.error_line(exc))
    from murus.progress import LazyProgress

    with LazyProgress(f"{case.name}", unit="s", quiet=not progress) as bar:
        res = run_case(built, progress=lambda done, total: bar.update(done, total, info="run"))
    try:
        write_outputs(res, out, figure=figure)
    except OutputError as exc:
        _out_error(exc)
    typer.echo(f"{summary_line(case.name, res)} -> {out}")
    if res.status == "interrupted":
        cliutil.failed(f"{case.name}: {res.result.message}; the results up to then are in {out} "
                       "(summary.json status 'interrupted')", code=130)
    if not res.ok:
        typer.echo(f"error: {case.name}: {res.status}: "
                   f"{res.result.message if res.result is not None else res.settled.message}",
                   err=True)
        raise typer.Exit(code=1)


def _run_coupled(case: Path, out: Path, figure: bool, progress: bool) -> None:
    """The blocks-and-zones branch of ``murus run`` (:mod:`murus.continuum.coupled_case`)."""
    from murus.continuum import coupled_case as module

    _run_blocks(case, out, figure, progress, module, coupled=True)


def _examples_dir(given: Path | None) -> Path | None:
    import murus

    cands = [given] if given else [Path.cwd() / "examples",
                                   Path(murus.__file__).resolve().parents[2] / "examples"]
    for c in cands:
        if c is not None and (c / "demo").is_dir():
            return c
    return None


@app.command()
def demo(
    out: Path = typer.Option(Path("out/demo"), "--out", "-o", help="Output folder."),
    examples: Path | None = typer.Option(None, help="Folder holding demo/*.toml."),
) -> None:
    """Run the demonstration cases (examples/demo/*.toml) and write their outputs."""
    from murus.outputs import OutputError, check_dir
    from murus.rocking.output import atomic_dir, output_names

    ex = _examples_dir(examples)
    if ex is None:
        fail("cannot find the examples/demo folder; run from the murus checkout or give --examples")
    cases = sorted((ex / "demo").glob("*.toml"))
    if not cases:
        fail(f"{ex / 'demo'}: no case files")
    names = ["demo_summary.csv"] + [f"{c.stem}/{n}" for c in cases for n in output_names()]
    try:
        check_dir(out, names)
    except OutputError as exc:
        _out_error(exc)

    def write(tmp: Path) -> None:
        from murus.config import CaseError
        from murus.rocking.case import build, load_case, run_case
        from murus.rocking.engine import RockingResult
        from murus.rocking.output import write_result_files

        lines = ["case,theta_max_over_alpha,impacts,overturned,uplift_time_s"]
        for c in cases:
            try:
                cfg, path, text = load_case(c)
                model, motion, kwargs = build(cfg, path, text)
            except CaseError as exc:
                fail(str(exc))
            res = run_case(model, motion, kwargs)
            sub = tmp / c.stem
            sub.mkdir()
            write_result_files(res, sub)
            s = res.summary()
            rigid = isinstance(res, RockingResult)  # a Winkler case counts zero crossings
            n = s["n_impacts"] if rigid else s["n_crossings"]
            lines.append(f"{c.stem},{s['theta_max_over_alpha']:.6f},{n},"
                         f"{s['overturned']},{s['t_uplift'] if rigid else None}")
            typer.echo(f"{c.stem}: theta_max/alpha = {s['theta_max_over_alpha']:.4f}, "
                       f"impacts = {n}, overturned = {s['overturned']}")
        (tmp / "demo_summary.csv").write_text("\n".join(lines) + "\n")

    try:
        atomic_dir(out, write, names=names)
    except OutputError as exc:
        _out_error(exc)
    typer.echo(f"outputs in {out}/")


def _verify_table(title: str, cases: dict, selected: list[str], quick: bool,
                  obtained: str = "obtained") -> None:
    """Run verification cases and print their rows as a table (case, expected, obtained, error,
    tolerance, result); exit 1 when a row fails. Rows with ``passed=None`` (problems not yet
    available) show ``n/a`` and count neither way."""
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    unknown = [c for c in selected if c not in cases]
    if unknown:
        fail(f"--case {unknown[0]}: unknown case; choose from {', '.join(cases)}")
    table = Table(title=title)
    for col in ("case", "expected", obtained, "error", "tolerance", "result"):
        table.add_column(col, justify="left" if col == "case" else "right")
    failed = 0
    for name in selected or list(cases):
        for r in cases[name](quick):
            if r["passed"] is None:
                table.add_row(escape(r["case"]), "-", "-", "-", f"{r['tolerance']:.3g}",
                              "[yellow]n/a")
                continue
            failed += not r["passed"]
            table.add_row(escape(r["case"]), f"{r['expected']:.4g}", f"{r['obtained']:.4g}",
                          f"{r['error']:.3g}", f"{r['tolerance']:.3g}",
                          "[green]pass" if r["passed"] else "[red]FAIL")
    Console().print(table)
    if failed:
        typer.echo(f"{failed} verification row(s) failed", err=True)
        raise typer.Exit(code=1)


@verify_app.command("dem")
def verify_dem(
    quick: bool = typer.Option(False, "--quick", help="Shorter runs (same tolerances)."),
    case: list[str] = typer.Option([], "--case", "-c",
                                   help="Run only these cases (repeatable); default all."),
) -> None:
    """Run the distinct-element verification cases and print expected, obtained and tolerance.

    Exits with code 1 when a case fails its tolerance."""
    from murus import G
    from murus.dem.verify import CASES

    _verify_table(f"murus.dem verification (g = {G:g} m/s2)", CASES, case, quick)


@verify_app.command("continuum")
def verify_continuum(
    quick: bool = typer.Option(False, "--quick", help="Coarser meshes, shorter runs (same "
                               "tolerances)."),
    case: list[str] = typer.Option([], "--case", "-c",
                                   help="Run only these cases (repeatable); default all."),
) -> None:
    """Run the continuum (zones) verification cases against closed forms and print expected,
    murus, error and tolerance; problems that need parts not built yet show n/a.

    Exits with code 1 when a case fails its tolerance."""
    from murus.continuum.verify import CASES

    _verify_table("murus.continuum verification", CASES, case, quick, obtained="murus")


@verify_app.command("limit")
def verify_limit(
    quick: bool = typer.Option(False, "--quick", help="Fewer bisection steps (same "
                               "tolerances)."),
    case: list[str] = typer.Option([], "--case", "-c",
                                   help="Run only these cases (repeatable); default all."),
) -> None:
    """Run the rigid-block limit analysis verification cases (closed forms, the minimum
    thickness of an arch, published and pseudo-static comparisons) and print expected,
    obtained and tolerance.

    Exits with code 1 when a case fails its tolerance."""
    from murus.limit.verify import CASES

    _verify_table("murus.limit verification", CASES, case, quick)


def main() -> None:  # pragma: no cover - entry point
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
