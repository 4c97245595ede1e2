"""Weighted global response of several cross-sections (Savalle et al. (2022), §3.2, Table 2)."""

import csv
from pathlib import Path

import numpy as np
import pytest

from murus.retaining.sections import SectionsError, first_passage_times, weighted_response

DATA = Path(__file__).resolve().parents[1] / "data" / "retaining" / "savalle2022_table2.csv"


def table2():
    rows = list(csv.DictReader(ln for ln in DATA.read_text().splitlines()
                               if not ln.startswith("#")))
    secs = [r for r in rows if r["section"] != "weighted"]
    w = [int(r["proportion_num"]) / int(r["proportion_den"]) for r in secs]
    times = [float(r["time_s"]) for r in secs]
    printed = float(next(r for r in rows if r["section"] == "weighted")["time_s"])
    return w, times, printed


def test_savalle2022_table2():
    """Sections whose d_top grows linearly and reaches 5 mm at the printed times: the weighted
    time at 5 mm is the printed 20.1 s to its last digit (exact mean 20.070 s)."""
    w, times, printed = table2()
    t = np.linspace(0.0, 30.0, 3001)
    hist = [(t, 0.005 * t / ti) for ti in times]  # reaches 5 mm at t = ti exactly
    res = weighted_response(hist, w, levels=[0.005])
    assert res.section_times[:, 0] == pytest.approx(times, abs=1e-9)
    assert res.time[0] == pytest.approx(sum(a * b for a, b in zip(w, times, strict=True)),
                                        rel=1e-12)
    assert res.time[0] == pytest.approx(printed, abs=0.05)


def test_first_passage_on_the_running_maximum():
    t = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    d = np.array([0.0, 2.0, -1.0, -3.0, 1.0])  # |d| envelope 0, 2, 2, 3, 3
    got = first_passage_times(t, d, [1.0, 2.0, 2.5, 3.0, 4.0])
    assert got[:4] == pytest.approx([0.5, 1.0, 2.5, 3.0])
    assert np.isnan(got[4])


def test_levels_default_and_left_out():
    t = np.linspace(0, 10, 101)
    res = weighted_response([(t, 0.01 * t), (t, 0.02 * t)], [1, 1])
    assert res.levels.max() == pytest.approx(0.1)  # the weaker section's largest d_top
    # at level L: t1 = 100 L, t2 = 50 L -> mean 75 L
    assert res.time == pytest.approx(75 * res.levels, rel=1e-9)
    res = weighted_response([(t, 0.01 * t), (t, 0.02 * t)], [1, 1], levels=[0.05, 0.15])
    assert res.levels.tolist() == [0.05] and res.levels_left_out.tolist() == [0.15]


@pytest.mark.parametrize("hist, w, word", [
    ([], [], "no section"),
    ([(np.arange(3.0), np.zeros(3))], [1, 2], "weights"),
    ([(np.arange(3.0), np.zeros(3))], [-1], "non-negative"),
    ([(np.array([0.0, 2.0, 1.0]), np.zeros(3))], [1], "increase"),
])
def test_bad_input(hist, w, word):
    with pytest.raises(SectionsError, match=word):
        weighted_response(hist, w)


def test_cli_weighted_response(tmp_path):
    """Through the CLI on d_top files in the format of 'murus retaining collapse': the global
    time at 5 mm is the weighted mean of the section times (Table 2)."""
    from typer.testing import CliRunner

    from murus.cli import app

    w, times, _ = table2()
    t = np.linspace(0.0, 30.0, 3001)
    files = []
    for k, ti in enumerate(times):
        f = tmp_path / f"s{k}.csv"
        np.savetxt(f, np.column_stack([t, 0.005 * t / ti, 0 * t]), delimiter=",",
                   header="t_s,d_top_m,acc_m_s2", comments="")
        files.append(str(f))
    out = tmp_path / "global.csv"
    r = CliRunner().invoke(app, ["retaining", "weighted-response", *files, "--weights",
                                 "7,7,7,2", "--out", str(out)])
    assert r.exit_code == 0, r.output
    g = np.loadtxt(out, delimiter=",", skiprows=1)
    t5 = np.interp(0.005, g[:, 1], g[:, 0])
    assert t5 == pytest.approx(sum(a * b for a, b in zip(w, times, strict=True)), rel=1e-6)
    r = CliRunner().invoke(app, ["retaining", "weighted-response", files[0], "--weights", "1,2"])
    assert r.exit_code == 2 and "weights" in r.output
