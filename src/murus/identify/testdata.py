"""Shaking-table test data: the file format, a reader with clear errors, a writer, and the
ordered test sequence of a specimen (issue 8, item 1; Mordant et al. (SERIES), §2 and Table 1).

File format (one test per file, CSV, UTF-8)
-------------------------------------------
A header block of ``# key: value`` lines, then one line of comma-separated column names, each
with its unit in brackets, then the samples, one line per instant::

    # murus shaking-table test
    # name: S03
    # kind: seismic
    # sampling_rate_hz: 200
    # pga_g: 0.0777
    # wall_length_m: 2.10
    # wall_height_m: 1.80
    # lvdt_positions_m: 0.05, 0.55, 1.05, 1.55, 2.05
    # top_mass_kg: 5000
    time [s],table_acc [m/s2],top_acc [m/s2],lvdt_1 [m],...,lvdt_5 [m],rot_bottom [rad],...
    0.000,0.0012,0.0031,1.2e-6,...

(the column line continues with ``rot_top [rad]``; it is one line in the file).

Header keys (other keys are kept, as strings, in ``ShakingTableTest.meta``):

========================  ========  =====================================================
key                       required  meaning
========================  ========  =====================================================
``name``                  no        label of the test (default: the file name without .csv)
``kind``                  no        ``seismic`` (default) or ``white_noise``
``sampling_rate_hz``      yes       sampling rate [Hz]; the samples are uniform in time
``pga_g``                 no        nominal (target) peak table acceleration [g]
``wall_length_m``         yes       length L of the wall (in the plane of shaking) [m]
``wall_height_m``         yes       height H of the wall [m]
``lvdt_positions_m``      if lvdt   positions x of the base vertical transducers, in the
                                    order lvdt_1, lvdt_2, ... [m]
``top_mass_kg``           no        mass on top of the wall [kg] (Eurocode 6 comparison)
========================  ========  =====================================================

Columns (names are case-sensitive; the order is free):

- ``time [s]`` optional; when present it must agree with ``sampling_rate_hz`` (uniform
  sampling, relative tolerance 1e-3 of the step on every interval);
- ``table_acc`` and ``top_acc`` required: horizontal accelerations of the shaking table and of
  the top of the wall (absolute), units ``m/s2``, ``g`` or ``cm/s2``;
- ``lvdt_1 .. lvdt_n`` optional: base vertical displacement transducers (wall base relative to
  the foundation), units ``m`` or ``mm``, numbered from 1 without gaps, one position each;
- ``rot_bottom``, ``rot_top`` optional: in-plane rotations of the bottom course (the base
  joint) and of the top of the wall, relative to the table, units ``rad`` or ``mrad``.

Conventions (checked in ``tests/identify``): positions ``x`` run along the wall from its left
end (``x = 0``) to its right end (``x = L``); a transducer reading is positive when the joint
*opens* (uplift of the wall base) and negative when it closes (compression), zeroed at rest
under the static load; rotations are positive clockwise, as ``theta`` in :mod:`murus.rocking`
(Mordant et al. (SERIES), §3.1.1), so that a positive rotation lifts the left end: a rigid rotation
``theta`` about the right corner gives ``lvdt(x) = (L - x) sin(theta)``. Accelerations are positive
towards ``+x``. Everything is converted to SI on reading (m, m/s2, rad, s).

HDF5 is not supported: CSV is readable by every laboratory tool and the test files are small
(tens of thousands of lines); :func:`write_test` writes the same format back.

Test sequence (Mordant et al. (SERIES), Table 1)
------------------------------------------------
A sequence is a folder of test files. The order and the nominal PGA come from a
``sequence.toml`` in the folder when there is one::

    name = "short wall without rubber"

    [[test]]
    file = "01_WN01.csv"
    kind = "white_noise"          # optional: overrides the file header

    [[test]]
    file = "02_S01.csv"
    pga_g = 0.0413                # optional: overrides the file header

Without ``sequence.toml`` the naming convention applies: every ``*.csv`` file of the folder,
in natural order of the names (``2_x`` before ``10_x``), kind and PGA from each header; a file
without a ``kind`` key whose name contains ``WN`` (upper case, e.g. ``03_WN02.csv``) is a
white-noise test. Seismic tests are numbered S01, S02 ... in order, as in Mordant et al. (SERIES).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from murus import G
from murus.errors import MurusError

__all__ = [
    "TestDataError",
    "ShakingTableTest",
    "TestSequence",
    "SequenceEntry",
    "read_test",
    "write_test",
    "read_sequence",
    "write_sequence",
    "UNITS",
    "KINDS",
]

KINDS = ("seismic", "white_noise")

#: Accepted units per channel family and their factor to SI.
UNITS = {
    "time": {"s": 1.0},
    "acc": {"m/s2": 1.0, "g": G, "cm/s2": 0.01},
    "lvdt": {"m": 1.0, "mm": 1e-3},
    "rot": {"rad": 1.0, "mrad": 1e-3},
}

_FAMILY = {"time": "time", "table_acc": "acc", "top_acc": "acc", "rot_bottom": "rot",
           "rot_top": "rot"}
_REQUIRED_KEYS = ("sampling_rate_hz", "wall_length_m", "wall_height_m")
_COLUMN = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*\[([^\]]*)\]\s*$")


class TestDataError(MurusError, ValueError):
    """A test file or sequence folder that does not follow the documented format."""

    __test__ = False  # not a pytest test class


def _family(name: str) -> str | None:
    if name in _FAMILY:
        return _FAMILY[name]
    if re.fullmatch(r"lvdt_[1-9][0-9]*", name):
        return "lvdt"
    return None


@dataclass
class ShakingTableTest:
    """One shaking-table test in SI units (see the module docstring for the conventions).

    Attributes
    ----------
    name : str
        Label of the test.
    sampling_rate : float
        Sampling rate [Hz], > 0; the samples are uniform in time.
    wall_length : float
        Length L of the wall in the plane of shaking [m], > 0.
    wall_height : float
        Height H of the wall [m], > 0.
    channels : dict of str to numpy.ndarray
        Samples of each channel, all of the same length (at least two): ``table_acc`` and
        ``top_acc`` (required) [m/s²], absolute horizontal accelerations of the table and of
        the top of the wall; ``lvdt_1`` ... ``lvdt_n`` [m], base vertical transducers,
        positive when the joint opens; ``rot_bottom``, ``rot_top`` [rad], in-plane rotations
        relative to the table, positive clockwise.
    kind : str
        ``"seismic"`` or ``"white_noise"``.
    pga_g : float or None
        Nominal (target) peak table acceleration [g].
    lvdt_positions : numpy.ndarray
        Position x of each transducer along the wall from its left end [m], in the order
        ``lvdt_1, lvdt_2, ...``.
    top_mass : float or None
        Mass on top of the wall [kg].
    meta : dict of str to str
        Other header keys of the file.
    source : str or None
        Path of the file read, used in error messages.

    Raises
    ------
    TestDataError
        If ``kind`` is unknown, a rate or dimension is not a positive number, a required
        channel is missing, the channels differ in length or have fewer than two samples, or
        the transducers and their positions differ in number.

    References
    ----------
    Mordant et al. (SERIES), §2, §3.1.1 (sign of the rotation) and Table 1.
    """

    __test__ = False  # not a pytest test class

    name: str
    sampling_rate: float
    wall_length: float
    wall_height: float
    channels: dict[str, np.ndarray]
    kind: str = "seismic"
    pga_g: float | None = None
    lvdt_positions: np.ndarray = field(default_factory=lambda: np.zeros(0))
    top_mass: float | None = None
    meta: dict[str, str] = field(default_factory=dict)
    source: str | None = None

    def __post_init__(self) -> None:
        where = self.source or self.name
        if self.kind not in KINDS:
            raise TestDataError(f"{where}: kind must be one of {KINDS}, got {self.kind!r}")
        for key, v in (("sampling_rate_hz", self.sampling_rate),
                       ("wall_length_m", self.wall_length), ("wall_height_m", self.wall_height)):
            if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
                raise TestDataError(f"{where}: {key} must be a positive number, got {v!r}")
        for ch in ("table_acc", "top_acc"):
            if ch not in self.channels:
                raise TestDataError(f"{where}: missing required channel {ch!r}")
        n = len(self.channels["table_acc"])
        chans = {}
        for k, v in self.channels.items():
            a = np.asarray(v, dtype=float)
            if a.shape != (n,):
                raise TestDataError(f"{where}: channel {k!r} has {a.size} samples, "
                                    f"table_acc has {n}")
            chans[k] = a
        self.channels = chans
        if n < 2:
            raise TestDataError(f"{where}: a test needs at least two samples")
        self.lvdt_positions = np.asarray(self.lvdt_positions, dtype=float).reshape(-1)
        n_lvdt = len(self.lvdt_names)
        if self.lvdt_positions.size != n_lvdt:
            raise TestDataError(f"{where}: {n_lvdt} lvdt channels but "
                                f"{self.lvdt_positions.size} lvdt_positions_m")

    # --- channels ---------------------------------------------------------------------------
    @property
    def n(self) -> int:
        return self.channels["table_acc"].size

    @property
    def dt(self) -> float:
        """Sampling step [s]."""
        return 1.0 / self.sampling_rate

    @property
    def t(self) -> np.ndarray:
        """Time [s] from 0."""
        return np.arange(self.n) * self.dt

    @property
    def table_acc(self) -> np.ndarray:
        return self.channels["table_acc"]

    @property
    def top_acc(self) -> np.ndarray:
        return self.channels["top_acc"]

    @property
    def lvdt_names(self) -> list[str]:
        names = [k for k in self.channels if k.startswith("lvdt_")]
        return sorted(names, key=lambda s: int(s.split("_")[1]))

    @property
    def lvdt(self) -> np.ndarray:
        """Base transducer readings, shape (n_lvdt, n) [m], positive opening."""
        names = self.lvdt_names
        if not names:
            return np.zeros((0, self.n))
        return np.vstack([self.channels[k] for k in names])

    @property
    def has_lvdt(self) -> bool:
        return len(self.lvdt_names) >= 2

    @property
    def has_rotations(self) -> bool:
        return "rot_bottom" in self.channels and "rot_top" in self.channels

    @property
    def rot_bottom(self) -> np.ndarray:
        return self.channels["rot_bottom"]

    @property
    def rot_top(self) -> np.ndarray:
        return self.channels["rot_top"]

    @property
    def measured_pga_g(self) -> float:
        """Peak absolute table acceleration [g]."""
        return float(np.max(np.abs(self.table_acc)) / G)


# --- reading -------------------------------------------------------------------------------

def _parse_float(text: str, where: str, key: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise TestDataError(f"{where}: {key} must be a number, got {text!r}") from None


def read_test(path) -> ShakingTableTest:
    """Read a test file of the documented format (module docstring); values in SI.

    Raises :class:`TestDataError` with a one-line message naming the file, line and column for
    a malformed header, a missing channel, an unknown unit, a non-numeric or NaN value, or a
    non-uniform time column.

    Parameters
    ----------
    path : str or pathlib.Path
        The test file.

    Returns
    -------
    ShakingTableTest
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise TestDataError(f"{path}: no such file") from None
    except UnicodeDecodeError:
        from murus.config import describe_encoding

        raise TestDataError(f"{path}: {describe_encoding(path)}, not UTF-8 text: save it as "
                            "UTF-8") from None
    except OSError as exc:
        raise TestDataError(f"{path}: cannot read ({exc.strerror or exc})") from None
    lines = text.splitlines()
    header: dict[str, tuple[str, int]] = {}
    i = 0
    while i < len(lines) and (lines[i].startswith("#") or not lines[i].strip()):
        body = lines[i][1:].strip() if lines[i].startswith("#") else ""
        if ":" in body:
            k, v = body.split(":", 1)
            k = k.strip()
            if k in header:
                raise TestDataError(f"{path}:{i + 1}: duplicate header key {k!r}")
            header[k] = (v.strip(), i + 1)
        i += 1
    if i >= len(lines):
        raise TestDataError(f"{path}: no column line after the header")
    col_line = i + 1
    names, factors = [], []
    for j, raw in enumerate(lines[i].split(",")):
        m = _COLUMN.match(raw)
        if not m:
            raise TestDataError(f"{path}:{col_line}: column {j + 1} {raw.strip()!r} is not "
                                "'name [unit]'")
        name, unit = m.group(1), m.group(2).strip()
        fam = _family(name)
        if fam is None:
            raise TestDataError(f"{path}:{col_line}: column {j + 1}: unknown channel {name!r}")
        if unit not in UNITS[fam]:
            raise TestDataError(f"{path}:{col_line}: column {j + 1} ({name}): bad unit "
                                f"{unit!r}; expected one of {sorted(UNITS[fam])}")
        if name in names:
            raise TestDataError(f"{path}:{col_line}: column {j + 1}: duplicate channel {name!r}")
        names.append(name)
        factors.append(UNITS[fam][unit])
    for ch in ("table_acc", "top_acc"):
        if ch not in names:
            raise TestDataError(f"{path}:{col_line}: missing required channel {ch!r}")
    for key in _REQUIRED_KEYS:
        if key not in header:
            raise TestDataError(f"{path}: missing header key {key!r} ('# {key}: value')")
    ncol = len(names)
    data_lines = lines[i + 1:]
    first = i + 2  # file line number of the first data line
    rows = []
    for r, raw in enumerate(data_lines):
        if not raw.strip():
            continue
        cells = raw.split(",")
        if len(cells) != ncol:
            raise TestDataError(f"{path}:{first + r}: {len(cells)} values, expected {ncol}")
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            for j, c in enumerate(cells):
                try:
                    float(c)
                except ValueError:
                    raise TestDataError(f"{path}:{first + r}: column {j + 1} ({names[j]}): "
                                        f"not a number: {c.strip()!r}") from None
    if len(rows) < 2:
        raise TestDataError(f"{path}: fewer than two data lines")
    data = np.asarray(rows, dtype=float) * np.asarray(factors)
    bad = ~np.isfinite(data)
    if bad.any():
        r, j = np.argwhere(bad)[0]
        line = first + [k for k, s in enumerate(data_lines) if s.strip()][r]
        raise TestDataError(f"{path}:{line}: column {j + 1} ({names[j]}): NaN or infinite value")

    def hval(key, conv=float):
        v, ln = header[key]
        if conv is float:
            return _parse_float(v, f"{path}:{ln}", key)
        return v

    fs = hval("sampling_rate_hz")
    L = hval("wall_length_m")
    H = hval("wall_height_m")
    for key, v in (("sampling_rate_hz", fs), ("wall_length_m", L), ("wall_height_m", H)):
        if not (math.isfinite(v) and v > 0):
            raise TestDataError(f"{path}:{header[key][1]}: {key} must be positive, got {v!r}")
    if "time" in names:
        t = data[:, names.index("time")]
        d = np.diff(t)
        dev = np.abs(d - 1.0 / fs) > 1e-3 / fs
        if dev.any():
            k = int(np.argmax(dev))
            line = first + [q for q, s in enumerate(data_lines) if s.strip()][k + 1]
            raise TestDataError(f"{path}:{line}: column {names.index('time') + 1} (time): "
                                f"non-uniform sampling: step {d[k]:.6g} s, expected "
                                f"{1.0 / fs:.6g} s (sampling_rate_hz {fs:g})")
    channels = {nm: data[:, j].copy() for j, nm in enumerate(names) if nm != "time"}
    lvdt = sorted((nm for nm in names if nm.startswith("lvdt_")),
                  key=lambda s: int(s.split("_")[1]))
    for k, nm in enumerate(lvdt):
        if nm != f"lvdt_{k + 1}":
            raise TestDataError(f"{path}:{col_line}: lvdt channels must be numbered "
                                f"lvdt_1..lvdt_{len(lvdt)} without gaps, found {nm!r}")
    positions = np.zeros(0)
    if lvdt:
        if "lvdt_positions_m" not in header:
            raise TestDataError(f"{path}: lvdt channels need the header key 'lvdt_positions_m'")
        v, ln = header["lvdt_positions_m"]
        parts = [p for p in v.replace(";", ",").split(",") if p.strip()]
        positions = np.array([_parse_float(p.strip(), f"{path}:{ln}", "lvdt_positions_m")
                              for p in parts])
        if positions.size != len(lvdt):
            raise TestDataError(f"{path}:{ln}: lvdt_positions_m has {positions.size} values "
                                f"for {len(lvdt)} lvdt channels")
        if np.any(positions < 0) or np.any(positions > L) or np.unique(positions).size < 2:
            raise TestDataError(f"{path}:{ln}: lvdt_positions_m must lie in [0, wall_length_m] "
                                "with at least two distinct positions")
    kind = header.get("kind", ("", 0))[0] or ("white_noise" if "WN" in path.stem else "seismic")
    if kind not in KINDS:
        raise TestDataError(f"{path}:{header['kind'][1]}: kind must be one of {KINDS}, "
                            f"got {kind!r}")
    pga = None
    if "pga_g" in header and header["pga_g"][0] not in ("", "/", "-"):
        pga = hval("pga_g")
    mass = None
    if "top_mass_kg" in header:
        mass = hval("top_mass_kg")
        if not (math.isfinite(mass) and mass > 0):
            raise TestDataError(f"{path}:{header['top_mass_kg'][1]}: top_mass_kg must be "
                                "positive")
    known = set(_REQUIRED_KEYS) | {"name", "kind", "pga_g", "lvdt_positions_m", "top_mass_kg"}
    meta = {k: v for k, (v, _) in header.items() if k not in known}
    return ShakingTableTest(
        name=header.get("name", (path.stem, 0))[0] or path.stem,
        sampling_rate=fs, wall_length=L, wall_height=H, channels=channels, kind=kind,
        pga_g=pga, lvdt_positions=positions, top_mass=mass, meta=meta, source=str(path))


