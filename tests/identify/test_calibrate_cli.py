"""``murus lab calibrate``: a test file written from a murus.rocking history (the table
acceleration of the test format is minus the model's ground acceleration) gives back the
restitution parameter that produced it; bad input is one line with exit code 2."""

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from murus.cli import app
from murus.identify.testdata import ShakingTableTest, write_test
from murus.motion.synthetic import sine_pulse
from murus.outputs import MANIFEST
from murus.rocking import RigidBlock, RockingModel, simulate
from murus.rocking.restitution import AmplitudeDependent


@pytest.fixture(scope="module")
def test_file(tmp_path_factory):
    body = RigidBlock(width=0.72, height=1.8, thickness=0.138, density=0.0, top_mass=5000.0)
    mdl = RockingModel(body, AmplitudeDependent(k0=1.5, k1=0.0))
    gm = sine_pulse(2.0 * 9.81 * math.tan(body.alpha), 2.5, cycles=3, dt=0.005, duration=5.0)
    r = simulate(mdl, gm, out_dt=0.005)
    n = min(gm.acc.size, r.theta.size)
    test = ShakingTableTest(name="S09", sampling_rate=200.0, wall_length=0.72, wall_height=1.8,
                            channels={"table_acc": -gm.acc[:n], "top_acc": np.zeros(n),
                                      "rot_bottom": r.theta[:n]},
                            kind="seismic", pga_g=2.0 * math.tan(body.alpha), top_mass=5000.0)
    path = tmp_path_factory.mktemp("lab") / "09_S09.csv"
    write_test(test, path)
    return path


def test_recovers_k0_and_writes_the_report(test_file, tmp_path):
    out = tmp_path / "cal"
    r = CliRunner().invoke(app, ["lab", "calibrate", str(test_file), "--params", "k0",
                                 "--out", str(out)])
    assert r.exit_code == 0, r.output
    d = json.loads((out / "calibration.json").read_text())
    # the file stores 200 Hz samples with a few digits: k0 within 1 %
    assert d["params"]["k0"] == pytest.approx(1.5, rel=0.01)
    # progress on stderr (not a terminal: lines, the last one when the fit ends)
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("lab calibrate: ") and "evaluations" in last
    assert last.endswith("(done)")
    assert {p.name for p in out.iterdir()} - {MANIFEST} == {"calibration.json", "calibration.md",
                                               "calibration.png", "calibration.svg"}


@pytest.mark.parametrize("args, word", [
    (["--params", "k7"], "unknown parameter"),
    (["--pivot", "middle"], "--pivot"),
    (["--channel", "rot_top"], "no channel"),
    (["--bounds", "k0=a:b"], "NAME=LOW:HIGH"),
])
def test_bad_input(test_file, tmp_path, args, word):
    out = tmp_path / "x"
    r = CliRunner().invoke(app, ["lab", "calibrate", str(test_file), *args, "--out", str(out)])
    assert r.exit_code == 2
    assert word in r.output and len(r.output.strip().splitlines()) == 1
    assert not out.exists()
