"""``murus report DIR``: one self-contained HTML page of an output folder (issue 21, item 4).

The folders of a rocking run and a DEM run are built here with the files those commands write
(summary fields as the engines write them, a figure, a history, the manifest with the command
line), so that the test takes seconds; the mechanism check is the real command. The page is
rendered in headless Chromium and the screenshot must not be blank (skipped with the reason
when no browser is installed: the CI script installs Debian's ``chromium``)."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest
from typer.testing import CliRunner

from murus.outputs import FILES, MANIFEST, OutputError, read_manifest, write_dir
from murus.report import build_report, detect, write_report

EXAMPLE = Path(__file__).parents[1] / "examples" / "mechanisms" / "two_storey_facade.toml"

ROCKING_CASE = """# a free block
[body]
width = 0.3
height = 3.0
density = 2140.67

[motion]
type = "free"
theta0_over_alpha = 0.9
"""


def _png(path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(4, 3), dpi=60)
    ax.plot([0, 1, 2, 3], [0, 1, 0, -1], lw=3)
    ax.set_title("response")
    fig.savefig(path)
    plt.close(fig)


def _rocking(tmp_path: Path) -> Path:
    case = tmp_path / "block.toml"
    case.write_text(ROCKING_CASE, encoding="utf-8")
    out = tmp_path / "r1"
    summary = {"theta_max": 0.0897, "n_impacts": 14, "overturned": False, "t_overturn": None,
               "energy_dissipated": 47.9, "status": "ok", "theta_max_over_alpha": 0.9,
               "limit_states": {"limited": True, "moderate": True, "overturning": False},
               "alpha": 0.0997, "p": 2.209, "method": "event", "input": {"body": {}}}

    def write(tmp: Path) -> None:
        (tmp / "summary.json").write_text(json.dumps(summary), encoding="utf-8")
        (tmp / "timeseries.csv").write_text("t_s,theta_rad\n0,0.0897\n0.01,0.0896\n",
                                            encoding="utf-8")
        _png(tmp / "response.png")

    write_dir(out, write, command=f"murus run {case} --out {out}")
    return out


def _dem(tmp_path: Path) -> Path:
    out = tmp_path / "d1"
    summary = {"status": "completed", "ok": True, "message": "", "t_end": 1.0, "steps": 12247,
               "dt": 8.2e-05, "bodies": 2, "height": 0.25, "final": {"u": 0.471},
               "peak_abs": {"u": 0.471}, "energy_error": 7.8e-07}

    def write(tmp: Path) -> None:
        (tmp / "summary.json").write_text(json.dumps(summary), encoding="utf-8")
        (tmp / "histories.csv").write_text("t,u\n0,0\n1,0.471\n", encoding="utf-8")
        _png(tmp / "blocks.png")

    write_dir(out, write, command=f"murus run inclined_plane.toml --out {out}")
    return out


def _mechanism(tmp_path: Path) -> Path:
    from murus.cli import app

    out = tmp_path / "m1"
    r = CliRunner().invoke(app, ["mechanism", str(EXAMPLE), "--out", str(out)])
    assert r.exit_code == 0, r.output
    return out


def _self_contained(page: str) -> None:
    assert not re.search(r"""src\s*=\s*["']?(https?:|//)""", page, re.I)
    assert not re.search(r"""<link[^>]+href\s*=\s*["']?(https?:|//)""", page, re.I)
    assert "<script" not in page.lower()
    assert "@import" not in page and "url(" not in page
    assert "@media print" in page and "size:A4" in page


def test_rocking_report(tmp_path):
    out = _rocking(tmp_path)
    assert detect(out) == "rocking"
    page = build_report(out)
    _self_contained(page)
    assert page.count('src="data:image/png;base64,') == 1  # the figure, embedded
    assert 'theta0_over_alpha = 0.9' in page  # the case file echoed
    assert f"murus run {tmp_path / 'block.toml'}" in page  # the command line
    # units declared by murus.rocking.summary
    assert re.search(r"<th>theta_max</th><td class=num>0.0897</td><td>rad</td>", page)
    assert re.search(r"<th>energy_dissipated</th><td class=num>47.9</td><td>J</td>", page)
    assert "not overturned" in page and "REACHED" in page
    assert "Housner" in page and "EURODYN" in page
    assert "modified after the run" not in page
    import os
    import time

    later = time.time() + 60
    os.utime(tmp_path / "block.toml", (later, later))
    assert "modified after the run" in build_report(out)


