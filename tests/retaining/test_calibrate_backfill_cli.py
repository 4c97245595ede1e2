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
