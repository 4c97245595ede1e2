"""Mordant et al. (SERIES), §3.2-3.3.1: the rocking-onset statements for the tests S07-S09 of Table
1.

The measured table signals are not available: one EN 1998-1 Type 1, ground B artificial record
(fixed seed) is scaled to the measured PGA of each test, as in
``validation/mordant_series_model.py``.
From rest, rocking starts at the first instant where ``|a_g|`` exceeds the onset acceleration
of the pivot law, so the statements below follow from the PGA alone and are asserted exactly;
nothing here compares rocking histories.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from murus import G
from murus.motion.artificial import generate_ec8
from murus.rocking import Housner, Pivot, RockingModel, series_clay_wall, simulate

TABLE1 = Path(__file__).resolve().parents[1] / "data" / "rocking" / "mordant_series_table1_pga.csv"
COLUMN = {"short": "short_no_rubber", "long": "long_no_rubber"}
WALLS = ("short", "long")
#: onset acceleration in units of g B / H (mass on top at H = 1.80 m)
ONSET = {"corner": 1 / 2, "kern": 1 / 6, "effective-width": 0.3, "neutral-axis": 1 / 4}

# the record of the validation section, generated once (about 0.6 s)
RECORD = generate_ec8(0.25 * G, "B", 1, n=1, seed=0, dt=0.01, rise=2.0, stationary=10.0,
                      decay=4.0)[0]


def _table1() -> dict[str, dict[str, float | None]]:
    with open(TABLE1) as fh:
        rows = csv.DictReader(line for line in fh if not line.startswith("#"))
        return {r["test"]: {k: float(v) if v.strip() else None for k, v in r.items()
                            if k != "test"} for r in rows}


PGA = {(w, t): row[COLUMN[w]] for t, row in _table1().items() for w in WALLS}


def _scaled(wall: str, test: str):
    return RECORD.scaled(PGA[(wall, test)] * G / RECORD.pga)


def _pivot(reading: str) -> Pivot:
    return Pivot() if reading == "corner" else Pivot("compressive-length", reading)


def _onset(wall: str, reading: str) -> float:
    """Onset acceleration [m/s2]."""
    b = series_clay_wall(wall)
    return ONSET[reading] * G * b.width / b.z_G


def test_table1_file():
    """The data file holds the nine tests and the no-rubber PGAs used in Mordant et al. (SERIES),
    §3."""
    t1 = _table1()
    assert list(t1) == [f"S{i:02d}" for i in range(1, 10)]
    assert [PGA[("long", t)] for t in ("S07", "S08", "S09")] == [0.4496, 0.5716, 0.6878]
    assert [PGA[("short", t)] for t in ("S07", "S08", "S09")] == [0.1784, 0.1869, 0.2336]
    assert t1["S08"]["short_rubber"] is None and t1["S09"]["short_rubber"] is None


@pytest.mark.parametrize("wall", WALLS)
@pytest.mark.parametrize("test", ["S07", "S08", "S09"])
def test_plain_criterion_peak_is_pga_over_corner_threshold(wall, test):
    """Eq. 9 on the corner: max RC(t) = PGA / (g B / 2H) for the exactly scaled record."""
    rec = _scaled(wall, test)
    assert rec.pga == pytest.approx(PGA[(wall, test)] * G, rel=1e-12)
    res = simulate(RockingModel(series_clay_wall(wall), Housner()), rec)
    expected = PGA[(wall, test)] * G / _onset(wall, "corner")
    assert res.rocking_criterion.max() == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("wall", WALLS)
def test_plain_model_rocks_at_s09_only(wall):
    """Mordant et al. (SERIES), §3.2, Figures 9-11: the plain model predicts no rocking for S07 and
    S08 and rocking for S09, on both walls; uplift happens within one step of the first sample of
    the record above the corner threshold."""
    body = series_clay_wall(wall)
    for test, rocks in (("S07", False), ("S08", False), ("S09", True)):
        assert (PGA[(wall, test)] * G > _onset(wall, "corner")) is rocks
        rec = _scaled(wall, test)
        res = simulate(RockingModel(body), rec)
        assert (res.t_uplift is not None) is rocks
        assert bool(res.rocking_criterion.max() > 1.0) is rocks
        if rocks:
            k = int(np.argmax(np.abs(rec.acc) > _onset(wall, "corner")))
            assert (k - 1) * rec.dt <= res.t_uplift <= k * rec.dt + 1e-9


@pytest.mark.parametrize("reading", ["effective-width", "kern", "neutral-axis"])
@pytest.mark.parametrize("wall", WALLS)
def test_modified_criterion_rocks_at_s07_to_s09(wall, reading):
    """Mordant et al. (SERIES), §3.3.1: with the pivot at the zero-stress point (eq. 11) rocking is
    predicted for all of S07-S09 on both walls, with each reading of the compressive length."""
    mdl = RockingModel(series_clay_wall(wall), pivot=_pivot(reading))
    for test in ("S07", "S08", "S09"):
        assert PGA[(wall, test)] * G > _onset(wall, reading)
        res = simulate(mdl, _scaled(wall, test))
        assert res.t_uplift is not None
        assert res.rocking_criterion.max() > 1.0


def test_modified_model_starts_rocking_earlier():
    """Short wall S07 (Figure 13): the plain model never lifts, the modified one does; at S09
    (both walls) the modified one lifts no later than the plain one (lower threshold, first
    crossing from rest)."""
    body = series_clay_wall("short")
    rec = _scaled("short", "S07")
    plain = simulate(RockingModel(body), rec)
    modified = simulate(RockingModel(body, pivot=Pivot("compressive-length")), rec)
    assert plain.t_uplift is None
    assert modified.t_uplift is not None
    for wall in WALLS:
        body = series_clay_wall(wall)
        rec = _scaled(wall, "S09")
        t_plain = simulate(RockingModel(body), rec).t_uplift
        t_mod = simulate(RockingModel(body, pivot=Pivot("compressive-length")), rec).t_uplift
        assert t_mod <= t_plain
