"""Continuum case files (issue 17, item 6): ``murus run`` on a ``[continuum]`` case, its
outputs, and one-line errors (file, line, key; exit 2; nothing written) for bad input.

Physics asserted through the case layer, against closed forms: an elastic column under its own
weight between smooth rigid walls (oedometric: sigma_v = -rho g depth, top settlement
rho g H^2 / (2 M), M = E (1 - nu) / ((1 + nu)(1 - 2 nu))), and the energy balance of the
shaken soil column of the examples (a conservation law).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from murus.cli import app
from murus.continuum.case import build, load_case

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "continuum"
RHO, E, NU, H, G_ACC = 2000.0, 1e8, 0.25, 10.0, 9.81

BASE = f"""[continuum]
gravity = {G_ACC}
initial_stress = "gravity"
settle_tolerance = 1e-7

[materials.soil]
model = "elastic"
density = {RHO}
E = {E}
nu = {NU}

[[zones]]
name = "soil"
material = "soil"
vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, {H}], [0.0, {H}]]
nx = 2
ny = 20

[[boundaries]]
kind = "roller"
direction = "x"
side = "soil.left"

[[boundaries]]
kind = "roller"
direction = "x"
line = [[1.0, 0.0], [1.0, {H}]]

[[boundaries]]
kind = "fixed"
side = "soil.bottom"

[[monitors]]
name = "uy_top"
gridpoint = [0.0, {H}]
quantity = "uy"

