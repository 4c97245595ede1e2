"""Helpers shared by the ``murus`` command groups: the one-line error with exit code 2, and a
context manager that turns user errors into it.

Every command group uses these, so that a bad input gives the same shape of message everywhere:
``error: <what is wrong and where>`` on standard error, exit code 2, nothing else.
"""

from __future__ import annotations

import json
import math
import re
import sys
import warnings
from contextlib import contextmanager

import typer

_NUMPY_REPR = re.compile(r"\bnp\.(?:float|int|uint|bool|complex|str)[a-z0-9_]*\(([^()]*)\)")


def plain(message) -> str:
    """``message`` on one line (white space folded) in a user's words: numpy scalar reprs such
    as ``np.float64(5.0)`` become ``5.0``."""
    text = _NUMPY_REPR.sub(r"\1", " ".join(str(message).split()))
    return re.sub(r"\bnp\.(True|False)_", r"\1", text)


_CASE_KEY = re.compile(r"\.toml(?: line \d+)?: \[")


def option_words(message: str, ctx=None, case_key: bool | None = None) -> str:
    """``message`` with the Python names of the current command's parameters written as its
    command-line options: ``delta_t must be > 0`` becomes ``--delta-t must be > 0``. A name is
    replaced where it has an underscore, or where it is followed by ``must``, ``=`` or ``:``
    (so that ordinary words are left alone). A message about a key of a case file keeps the
    key's name: ``case_key`` says so (:func:`guard` knows it from the error's key path and
    file); when it is None (a bare message) the message's ``FILE.toml line N: [`` tells."""
    try:  # typer >= 0.20 carries its own copy of click
        from typer._click.globals import get_current_context
    except ImportError:  # pragma: no cover - older typer
        from click import get_current_context

    ctx = ctx or get_current_context(silent=True)
    if case_key is None:
        case_key = bool(_CASE_KEY.search(message))
    if ctx is None or case_key:  # a case file's keys keep their names
        return message
    for p in ctx.command.params:
        longs = [o for o in getattr(p, "opts", []) if o.startswith("--")]
        if not longs or not p.name or len(p.name) < 2:
            continue
        name = re.escape(p.name)
        pat = (rf"(?<![\w.\[-])({name})(?![\w\]-])" if "_" in p.name
               else rf"(?<![\w.\[-])({name})(?=\s+must\b|\s*=|:)")
        message = re.sub(pat, longs[0], message)
    return message


def error_line(exc: BaseException) -> str:
    """The one-line message of the error ``exc``: a :class:`murus.errors.MurusError` that
    carries a key path and a source file but no location yet (not a
    :class:`murus.config.CaseError`, located where it is raised) is located by
    :func:`murus.config.where` (``FILE line N: [key] message``); any other error gives its
    message (its type name when empty). Only the first line is kept.

    Parameters
    ----------
    exc : BaseException
        The error.

    Returns
    -------
    str
        One line.
    """
    from murus.errors import MurusError

    msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    if isinstance(exc, MurusError) and exc.key and exc.source is not None:
        from pathlib import Path

        from murus.config import CaseError, where

        if isinstance(exc, CaseError):
            return msg

        try:
            text = Path(exc.source).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError):
            text = ""
        msg = f"{where(Path(exc.source), text, exc.key)} {msg}"
    return msg


def _case_key(exc: BaseException) -> bool | None:
    """True when ``exc`` is about a key of a case file (a key path and a file); None when it
    does not say (:func:`option_words` then reads the message)."""
    from murus.errors import MurusError

    if isinstance(exc, MurusError) and exc.key and exc.source is not None:
        return True
    return None


def fail(message, case_key: bool | None = None) -> None:
    """Print ``error: message`` (one line, :func:`plain`, parameters named by their options:
    :func:`option_words`, unless ``case_key``: the message is about a key of a case file) on
    stderr and exit with code 2."""
    typer.echo(f"error: {option_words(plain(message), case_key=case_key)}", err=True)
    raise typer.Exit(code=2)


def failed(message, code: int = 1) -> None:
    """A job that ran but did not succeed: print ``error: message`` (one line) on stderr and
    exit with ``code`` (1; 130 for an interrupt). Bad input uses :func:`fail` (exit 2)."""
    typer.echo(f"error: {plain(message)}", err=True)
    raise typer.Exit(code=code)


def _note(message, category, filename, lineno, file=None, line=None) -> None:
    """``warnings.showwarning`` of the command line: ``note: <message>`` on one line of stderr,
    without the source file, line and code that Python prints."""
    text = " ".join(str(message).split())
    kind = "" if category in (UserWarning, RuntimeWarning) else f" ({category.__name__})"
    try:
        (file or sys.stderr).write(f"note: {text}{kind}\n")
    except (OSError, ValueError):  # stderr closed
        pass


def warnings_as_notes() -> None:
    """Show Python warnings as one-line notes on stderr (the ``murus`` command installs it);
    each distinct note is shown once."""
    warnings.showwarning = _note
    warnings.simplefilter("default")


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
            msg = error_line(exc)
        fail(msg or type(exc).__name__, case_key=_case_key(exc))


def json_safe(v):
    """``v`` with NaN and infinities replaced by None (JSON has no such numbers), numpy
    scalars made Python numbers, dict keys made strings; lists, tuples and dicts recursively."""
    if hasattr(v, "item") and not isinstance(v, dict | list | tuple):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, dict):
        return {str(k): json_safe(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [json_safe(x) for x in v]
    return v


def dumps(obj) -> str:
    """Indented JSON of :func:`json_safe` ``(obj)``."""
    return json.dumps(json_safe(obj), indent=2)
