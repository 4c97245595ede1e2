"""``murus retaining calibrate-backfill``: one biaxial test through the CLI writes a figure, the
stress-strain table and a summary whose peak angle is the one of the table (phi = asin of the
largest stress ratio); bad input is one line with exit code 2 and nothing written."""

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from murus.cli import app
from murus.outputs import MANIFEST


def test_single_biaxial_test_outputs(tmp_path):
    out = tmp_path / "bx"
    r = CliRunner().invoke(app, ["retaining", "calibrate-backfill", "--discs", "100",
                                 "--rolling", "0.1", "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert "phi_peak" in r.output
    assert {p.name for p in out.iterdir()} - {MANIFEST} == {"biaxial.png", "biaxial.svg",
                                                           "biaxial.csv", "biaxial.json"}
    s = json.loads((out / "biaxial.json").read_text())
    tab = np.loadtxt(out / "biaxial.csv", delimiter=",", skiprows=1)
    ratio = (tab[:, 1] - tab[:, 2]) / (tab[:, 1] + tab[:, 2])
    assert s["phi_peak_deg"] == pytest.approx(math.degrees(math.asin(ratio.max())), abs=1e-3)
    assert s["phi_peak_deg"] >= s["phi_cs_deg"]
    # the confining stress is held by the servo (5 %: tests/dem/test_biaxial.py)
    assert np.median(tab[len(tab) // 2:, 2]) == pytest.approx(50e3, rel=0.05)


@pytest.mark.parametrize("args, word", [
    (["--target", "95"], "--target"),
    (["--friction", "-5"], "friction"),
])
def test_bad_input(tmp_path, args, word):
    out = tmp_path / "x"
    r = CliRunner().invoke(app, ["retaining", "calibrate-backfill", *args, "--out", str(out)])
    assert r.exit_code == 2
    assert word in r.output and len(r.output.strip().splitlines()) == 1
    assert not out.exists()


def _fake_test(phi_of_mu):
    """A stand-in for murus.dem.biaxial.biaxial_test: peak angle phi_of_mu(mu, seed)."""
    from murus.dem import biaxial as B

    def fake(joint, seed=0, **kw):
        phi = phi_of_mu(joint.rolling, seed)
        return B.BiaxialResult(
            axial_strain=np.array([0.0, 0.01]), sigma1=np.array([1.0, 2.0]),
            sigma3=np.ones(2), volumetric_strain=np.zeros(2), sigma3_target=1.0,
            phi_peak_deg=phi, phi_cs_deg=phi - 3, strain_at_peak=0.01, porosity0=0.2, n=10,
            rolling=joint.rolling, friction_deg=30.0, strain_rate=1.0, dt=1.0, steps=1,
            wall=0.0)

    return fake


def test_calibration_reports_the_scatter_over_the_assemblies(tmp_path, monkeypatch):
    # phi = 30 + 15 mu, shifted by 0.5 (seed - 1.5) deg for the seeds 0-3: the mean is the
    # line, the sample standard deviation over the four seeds sqrt(1.25 / 3) = 0.6455 deg
    from murus.dem import biaxial as B

    monkeypatch.setattr(B, "biaxial_test",
                        _fake_test(lambda mu, s: 30.0 + 15.0 * mu + 0.5 * (s - 1.5)))
    out = tmp_path / "bx"
    r = CliRunner().invoke(app, ["retaining", "calibrate-backfill", "--target", "37.7",
                                 "--seeds", "4", "--out", str(out)])
    assert r.exit_code == 0, r.output
    s = json.loads((out / "biaxial.json").read_text())
    c = s["calibration"]
    assert s["ok"] is True and s["status"] == c["status"] == "converged"
    assert c["rolling"] == pytest.approx(7.7 / 15.0, abs=0.5 / 15.0)
    assert c["std_deg"] == pytest.approx(math.sqrt(1.25 / 3), rel=1e-9)
    assert c["seeds"] == 4 and len(c["phi_peak_deg_assemblies"]) == 4


@pytest.mark.parametrize("target, status", [(37.7, "non_monotone"), (60.0, "outside_bracket")])
def test_calibration_that_does_not_converge_exits_1(tmp_path, monkeypatch, target, status):
    # a mean phi(mu_r) with a dip in (0.3, 0.6): the interpolated first point (0.51) falls in
    # it, below the angle of the bracket's lower end; 60 deg is above the bracket's 45 deg
    from murus.dem import biaxial as B

    monkeypatch.setattr(B, "biaxial_test", _fake_test(
        lambda mu, s: 28.0 if 0.3 < mu < 0.6 else 30.0 + 15.0 * mu))
    out = tmp_path / "bx"
    r = CliRunner().invoke(app, ["retaining", "calibrate-backfill", "--target", str(target),
                                 "--seeds", "2", "--out", str(out)])
    assert r.exit_code == 1, r.output
    s = json.loads((out / "biaxial.json").read_text())
    assert s["ok"] is False and s["status"] == s["calibration"]["status"] == status
    err = [x for x in r.stderr.splitlines() if x.startswith("error:")]
    assert len(err) == 1 and status in err[0]
    # without --out: the same exit code and reason
    r = CliRunner().invoke(app, ["retaining", "calibrate-backfill", "--target", str(target),
                                 "--seeds", "2"])
    assert r.exit_code == 1 and status in r.stderr
