"""``murus mechanism CASE.toml``: kinematic checks of the local mechanisms of a façade.

Thin layer over :mod:`murus.mechanisms` (Circolare 2019 n. 7 §C8.7.1.2.1): reads the case file
(:mod:`murus.mechanisms.case`), runs every hinge level of the simple overturning and the vertical
flexure of the storeys, prints a PASS/FAIL table with the capacity / demand ratios (``--json``:
the summary as JSON) and, with ``--out DIR``, writes ``summary.json`` and one figure of the
capacity curve against the demand per mechanism. Bad input exits with code 2 and one line on
stderr; nothing is written then. A failed check is a result, not an error (exit code 0).
"""

from __future__ import annotations

from pathlib import Path

import typer

from murus.cliutil import dumps, guard

__all__ = ["mechanism", "summary"]


def summary(run: dict, title: str = "") -> dict:
    """The JSON summary of a run of :func:`murus.mechanisms.case.run_case`.

    Parameters
    ----------
    run : dict
        The run.
    title : str
        The case's title.

    Returns
    -------
    dict
    """
    res = run["results"]
    gov = run["governing"]
    s = run["seismic"]
    return {
        "title": title,
        "units": {"a": "m/s2", "d": "m", "M_star": "kg", "z": "m"},
        "FC": s.FC, "q": s.q,
        "limit_states": sorted(s.spectra),
        "governing": {"name": gov.name, "ratio": gov.ratio, "passed": gov.passed},
        "passed": all(r.passed for r in res),
        "mechanisms": [r.summary() for r in res],
    }


def _slug(name: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in name).strip("_")


def _label(name: str) -> str:
    """A short label of a mechanism for the table."""
    return (name.replace("overturning from storey ", "overturning ")
            .replace("vertical flexure of storey ", "v. flexure ")
            .replace("corner overturning ", "corner "))


def _by_activation(c) -> bool:
    """The ratio of a nonlinear check is the activation one (C8.7.1.2.1.8, last paragraph)."""
    d = c.details
    return c.method == "nonlinear" and d.get("activation_ratio", 0) > d.get(
        "displacement_ratio", float("inf"))


def _print_table(run: dict, title: str) -> None:
    from rich import box
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    table = Table(title=f"{escape(title)}: local mechanisms (Circolare 2019 §C8.7.1.2.1)",
                  box=box.SIMPLE, pad_edge=False)
    for col in ("mechanism", "alpha0", "check", "capacity", "demand", "ratio", "result"):
        table.add_column(col, justify="left" if col in ("mechanism", "check") else "right",
                         no_wrap=True)
    for r in run["results"]:
        first = True
        for c in r.checks:
            unit = "m/s2" if c.unit == "m/s2" else "mm"
            k = 1.0 if c.unit == "m/s2" else 1e3
            table.add_row(
                escape(_label(r.name)) if first else "", f"{r.alpha0:.3f}" if first else "",
                f"{c.limit_state} {'a' if c.method == 'linear' else 'd'}",
                f"{c.capacity * k:.3g} {unit}", f"{c.demand * k:.3g} {unit}",
                f"{c.ratio:.2f}" + ("*" if _by_activation(c) else ""),
                ("[green]PASS" if c.passed else "[red]FAIL") if c.governs
                else ("[dim]pass" if c.passed else "[dim]fail"))
            first = False
    Console().print(table)
    typer.echo("a: linear check of the activation acceleration a0* (m/s2); d: nonlinear check "
               "of the displacement (mm); ratio = capacity / demand; *: the activation "
               "acceleration governs (ag,SLD > ag,SLV, §C8.7.1.2.1.8); lower case: for "
               "information, not in the verdict (the linear SLV check is the simplified "
               "method, §C8.7.1.2.1.7)")
    g = run["governing"]
    typer.echo(f"governing: {g.name}, capacity/demand {g.ratio:.2f} "
               f"({'PASS' if g.passed else 'FAIL'})")


def mechanism(
    case: Path = typer.Argument(..., help="Case file (TOML), see murus.mechanisms.case."),
    json_out: bool = typer.Option(False, "--json", help="Print the summary as JSON."),
    out: Path | None = typer.Option(None, "--out", help="Folder for summary.json and the "
                                    "capacity figures."),
) -> None:
    """Kinematic checks of local mechanisms of a masonry façade (NTC 2018, Circolare 2019
    §C8.7.1): simple overturning at every hinge level and vertical flexure, linear (a0*) and
    nonlinear (displacement) checks at SLD, SLV, SLC.

    Parameters
    ----------
    case : pathlib.Path
        The case file.
    json_out : bool
        Print the summary as JSON.
    out : pathlib.Path, optional
        Output folder.
    """
    from murus.config import CaseError
    from murus.mechanisms.case import load_case, run_case
    from murus.outputs import OutputError

    with guard(CaseError, ValueError, first_line=True):
        cfg, path, text = load_case(case)
        run = run_case(cfg, path, text)
    summ = summary(run, cfg.title)
    names = ["summary.json"] + [f"capacity_{_slug(r.name)}.png" for r in run["results"]]
    if out is not None:
        import matplotlib

        matplotlib.use("Agg", force=True)
        import matplotlib.pyplot as plt

        from murus.mechanisms.facade import plot_capacity
        from murus.outputs import command_line, staged_dir

        with guard(OutputError), staged_dir(out, command_line(), names=names) as tmp:
            (tmp / "summary.json").write_text(dumps(summ), encoding="utf-8")
            for r, name in zip(run["results"], names[1:], strict=True):
                ax = plot_capacity(r, seismic=run["seismic"])
                ax.figure.tight_layout()
                ax.figure.savefig(tmp / name, dpi=110)
                plt.close(ax.figure)
    if json_out:
        typer.echo(dumps(summ))
    else:
        _print_table(run, cfg.title)
        if out is not None:
            typer.echo(f"wrote {Path(out) / 'summary.json'} and {len(names) - 1} figure(s)")
