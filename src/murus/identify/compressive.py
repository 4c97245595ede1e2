"""Compressive (contact) length of the wall base from the base vertical transducers (issue 8,
item 3; Mordant et al. (SERIES), §2.2.2, Table 2 and Figure 5).

Plane base section (Mordant et al. (SERIES), §2.2.2, after its reference [2]): at each instant the
readings ``d_i`` of the transducers at positions ``x_i`` (conventions of
:mod:`murus.identify.testdata`: ``x`` from the left end, ``d > 0`` opening, zeroed at rest
under the static load) are fitted by the least-squares line ``d(x) = a + b x``; the base is in
contact where ``d(x) <= closure`` on ``0 <= x <= L``, so the contact (compressive) length is

- ``L`` if the line is everywhere at or below ``closure``, 0 if everywhere above;
- otherwise, with ``x0 = (closure - a) / b``: ``clip(x0, 0, L)`` for ``b > 0`` (the left part
  is in contact) and ``L - clip(x0, 0, L)`` for ``b < 0``.

``closure`` [m] is the elastic closure of the base joint under the static load, the
transducers being zeroed under it: the joint opens only when the reading exceeds it. It is 0 by
default (a rigid base: any opening is a loss of contact, the plane-section assumption of
Mordant et al. (SERIES)); a positive value (for instance three times the transducer noise, or the
closure of a rubber layer) stops noise from being read as uplift. With a linear elastic (Winkler)
bed the line reaches ``closure`` exactly where the no-tension stress vanishes, so the measured
length is the Eurocode 6 linear stress-block length for the same eccentricity (verified in the
tests).

The lifted length is ``L - Lc``. The minimum contact length of a test is reported in mm and in
% of ``L``, and compared with :mod:`murus.eurocode.ec6` in the layout of Mordant et al. (SERIES),
Table 2: the equivalent static load case ``2.5 a m g`` at the top (``EquivalentStatic``), constant
and linear stress blocks, with ``a`` the measured PGA of the test [g] (``level="measured"``, the
"acceleration level" of Table 2) or its nominal PGA (``level="nominal"``).

Units: m (mm in the table), s, g.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus.errors import MurusError

__all__ = ["CompressiveError", "contact_length", "fit_plane", "TestContact", "test_contact",
           "CompressiveTable", "compressive_table", "plot_contact_length"]


class CompressiveError(MurusError, ValueError):
    """Invalid input to the contact-length computation."""


def fit_plane(positions, displacements):
    """Least-squares line ``d = a + b x`` through the readings at every instant.

    ``positions``: (n_lvdt,) [m]; ``displacements``: (n_lvdt, n_t) or (n_lvdt,) [m].
    Returns ``(a, b)`` arrays of shape (n_t,) (or floats) [m, -]."""
    x = np.asarray(positions, dtype=float).reshape(-1)
    d = np.asarray(displacements, dtype=float)
    one = d.ndim == 1
    if one:
        d = d[:, None]
    if d.shape[0] != x.size:
        raise CompressiveError(f"{x.size} positions but {d.shape[0]} transducer rows")
    if x.size < 2 or np.ptp(x) == 0.0:
        raise CompressiveError("at least two transducers at distinct positions are needed")
    if not np.all(np.isfinite(d)):
        raise CompressiveError("transducer readings must be finite")
    xm = x.mean()
    dx = x - xm
    b = (dx @ d) / (dx @ dx)
    a = d.mean(axis=0) - b * xm
    return (float(a[0]), float(b[0])) if one else (a, b)


def contact_length(positions, displacements, length: float, closure: float = 0.0):
    """Contact length [m] at each instant (module docstring). Shapes as :func:`fit_plane`.

    Parameters
    ----------
    positions : array_like
        Transducer positions along the wall [m].
    displacements : array_like
        Their readings [m], one row per instant.
    length : float
        Wall length [m].
    closure : float
        Elastic closure of the base joint [m].

    Returns
    -------
    numpy.ndarray
        [m].
    """
    if not (math.isfinite(length) and length > 0):
        raise CompressiveError(f"the wall length must be positive, got {length!r}")
    if not (math.isfinite(closure) and closure >= 0):
        raise CompressiveError(f"closure must be >= 0 m, got {closure!r}")
    a, b = fit_plane(positions, displacements)
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    c0 = a - closure  # line minus the closure: contact where <= 0
    with np.errstate(divide="ignore", invalid="ignore"):
        x0 = np.clip(-c0 / b, 0.0, length)
    lc = np.where(b > 0, x0, length - x0)
    flat = b == 0
    lc = np.where(flat, np.where(c0 <= 0, length, 0.0), lc)
    return float(lc) if lc.ndim == 0 else lc


@dataclass
class TestContact:
    """Contact length of one test: history ``lc`` [m] on ``t`` [s], its minimum ``lc_min``
    [m] at ``t_min`` [s], the wall length ``length`` [m]."""

    __test__ = False

    name: str
    t: np.ndarray
    lc: np.ndarray
    length: float

    @property
    def lc_min(self) -> float:
        return float(np.min(self.lc))

    @property
    def t_min(self) -> float:
        return float(self.t[int(np.argmin(self.lc))])

    @property
    def lc_min_mm(self) -> float:
        return 1000.0 * self.lc_min

    @property
    def lc_min_percent(self) -> float:
        return 100.0 * self.lc_min / self.length

    @property
    def lifted(self) -> np.ndarray:
        """Lifted length ``L - Lc`` [m] (Mordant et al. (SERIES), Figures 19-20)."""
        return self.length - self.lc


def test_contact(test, closure: float = 0.0) -> TestContact:
    """Contact-length history of a :class:`~murus.identify.testdata.ShakingTableTest`.

    Parameters
    ----------
    test : ShakingTableTest
        A test with base transducers.
    closure : float
        Elastic closure of the base joint [m].

    Returns
    -------
    TestContact
    """
    if not test.has_lvdt:
        raise CompressiveError(f"{test.source or test.name}: no base transducers "
                               "(lvdt_1, lvdt_2 ... columns)")
    lc = contact_length(test.lvdt_positions, test.lvdt, test.wall_length, closure)
    return TestContact(name=test.name, t=test.t, lc=np.asarray(lc), length=test.wall_length)


test_contact.__test__ = False


@dataclass
class CompressiveTable:
    """Rows in the layout of Mordant et al. (SERIES), Table 2 (one per seismic test of a sequence):
    specimen, acceleration level [g], measured minimum compressive length [%, mm], EN 1996-1-1
    linear and constant assessments [%, mm] (NaN when the top mass is unknown)."""

    specimen: str
    rows: list[dict]

    def to_markdown(self) -> str:
        head = ("| Specimen | Test | Acceleration level [g] | Compressive length [%] | [mm] | "
                "Assessment (linear) [%] | [mm] | Assessment (constant) [%] | [mm] |")
        out = [head, "|---|---|---|---|---|---|---|---|---|"]

        def c(v, fmt):
            return "/" if v is None or not math.isfinite(v) else format(v, fmt)

        for r in self.rows:
            out.append(
                f"| {self.specimen} | {r['test']} | {c(r['level_g'], '.3f')} | "
                f"{c(r['lc_percent'], '.2f')} | {c(r['lc_mm'], '.1f')} | "
                f"{c(r['linear_percent'], '.2f')} | {c(r['linear_mm'], '.1f')} | "
                f"{c(r['constant_percent'], '.2f')} | {c(r['constant_mm'], '.1f')} |")
        return "\n".join(out)

    def to_csv(self) -> str:
        keys = ["test", "level_g", "pga_nominal_g", "lc_percent", "lc_mm", "t_min_s",
                "linear_percent", "linear_mm", "constant_percent", "constant_mm"]
        lines = [",".join(keys)]
        for r in self.rows:
            lines.append(",".join("" if r[k] is None else (f"{r[k]:.6g}" if isinstance(
                r[k], float) else str(r[k])) for k in keys))
        return "\n".join(lines) + "\n"


def compressive_table(sequence, closure: float = 0.0, level: str = "measured",
                      factor: float = 2.5) -> CompressiveTable:
    """Mordant et al. (SERIES), Table 2 for every seismic test with base transducers in
    ``sequence``.

    The Eurocode 6 columns use :class:`murus.eurocode.ec6.EquivalentStatic` with the top mass
    of the test file (``top_mass_kg``), the wall height and ``factor`` (2.5: the plateau of the
    EN 1998-1 spectrum, as in Mordant et al. (SERIES), Table 2).

    Parameters
    ----------
    sequence : TestSequence
        The tests of a specimen.
    closure : float
        Elastic closure of the base joint [m].
    level : str
        ``"measured"`` or ``"nominal"`` PGA.
    factor : float
        Spectral amplification of the equivalent static load [-].

    Returns
    -------
    CompressiveTable

    References
    ----------
    Mordant et al. (SERIES), Table 2; EN 1996-1-1.
    """
    from murus.eurocode.ec6 import EquivalentStatic

    if level not in ("measured", "nominal"):
        raise CompressiveError(f"level must be 'measured' or 'nominal', got {level!r}")
    rows = []
    for e in sequence.seismic:
        test = e.test
        if not test.has_lvdt:
            continue
        tc = test_contact(test, closure)
        lev = test.measured_pga_g if level == "measured" or e.pga_g is None else e.pga_g
        L = test.wall_length
        lin = con = float("nan")
        if test.top_mass is not None:
            es = EquivalentStatic(mass=test.top_mass, height=test.wall_height, factor=factor)
            lin = float(es.compressive_length(L, lev, "linear"))
            con = float(es.compressive_length(L, lev, "constant"))
        rows.append({"test": e.label, "level_g": float(lev), "pga_nominal_g": e.pga_g,
                     "lc_percent": tc.lc_min_percent, "lc_mm": tc.lc_min_mm,
                     "t_min_s": tc.t_min,
                     "linear_percent": 100 * lin / L, "linear_mm": 1000 * lin,
                     "constant_percent": 100 * con / L, "constant_mm": 1000 * con})
    if not rows:
        raise CompressiveError(f"sequence {sequence.name!r}: no seismic test with base "
                               "transducers")
    return CompressiveTable(specimen=sequence.name, rows=rows)


def plot_contact_length(table: CompressiveTable, ax=None):
    """Minimum compressive length [%] against the acceleration level (Mordant et al. (SERIES),
    Figure 5), with the Eurocode 6 assessments."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(6, 4))
    lv = np.array([r["level_g"] for r in table.rows])
    order = np.argsort(lv, kind="stable")
    for key, lab, st in (("lc_percent", "measured (plane section)", "o-"),
                         ("linear_percent", "EN 1996-1-1 linear", "s--"),
                         ("constant_percent", "EN 1996-1-1 constant", "^:")):
        y = np.array([r[key] for r in table.rows], dtype=float)
        if np.any(np.isfinite(y)):
            ax.plot(lv[order], y[order], st, label=lab)
    ax.set_xlabel("acceleration level [g]")
    ax.set_ylabel("compressive length [% of L]")
    ax.set_ylim(-5, 105)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(table.specimen)
    return ax
