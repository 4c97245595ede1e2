"""Rigid-block limit analysis (murus.limit): every verification row with its tolerance, the
associative / non-associative difference, bad models, the command line and its outputs."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from murus.cli import app
from murus.limit import Assembly, LimitModelError, analyse, find_interfaces, from_case
from murus.limit import verify as V

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

BASE = """[dem]
duration = 1.0

[materials.stone]
density = 2000.0
kn = 1e9
ks = 1e9
friction_deg = 40.0

[[blocks]]
kind = "rectangle"
width = 2.0
height = 0.2
center = [0.0, -0.1]
kinematic = "fixed"

[[blocks]]
kind = "rectangle"
width = 0.25
height = 1.0
center = [0.0, 0.5]
"""


def _err(r) -> str:
    return (r.stderr if r.stderr else r.output).strip()


# ---------------------------------------------------------------------- verification rows
@pytest.mark.parametrize("name", [n for n in V.CASES if n != "arch"])
def test_verification_rows(name):
    rows = V.CASES[name](quick=True)
    assert rows
    for r in rows:
        assert r["passed"], r
        assert r["error"] <= r["tolerance"], r


def test_arch_minimum_thickness_rows():
    rows = V.case_arch(quick=True)
    for r in rows:
        assert r["passed"], r
    t40 = rows[0]["obtained"]
    # a discrete arch needs at most the continuous thickness (hinges only at joints)
    assert t40 <= V.T_MILANKOVITCH + 1e-4
    assert abs(t40 - V.T_MILANKOVITCH) / V.T_MILANKOVITCH <= 0.005


def test_block_topples_at_b_over_h_exactly_and_mechanism():
    r = analyse(V.block_on_base(0.25, 1.0))
    assert r.load_factor == pytest.approx(0.25, abs=1e-6)
    u, v, om = r.mechanism[1]
    # rotation about the right corner (0.125, 0): the centroid (0, 0.5) moves right and up
    assert u == pytest.approx(1.0) and om < 0
    assert v == pytest.approx(-om * 0.125, rel=1e-6)
    # all the weight on the right corner, shear = lambda W
    W = r.assembly.mass[1] * r.assembly.gravity
    assert r.normal[0] == pytest.approx(W, rel=1e-9)
    assert abs(r.shear[0]) == pytest.approx(0.25 * W, rel=1e-9)
    assert abs(r.eccentricity[0]) == pytest.approx(0.125, rel=1e-9)


def test_sliding_mechanism_does_not_dilate_unless_associative():
    asm = V.block_on_base(1.0, 0.5, friction_deg=10.0)
    na = analyse(asm)
    ass = analyse(asm, friction="associative")
    assert na.mechanism[1, 1] == pytest.approx(0.0, abs=1e-9)
    assert ass.mechanism[1, 1] == pytest.approx(math.tan(math.radians(10.0)), rel=1e-6)


def test_associative_exceeds_non_associative_on_a_confined_wall():
    f = EXAMPLES / "limit" / "wall_panel.toml"
    na = analyse(f)
    ass = analyse(f, friction="associative")
    assert na.converged
    assert ass.load_factor >= na.load_factor
    assert ass.load_factor > na.load_factor * 1.03  # 0.4857 vs 0.4577
    assert na.load_factor == pytest.approx(0.457, rel=0.01)  # path-dependent within 0.5 %
    # the forces returned obey Coulomb with their own normal forces but for 1.2e-4 of the
    # largest block weight (the iterates exceed it by 0.035: chosen among the LP's optima)
    assert na.coulomb_residual <= 1e-3
    assert ass.coulomb_residual <= 1e-7
    assert np.all(na.n1 >= -1e-6) and np.all(na.n2 >= -1e-6)


def test_tilt_with_cohesion_solves_lambda_equals_sin():
    asm = Assembly.from_polygons([V._rect(-1, -0.2, 2, 0.2), V._rect(0, 0, 1.0, 0.5)],
                                 supports=[0], friction_deg=20.0, cohesion=500.0)
    r = analyse(asm, load="tilt")
    th = math.radians(r.angle_deg)
    W = r.assembly.mass[1] * r.assembly.gravity
    # sliding: W sin = W cos tan(phi) + c A
    assert W * math.sin(th) == pytest.approx(W * math.cos(th) * math.tan(math.radians(20.0))
                                             + 500.0 * 1.0, rel=1e-6)


def test_examples_are_dem_cases_and_match_the_closed_forms():
    from murus.dem.case import build, load_case

    for name in ("arch", "wall_panel", "ftl_wall3_window"):
        cfg, path, text = load_case(EXAMPLES / "limit" / f"{name}.toml")
        build(cfg, path, text)
    asm = from_case(EXAMPLES / "limit" / "arch.toml")
    assert asm.nblock == 21
    assert len(find_interfaces(asm)) == 21
    r = analyse(EXAMPLES / "limit" / "arch.toml")
    assert 0.05 < r.load_factor < 0.3


def test_opening_rows_are_closed_forms_that_depend_on_the_loads():
    rows = V.case_opening()
    assert len(rows) == 10
    for r in rows:
        assert r["passed"], r
    # an overburden on the lintel raises the factor above b/h, a live point load lowers it
    bh = 0.4 / 1.5
    assert rows[0]["expected"] > bh and rows[-1]["expected"] < bh
    W_p, W_l = 2.0, 1.0
    assert V.portal_sway(0.4, 1.5, W_p, W_l) == pytest.approx(bh, rel=1e-15)
    assert V.portal_sway(0.4, 1.5, W_p, W_l, Q=W_l) == pytest.approx(bh * 3.0 / 2.0, rel=1e-15)
    assert V.portal_sway(0.4, 1.5, W_p, W_l, P=W_l) == pytest.approx(bh * 2.0 / 3.0, rel=1e-15)


def test_window_wall_example_is_the_rebuilt_pattern():
    """examples/limit/ftl_wall3_window.toml is :func:`coursed_wall` of FTL_WALL3_PATTERN (the
    HybriDFEM rebuild of the Ferris and Tin-Loi window wall; no published value is asserted:
    tests/data/limit/README.md)."""
    asm = from_case(EXAMPLES / "limit" / "ftl_wall3_window.toml")
    ref = V.coursed_wall(V.FTL_WALL3_PATTERN, 4)
    assert asm.nblock == ref.nblock == 47
    for a, b in zip(asm.polygons, ref.polygons, strict=True):
        assert np.allclose(np.sort(a, axis=0), np.sort(b, axis=0), atol=1e-9)
    assert len(find_interfaces(asm)) == len(find_interfaces(ref))
    # the window: no block overlaps x = 0.6 .. 1.0 m in courses 4 to 8
    for v in ref.polygons[1:]:
        y = v[:, 1].mean()
        if 3 * 0.175 < y < 8 * 0.175:
            assert v[:, 0].max() <= 0.6 + 1e-9 or v[:, 0].min() >= 1.0 - 1e-9
    na = analyse(ref)
    ass = analyse(ref, friction="associative")
    assert na.converged
    assert ass.load_factor > na.load_factor
    # the iterates exceed Coulomb by 0.37 of a block weight here; the forces returned do not
    # (2e-7 measured: chosen among the optima of the last LP)
    assert na.coulomb_residual <= 1e-3


def test_running_bond_wall_from_walls_table():
    asm = from_case(EXAMPLES / "dem" / "running_bond_wall.toml")
    itf = find_interfaces(asm)
    # 5 blocks per course, 10 courses: 4 head joints per course, 5 + 9 x 9 bed stretches
    assert asm.nblock == 51
    assert len(itf) == 10 * 4 + 5 + 9 * 9


# ---------------------------------------------------------------------- bad models
def test_floating_block_is_named():
    asm = Assembly.from_polygons([V._rect(-1, -0.2, 2, 0.2), V._rect(0, 0, 0.5, 0.5),
                                  V._rect(3, 3, 0.5, 0.5)], supports=[0])
    with pytest.raises(LimitModelError, match="block 2: the block has no path"):
        analyse(asm)


def test_overlap_and_no_interface_and_no_support():
    asm = Assembly.from_polygons([V._rect(-1, -0.2, 2, 0.2), V._rect(0, -0.1, 0.5, 0.5)],
                                 supports=[0])
    with pytest.raises(LimitModelError, match="block 1: overlaps block 0"):
        analyse(asm)
    asm = Assembly.from_polygons([V._rect(-1, -0.2, 2, 0.2), V._rect(0, 0.1, 0.5, 0.5)],
                                 supports=[0])
    with pytest.raises(LimitModelError, match="no interface"):
        analyse(asm)
    asm = Assembly.from_polygons([V._rect(-1, -0.2, 2, 0.2), V._rect(0, 0, 0.5, 0.5)])
    with pytest.raises(LimitModelError, match="no support"):
        analyse(asm)


def test_unbounded_and_infeasible_lp_name_the_block():
    # a block locked in a slot between supports: no mechanism, the load factor is unbounded
    polys = [V._rect(-1, -0.2, 3, 0.2), V._rect(-1, 0, 1, 0.5), V._rect(0.5, 0, 1, 0.5),
             V._rect(0, 0, 0.5, 0.5), V._rect(-1, 0.5, 3, 0.2)]
    asm = Assembly.from_polygons(polys, supports=[0, 1, 2, 4], friction_deg=30.0)
    with pytest.raises(LimitModelError, match="^block 3: the load factor is unbounded"):
        analyse(asm)
    # a block held only by a frictionless vertical face: no equilibrium for any load factor
    asm = Assembly.from_polygons([V._rect(-1, -0.2, 1, 2), V._rect(0, 0.5, 0.3, 0.3)],
                                 supports=[0], friction_deg=0.0)
    with pytest.raises(LimitModelError, match="^block 1: no equilibrium for any load factor"):
        analyse(asm)


BAD = {
    "floating": (BASE + '\n[[blocks]]\nkind = "rectangle"\nwidth = 0.2\nheight = 0.2\n'
                 'center = [3.0, 3.0]\n', "blocks[2]", "no path of interfaces"),
    "overlap": (BASE.replace("center = [0.0, 0.5]", "center = [0.0, 0.45]"), "blocks[1]",
                "overlaps"),
    "disc": (BASE + '\n[[blocks]]\nkind = "disc"\nradius = 0.1\ncenter = [0.5, 0.1]\n',
             "blocks[2]", "polygon blocks"),
    "load": (BASE, None, "--load must be"),
}


@pytest.mark.parametrize("kind", list(BAD))
def test_cli_bad_input_is_one_line_exit_2(tmp_path, kind):
    text, key, words = BAD[kind]
    case = tmp_path / "bad.toml"
    case.write_text(text)
    out = tmp_path / "out"
    args = ["limit", str(case), "--out", str(out)]
    if kind == "load":
        args += ["--load", "vertical"]
    r = CliRunner().invoke(app, args)
    err = _err(r)
    assert r.exit_code == 2, err
    assert len(err.splitlines()) == 1, err
    assert err.startswith("error: "), err
    if key:
        assert "bad.toml line" in err and key in err, err
    assert words in err, err
    assert not out.exists()


# ---------------------------------------------------------------------- command line
def test_cli_json_and_outputs(tmp_path):
    case = tmp_path / "block.toml"
    case.write_text(BASE)
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["limit", str(case), "--json", "--out", str(out)])
    assert r.exit_code == 0, _err(r)
    s = json.loads(r.stdout)
    assert s["load_factor"] == pytest.approx(0.25, abs=1e-6)
    assert s["mechanism"][0]["block"] == 1
    assert set(s["mechanism"][0]) >= {"u", "v", "omega"}
    for name in ("summary.json", "joints.csv", "mechanism.png"):
        assert (out / name).is_file()
    head = (out / "joints.csv").read_text().splitlines()[0]
    assert "N_N" in head and "eccentricity_m" in head
    r = CliRunner().invoke(app, ["limit", str(case), "--load", "tilt", "--direction", "-1"])
    assert r.exit_code == 0, _err(r)
    assert "14.0362 deg" in r.stdout


def test_cli_verify_limit_one_case():
    r = CliRunner().invoke(app, ["verify", "limit", "--case", "leaning"])
    assert r.exit_code == 0, _err(r)
    assert "pass" in r.stdout
