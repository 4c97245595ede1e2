"""A DEM run that did not succeed says so (issue 15, item 2): blocks that interpenetrate by more
than 10 % of their size stop the settling or the run with a status that is not ok, ``murus run``
writes its outputs with ``"ok": false`` and exits 1; overflowing inputs (kn = 1e300,
dt = 1e-300) and clumps whose parts overlap are refused with a one-line error naming the file,
line and key (exit 2, nothing written)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from dem_inputs import BLOCK_ON_BASE
from typer.testing import CliRunner

from murus.cli import app
from murus.config import key_line
from murus.dem import Joint, Model
from murus.dem.engine import OVERLAP_LIMIT, body_sizes, overlap_fraction
from murus.dem.model import ModelError

G = 9.81

CASE = BLOCK_ON_BASE + """\
[[monitors]]
name = "uy"
body = 1
quantity = "uy"
"""


def _case(tmp_path, kn="1e9", dem="", extra=""):
    duration = "0.2"
    if dem.startswith("duration"):
        duration, dem = dem.split("=")[1].strip(), ""
    p = tmp_path / "case.toml"
    p.write_text(CASE.format(kn=kn, dem=dem, extra=extra, duration=duration))
    return p


def _err(r) -> str:
    return (r.stderr if r.stderr else r.output).strip()


def test_body_sizes_and_overlap_of_a_settled_block():
    # a 0.4 x 0.2 m block (2000 kg/m3, t = 1 m) on a fixed base, kn = 1e6 Pa/m: at rest the
    # contact carries m g over L = 0.4 m, so the overlap is m g / (kn L t) = 3.92 mm, 1.96 % of
    # the block's thickness along the contact normal (its height, 0.2 m); the smallest widths
    # across of the bodies (body_sizes): 0.2 m, 0.2 m, 0.1 m and a disc's diameter
    m = Model(joint=Joint(kn=1e6, ks=1e6, friction_deg=30.0))
    m.add_rectangle(2.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
    m.add_rectangle(0.4, 0.2, center=(0.0, 0.1), angle=0.0)
    m.add_rectangle(0.3, 0.1, center=(5.0, 5.0), angle=0.7, kinematic="fixed")
    m.add_disc((-5.0, 5.0), 0.05, kinematic="fixed")
    st = m.settle(tol=1e-6)
    assert st.converged
    assert body_sizes(m) == pytest.approx([0.2, 0.2, 0.1, 0.1], rel=1e-9)
    frac, a, b, depth = overlap_fraction(m)
    exact = 2000 * 0.08 * G / (1e6 * 0.4)
    assert (a, b) == (0, 1)
    assert depth == pytest.approx(exact, rel=1e-3)
    assert frac == pytest.approx(exact / 0.2, rel=1e-3)
    assert st.overlap == pytest.approx(frac, rel=1e-3)


def test_overlap_of_a_sub_contact_of_zero_extent(monkeypatch):
    """A sub-contact whose extent along its normal is zero (or below the body's width by
    rounding) has an exact fraction above its bound: the check reports it instead of failing
    on an empty selection (seen at the end of the settling of DSRW4 on its continuum backfill,
    issue 18)."""
    import murus.dem.engine as E

    m = Model(joint=Joint(kn=1e6, ks=1e6, friction_deg=30.0))
    m.add_rectangle(2.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
    m.add_rectangle(0.4, 0.2, center=(0.0, 0.1), angle=0.0)
    assert m.settle(tol=1e-6).converged
    monkeypatch.setattr(E, "_extent", lambda m, b, nx, ny: np.zeros(len(b)))
    frac, a, b, depth = overlap_fraction(m)
    assert frac == np.inf and (a, b) == (0, 1) and depth > 0


def test_soft_contact_stops_the_settling_and_the_run(tmp_path):
    # kn = 1e5 Pa/m: the static overlap would be 39 mm, 19.6 % of the block's height > 10 %
    m = Model(joint=Joint(kn=1e5, ks=1e5, friction_deg=30.0))
    m.add_rectangle(2.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
    m.add_rectangle(0.4, 0.2, center=(0.0, 0.1))
    st = m.settle()
    assert not st.converged and "10 %" in st.message
    assert OVERLAP_LIMIT < st.overlap < 0.25
    # through the CLI: outputs written with ok = false, a one-line reason, exit 1
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(_case(tmp_path, "1e5")), "--out", str(out)])
    assert r.exit_code == 1, r.output
    s = json.loads((out / "summary.json").read_text())
    assert s["ok"] is False and s["status"] == "not_settled"
    assert "interpenetrate" in s["message"]
    assert [x for x in r.stderr.splitlines() if x.startswith("error:")] == [
        f"error: case.toml: not_settled: {s['message']}"]
    # without settling the run itself stops (status interpenetration) before the block sinks
    # much deeper than the limit
    out2 = tmp_path / "out2"
    r = CliRunner().invoke(app, ["run", str(_case(tmp_path, "1e5", dem="settle = false")),
                                 "--out", str(out2)])
    assert r.exit_code == 1, r.output
    s = json.loads((out2 / "summary.json").read_text())
    assert s["ok"] is False and s["status"] == "interpenetration"
    assert s["t_end"] < 0.2
    assert -0.2 * 0.2 < s["final"]["uy"] < -OVERLAP_LIMIT * 0.2 * 0.5


def test_good_run_is_ok(tmp_path):
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(_case(tmp_path)), "--out", str(out),
                                 "--no-progress"])
    assert r.exit_code == 0, r.output
    s = json.loads((out / "summary.json").read_text())
    assert s["ok"] is True and s["status"] == "completed"
    assert r.stderr == ""  # --no-progress: nothing on stderr
    # by default, progress lines on stderr (not a terminal: a line at the start, every 10 s
    # and at the end), the summary alone on stdout
    r = CliRunner().invoke(app, ["run", str(_case(tmp_path)), "--out", str(tmp_path / "o2")])
    assert r.exit_code == 0, r.output
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("case.toml: ") and last.endswith("(done)") and "steps (100 %)" in last
    assert len(r.stdout.strip().splitlines()) == 1


@pytest.mark.parametrize("kn, dem, extra, key", [
    ("1e300", "", "", "materials.stone.kn"),
    ("1e9", "dt = 1e-300", "", "dem.dt"),
    ("1e-3", "", "", "materials.stone.kn"),  # the stable step exceeds the duration
    ("1e9", "", "[motion]\ntype = 'sine-pulse'\namplitude = 1.0\nfrequency = 1.0\n"
     "dt = 1e-300\n", "motion.dt"),
    # 1.4e8 steps of 73 us, each sampled: histories of 60 GB
    ("1e9", "duration = 1e4", "[output]\nsample_dt = 1e-300\n", "output.sample_dt"),
])
def test_overflowing_input_names_the_key(tmp_path, kn, dem, extra, key):
    if "motion" in extra:  # the sine pulse moves a base block
        extra = extra.replace("[motion]", "[[blocks]]\nkind = 'rectangle'\nwidth = 0.1\n"
                              "height = 0.1\ncenter = [5.0, -0.05]\nkinematic = 'base'\n\n"
                              "[motion]")
    p = _case(tmp_path, kn, dem, extra)
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(p), "--out", str(out)])
    assert r.exit_code == 2, r.output
    msg = _err(r)
    assert len(msg.splitlines()) == 1 and "Maximum allowed size" not in msg
    loc = tuple(key.split("."))
    assert f"[{key}]" in msg and f"line {key_line(p.read_text(), loc)}:" in msg
    assert not out.exists()


def test_clump_with_overlapping_parts_is_refused(tmp_path):
    clump = ("[[blocks]]\nkind = 'clump'\nparts = [{vertices = [[1, 0], [1.4, 0], [1.4, 0.2], "
             "[1, 0.2]]}, {center = [1.4, 0.3], radius = 0.15}]\n")
    p = _case(tmp_path, extra=clump)
    r = CliRunner().invoke(app, ["run", str(p), "--out", str(tmp_path / "o")])
    assert r.exit_code == 2
    msg = _err(r)
    assert len(msg.splitlines()) == 1
    assert "[blocks[2].parts]" in msg
    assert "clump blocks[2]" in msg and "parts 0 and 1 overlap by 0.05 m" in msg
    assert f"line {key_line(p.read_text(), ('blocks', 2, 'parts'))}:" in msg
    # the same clump through the API; parts that only touch are accepted
    m = Model()
    with pytest.raises(ModelError, match="clump parts 0 and 1 overlap by 0.05 m"):
        m.add_clump([np.array([[1, 0], [1.4, 0], [1.4, 0.2], [1, 0.2]]),
                     ("disc", (1.4, 0.3), 0.15)])
    b = m.add_clump([np.array([[1, 0], [1.4, 0], [1.4, 0.2], [1, 0.2]]),
                     ("disc", (1.2, 0.3), 0.1)])
    m.build()
    assert m.bmass[b] == pytest.approx(2000.0 * (0.08 + math.pi * 0.01))


@pytest.mark.parametrize("solver, key", [
    ("method = 'newmark'\ndt = 1e-300", "solver.dt"),
    ("out_dt = 1e-300", "solver.out_dt"),
    ("duration = 1e300", "solver.duration"),
])
def test_rocking_overflowing_input_names_the_key(tmp_path, solver, key):
    p = tmp_path / "r.toml"
    p.write_text("[body]\nwidth = 0.6\nheight = 6.0\ndensity = 2000.0\n[motion]\n"
                 "type = 'sine-pulse'\namplitude_g = 0.3\nfrequency = 1.0\n[solver]\n"
                 f"{solver}\n")
    r = CliRunner().invoke(app, ["run", str(p), "--out", str(tmp_path / "o")])
    assert r.exit_code == 2
    msg = _err(r)
    assert len(msg.splitlines()) == 1 and f"[{key}]" in msg
    assert f"line {key_line(p.read_text(), tuple(key.split('.')))}:" in msg


def test_block_that_would_tunnel_through_its_base_is_stopped(tmp_path):
    # kn = 1e-3 Pa/m: the stable time step is 73 s (0.2 sqrt(m / (kn L t))), in which the
    # block falls g dt^2 / 2 ~ 26 km, through its base between two contact detections; the
    # first step already moves it more than 10 % of its height
    p = _case(tmp_path, "1e-3", dem="duration = 1000", extra="")
    text = p.read_text().replace("duration = 1000\n", "duration = 1000\nsettle = false\n")
    p.write_text(text)
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(p), "--out", str(out), "--no-progress"])
    assert r.exit_code == 1, r.output
    s = json.loads((out / "summary.json").read_text())
    assert s["ok"] is False and s["status"] == "interpenetration" and s["steps"] == 1
    assert "moves" in s["message"] and "10 %" in s["message"]
    # with the settling: the settling stops, not converged
    p.write_text(text.replace("settle = false\n", ""))
    r = CliRunner().invoke(app, ["run", str(p), "--out", str(tmp_path / "o2"),
                                 "--no-progress"])
    assert r.exit_code == 1
    s = json.loads((tmp_path / "o2" / "summary.json").read_text())
    assert s["status"] == "not_settled" and "moves" in s["message"]
