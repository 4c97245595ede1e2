"""Case files of blocks and zones together (issue 17, item 6): ``murus run`` on a ``[dem]``
case with ``[[zones]]`` and ``[[interfaces]]``, its outputs, and one-line errors (file, line,
key; exit 2; nothing written) for bad input.

Physics through the case layer, against a closed form: a backfill of elastic-plastic sand
(Mohr-Coulomb, friction 35 deg, nu = 0.3: K0 = nu / (1 - nu) = 0.43 above K_A = 0.27, so it
stays elastic) between a smooth wall of two stacked blocks and a smooth roller on the far side,
on a smooth base: in uniaxial strain the horizontal stress is K0 times the vertical one, so the
settled interface carries the at-rest thrust ``1/2 K0 gamma H^2``. The wall is not rigid: its
joints and the interface springs let it move by ``~F / (k L)`` (0.2-0.4 um here), which relieves
the backfill by about ``M u / L``; measured 0.5 % (0.7-1.3 % with springs ten times softer), hence
the tolerance of 1 %.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from murus.cli import app
from murus.continuum.coupled_case import build, is_coupled_case, load_case, run_case

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "continuum"
RHO, E, NU, H, G_ACC = 1600.0, 5e6, 0.3, 1.0, 9.81

BASE = f"""[dem]
duration = 0.02
gravity = {G_ACC}
settle_tolerance = 1e-6
settle_max_steps = 400000

[continuum]
initial_stress = "gravity"

[materials.stone]
density = 2500.0
kn = 1e11
ks = 1e11
friction_deg = 40.0

[materials.contact]
kn = 1e11
ks = 1e11
friction_deg = 0.0

[materials.sand]
model = "mohr-coulomb"
density = {RHO}
E = {E}
nu = {NU}
friction_deg = 35.0

[[blocks]]
kind = "rectangle"
width = 1.0
height = 0.2
center = [0.0, -0.1]
kinematic = "base"

[[walls]]
courses = 2
blocks_per_course = 1
block_width = 0.5
block_height = 0.5
stagger = 0.0
origin = [-0.5, 0.0]

[[zones]]
name = "fill"
material = "sand"
vertices = [[0.0, 0.0], [2.0, 0.0], [2.0, {H}], [0.0, {H}]]
nx = 8
ny = 8

[[boundaries]]
kind = "roller"
direction = "x"
side = "fill.right"

[[boundaries]]
kind = "roller"
direction = "y"
side = "fill.bottom"

[[interfaces]]
side = "fill.left"
material = "contact"

[[monitors]]
name = "u_crest"
body = 2
quantity = "ux"

[[monitors]]
name = "uy_soil"
gridpoint = [1.0, {H}]
quantity = "uy"