def test_dem_report(tmp_path):
    out = _dem(tmp_path)
    assert detect(out) == "dem"
    page = build_report(out)
    _self_contained(page)
    assert page.count('src="data:image/png;base64,') == 1
    assert re.search(r"<th>dt</th><td class=num>8.2e-05</td><td>s</td>", page)
    assert "histories.csv" in page and "Cundall" in page and "PASS" in page


def test_mechanism_report_and_files(tmp_path):
    out = _mechanism(tmp_path)
    assert detect(out) == "mechanism"
    page = build_report(out)
    _self_contained(page)
    assert page.count('src="data:image/png;base64,') == len(list(out.glob("*.png"))) > 0
    assert "[[storeys]]" in page  # the case file, echoed from the manifest's command line
    assert "a0_star [m/s2]" in page and "M_star [kg]" in page
    assert "FAIL" in page and "Circolare" in page
    # written through murus.outputs: recorded in the manifest, the run's command kept
    path = write_report(out)
    assert path == out / "report.html" and path.read_text(encoding="utf-8") == page
    assert "report.html" in read_manifest(out)
    assert "murus mechanism" in json.loads((out / MANIFEST).read_text())["command"]
    write_report(out)  # murus's own report is replaced


def test_report_never_overwrites_a_users_file(tmp_path):
    out = _dem(tmp_path)
    (out / "report.html").write_text("mine", encoding="utf-8")
    with pytest.raises(OutputError, match="not written by murus"):
        write_report(out)
    assert (out / "report.html").read_text() == "mine"
    from murus.cli import app

    r = CliRunner().invoke(app, ["report", str(out)])
    assert r.exit_code == 2 and "not written by murus" in r.output
    r = CliRunner().invoke(app, ["report", str(tmp_path / "missing")])
    assert r.exit_code == 2


def test_generic_folder_without_manifest(tmp_path):
    """A folder of no known kind (a study folder has no manifest): every JSON as a table,
    every CSV's head, every figure; the report is recorded in the folder's list of murus
    files."""
    out = tmp_path / "x"
    out.mkdir()
    (out / "study.json").write_text(json.dumps({"name": "s", "spec": {"a": 1}}))
    (out / "values.json").write_text(json.dumps({"k": 2.5, "rows": [{"a": 1}, {"a": 2}]}))
    (out / "table.csv").write_text("a,b\n1,2\n", encoding="utf-8")
    _png(out / "fig.png")
    assert detect(out) == "folder"
    page = build_report(out)
    _self_contained(page)
    assert "values.json" in page and "table.csv" in page and "data:image/png" in page
    from murus.cli import app

    r = CliRunner().invoke(app, ["report", str(out)])
    assert r.exit_code == 0, r.output
    assert "report.html" in json.loads((out / FILES).read_text())["files"]


def test_report_renders_in_headless_chromium(tmp_path):
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        pytest.skip("no chromium on PATH (the CI script installs Debian's chromium; "
                    "it could not be installed here)")
    from matplotlib.image import imread

    page = write_report(_rocking(tmp_path))
    shot = tmp_path / "shot.png"
    subprocess.run([browser, "--headless", "--disable-gpu", "--no-sandbox",
                    f"--screenshot={shot}", "--window-size=1200,1600",
                    page.resolve().as_uri()], check=True, timeout=120,
                   capture_output=True)
    img = imread(shot)[..., :3]
    assert img.shape[:2] == (1600, 1200)
    assert img.std() > 0.05  # not a blank page
    assert (img < 0.5).mean() > 0.002  # text and figure drawn, not all white