[[monitors]]
name = "syy_mid"
zone = [0.25, 5.1]
quantity = "syy"
"""


def _err(r) -> str:
    return (r.stderr if r.stderr else r.output).strip()


def _line(text: str, needle: str) -> int:
    return next(i for i, s in enumerate(text.splitlines(), 1) if needle in s)


def test_gravity_column_settles_to_the_oedometric_closed_form(tmp_path):
    case = tmp_path / "column.toml"
    case.write_text(BASE)
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(case), "--out", str(out), "--no-progress"])
    assert r.exit_code == 0, _err(r)
    s = json.loads((out / "summary.json").read_text())
    assert s["ok"] and s["settle"]["converged"]
    M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
    assert s["final"]["uy_top"] == pytest.approx(-RHO * G_ACC * H * H / (2 * M), rel=0.02)
    assert s["final"]["syy_mid"] == pytest.approx(-RHO * G_ACC * (H - 5.25), rel=0.01)
    assert (out / "zones.png").stat().st_size > 0


def test_soil_column_example_closes_its_energy_balance(tmp_path):
    from murus.continuum.case import run_case

    src = (EXAMPLES / "soil_column.toml").read_text()
    case = tmp_path / "col.toml"
    case.write_text(src.replace("duration = 4.0", "duration = 1.2").replace(
        "vtk_every = 40", "vtk_every = 0"))
    cfg, path, text = load_case(case)

    run = run_case(build(cfg, path, text))
    assert run.ok, run.result.message
    e = {k: np.asarray(v) for k, v in run.result.values.items() if k.startswith("energy.")}
    scale = np.abs(e["energy.base_work"]).max()
    assert scale > 0
    assert np.abs(e["energy.error"]).max() < 0.01 * scale
    # the monitor relative to the base is the top's displacement minus the base's
    assert np.isfinite(run.result.values["u_top"]).all()


def test_soil_column_example_runs_from_the_cli(tmp_path):
    case = tmp_path / "col.toml"
    text = (EXAMPLES / "soil_column.toml").read_text().replace("duration = 4.0",
                                                               "duration = 0.4")
    case.write_text(text.replace("vtk_every = 40", "vtk_every = 20"))
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(case), "--out", str(out), "--no-progress"])
    assert r.exit_code == 0, _err(r)
    rows = list(csv.reader((out / "histories.csv").open()))
    assert rows[0][:3] == ["t_s", "u_top", "sxy_base"]
    t = np.array([float(x[0]) for x in rows[1:]])
    assert t[-1] == pytest.approx(0.4, abs=0.01)
    assert (out / "vtk" / "zones.pvd").exists()
    assert len(list((out / "vtk").glob("zones_*.vtu"))) == 1 + 4  # start + every 0.1 s


BAD = {
    "self-intersecting region": (
        ("vertices = [[0.0, 0.0], [1.0, 0.0], [1.0, 10.0], [0.0, 10.0]]",
         "vertices = [[0.0, 0.0], [1.0, 10.0], [1.0, 0.0], [0.0, 10.0]]"),
        "zones[0].vertices", "intersect"),
    "zero-size mesh": (("nx = 2\nny = 20", "size = 0.0"), "zones[0].size", "greater than 0"),
    "nu at 0.5": ((f"nu = {NU}", "nu = 0.5"), "materials.soil.nu", "incompressible"),
    "dilation above friction": (
        ('model = "elastic"', 'model = "mohr-coulomb"\nfriction_deg = 30.0\ndilation_deg = 35.0'),
        "materials.soil.dilation_deg", "friction"),
    "boundary names no gridpoint": (
        (f"line = [[1.0, 0.0], [1.0, {H}]]", "line = [[5.0, 0.0], [5.0, 1.0]]"),
        "boundaries[1].line", "no gridpoint"),
    "unknown material": (('material = "soil"', 'material = "sand"'), "zones[0].material",
                         "unknown material"),
    "free field on a horizontal side": (('kind = "fixed"', 'kind = "free-field"'),
                                        "boundaries[2]", "must be vertical"),
    "frame on a fixed side": (('kind = "fixed"\n', 'kind = "fixed"\nframe = "base"\n'),
                              "boundaries[2]", "goes with kind = 'quiet'"),
    "unknown quiet frame": (('kind = "fixed"\n', 'kind = "quiet"\nframe = "sideways"\n'),
                            "boundaries[2].frame", "'rest' or 'base'"),
    "motion without a base": (("[[monitors]]", '[motion]\ntype = "sine-pulse"\namplitude = 1.0\n'
                                               'frequency = 2.0\n\n[[monitors]]'),
                              "motion", "kind 'base'"),
}


@pytest.mark.parametrize("kind", list(BAD))
def test_bad_input_is_one_line_exit_2_and_no_output(tmp_path, kind):
    (old, new), key, words = BAD[kind]
    assert old in BASE
    text = BASE.replace(old, new, 1)
    case = tmp_path / "bad.toml"
    case.write_text(text)
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(case), "--out", str(out)])
    err = _err(r)
    assert r.exit_code == 2, err
    assert len(err.splitlines()) == 1, err
    assert err.startswith("error: bad.toml line "), err
    assert f"[{key}" in err, err
    assert words in err, err
    assert not out.exists()
    assert not list(tmp_path.glob(".out*"))


@pytest.mark.parametrize("name", ["soil_column", "layer_free_field"])
def test_examples_run_briefly(tmp_path, name):
    import re

    from murus.continuum.case import run_case

    text = re.sub(r"duration = [0-9.]+", "duration = 0.2",
                  (EXAMPLES / f"{name}.toml").read_text())
    case = tmp_path / f"{name}.toml"
    case.write_text(text)
    cfg, path, text = load_case(case)
    run = run_case(build(cfg, path, text))
    assert run.ok, run.summary()
    assert run.result.t[-1] == pytest.approx(0.2, abs=0.01)


def test_a_quiet_side_takes_its_frame_from_the_case(tmp_path):
    """``frame = "base"`` on a quiet boundary sets the model's dashpot frame to the base;
    without it, rest (the classical quiet boundary)."""
    from murus.continuum import kernels as K

    for frame, want in (("", 0.0), ('frame = "base"\n', 1.0)):
        text = BASE.replace('kind = "roller"\ndirection = "x"\nside = "soil.left"\n',
                            f'kind = "quiet"\n{frame}side = "soil.left"\n', 1)
        case = tmp_path / "q.toml"
        case.write_text(text)
        model = build(*load_case(case)).model
        assert model.P[K.P_QFRAME] == want
        assert np.any(model.gdash != 0.0)
