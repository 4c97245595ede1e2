"""``murus motion info --channel`` on network files and ``generate ec8 --format at2``."""

import json
from pathlib import Path

import numpy as np
from typer.testing import CliRunner

from murus.cli import app
from murus.motion import read
from murus.outputs import MANIFEST

runner = CliRunner()
CLC = Path(__file__).resolve().parents[1] / "data" / "records" / "CICLC_trim.v1"


def test_info_lists_channels_and_reads_the_chosen_one():
    r = runner.invoke(app, ["motion", "info", str(CLC)])
    assert r.exit_code == 0, r.output
    assert "[dmg]" in r.stdout
    assert "channel 1 (90 Deg) of 3: 1 (90 Deg), 2 (360 Deg), 3 (Up)" in r.stdout
    r = runner.invoke(app, ["motion", "info", str(CLC), "--channel", "Up", "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["channel"] == 3 and s["component"] == "Up" and s["station"] == "CLC"
    assert s["npts"] == 400 and s["dt"] == 0.01
    assert s["pga"] == read(CLC, channel=3).pga
    r = runner.invoke(app, ["motion", "info", str(CLC), "--channel", "7"])
    assert r.exit_code == 2
    assert "CICLC_trim.v1: no channel matches channel '7'" in r.stderr


def test_info_unrecognised_format(tmp_path):
    p = tmp_path / "odd.v1"
    p.write_text("Rcrd of something\nRcrd 2\n")
    r = runner.invoke(app, ["motion", "info", str(p)])
    assert r.exit_code == 2
    assert "odd.v1: unrecognised record format (first line: 'Rcrd of something')" in r.stderr


def test_generate_ec8_format_at2(tmp_path):
    out = tmp_path / "ec8"
    r = runner.invoke(app, ["motion", "generate", "ec8", "--ag", "0.25", "--n", "1",
                            "--format", "at2", "--out", str(out)])
    assert r.exit_code == 0, r.output
    names = sorted(p.name for p in out.iterdir() if p.name != MANIFEST)
    assert names[0] == "ec8_B1_01.at2"
    gm = read(out / "ec8_B1_01.at2")
    assert gm.meta["format"] == "at2" and gm.dt == 0.01
    assert np.isfinite(gm.pga) and gm.pga > 0
    r = runner.invoke(app, ["motion", "generate", "ec8", "--ag", "0.25", "--format", "mseed",
                            "--out", str(tmp_path / "x")])
    assert r.exit_code == 2 and "--format 'mseed': use csv or at2" in r.stderr
    assert not (tmp_path / "x").exists()
