"""`murus run` and case files: outputs, and one-line errors with exit code 2 (issue 2, item 7)."""

import json
import math

import numpy as np
import pytest
from rocking_inputs import rocking_case, write_record
from typer.testing import CliRunner

from murus.cli import app

runner = CliRunner()

CASE = rocking_case(6.0, body="top_mass = 0.0\n", motion="scale = 1.0\n")



def run(tmp_path, case_text, out="out"):
    (tmp_path / "case.toml").write_text(case_text)
    return runner.invoke(app, ["run", str(tmp_path / "case.toml"), "--out", str(tmp_path / out)])


def test_run_writes_outputs(tmp_path):
    write_record(tmp_path)
    r = run(tmp_path, CASE)
    assert r.exit_code == 0, r.output
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    for key in ("theta_max", "theta_max_over_alpha", "overturned", "impacts", "uplift_time",
                "alpha", "p", "restitution"):
        assert key in s
    assert s["alpha"] == pytest.approx(math.atan(0.25 / 1.0), rel=1e-12)
    assert s["restitution"] == pytest.approx(1 - 1.5 * math.sin(s["alpha"]) ** 2, rel=1e-12)
    assert s["theta_max_over_alpha"] == pytest.approx(s["theta_max"] / s["alpha"], rel=1e-12)
    ts = np.genfromtxt(tmp_path / "out" / "timeseries.csv", delimiter=",", names=True)
    assert ts["t_s"][-1] == pytest.approx(6.0)
    # the timeseries is the run: its largest |theta| is the summary's within the output sampling
    assert np.max(np.abs(ts["theta_rad"])) <= s["theta_max"] * (1 + 1e-9)
    assert (tmp_path / "out" / "response.png").stat().st_size > 10_000


def test_sine_pulse_and_newmark_case(tmp_path):
    case = """
[body]
width = 0.72
height = 1.8
thickness = 0.138
top_mass = 5000.0
[restitution]
law = "constant"
value = 0.9
[motion]
type = "sine-pulse"
amplitude_g = 0.3
frequency = 2.0
cycles = 1
[solver]
method = "newmark"
dt = 0.001
duration = 3.0
"""
    r = run(tmp_path, case)
    assert r.exit_code == 0, r.output
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["restitution"] == 0.9
    # uplift when 0.3 g sin(4 pi t) = g tan(alpha): t = asin(tan(alpha)/0.3) / (4 pi)
    t_up = math.asin(math.tan(s["alpha"]) / 0.3) / (4 * math.pi)
    assert s["uplift_time"] == pytest.approx(t_up, abs=1e-6)


BAD = [
    ("width = 0.25", "width = -0.25", "line 3", "width"),
    ("width = 0.25", "width = 0.0", "line 3", "width"),
    ('law = "housner"', 'law = "constant"\nvalue = 1.5', "line 10", "value"),
    ('law = "housner"', 'law = "housnr"', "line 9", "law"),
    ("top_mass = 0.0", "top_mass = 0.0\ncolour = 1", "line 8", "colour"),
    ('file = "record.csv"', 'file = "missing.csv"', "line 11", "missing.csv"),
    ('method = "event"', 'method = "newmark"', "line 14", "dt"),  # the [solver] table
    ("duration = 6.0", "duration = 6.0 6", "line 16", "TOML"),
]


@pytest.mark.parametrize("old, new, line, word", BAD)
def test_bad_case_is_one_line_exit_2_no_output(tmp_path, old, new, line, word):
    write_record(tmp_path)
    r = run(tmp_path, CASE.replace(old, new))
    assert r.exit_code == 2
    err = r.stderr.strip() if r.stderr else r.output.strip()
    assert len(err.splitlines()) == 1, err
    assert word in err and "case.toml" in err and line in err, err
    assert not (tmp_path / "out").exists()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".out")] == []


@pytest.mark.parametrize(
    "content, word",
    [
        ("0.0,0.0\n0.01,0.1\n0.01,0.2\n", "line 3"),  # non-increasing time
        ("0.0,0.0\n0.01,abc\n0.02,0.2\n", "line 2"),  # text in a number field
        ("0.0,0.0\n0.01,nan\n0.02,0.2\n", "line 2"),  # NaN
    ],
)
def test_malformed_record_names_file_and_line(tmp_path, content, word):
    (tmp_path / "record.csv").write_text(content)
    r = run(tmp_path, CASE)
    assert r.exit_code == 2
    err = r.stderr.strip() if r.stderr else r.output.strip()
    assert len(err.splitlines()) == 1, err
    assert "record.csv" in err and word in err, err
    assert not (tmp_path / "out").exists()


def test_existing_output_replaced_only_on_success(tmp_path):
    write_record(tmp_path)
    assert run(tmp_path, CASE).exit_code == 0
    before = (tmp_path / "out" / "summary.json").read_text()
    r = run(tmp_path, CASE.replace("width = 0.25", "width = -1"))
    assert r.exit_code == 2
    assert (tmp_path / "out" / "summary.json").read_text() == before


def test_help_lists_commands():
    r = runner.invoke(app, ["--help"])
    assert r.exit_code == 0
    assert "run" in r.output and "motion" in r.output and "demo" in r.output