[output]
sample_dt = 0.01
"""


def _err(r) -> str:
    return (r.stderr if r.stderr_bytes is not None else r.output).strip()


@pytest.mark.parametrize("initial", ["gravity", "k0"])
def test_settled_backfill_carries_the_at_rest_thrust(tmp_path, initial):
    case = tmp_path / "fill.toml"
    case.write_text(BASE.replace('initial_stress = "gravity"', f'initial_stress = "{initial}"'))
    assert is_coupled_case(case)
    cfg, path, text = load_case(case)
    run = run_case(build(cfg, path, text))
    assert run.ok, run.summary()
    k0 = NU / (1.0 - NU)
    thrust = 0.5 * k0 * RHO * G_ACC * H * H
    iface = run.built.cm.iface
    assert iface.normal_force() == pytest.approx(thrust, rel=0.01)
    assert abs(iface.shear_force()) <= 1e-9 * thrust  # a smooth interface (friction 0)


def test_cli_writes_the_histories_of_blocks_and_zones_and_both_vtk_series(tmp_path):
    case = tmp_path / "fill.toml"
    case.write_text(BASE.replace("sample_dt = 0.01", "sample_dt = 0.01\nvtk_every = 1"))
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(case), "--out", str(out), "--no-progress"])
    assert r.exit_code == 0, _err(r)
    rows = list(csv.reader((out / "histories.csv").open()))
    assert rows[0][:3] == ["t_s", "u_crest", "uy_soil"]
    assert "energy.zones_strain" in rows[0] and "energy.interface_elastic" in rows[0]
    assert float(rows[-1][0]) == pytest.approx(0.02, abs=1e-3)
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "completed" and s["ok"] and s["zones"] == 64 and s["bodies"] == 3
    assert (out / "model.png").stat().st_size > 0
    assert (out / "vtk" / "series.pvd").exists() and (out / "vtk" / "zones.pvd").exists()
    assert len(list((out / "vtk").glob("zones_*.vtu"))) == 3  # start, 0.01 s, 0.02 s
    assert len(list((out / "vtk").glob("frame_*.vtp"))) == 3


BAD = {
    "interface names an unknown side": (('side = "fill.left"', 'side = "fill.west"'),
                                        "interfaces[0].side", "fill.west"),
    "zones overlap the blocks": (("[[0.0, 0.0], [2.0, 0.0]", "[[-0.1, 0.0], [2.0, 0.0]"),
                                 "zones[0]", "overlaps block"),
    "gravity given twice differently": (('initial_stress = "gravity"',
                                         'initial_stress = "gravity"\ngravity = 9.8'),
                                        "continuum.gravity", "differs"),
    "small-strain zones": (('initial_stress = "gravity"',
                            'initial_stress = "gravity"\nlarge_strain = false'),
                           "continuum.large_strain", "large-strain"),
    "duration in [continuum]": (('initial_stress = "gravity"',
                                 'initial_stress = "gravity"\nduration = 1.0'),
                                "continuum.duration", "[dem]"),
    "unknown interface material": (('material = "contact"', 'material = "glue"'),
                                   "interfaces[0].material", "joint material"),
    "motion without a base": (('kinematic = "base"',
                               'kinematic = "fixed"\n\n[motion]\ntype = "sine-pulse"\n'
                               'amplitude = 1.0\nfrequency = 5.0'),
                              "motion", "there is none"),
    "zone monitor with a block quantity": (('quantity = "uy"', 'quantity = "rot"'),
                                           "monitors[1].quantity", ""),
}


@pytest.mark.parametrize("kind", list(BAD))
def test_bad_input_is_one_line_exit_2_and_no_output(tmp_path, kind):
    (old, new), key, words = BAD[kind]
    assert old in BASE
    case = tmp_path / "bad.toml"
    case.write_text(BASE.replace(old, new, 1))
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


def test_wall_backfill_example_runs_briefly_and_closes_its_energy_balance(tmp_path):
    """The example, 0.3 s of it (the whole run takes seconds, most of it the 1.5 s of
    shaking): it settles, runs, and one energy balance of blocks, zones and interface closes
    within 1 % of the work of the base (a conservation law)."""
    import re

    import numpy as np

    text = re.sub(r"duration = [0-9.]+", "duration = 0.3",
                  (EXAMPLES / "wall_backfill.toml").read_text())
    case = tmp_path / "wall_backfill.toml"
    case.write_text(text)
    cfg, path, text = load_case(case)
    b = build(cfg, path, text)
    assert b.cm.zones.nz == 200 and b.cm.dem.nbody == 11
    assert b.monitors == ["d_crest", "rot_crest", "u_soil", "sxx_heel"]
    assert b.zones.ff_sides  # the far side is a free field
    run = run_case(b)
    assert run.ok, run.summary()
    v = run.result.values
    work = np.abs(v["energy.base_work"]) + np.abs(v["energy.zones_base_work"])
    assert work.max() > 0
    assert np.abs(v["energy.error"]).max() < 0.01 * work.max()


def test_stop_on_a_gridpoint_monitor(tmp_path):
    """[stop] may name a gridpoint's monitor: the run stops at the first sample where it
    holds (a stop is a result: status "stopped", ok)."""
    case = tmp_path / "fill.toml"
    case.write_text(BASE + '\n[stop]\nmonitor = "uy_soil"\nop = "<"\nvalue = 1.0\n')
    cfg, path, text = load_case(case)
    run = run_case(build(cfg, path, text))
    assert run.result.status == "stopped" and run.ok
    assert run.result.t[-1] == pytest.approx(0.01, abs=1e-3)
    assert "uy_soil < 1" in run.built.stop_desc


def test_ctrl_c_keeps_the_finished_work_and_exits_130(tmp_path, monkeypatch):
    """A Ctrl-C during the dynamic run (sent at the second sample) stops it between chunks:
    the outputs up to then are written (summary.json status "interrupted") and the command
    exits 130."""
    import os
    import signal

    import murus.continuum.coupled_case as CC

    real = CC.build

    def build_with_ctrl_c(*a, **kw):
        b = real(*a, **kw)
        count = [0]

        def ctrl_c(m):
            count[0] += 1
            if count[0] == 2:
                os.kill(os.getpid(), signal.SIGINT)
            return False

        b.run_kwargs["stop"] = ctrl_c
        return b

    monkeypatch.setattr(CC, "build", build_with_ctrl_c)
    case = tmp_path / "fill.toml"
    case.write_text(BASE.replace("duration = 0.02", "duration = 0.2"))
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(case), "--out", str(out), "--no-progress"])
    assert r.exit_code == 130, _err(r)
    s = json.loads((out / "summary.json").read_text())
    assert s["status"] == "interrupted" and not s["ok"]
    assert s["t_end"] < 0.2
    assert (out / "histories.csv").exists()


def test_a_motion_of_the_zones_base_alone_drives_them(tmp_path):
    """No block is the base: [motion] moves the zones' "base" gridpoints (through the blocks'
    model, which carries it). After one cycle of the sine pulse a sin(2 pi f t) the base has
    moved by a / (2 pi f^2) and stays there (a closed form)."""
    a, f = 2.0, 20.0
    text = (BASE.replace('kinematic = "base"', 'kinematic = "fixed"')
            .replace('kind = "roller"\ndirection = "y"\nside = "fill.bottom"',
                     'kind = "base"\nside = "fill.bottom"')
            .replace('[[monitors]]\nname = "u_crest"',
                     '[[monitors]]\nname = "u_base"\ngridpoint = [1.0, 0.0]\n'
                     'quantity = "ux"\n\n[[monitors]]\nname = "u_crest"'))
    text += f'\n[motion]\ntype = "sine-pulse"\namplitude = {a}\nfrequency = {f}\n'
    text = text.replace("duration = 0.02", "duration = 0.06")
    assert 'kind = "base"' in text and "u_base" in text
    case = tmp_path / "shaken.toml"
    case.write_text(text)
    cfg, path, text = load_case(case)
    run = run_case(build(cfg, path, text))
    assert run.ok, run.summary()
    u = run.result.values["u_base"]
    t = run.result.t
    want = a / (2.0 * 3.141592653589793 * f * f)
    assert u[t > 1.0 / f + 1e-3] == pytest.approx(want, rel=0.01)