def test_fragility_study_report(tmp_path):
    """A study folder (no manifest): the Dataset's variables with units, the verdicts and the
    lognormal fragility fitted on the stripes; references by kind (Baker 2015)."""
    import numpy as np
    import xarray as xr

    out = tmp_path / "f1"
    out.mkdir()
    (out / "study.json").write_text(json.dumps({"name": "frag", "spec": {
        "im": "PGA", "sweep": {"im": [0.2, 0.8]}}}))
    over = np.array([[0.0, 0.0, 0.0, 1.0], [1.0, 1.0, 0.0, 1.0]])
    ds = xr.Dataset(
        {"overturned": (("im", "record"), over, {"units": "1"}),
         "theta_max_over_alpha": (("im", "record"), 0.3 + over, {"units": "1"}),
         "theta_max": (("im", "record"), 0.03 + over / 10, {"units": "rad",
                                                             "long_name": "largest rotation"})},
        coords={"im": ("im", [0.2, 0.8], {"units": "g"}), "record": ["a", "b", "c", "d"]})
    ds.to_netcdf(out / "result.nc")
    assert detect(out) == "rocking-study"
    page = build_report(out)
    _self_contained(page)
    assert "<th>theta_max</th><td>im, record</td><td>rad</td>" in page
    assert "4 of 8 histories" in page
    assert re.search(r"median \[g\]", page) and "Baker" in page
    (out / "study.json").write_text(json.dumps({"name": "spectrum", "spec": {
        "im": None, "sweep": {"K_over_Kd": [0.0, 1.0]}}}))
    assert "Baker" not in build_report(out)  # a spectrum: no fragility reference


def test_folder_of_runs(tmp_path):
    """``murus demo``: one rocking run per sub-folder; their units, verdicts, references."""
    out = tmp_path / "demo"

    def write(tmp: Path) -> None:
        for name, over in (("a", False), ("b", True)):
            (tmp / name).mkdir()
            (tmp / name / "summary.json").write_text(json.dumps(
                {"theta_max": 0.2, "overturned": over, "t_overturn": 3.5 if over else None}))
        (tmp / "demo_summary.csv").write_text("case,overturned\na,0\nb,1\n")

    write_dir(out, write, command=f"murus demo --out {out}")
    assert detect(out) == "folder"
    page = build_report(out)
    assert re.search(r"<th>theta_max</th><td class=num>0.2</td><td>rad</td>", page)
    assert "b: overturned: at t = 3.5 s" in page and "a: not overturned" in page
    assert "Housner" in page and "demo_summary.csv" in page


@pytest.mark.parametrize("kind, files, ref", [
    ("limit", {"summary.json": {"load_factor": 0.46, "converged": True,
                                "units": {"load_factor": "-"}}}, "Livesley"),
    ("retaining-collapse", {"summary.json": {"wall": "DSRW1", "collapsed": True, "t_col": 4.2,
                                             "A_col": 6.1}}, "Savalle"),
    ("continuum", {"summary.json": {"status": "completed", "ok": True, "zones": 40,
                                    "gridpoints": 55, "steps": 10, "dt": 1e-4}}, "Marti"),
    ("motion-record", {"measures.json": {"pga": 1.2, "units": {"pga": "m/s2"}},
                       "record.png": None}, "Arias"),
    ("lab-sequence", {"summary.json": {"evolution": [{"test": "WN01", "f1_hz": 8.0},
                                                     {"test": "WN02", "f1_hz": 6.0}]},
                      "report.md": "# Sequence\n\n| a | b |\n|---|---|\n| 1 | 2 |\n",
                      "frequency.png": None}, "Mordant"),
])
def test_kinds(tmp_path, kind, files, ref):
    out = tmp_path / kind

    def write(tmp: Path) -> None:
        for name, content in files.items():
            if content is None:
                _png(tmp / name)
            elif isinstance(content, str):
                (tmp / name).write_text(content, encoding="utf-8")
            else:
                (tmp / name).write_text(json.dumps(content), encoding="utf-8")

    write_dir(out, write, command=f"murus {kind} --out {out}")
    assert detect(out) == kind
    page = build_report(out)
    _self_contained(page)
    assert ref in page and "<h2>Verdicts</h2>" in page
