"""DEM case files (murus.dem.case) and ``murus run`` on them: the examples parse and build, the
inclined plane through the CLI gives the closed-form sliding acceleration, and each class of bad
input is one line naming the key, exit code 2 and no output folder."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from dem_inputs import BLOCK_ON_BASE
from typer.testing import CliRunner

from murus.cli import app
from murus.config import CaseError
from murus.config import key_line as locate
from murus.dem.case import build, load_case

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "dem"

BASE = BLOCK_ON_BASE.format(duration="0.05", dem="", kn="1e9",
                            extra='material = "stone"\n') + """\
[[monitors]]
name = "u"
body = 1
quantity = "ux"
relative = true
"""


def _err(r) -> str:
    return (r.stderr if r.stderr else r.output).strip()


@pytest.mark.parametrize("name", ["inclined_plane", "running_bond_wall", "tilting_table"])
def test_examples_parse_and_build(name):
    cfg, path, text = load_case(EXAMPLES / f"{name}.toml")
    built = build(cfg, path, text)
    m = built.model
    assert m.nbody >= 2
    assert built.run_kwargs["duration"] <= 3.0
    assert built.monitors


def test_wall_example_is_50_blocks_on_a_base():
    cfg, path, text = load_case(EXAMPLES / "running_bond_wall.toml")
    built = build(cfg, path, text)
    m = built.model
    assert m.nbody == 51
    assert int((m.bkin == 0).sum()) == 50
    assert int((m.bkin == 2).sum()) == 1
    assert built.height == pytest.approx(2.0)
    assert built.stop_desc == "d_top abs> 0.4"  # 0.2 H
    # "wall top": a block of the tenth course
    top = built.run_kwargs["probes"]["d_top"].spec[1]
    assert m.bpos[top, 1] == pytest.approx(1.9)


def test_inclined_plane_through_cli(tmp_path):
    out = tmp_path / "incl"
    r = CliRunner().invoke(app, ["run", str(EXAMPLES / "inclined_plane.toml"), "--out",
                                 str(out), "--no-figure"])
    assert r.exit_code == 0, _err(r)
    assert "1 s simulated" in r.output and "completed" in r.output
    d = np.genfromtxt(out / "histories.csv", delimiter=",", names=True)
    t, u = d["t_s"], d["u"]
    sel = t > 0.1
    a = 2.0 * np.polyfit(t[sel], u[sel], 2)[0]
    b, phi = math.radians(30.0), math.radians(25.0)
    exact = 9.81 * (math.sin(b) - math.cos(b) * math.tan(phi))
    assert exact == pytest.approx(0.9434, abs=1e-4)
    assert a == pytest.approx(exact, rel=0.01)
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "completed" and s["settle"]["converged"]
    assert not (out / "blocks.png").exists()


def _edit(text: str, old: str, new: str) -> str:
    assert old in text
    return text.replace(old, new, 1)


BAD = {
    "unknown material": (lambda s: _edit(s, 'material = "stone"', 'material = "granite"'),
                         "[blocks[1].material]", "unknown material 'granite'", 22),
    "overlap": (lambda s: _edit(s, "center = [0.0, 0.1]", "center = [0.0, 0.05]"),
                "[blocks[1]]", "blocks 0 ([[blocks]] 0) and 1", 17),
    "non-convex": (lambda s: _edit(
        s, 'kind = "rectangle"\nwidth = 0.4\nheight = 0.2\ncenter = [0.0, 0.1]',
        'kind = "polygon"\nvertices = [[0, 0], [0.4, 0], [0.4, 0.4], [0.3, 0.4], [0.3, 0.1],'
        ' [0, 0.1]]'), "[blocks[1].vertices]", "not convex", 19),
    "dt above stable": (lambda s: _edit(s, "duration = 0.05", "duration = 0.05\ndt = 0.01"),
                        "[dem.dt]", "exceeds the stable time step", 3),
    "unknown monitor": (lambda s: s + '[stop]\nmonitor = "v"\nvalue = 1.0\n',
                        "[stop.monitor]", "unknown monitor 'v'", 30),
    "unknown body": (lambda s: _edit(s, "body = 1", 'body = "roof"'),
                     "[monitors[0].body]", "unknown body 'roof'", 26),
    "damping frame": (lambda s: s + '[dem.damping]\nframe = "relative"\n',
                      "[dem.damping.frame]", "'base' or 'absolute'", 30),
    "unknown key": (lambda s: _edit(s, "width = 0.4", "widht = 0.4"),
                    "[blocks[1].widht]", "unknown key", 19),
}


@pytest.mark.parametrize("kind", list(BAD))
def test_bad_input_is_one_line_exit_2_and_no_output(tmp_path, kind):
    edit, key, words, line = BAD[kind]
    case = tmp_path / "bad.toml"
    case.write_text(edit(BASE))
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(case), "--out", str(out)])
    err = _err(r)
    assert r.exit_code == 2, err
    assert len(err.splitlines()) == 1, err
    assert err.startswith(f"error: bad.toml line {line}: {key}"), err
    assert words in err
    assert not out.exists()
    assert not list(tmp_path.glob(".out*"))


def test_clump_of_convex_parts_builds(tmp_path):
    text = _edit(BASE, 'kind = "rectangle"\nwidth = 0.4\nheight = 0.2\ncenter = [0.0, 0.1]',
                 'kind = "clump"\nparts = [{vertices = [[0, 0], [0.4, 0], [0.4, 0.1], '
                 '[0, 0.1]]}, {vertices = [[0.3, 0.1], [0.4, 0.1], [0.4, 0.4], [0.3, 0.4]]}]')
    case = tmp_path / "clump.toml"
    case.write_text(text)
    cfg, path, txt = load_case(case)
    m = build(cfg, path, txt).model
    assert m.nbody == 2 and len(m.world_polygons()) == 3


def test_locate_counts_array_tables():
    assert locate(BASE, ("blocks", 1, "center")) == 21
    assert locate(BASE, ("blocks", 0)) == 10
    assert locate(BASE, ("materials", "stone", "kn")) == 6
    assert locate(BASE, ("dem", "duration")) == 2


def test_two_materials_need_a_default_joint(tmp_path):
    text = BASE.replace("[[blocks]]", "[materials.steel]\nkn = 1e10\nks = 1e10\n\n[[blocks]]", 1)
    case = tmp_path / "two.toml"
    case.write_text(text)
    cfg, path, txt = load_case(case)
    with pytest.raises(CaseError, match=r"two.toml line 1: \[dem.joint\] several materials"):
        build(cfg, path, txt)


def test_wall_example_through_cli_stops_at_a_fifth_of_the_height(tmp_path):
    out = tmp_path / "wall"
    r = CliRunner().invoke(app, ["run", str(EXAMPLES / "running_bond_wall.toml"), "--out",
                                 str(out), "--progress"])
    assert r.exit_code == 0, _err(r)
    assert "stopped (d_top abs> 0.4)" in r.output
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "stopped" and s["bodies"] == 51
    assert abs(s["final"]["d_top"]) > 0.4 and s["t_end"] < 3.0
    assert (out / "blocks.png").stat().st_size > 0
    assert (out / "vtk" / "series.pvd").exists()
    assert len(list((out / "vtk").glob("frame_*.vtp"))) >= 10


def test_tilting_table_topples_near_atan_b_over_h(tmp_path):
    out = tmp_path / "tilt"
    r = CliRunner().invoke(app, ["run", str(EXAMPLES / "tilting_table.toml"), "--out",
                                 str(out), "--no-figure"])
    assert r.exit_code == 0, _err(r)
    d = np.genfromtxt(out / "histories.csv", delimiter=",", names=True)
    # onset of toppling: the rotation leaves zero (1e-4 rad) at atan(0.25) = 14.04 deg
    i = np.nonzero(np.abs(d["rot"]) > 1e-4)[0][0]
    assert d["tilt"][i] == pytest.approx(math.degrees(math.atan(0.25)), abs=0.5)


def test_rocking_cases_are_not_dem_cases():
    from murus.dem.case import is_dem_case

    demo = EXAMPLES.parent / "demo"
    assert not any(is_dem_case(p) for p in demo.glob("*.toml"))
    assert all(is_dem_case(p) for p in EXAMPLES.glob("*.toml"))
    assert not is_dem_case(EXAMPLES / "missing.toml")
