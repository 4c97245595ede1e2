"""``murus report DIR``: the one-page HTML report of an output folder (:mod:`murus.report`)."""

from __future__ import annotations

from pathlib import Path

import typer

from murus import cliutil


def report(
    folder: Path = typer.Argument(..., help="An output folder of murus (of any command)."),
    open_: bool = typer.Option(False, "--open", help="Open the report in the web browser."),
) -> None:
    """One self-contained HTML page of an output folder, DIR/report.html: the input echoed,
    the results with units, the verdicts, the figures embedded and the references of the
    methods; no external resources, prints cleanly to PDF from a browser."""
    from murus.outputs import OutputError
    from murus.report import detect, write_report

    try:
        path = write_report(folder)
    except OutputError as exc:
        cliutil.fail(str(exc))
    typer.echo(f"{detect(folder)} report -> {path}")
    if open_:
        import webbrowser

        webbrowser.open(path.resolve().as_uri())
