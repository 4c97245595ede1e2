"""The ``murus motion`` commands through the root CLI."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

from murus.cli import app
from murus.motion import read
from murus.motion.synthetic import ramp_velocity
from murus.outputs import MANIFEST

runner = CliRunner()


def test_info_peaks_after_stated_baseline(tmp_path):
    """A record that is only an acceleration offset c0 + c1 t: the raw PGD is the double
    integral (c0 T²/2 + c1 T³/6); the end correction removes it exactly. A record that already
    ends at rest (an artificial EN 1998-1 record) keeps its raw PGV and PGD."""
    dt, n = 0.01, 1001
    t = dt * np.arange(n)
    a = 0.02 + 0.003 * t
    f = tmp_path / "drift.csv"
    rows = "\n".join(f"{x:.6f},{y:.12g}" for x, y in zip(t, a, strict=True))
    f.write_text("# units: m/s2\n" + rows)
    r = runner.invoke(app, ["motion", "info", str(f), "--json"])
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    T = t[-1]
    assert d["pgd_raw"] == pytest.approx(0.02 * T**2 / 2 + 0.003 * T**3 / 6, rel=1e-9)
    assert d["pgv"] < 1e-10 and d["pgd"] < 1e-10
    r = runner.invoke(app, ["motion", "info", str(f)])
    assert "after baseline correction" in r.stdout and "baseline: end correction" in r.stdout
    from murus.motion.artificial import generate_ec8

    rec = generate_ec8(2.5, "B", 1, n=1, seed=3)[0]
    g = tmp_path / "ec8.csv"
    g.write_text("# units: m/s2\n" + "\n".join(
        f"{x:.6f},{float(y)!r}" for x, y in zip(rec.time, rec.acc, strict=True)))
    d = json.loads(runner.invoke(app, ["motion", "info", str(g), "--json"]).stdout)
    assert d["pgd"] == pytest.approx(d["pgd_raw"], rel=1e-6)
    assert d["pgv"] == pytest.approx(d["pgv_raw"], rel=1e-6)


def test_ramp_info_spectrum(tmp_path):
    out = tmp_path / "ramp.csv"
    r = runner.invoke(app, ["motion", "ramp", "--amplitude-rate", "0.5", "--frequency", "3",
                            "--duration", "4", "--out", str(out), "--dt", "0.002"])
    assert r.exit_code == 0, r.output
    gm = read(out)
    assert gm.dt == 0.002 and gm.duration == pytest.approx(4.0)
    r = runner.invoke(app, ["motion", "info", str(out), "--json"])
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["npts"] == 2001 and d["dt"] == 0.002
    # trapezoidal integration error of the sampled ramp: O((W dt)²/12)
    rel = (2 * np.pi * 3 * 0.002) ** 2 / 6
    assert d["pgv_raw"] == pytest.approx(np.max(np.abs(ramp_velocity(0.5, 3, gm.time))),
                                         rel=rel)
    assert {"pga", "arias", "d5_95", "pgv", "pgd", "pgd_raw"} <= set(d)
    assert "end correction" in d["baseline"]
    r = runner.invoke(app, ["motion", "spectrum", str(out), "--out", str(tmp_path / "sp")])
    assert r.exit_code == 0, r.output
    lines = (tmp_path / "sp" / "spectrum.csv").read_text().splitlines()
    assert lines[0].split(",")[0] == "period" and "psa" in lines[0].split(",")
    T, psa = np.array([[float(x) for x in ln.split(",")][::5] for ln in lines[1:]]).T
    assert T[0] == pytest.approx(0.01) and psa[0] == pytest.approx(gm.pga, rel=0.01)
    assert (tmp_path / "sp" / "spectrum.png").stat().st_size > 1000


def test_bad_input_exit_2_one_line_nothing_written(tmp_path):
    bad = tmp_path / "record.csv"
    bad.write_text("0 1\n0.01 2\n0.02 abc\n")
    out = tmp_path / "sp"
    r = runner.invoke(app, ["motion", "spectrum", str(bad), "--units", "g", "--out", str(out)])
    assert r.exit_code == 2
    msg = r.stderr.strip()
    assert msg == "error: record.csv line 3: 'abc' is not a number"
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["record.csv"]
    r = runner.invoke(app, ["motion", "info", str(tmp_path / "missing.at2")])
    assert r.exit_code == 2 and len(r.stderr.strip().splitlines()) == 1
    r = runner.invoke(app, ["motion", "ramp", "--amplitude-rate", "-1", "--frequency", "3",
                            "--duration", "4", "--out", str(tmp_path / "x.csv")])
    assert r.exit_code == 2 and not (tmp_path / "x.csv").exists()
    r = runner.invoke(app, ["motion", "generate", "ec8", "--ag", "0.25", "--ground", "Z",
                            "--out", str(tmp_path / "g")])
    assert r.exit_code == 2 and "ground type" in r.stderr
    assert not (tmp_path / "g").exists()


def test_generate_ec8(tmp_path):
    out = tmp_path / "ec8"
    r = runner.invoke(app, ["motion", "generate", "ec8", "--ag", "0.25", "--ground", "B",
                            "--type", "1", "--n", "3", "--seed", "1", "--out", str(out)])
    assert r.exit_code == 0, r.output
    names = sorted(p.name for p in out.iterdir() if p.name != MANIFEST)
    assert names == ["ec8_B1_01.csv", "ec8_B1_02.csv", "ec8_B1_03.csv", "report.json",
                     "report.txt", "spectra.png"]
    rep = json.loads((out / "report.json").read_text())
    assert rep["passed"] is True
    gm = read(out / "ec8_B1_01.csv")
    assert abs(gm.velocity()[-1]) < 0.01 and abs(gm.displacement()[-1]) < 0.01


def test_ramp_vertical_at2_refused(tmp_path):
    out = tmp_path / "r.at2"
    r = runner.invoke(app, ["motion", "ramp", "--amplitude-rate", "0.5", "--frequency", "3",
                            "--duration", "1", "--out", str(out), "--vertical", "opposition"])
    assert r.exit_code == 2 and "one component" in r.stderr and not out.exists()
    out = tmp_path / "r.csv"
    r = runner.invoke(app, ["motion", "ramp", "--amplitude-rate", "0.5", "--frequency", "3",
                            "--duration", "1", "--out", str(out), "--vertical", "opposition"])
    assert r.exit_code == 0
    gm = read(out)
    assert np.allclose(gm.acc_v, -0.5 * gm.acc, rtol=1e-15, atol=0)