# --- writing -------------------------------------------------------------------------------

_ORDER = ("table_acc", "top_acc")


def write_test(test: ShakingTableTest, path, with_time: bool = True) -> Path:
    """Write ``test`` in the documented format (SI units, ``%.9g``); returns the path.

    Parameters
    ----------
    test : ShakingTableTest
        The test.
    path : str or pathlib.Path
        The file.
    with_time : bool
        Write the time column.

    Returns
    -------
    pathlib.Path
    """
    path = Path(path)
    head = ["# murus shaking-table test", f"# name: {test.name}", f"# kind: {test.kind}",
            f"# sampling_rate_hz: {test.sampling_rate:.12g}"]
    if test.pga_g is not None:
        head.append(f"# pga_g: {test.pga_g:.6g}")
    head += [f"# wall_length_m: {test.wall_length:.9g}",
             f"# wall_height_m: {test.wall_height:.9g}"]
    if test.lvdt_positions.size:
        head.append("# lvdt_positions_m: " + ", ".join(f"{x:.6g}" for x in test.lvdt_positions))
    if test.top_mass is not None:
        head.append(f"# top_mass_kg: {test.top_mass:.9g}")
    for k, v in test.meta.items():
        head.append(f"# {k}: {v}")
    names = list(_ORDER) + test.lvdt_names + [k for k in ("rot_bottom", "rot_top")
                                              if k in test.channels]
    units = {"acc": "m/s2", "lvdt": "m", "rot": "rad"}
    cols = [f"{nm} [{units[_family(nm)]}]" for nm in names]
    arrays = [test.channels[nm] for nm in names]
    if with_time:
        cols.insert(0, "time [s]")
        arrays.insert(0, test.t)
    head.append(",".join(cols))
    data = np.column_stack(arrays)
    with path.open("w", encoding="utf-8", newline="\n") as fh:
        fh.write("\n".join(head) + "\n")
        np.savetxt(fh, data, fmt="%.9g", delimiter=",")
    return path


