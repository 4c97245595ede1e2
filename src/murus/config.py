"""Case files: TOML parsed with ``tomllib`` and validated with pydantic, with errors that name the
file, the line and the key in one line (GUIDE §3)."""

from __future__ import annotations

import math
import re
import tomllib
import types
import typing
from pathlib import Path
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, ValidationInfo, field_validator

from murus.errors import MurusError, key_name


class CaseError(MurusError, ValueError):
    """An invalid case file; ``str()`` is one line naming the file, line and key.

    Made by :func:`fail_at` (or :func:`locate`), it also carries the key path (:attr:`key`), the
    file (:attr:`source`) and the message without its location (:attr:`reason`), so that a
    caller that re-locates the error (a study naming the grid node, a command naming its
    option) reads them instead of parsing the message.

    Parameters
    ----------
    *args
        The one-line message.
    key, source
        As for :class:`murus.errors.MurusError`.
    reason : str, optional
        The message without the location (default: the message).
    """

    def __init__(self, *args, key=(), source=None, reason: str | None = None) -> None:
        super().__init__(*args, key=key, source=source)
        self.reason = reason if reason is not None else (str(args[0]) if args else "")


#: Physical sense of case-file keys, declared once for every case schema (by key name):
#: ``name: (largest magnitude, unit, what)``. A value beyond it is refused with the limit named;
#: the limits are far beyond any masonry wall or shaking table, so good input is never refused.
#: :data:`PHYSICAL_MINIMA` gives the smallest non-zero magnitude of some of them (zero and the
#: sign are each schema's own checks).
PHYSICAL_LIMITS: dict[str, tuple[float, str, str]] = {
    **{k: (1.0e3, "m", "a length") for k in (
        "width", "height", "thickness", "block_width", "block_height", "layer_thickness",
        "effective_height", "radius", "length")},
    "density": (3.0e4, "kg/m3", "a density (osmium: 22,600 kg/m3)"),
    "top_mass": (1.0e9, "kg", "a mass"),
    "scale": (1.0e3, "-", "a scale factor of the motion"),
    "amplitude": (1.0e3, "m/s2", "a ground acceleration (100 g)"),
    "amplitude_g": (100.0, "g", "a ground acceleration"),
    "frequency": (1.0e4, "Hz", "a frequency"),
    "kv_ratio": (1.0, "-", "the ratio kv / kh (EN 1998-5 (7.2): 0.5 or 0.33)"),
}

#: Smallest non-zero magnitude of a length (0.1 mm: below a mortar joint, a rubber layer or a
#: grain of a disc packing) and of a density (1 kg/m3: air is 1.2).
PHYSICAL_MINIMA: dict[str, float] = {
    **{k: 1.0e-4 for k in ("width", "height", "thickness", "block_width", "block_height",
                           "layer_thickness", "effective_height", "radius", "length")},
    "density": 1.0,
}


def check_physical(key: str, value, label: str | None = None) -> None:
    """Raise ValueError when ``value`` of the key ``key`` of :data:`PHYSICAL_LIMITS` is beyond
    its physical limit; ``label`` names the value in the message (default ``key``; the CLI
    passes its option, e.g. ``--width``). Other keys and non-numbers pass."""
    lim = PHYSICAL_LIMITS.get(key)
    if lim is None or not isinstance(value, int | float) or isinstance(value, bool):
        return
    if not math.isfinite(value):
        raise ValueError(f"{label + ' ' if label else ''}{value}: not a finite number")
    unit = "" if lim[1] == "-" else f" {lim[1]}"
    what = f"{label} " if label else ""
    low = PHYSICAL_MINIMA.get(key, 0.0)
    if 0.0 < abs(value) < low:
        raise ValueError(f"{what}{value:g}{unit} is outside the physical range of {lim[2]}: a "
                         f"non-zero magnitude is at least {low:g}{unit}")
    if abs(value) <= lim[0]:
        return
    raise ValueError(f"{what}{value:g}{unit} is outside the physical range of {lim[2]}: its "
                     f"magnitude is at most {lim[0]:g}{unit}")


def _only_numbers(ann) -> bool:
    """True when the annotation ``ann`` admits numbers (int, float) and None only."""
    if typing.get_origin(ann) is Annotated:
        ann = typing.get_args(ann)[0]
    if typing.get_origin(ann) in (typing.Union, types.UnionType):
        args = [a for a in typing.get_args(ann) if a is not type(None)]
        return bool(args) and all(_only_numbers(a) for a in args)
    return ann in (int, float)


