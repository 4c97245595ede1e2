"""The ``murus`` command line.

The CLI is thin: it parses, calls the library and writes outputs. Heavy imports stay inside the
commands so that ``murus --help`` is fast. Bad input exits with code 2 and a one-line message.
"""

from __future__ import annotations

import typer

from murus.motion.cli import app as motion_app

app = typer.Typer(
    name="murus",
    help="Seismic assessment of masonry walls: rocking, ground motions, Eurocode checks.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
app.add_typer(motion_app, name="motion")


def main() -> None:  # pragma: no cover - entry point
    app()


if __name__ == "__main__":  # pragma: no cover
    main()
