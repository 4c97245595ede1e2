"""Case files: TOML parsed with ``tomllib`` and validated with pydantic, with errors that name the
file, the line and the key in one line (GUIDE §3)."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

from pydantic import BaseModel, ConfigDict, ValidationError


class CaseError(ValueError):
    """An invalid case file; ``str()`` is one line naming the file, line and key."""


class Strict(BaseModel):
    """Base of every case-file table: unknown keys are errors."""

    model_config = ConfigDict(extra="forbid", frozen=True)


_TABLE = re.compile(r"^\s*\[\s*([A-Za-z0-9_.\-\"' ]+?)\s*\]\s*(#.*)?$")


def key_line(text: str, loc: tuple) -> int | None:
    """1-based line of the key ``loc`` (a pydantic location such as ``("body", "width")``) in the
    TOML ``text``, or of its table when the key is absent; ``None`` when neither is found."""
    names = [str(x) for x in loc if not isinstance(x, int)]
    if not names:
        return None
    lines = text.splitlines()
    table: list[str] = []
    table_line: dict[str, int] = {}
    for i, raw in enumerate(lines, start=1):
        m = _TABLE.match(raw)
        if m:
            table = [p.strip().strip("\"'") for p in m.group(1).split(".")]
            table_line.setdefault(".".join(table), i)
            continue
        km = re.match(r"^\s*([A-Za-z0-9_\-\"']+)\s*=", raw)
        if not km:
            continue
        key = km.group(1).strip("\"'")
        if table + [key] == names:
            return i
    # the table of a missing key, or its parent
    for k in range(len(names), 0, -1):
        dotted = ".".join(names[:k])
        if dotted in table_line:
            return table_line[dotted]
    return None


def _where(path: Path, text: str, loc: tuple) -> str:
    line = key_line(text, loc)
    key = ".".join(str(x) for x in loc if not isinstance(x, int)) or "(top level)"
    return f"{path.name}{f' line {line}' if line else ''}: [{key}]"


def load_toml(path) -> tuple[dict, str]:
    """Parse a TOML file; errors become one-line :class:`CaseError`."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise CaseError(f"{path}: no such case file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise CaseError(f"{path}: cannot read the case file ({exc})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"{path.name}: invalid TOML: {exc}") from None
    return data, text


def validate(model: type[BaseModel], data: dict, path: Path, text: str):
    """Validate ``data`` against ``model``; the first error becomes a one-line CaseError."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        loc = tuple(err.get("loc", ()))
        raise CaseError(f"{_where(path, text, loc)} {error_message(err)}") from None


def error_message(err: dict) -> str:
    """The message of one pydantic error, in the words of a case file (unknown key, required
    key is missing, or the validator's message with the offending value)."""
    msg = err.get("msg", "invalid value")
    if err.get("type") == "extra_forbidden":
        return "unknown key"
    if err.get("type") == "missing":
        return "required key is missing"
    msg = msg.removeprefix("Value error, ")
    if "input" in err and not isinstance(err["input"], dict):
        msg = f"{msg} (got {err['input']!r})"
    return msg


def fail_at(path: Path, text: str, loc: tuple, msg: str) -> CaseError:
    """A CaseError for the key ``loc`` of the case file."""
    return CaseError(f"{_where(path, text, loc)} {msg}")