def _not_a_number(ann, value) -> object:
    """The first string or boolean inside ``value`` standing where ``ann`` admits only numbers
    (scalars, lists and tuples of numbers); ``None`` when there is none."""
    if typing.get_origin(ann) is Annotated:
        ann = typing.get_args(ann)[0]
    if isinstance(value, str | bool) and _only_numbers(ann):
        return value
    origin = typing.get_origin(ann)
    if origin in (typing.Union, types.UnionType):
        for a in typing.get_args(ann):
            if typing.get_origin(a) in (list, tuple) and isinstance(value, list | tuple):
                return _not_a_number(a, value)
        return None
    if origin in (list, tuple) and isinstance(value, list | tuple):
        args = [a for a in typing.get_args(ann) if a is not Ellipsis]
        for i, v in enumerate(value):
            a = args[0] if origin is list or len(args) == 1 else args[min(i, len(args) - 1)]
            bad = _not_a_number(a, v)
            if bad is not None:
                return bad
    return None


class Strict(BaseModel):
    """Base of every case-file table: unknown keys are errors; numbers must be written as
    numbers (``width = "0.6"`` and ``width = true`` are refused, not coerced); the keys of
    :data:`PHYSICAL_LIMITS` are refused beyond their physical limit."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    @field_validator("*", mode="before")
    @classmethod
    def _strict_numbers(cls, value, info: ValidationInfo):
        field = cls.model_fields.get(info.field_name)
        if field is None:
            return value
        bad = _not_a_number(field.annotation, value)
        if bad is not None:
            kind = "a string" if isinstance(bad, str) else "a boolean"
            raise ValueError(f"a number is expected, not {kind}: write it without quotes")
        check_physical(info.field_name, value)
        return value


class MotionFields(Strict):
    """The ``[motion]`` keys shared by every kind of case file: a record (file, units, dt,
    scale, format; ``channel`` of a multi-channel file, ``vertical = true`` to take the file's
    vertical channel as the vertical acceleration, or ``vertical = "file"`` for a separate
    file holding it) or an analytic signal (amplitude or amplitude_g, frequency, cycles).
    Each case schema adds its own motion types and keys."""

    file: str | None = None
    units: Literal["g", "m/s2", "cm/s2"] | None = None
    dt: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    scale: float = Field(default=1.0, allow_inf_nan=False)
    format: Literal["at2", "esm", "cosmos", "dmg", "knet", "csv", "sac", "mseed"] | None = None
    channel: int | str | None = None
    vertical: bool | str = False
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
        if kind != "record" and (self.channel is not None or self.vertical):
            raise ValueError("channel and vertical go with a record file")
        if kind in pulses and (self.amplitude is None) == (self.amplitude_g is None):
            raise ValueError(f"type '{kind}' needs exactly one of amplitude, amplitude_g")


_HEAD = re.compile(r"^\s*(\[\[?)\s*([A-Za-z0-9_.\-\"' ]+?)\s*\]\]?\s*(#.*)?$")
_PART = r"(?:[A-Za-z0-9_\-]+|\"[^\"]*\"|'[^']*')"
_KEY = re.compile(rf"^\s*({_PART}(?:\s*\.\s*{_PART})*)\s*=")
_SPLIT = re.compile(rf"\s*({_PART})\s*(?:\.|$)")


def key_line(text: str, loc: tuple) -> int | None:
    """1-based line of the key ``loc`` (a pydantic location such as ``("body", "width")``) in the
    TOML ``text``, with array-of-table entries: ``("blocks", 2, "width")`` is the key ``width``
    of the third ``[[blocks]]``; the line of the closest enclosing table when the key itself is
    absent (a default or a missing key); ``None`` when nothing matches. A dotted key
    (``tie.stiffness = 1`` or ``"restraint.tie.stiffness" = [...]`` in a ``[sweep]`` table) is
    found by its parts and by its dotted name (``("sweep", "restraint.tie.stiffness")``)."""
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
            parts = tuple(p.strip("\"'") for p in _SPLIT.findall(km.group(1)))
            keys.setdefault(table + parts, i)
            if len(parts) > 1:  # a dotted key also answers to its dotted name
                keys.setdefault(table + (".".join(parts),), i)
    loc = tuple(loc)
    for k in range(len(loc), 0, -1):
        if loc[:k] in keys:
            return keys[loc[:k]]
        if loc[:k] in heads:
            return heads[loc[:k]]
    return None


def where(path: Path | None, text: str, loc: tuple, indices: bool = False) -> str:
    """The location of the key path ``loc`` in a message: ``FILE line N: [key]`` (the line by
    :func:`key_line`, left out when not found; without a file ``[key]`` alone).

    Parameters
    ----------
    path : pathlib.Path or None
        The case file (its name is written), or None.
    text : str
        The TOML text of the file.
    loc : tuple of str and int
        The key path.
    indices : bool
        Write array-of-table indices (``blocks[2].width``, :func:`murus.errors.key_name`);
        default: names only (``blocks.width``).

    Returns
    -------
    str
        The location, without a trailing space.
    """
    loc = tuple(loc)
    key = (key_name(loc) if indices else
           ".".join(str(x) for x in loc if not isinstance(x, int)) or "(top level)")
    if path is None:
        return f"[{key}]"
    line = key_line(text, loc)
    return f"{Path(path).name}{f' line {line}' if line else ''}: [{key}]"



def load_toml(path) -> tuple[dict, str]:
    """Parse a TOML file; errors become one-line :class:`CaseError`."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise CaseError(f"{path}: no such case file", source=path) from None
    except IsADirectoryError:
        raise CaseError(f"{path}: is a folder, not a case file", source=path) from None
    except UnicodeDecodeError:
        raise CaseError(f"{path}: cannot read the case file: {describe_encoding(path)}, "
                        "not UTF-8 text", source=path) from None
    except OSError as exc:
        raise CaseError(f"{path}: cannot read the case file ({exc.strerror or exc})",
                        source=path) from None
    if not text.strip():
        raise CaseError(f"{path}: the case file is empty", source=path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseError(f"{path.name}: invalid TOML: {exc}", source=path) from None
    if not data:
        raise CaseError(f"{path}: the case file has only comments: no table or key",
                        source=path)
    return data, text


def describe_encoding(path) -> str:
    """What a file that is not UTF-8 text looks like, in a user's words: "UTF-16 text" (byte
    order mark or alternate zero bytes), "UTF-32 text", "binary data" (zero bytes) or "text in
    another encoding (e.g. Latin-1)"."""
    with open(path, "rb") as f:
        head = f.read(4096)
    if head.startswith((b"\xff\xfe\x00\x00", b"\x00\x00\xfe\xff")):
        return "UTF-32 text"
    if head.startswith((b"\xff\xfe", b"\xfe\xff")):
        return "UTF-16 text"
    if len(head) >= 4 and (head[1::2].count(0) > 0.4 * len(head) / 2
                           or head[0::2].count(0) > 0.4 * len(head) / 2):
        return "UTF-16 text (no byte order mark)"
    if b"\x00" in head:
        return "binary data"
    return "text in another encoding (e.g. Latin-1)"


def validate(model: type[BaseModel], data: dict, path: Path, text: str):
    """Validate ``data`` against ``model``; the first error becomes a one-line CaseError."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        loc = tuple(err.get("loc", ()))
        raise fail_at(path, text, loc, error_message(err)) from None


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


def fail_at(path: Path | None, text: str, loc: tuple, msg: str,
            indices: bool = False) -> CaseError:
    """A :class:`CaseError` for the key path ``loc`` of the case file: the one place that
    turns a key path into file and line (:func:`where`).

    Parameters
    ----------
    path : pathlib.Path or None
        The case file (None: the message names the key only).
    text : str
        Its TOML text.
    loc : tuple of str and int
        The key path.
    msg : str
        What is wrong (one line).
    indices : bool
        Name array-of-table entries with their index (:func:`where`).

    Returns
    -------
    CaseError
        To be raised; it carries ``loc``, ``path`` and ``msg``.
    """
    return CaseError(f"{where(path, text, loc, indices)} {msg}", key=tuple(loc), source=path,
                     reason=msg)


def locate(exc: BaseException, path: Path | None, text: str, prefix: tuple = (),
           default: tuple = (), msg: str | None = None, indices: bool = False) -> CaseError:
    """The :class:`CaseError` of an error raised by a model object built from the case file:
    its key path (:attr:`murus.errors.MurusError.key`, relative to the object) under the table
    ``prefix``; ``default`` when the error carries no key.

    Parameters
    ----------
    exc : BaseException
        The error (a :class:`murus.errors.MurusError` carries its key path).
    path, text
        The case file and its text (:func:`fail_at`).
    prefix : tuple
        The key path of the table the object was built from, e.g. ``("restraint",)``.
    default : tuple
        The key path when ``exc`` has none (default ``prefix``).
    msg : str, optional
        The message (default ``str(exc)``).
    indices : bool
        As for :func:`fail_at`.

    Returns
    -------
    CaseError
    """
    key = getattr(exc, "key", ())
    loc = tuple(prefix) + tuple(key) if key else tuple(default or prefix)
    return fail_at(path, text, loc, str(exc) if msg is None else msg, indices)
