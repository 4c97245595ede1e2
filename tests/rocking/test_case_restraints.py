"""Case files with restraints, pivot and restitution laws (issue 4, item 8): every term by name,
and bad combinations refused with one line naming file, line and key, exit code 2, no output."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import pytest
from typer.testing import CliRunner

from murus.cli import app
from murus.rocking import simulate
from murus.rocking.case import build, load_case

runner = CliRunner()
EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "demo"

BASE = """
[body]
width = 0.3
height = 3.0
density = 2140.67
{extra}
[motion]
type = "free"
theta0_over_alpha = 0.5
[solver]
duration = 2.0
"""


def _run(tmp_path, extra):
    (tmp_path / "case.toml").write_text(BASE.format(extra=extra))
    return runner.invoke(app, ["run", str(tmp_path / "case.toml"), "--out",
                               str(tmp_path / "out"), "--no-figure"])


def test_example_cases_build_every_term():
    cfg, path, text = load_case(EXAMPLES / "restrained_block1_damped.toml")
    model, motion, kw = build(cfg, path, text)
    assert model.motion_sides == "one"
    assert model.tie.stiffness == pytest.approx(6.9227e4)
    # c = 1 % of c_d = 2 m g delta_t / h (EURODYN (2020), eq. 13)
    cd = 2 * model.body.mass * 9.81 * 10.0 / 3.0
    assert model.damper.coefficient == pytest.approx(0.01 * cd, rel=1e-12)
    assert model.transverse_walls.stiffness == 4.5e8
    cfg, path, text = load_case(EXAMPLES / "series_short_wall_modified.toml")
    model, motion, kw = build(cfg, path, text)
    assert model.pivot.law == "compressive-length"
    assert model.restitution.k0_free == 0.5
    r = simulate(model, motion, **kw)
    assert r.success and r.t_uplift is not None


def test_run_with_all_restraints_and_laws(tmp_path):
    extra = """
[restitution]
law = "amplitude-dependent"
k0 = 1.2
k1 = 0.6
variant = "iterated"
[pivot]
law = "compressive-length"
reading = "kern"
[restraint]
motion_sides = "one"
[restraint.tie]
stiffness = 7e4
height = 2.8
pretension = 200.0
yield_force = 5e3
[restraint.damper]
coefficient = 500.0
height = 3.0
[restraint.transverse_walls]
stiffness = 4.5e8
effective_height = 2.5
"""
    r = _run(tmp_path, extra)
    assert r.exit_code == 0, r.output
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    m = s["input"]["model"]
    assert m["tie"]["pretension"] == 200.0 and m["damper"]["coefficient"] == 500.0
    assert m["pivot"]["reading"] == "kern" and m["restitution"]["variant"] == "iterated"
    assert s["theta_max_over_alpha"] == pytest.approx(0.5, rel=1e-9)


@pytest.mark.parametrize(
    ("extra", "key", "message"),
    [
        ("[restraint]\nmotion_sides = \"one\"\n", "restraint",
         "one-sided wall needs transverse walls"),
        ("[restraint.tie]\nstiffness = 7e4\nheight = 3.5\n", "tie", "above the wall"),
        ("[restraint.damper]\ncoefficient = 1e3\nheight = 2.0\nx = 0.4\n", "damper",
         "outside the wall"),
        ("[restraint.transverse_walls]\nstiffness = 4.5e8\neffective_height = 3.0\n",
         "restraint", "motion_sides = 'one'"),
        ("[restraint.damper]\nfraction = 0.01\nheight = 3.0\n", "damper", "needs delta_t"),
        ("[restraint.tie]\nstiffness = -7e4\nheight = 3.0\n", "stiffness", "greater than 0"),
        ("[restitution]\nlaw = \"housner\"\nk0 = 1.0\n", "restitution", "takes no k0"),
        ("[restitution]\nlaw = \"amplitude-dependent\"\nvariant = \"later\"\n", "variant",
         "causal"),
        ("[pivot]\nlaw = \"zero-stress\"\n", "law", "corner"),
    ],
)
def test_bad_combinations_exit_2_with_one_line(tmp_path, extra, key, message):
    r = _run(tmp_path, extra)
    assert r.exit_code == 2, r.output
    err = r.stderr.strip() if r.stderr_bytes is not None else r.output.strip()
    assert len(err.splitlines()) == 1
    assert message in err and key in err
    assert "case.toml" in err and "line" in err
    assert not (tmp_path / "out").exists()


def test_demo_runs_the_new_cases(tmp_path):
    ex = tmp_path / "examples"
    shutil.copytree(EXAMPLES, ex / "demo")
    r = runner.invoke(app, ["demo", "--out", str(tmp_path / "demo"), "--examples", str(ex)])
    assert r.exit_code == 0, r.output
    rows = (tmp_path / "demo" / "demo_summary.csv").read_text().splitlines()
    names = {row.split(",")[0] for row in rows[1:]}
    assert {"restrained_block1_damped", "series_short_wall_modified"} <= names
    assert math.isfinite(float(rows[1].split(",")[1]))


def test_winkler_base_case(tmp_path):
    """[base] model = "winkler": the run goes to the elastic-layer model and its outputs carry
    the contact length; the first row is the static state on the lowered corner."""
    extra = """
[base]
model = "winkler"
modulus = 1.0e7
layer_thickness = 0.01
damping_ratio = 0.05
"""
    r = _run(tmp_path, extra)
    assert r.exit_code == 0, r.output
    import numpy as np

    ts = np.genfromtxt(tmp_path / "out" / "timeseries.csv", delimiter=",", names=True)
    from murus.rocking import RigidBlock, WinklerBase
    from murus.rocking.winkler import initial_settlement

    body = RigidBlock(0.3, 3.0, density=2140.67)
    v0 = initial_settlement(body, WinklerBase(1e9), theta=0.5 * body.alpha)
    assert ts["v_m"][0] == pytest.approx(v0, rel=1e-8)
    assert ts["contact_length_m"].min() < 0.3  # the free rocking from 0.5 alpha lifts the heel


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ("[base]\nmodel = \"winkler\"\nmodulus = 1e7\n", "layer_thickness"),
        ("[base]\nmodel = \"winkler\"\nstiffness = 1e9\n[restitution]\nlaw = \"housner\"\n",
         "does not apply to a Winkler base"),
        ("[base]\nstiffness = 1e9\n", "rigid base takes no stiffness"),
    ],
)
def test_bad_winkler_cases(tmp_path, extra, message):
    r = _run(tmp_path, extra)
    assert r.exit_code == 2, r.output
    err = r.stderr.strip()
    assert len(err.splitlines()) == 1 and message in err and "line" in err
    assert not (tmp_path / "out").exists()