# --- sequences -----------------------------------------------------------------------------

@dataclass
class SequenceEntry:
    """One test of a sequence: its position (1-based), file, kind, nominal PGA [g] and the
    loaded data.

    Attributes
    ----------
    number : int
        Position in the sequence (1-based).
    file : str
    kind : str
        ``"seismic"`` or ``"white_noise"``.
    pga_g : float or None
        Nominal PGA [g].
    test : ShakingTableTest
    label : str
    """

    number: int
    file: str
    kind: str
    pga_g: float | None
    test: ShakingTableTest
    label: str = ""


@dataclass
class TestSequence:
    """The ordered tests of one specimen (Mordant et al. (SERIES), Table 1 and §2: white-noise tests
    between seismic tests of increasing level).

    Attributes
    ----------
    name : str
    entries : list of SequenceEntry
    folder : str or None
    """

    __test__ = False

    name: str
    entries: list[SequenceEntry]
    folder: str | None = None

    def __len__(self) -> int:
        return len(self.entries)

    def __iter__(self):
        return iter(self.entries)

    @property
    def seismic(self) -> list[SequenceEntry]:
        return [e for e in self.entries if e.kind == "seismic"]

    @property
    def white_noise(self) -> list[SequenceEntry]:
        return [e for e in self.entries if e.kind == "white_noise"]

    def table1(self) -> list[dict]:
        """Rows like Mordant et al. (SERIES), Table 1: seismic test number, label, nominal and
        measured PGA."""
        return [{"no": k + 1, "test": e.label, "pga_nominal_g": e.pga_g,
                 "pga_measured_g": e.test.measured_pga_g} for k, e in enumerate(self.seismic)]


