"""``murus limit``: rigid-block limit analysis of a DEM case file (thin layer over
:func:`murus.limit.analyse`). Bad input exits with code 2 and a one-line ``error:`` message on
stderr; the library (scipy, matplotlib) is imported inside the command."""

from __future__ import annotations

from pathlib import Path

import typer

from murus.cliutil import dumps, guard

FILES = ["summary.json", "joints.csv", "mechanism.png"]


def write_files(result, folder: Path, figure: bool = True) -> None:
    """``summary.json`` (load factor, tilt angle, mechanism), ``joints.csv`` (forces of the
    interfaces at collapse, units in the header) and ``mechanism.png`` into ``folder``."""
    folder = Path(folder)
    (folder / "summary.json").write_text(dumps(result.summary()) + "\n")
    (folder / "joints.csv").write_text(result.joints_csv())
    if figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from murus.limit.plots import plot_mechanism

        ax = plot_mechanism(result)
        ax.figure.savefig(folder / "mechanism.png", dpi=120)
        plt.close(ax.figure)


def limit(
    case: Path = typer.Argument(..., help="DEM case file (TOML): [[blocks]] and [[walls]] of "
                                "polygons, fixed or base blocks as supports."),
    load: str = typer.Option("horizontal", "--load", help="'horizontal': a horizontal body "
                             "force proportional to the weights (load factor in g); 'tilt': "
                             "the critical tilt angle of the base."),
    friction: str = typer.Option("non-associative", "--friction", help="'non-associative' "
                                 "(dry joints do not dilate; Gilbert et al. 2006) or "
                                 "'associative' (normality, an upper value)."),
    direction: int = typer.Option(1, "--direction", help="+1: load along +x; -1: along -x."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON (load_factor, mechanism, "
                                 "...) instead of text."),
    out: Path | None = typer.Option(None, "--out", "-o", help="Output folder: summary.json, "
                                    "joints.csv, mechanism.png."),
    no_figure: bool = typer.Option(False, "--no-figure", help="Skip mechanism.png."),
) -> None:
    """Collapse load factor, mechanism and joint forces of the blocks of a DEM case file by
    rigid-block limit analysis (Livesley 1978)."""
    from murus.errors import MurusError
    from murus.outputs import OutputError

    with guard(MurusError, ValueError, OutputError, first_line=True):
        names = FILES if not no_figure else FILES[:2]
        if out is not None:
            from murus.outputs import check_dir

            check_dir(out, names)
        if load not in ("horizontal", "tilt"):
            raise ValueError(f"--load must be 'horizontal' or 'tilt', got '{load}'")
        if friction not in ("non-associative", "associative"):
            raise ValueError("--friction must be 'non-associative' or 'associative', got "
                             f"'{friction}'")
        if direction not in (1, -1):
            raise ValueError(f"--direction must be 1 or -1, got {direction}")
        from murus.limit.solve import analyse

        result = analyse(case, load=load, friction=friction, direction=direction)
        if out is not None:
            from murus.outputs import command_line, staged_dir

            with staged_dir(out, command_line(), names) as tmp:
                write_files(result, tmp, figure=not no_figure)
    if as_json:
        typer.echo(dumps(result.summary()))
        return
    s = result.summary()
    what = (f"critical tilt {s['angle_deg']:.4f} deg (tan = {s['load_factor']:.6g})"
            if load == "tilt" else f"load factor {s['load_factor']:.6g} (g)")
    note = "" if s["converged"] else " (the non-associative scheme did not converge)"
    if s["friction"] == "non-associative" and s["coulomb_residual"] > 1e-3:
        note += (f" (forces exceed Coulomb by up to {s['coulomb_residual']:.2g} of a block "
                 "weight: an estimate, see docs/limit_analysis.md)")
    typer.echo(f"{case.name}: {what}, {s['friction']} friction, {s['blocks']} blocks, "
               f"{s['interfaces']} interfaces, {s['iterations']} LP solution(s){note}")
    if out is not None:
        typer.echo(f"outputs in {out}/")
