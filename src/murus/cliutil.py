"""Helpers shared by the ``murus`` command groups: the one-line error with exit code 2, and a
context manager that turns user errors into it.

Every command group uses these, so that a bad input gives the same shape of message everywhere:
``error: <what is wrong and where>`` on standard error, exit code 2, nothing else.
"""

from __future__ import annotations

from contextlib import contextmanager

import typer


def fail(message) -> None:
    """Print ``error: message`` (white space folded to one line) on stderr and exit with code 2."""
    typer.echo(f"error: {' '.join(str(message).split())}", err=True)
    raise typer.Exit(code=2)


@contextmanager
def guard(*errors: type[BaseException], first_line: bool = False):
    """Turn the exceptions ``errors`` raised inside the block into :func:`fail`.

    ``first_line``: keep only the first line of the message (pydantic-style multi-line
    messages); an empty message becomes the exception's type name."""
    try:
        yield
    except errors as exc:
        msg = str(exc)
        if first_line and msg:
            msg = msg.splitlines()[0]
        fail(msg or type(exc).__name__)