def _natural_key(s: str):
    return [int(p) if p.isdigit() else p.lower() for p in re.split(r"(\d+)", s)]


def read_sequence(folder) -> TestSequence:
    """Read a sequence folder (``sequence.toml`` or the naming convention, module docstring).

    Parameters
    ----------
    folder : str or pathlib.Path
        The sequence folder.

    Returns
    -------
    TestSequence
    """
    import tomllib

    folder = Path(folder)
    if not folder.is_dir():
        raise TestDataError(f"{folder}: not a folder")
    toml = folder / "sequence.toml"
    specs: list[dict] = []
    name = folder.name
    if toml.exists():
        try:
            doc = tomllib.loads(toml.read_text(encoding="utf-8"))
        except UnicodeDecodeError:
            from murus.config import describe_encoding

            raise TestDataError(f"{toml}: {describe_encoding(toml)}, not UTF-8 text: save it "
                                "as UTF-8") from None
        except tomllib.TOMLDecodeError as exc:
            raise TestDataError(f"{toml}: {' '.join(str(exc).split())}") from None
        name = str(doc.get("name", name))
        tests = doc.get("test")
        if not isinstance(tests, list) or not tests:
            raise TestDataError(f"{toml}: needs at least one [[test]] table with a 'file' key")
        for k, spec in enumerate(tests):
            if not isinstance(spec, dict) or "file" not in spec:
                raise TestDataError(f"{toml}: [[test]] number {k + 1} has no 'file' key")
            unknown = set(spec) - {"file", "kind", "pga_g", "label"}
            if unknown:
                raise TestDataError(f"{toml}: [[test]] number {k + 1}: unknown key "
                                    f"{sorted(unknown)[0]!r}")
            if "kind" in spec and spec["kind"] not in KINDS:
                raise TestDataError(f"{toml}: [[test]] number {k + 1}: kind must be one of "
                                    f"{KINDS}, got {spec['kind']!r}")
            if "pga_g" in spec and not isinstance(spec["pga_g"], int | float):
                raise TestDataError(f"{toml}: [[test]] number {k + 1}: pga_g must be a number")
            specs.append(spec)
    else:
        files = sorted((p.name for p in folder.glob("*.csv")), key=_natural_key)
        if not files:
            raise TestDataError(f"{folder}: no sequence.toml and no *.csv test files")
        specs = [{"file": f} for f in files]
    entries = []
    n_seismic = 0
    for k, spec in enumerate(specs):
        test = read_test(folder / spec["file"])
        kind = spec.get("kind", test.kind)
        test.kind = kind
        pga = spec.get("pga_g", test.pga_g)
        pga = None if pga is None else float(pga)
        test.pga_g = pga
        if kind == "seismic":
            n_seismic += 1
        label = spec.get("label") or test.name or (
            f"S{n_seismic:02d}" if kind == "seismic" else f"WN{k + 1:02d}")
        entries.append(SequenceEntry(number=k + 1, file=str(spec["file"]), kind=kind,
                                     pga_g=pga, test=test, label=str(label)))
    return TestSequence(name=name, entries=entries, folder=str(folder))


def write_sequence(folder, tests: list[ShakingTableTest], name: str = "sequence") -> Path:
    """Write ``tests`` as ``NN_<name>.csv`` files and a ``sequence.toml`` in ``folder``.

    Parameters
    ----------
    folder : str or pathlib.Path
        Created if needed.
    tests : list of ShakingTableTest
        In order.
    name : str
        Name of the specimen.

    Returns
    -------
    pathlib.Path
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    lines = [f"name = {_toml_str(name)}", ""]
    for k, test in enumerate(tests):
        fname = f"{k + 1:02d}_{re.sub(r'[^A-Za-z0-9_.-]', '_', test.name)}.csv"
        write_test(test, folder / fname)
        lines += ["[[test]]", f"file = {_toml_str(fname)}", f"kind = {_toml_str(test.kind)}"]
        if test.pga_g is not None:
            lines.append(f"pga_g = {test.pga_g:.6g}")
        lines.append("")
    (folder / "sequence.toml").write_text("\n".join(lines), encoding="utf-8")
    return folder


def _toml_str(s: str) -> str:
    return '"' + str(s).replace("\\", "\\\\").replace('"', '\\"') + '"'
