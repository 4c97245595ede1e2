"""Case files: TOML parsed with ``tomllib`` and validated with pydantic, with errors that name the
file, the line and the key in one line (GUIDE §3)."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError


class CaseError(ValueError):
    """An invalid case file; ``str()`` is one line naming the file, line and key."""


class Strict(BaseModel):
    """Base of every case-file table: unknown keys are errors."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class MotionFields(Strict):
    """The ``[motion]`` keys shared by every kind of case file: a record (file, units, dt,
    scale, format) or an analytic signal (amplitude or amplitude_g, frequency, cycles). Each
    case schema adds its own motion types and keys."""

    file: str | None = None
    units: Literal["g", "m/s2", "cm/s2"] | None = None
    dt: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    scale: float = Field(default=1.0, allow_inf_nan=False)
    format: Literal["at2", "esm", "cosmos", "csv"] | None = None
    amplitude: float | None = Field(default=None, allow_inf_nan=False)
    amplitude_g: float | None = Field(default=None, allow_inf_nan=False)
    frequency: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    cycles: float = Field(default=1.0, gt=0, allow_inf_nan=False)

    def check_source(self, kind: str, pulses: tuple[str, ...]) -> None:
        """The checks every motion table shares: a record has a file and nothing else does;
        an analytic pulse of ``pulses`` has exactly one of amplitude, amplitude_g."""
        if kind == "record" and not self.file:
            raise ValueError("a record needs file = '...'")
        if kind != "record" and self.file:
            raise ValueError(f"type '{kind}' takes no file")
        if kind in pulses and (self.amplitude is None) == (self.amplitude_g is None):
            raise ValueError(f"type '{kind}' needs exactly one of amplitude, amplitude_g")


_HEAD = re.compile(r"^\s*(\[\[?)\s*([A-Za-z0-9_.\-\"' ]+?)\s*\]\]?\s*(#.*)?$")
_KEY = re.compile(r"^\s*([A-Za-z0-9_\-\"']+)\s*=")


def key_line(text: str, loc: tuple) -> int | None:
    """1-based line of the key ``loc`` (a pydantic location such as ``("body", "width")``) in the
    TOML ``text``, with array-of-table entries: ``("blocks", 2, "width")`` is the key ``width``
    of the third ``[[blocks]]``; the line of the closest enclosing table when the key itself is
    absent (a default or a missing key); ``None`` when nothing matches."""
    counts: dict[tuple, int] = {}
    table: tuple = ()
    heads: dict[tuple, int] = {}
    keys: dict[tuple, int] = {}
    for i, raw in enumerate(text.splitlines(), start=1):
        m = _HEAD.match(raw)
        if m:
            names = tuple(p.strip().strip("\"'") for p in m.group(2).split("."))
            if m.group(1) == "[[":
                n = counts.get(names, -1) + 1
                counts[names] = n
                table = names + (n,)
            else:
                table = names
            heads.setdefault(table, i)
            continue
        km = _KEY.match(raw)
        if km:
            keys.setdefault(table + (km.group(1).strip("\"'"),), i)
    loc = tuple(loc)
    for k in range(len(loc), 0, -1):
        if loc[:k] in keys:
            return keys[loc[:k]]
        if loc[:k] in heads:
            return heads[loc[:k]]
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
