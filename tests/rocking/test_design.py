"""Design equations of EURODYN (2020) (eq. 8-13) against closed forms, Table 1, and the `design`
CLI."""

import csv
import json
import math

import pytest
import typer
from typer.testing import CliRunner

from murus.rocking import RigidBlock, restrained_wall_block
from murus.rocking.design import (
    COMMERCIAL_DIAMETERS_MM,
    DesignError,
    bed_stiffness_equal,
    bed_stiffness_from_walls,
    design_report,
    reference_damping,
    resonance_frequencies,
    tie_design,
    tie_geometry,
)
from murus.rocking.design_cli import app as design_app

G = 9.81
BLOCKS = [f"block{i}" for i in range(1, 7)]


def _table1(data_dir):
    with open(data_dir / "rocking" / "eurodyn2020_table1.csv") as fh:
        return {r["label"]: r for r in csv.DictReader(ln for ln in fh if not ln.startswith("#"))}


# -- eq. 10, 11 ------------------------------------------------------------------------------
def test_eq10_seed_values():
    # EURODYN (2020), §4.3: E_x = 1.5e9, t = 0.3 m, L_eff = 1.0 m -> K' = 4.5e8 N/m/m (§4.2)
    assert bed_stiffness_from_walls(1.5e9, 0.3, 1.0) == pytest.approx(4.5e8, rel=1e-15)
    assert bed_stiffness_from_walls(2.0e9, 0.5, 2.0) == pytest.approx(5.0e8, rel=1e-15)


@pytest.mark.parametrize("blk", BLOCKS)
def test_eq11_printed_and_equal_frequencies(blk):
    b = restrained_wall_block(blk)
    K = 3.0e5
    geo = tie_geometry(b)
    kb = bed_stiffness_equal(b, K)
    assert kb == pytest.approx(K * 3 / 8 * geo.R_t**2 / (b.R**3 * math.cos(b.alpha)), rel=1e-12)
    # equating eq. 8 and eq. 9 gives 3 K R_t^2 / (8 R^3): the printed eq. 11 times cos(alpha)
    r = resonance_frequencies(b, K=K, K_bed=kb * math.cos(b.alpha))
    assert r.omega_minus == pytest.approx(r.omega_plus, rel=1e-12)
    # with the printed cos(alpha) eq. 9 is higher by a factor just above 1
    r2 = resonance_frequencies(b, K=K, K_bed=kb)
    assert r2.omega_minus > r2.omega_plus


# -- geometry --------------------------------------------------------------------------------
def test_tie_geometry_closed_forms():
    b = restrained_wall_block("block1")  # b = 0.3, h = 3.0
    g0 = tie_geometry(b)  # top, mid-thickness
    assert g0.height == 3.0 and g0.x == 0.0
    assert g0.R_t == pytest.approx(math.hypot(0.15, 3.0), rel=1e-15)
    assert g0.alpha_t == pytest.approx(math.atan(0.15 / 3.0), rel=1e-15)
    assert (g0.R_t_neg, g0.alpha_t_neg) == (g0.R_t, g0.alpha_t)
    assert g0.R_t * math.cos(g0.alpha_t) == pytest.approx(g0.lever, rel=1e-14)
    g1 = tie_geometry(b, 2.0, x=0.15)  # on the face above O
    assert g1.R_t == pytest.approx(2.0, rel=1e-15) and g1.alpha_t == 0.0
    assert g1.R_t_neg == pytest.approx(math.hypot(0.3, 2.0), rel=1e-15)
    assert g1.alpha_t_neg == pytest.approx(math.atan(0.3 / 2.0), rel=1e-15)
    g2 = tie_geometry(b, 1.0, x=-0.15)
    assert g2.R_t == pytest.approx(math.hypot(0.3, 1.0), rel=1e-15)
    assert g2.R_t_neg == pytest.approx(1.0, rel=1e-15)


@pytest.mark.parametrize(
    "height, x, word",
    [
        (4.0, 0.0, "tie height 4.0 m is above the wall (h = 3.0 m)"),
        (0.0, 0.0, "tie height must be positive"),
        (-1.0, 0.0, "tie height must be positive"),
        (float("nan"), 0.0, "tie height must be a finite number"),
        ("abc", 0.0, "tie height must be a number"),
        (2.0, 0.2, "tie x 0.2 m is outside the wall thickness"),
    ],
)
def test_tie_geometry_validation(height, x, word):
    with pytest.raises(DesignError, match=r"^" + word.replace("(", r"\(").replace(")", r"\)")):
        tie_geometry(restrained_wall_block("block1"), height, x)


# -- eq. 8, 9 --------------------------------------------------------------------------------
@pytest.mark.parametrize("blk", BLOCKS)
def test_eq8_eq9_and_linearised_identities(blk):
    b = restrained_wall_block(blk)
    m, R, I_O, zG = b.mass, b.R, b.I_O, b.z_G
    K, Kb, ht = 5.0e6, 2.0e6, 0.8 * b.height
    r = resonance_frequencies(b, K=K, tie_height=ht, K_bed=Kb)
    geo = tie_geometry(b, ht)
    assert r.p == pytest.approx(math.sqrt(m * G * R / I_O), rel=1e-14)
    assert r.p == pytest.approx(math.sqrt(3 * G / (4 * R)), rel=1e-12)  # uniform rectangle
    # eq. 8 = sqrt((K R_t^2 - m g R) / I_O), eq. 9 = sqrt((K' (2R)^3 / 3 - m g R) / I_O)
    assert r.omega_plus == pytest.approx(math.sqrt((K * geo.R_t**2 - m * G * R) / I_O), rel=1e-12)
    h2 = 2.0 * R
    assert r.omega_minus == pytest.approx(math.sqrt((Kb * h2**3 / 3 - m * G * R) / I_O), rel=1e-12)
    # linearised: K h_t^2 - m g z_G and K' h'^3/3 - m g z_G (h' = h by default)
    assert r.bed_height == b.height
    assert r.K_theta_plus == pytest.approx(K * ht**2 - m * G * zG, rel=1e-12)
    assert r.K_theta_minus == pytest.approx(Kb * b.height**3 / 3 - m * G * zG, rel=1e-12)
    assert r.omega_plus_lin == pytest.approx(math.sqrt(r.K_theta_plus / I_O), rel=1e-14)
    assert r.omega_minus_lin == pytest.approx(math.sqrt(r.K_theta_minus / I_O), rel=1e-14)
    assert zG == pytest.approx(R * math.cos(b.alpha), rel=1e-14)
    # a tie on the face above O (R_t = h_t): eq. 8 and the linearised value differ only by the
    # gravity term m g R versus m g R cos(alpha)
    r_face = resonance_frequencies(b, K=K, tie_height=ht, tie_x=0.5 * b.width)
    diff = (r_face.omega_plus_lin**2 - r_face.omega_plus**2) * I_O
    assert diff == pytest.approx(m * G * R * (1 - math.cos(b.alpha)), rel=1e-6)


def test_eq9_linearised_bed_height_two_R_would_match():
    # the linearised bed term with h' -> 2R reproduces eq. 9 except for the gravity term
    b = RigidBlock(width=0.3, height=3.0, density=2000.0)
    Kb = 1.0e6
    r = resonance_frequencies(b, K_bed=Kb, bed_height=b.height)
    lin_2R = (Kb * (2 * b.R) ** 3 / 3 - b.mass * G * b.R) / b.I_O
    assert r.omega_minus**2 == pytest.approx(lin_2R, rel=1e-12)
    assert r.omega_minus_lin**2 == pytest.approx(
        (Kb * 3.0**3 / 3 - b.mass * G * b.z_G) / b.I_O, rel=1e-12)


def test_weak_restraint_gives_nan():
    b = restrained_wall_block("block1")
    r = resonance_frequencies(b)  # free-standing: K = K' = 0
    assert math.isnan(r.omega_plus) and math.isnan(r.omega_minus)
    assert math.isnan(r.omega_plus_lin) and math.isnan(r.omega_minus_lin)
    assert not r.oscillates_plus and not r.oscillates_minus
    # threshold of eq. 8: K R_t^2 = m g R
    k_crit = b.mass * G * b.R / tie_geometry(b).R_t ** 2
    assert not resonance_frequencies(b, K=0.99 * k_crit).oscillates_plus
    assert resonance_frequencies(b, K=1.01 * k_crit).oscillates_plus
    d = r.as_dict()
    assert d["omega_plus"] is None and d["omega_minus_lin"] is None
    json.dumps(d, allow_nan=False)


@pytest.mark.parametrize(
    "kwargs, word",
    [
        ({"K": -1.0}, "K must be a non-negative"),
        ({"K_bed": float("inf")}, "K' (bed stiffness) must be a finite number"),
        ({"bed_height": 3.5}, "bed height 3.5 m is above the wall"),
        ({"tie_height": 4.0}, "tie height 4.0 m is above the wall"),
        ({"g": 0.0}, "g must be a positive"),
    ],
)
def test_resonance_validation(kwargs, word):
    with pytest.raises(DesignError) as exc:
        resonance_frequencies(restrained_wall_block("block1"), **kwargs)
    assert str(exc.value).startswith(word) and "\n" not in str(exc.value)


# -- eq. 12 ----------------------------------------------------------------------------------
@pytest.mark.parametrize("blk", BLOCKS)
@pytest.mark.parametrize("frac", [1.0, 0.75, 0.5])
def test_eq12_round_trip(blk, frac):
    b = restrained_wall_block(blk)
    ht = frac * b.height
    td = tie_design(b, ht)
    W, s, h = b.mass * G, b.width, b.height
    assert td.W == pytest.approx(W, rel=1e-15)
    assert td.T_d * ht + W * s / 2 == pytest.approx(0.2 * W * h / 2, rel=1e-12)
    assert td.sigma_d == pytest.approx(0.7 * 430e6 / 1.05, rel=1e-15)
    assert td.T_d == pytest.approx(td.sigma_d * math.pi * td.phi_d**2 / 4, rel=1e-12)
    assert td.area == pytest.approx(math.pi * td.phi_d**2 / 4, rel=1e-15)
    assert td.K_d == pytest.approx(210e9 * td.area / 10.0, rel=1e-15)
    assert td.needed and not td.commercial


def test_block1_numbers_against_table1(data_dir):
    row = _table1(data_dir)["block1"]
    m_tab = float(row["m_kg"])  # 1926 kg as printed (21 kN/m3 x 0.9 m3 / 9.81 = 1926.6)
    b = restrained_wall_block("block1")
    assert b.mass == pytest.approx(m_tab, abs=1.0)
    # eq. 12 with s = 0.3, h = 3.0, h_t = h, mu = 0.2: T_d = W (0.3 - 0.15) / 3 = W / 20
    td = tie_design(b)
    assert td.T_d == pytest.approx(m_tab * G / 20, rel=5e-4)
    assert td.T_d == pytest.approx(945.0, rel=1e-12)  # W = 21 kN/m3 x 0.9 m3 = 18.9 kN
    assert td.phi_d * 1000 == pytest.approx(2.04872, abs=1e-5)
    assert td.K_d == pytest.approx(69226.74, rel=1e-6)
    # omega_r+ of eq. 8 with K = K_d at the top, mid-thickness
    r = resonance_frequencies(b, K=td.K_d)
    R_t2 = 3.0**2 + 0.15**2
    expect = math.sqrt(3 * G / (4 * b.R)) * math.sqrt(td.K_d * R_t2 / (m_tab * G * b.R) - 1)
    assert r.omega_plus == pytest.approx(expect, rel=1e-3)  # table mass rounded to 1 kg
    assert r.omega_plus == pytest.approx(10.10519, abs=1e-5)
    # eq. 13 with delta_t = 0.1 s: c_d = 2 m g 0.1 / 3
    assert reference_damping(b, 0.1) == pytest.approx(2 * m_tab * G * 0.1 / 3.0, rel=5e-4)
    assert reference_damping(b, 0.1) == pytest.approx(1260.0, rel=1e-12)


def test_commercial_diameter():
    b = restrained_wall_block("block1")
    td = tie_design(b, round_to_commercial=True)
    assert td.phi_d == 0.008 and td.commercial
    assert td.phi_required == pytest.approx(tie_design(b).phi_d, rel=1e-15)
    assert td.K_d == pytest.approx(210e9 * math.pi * 0.008**2 / 4 / 10, rel=1e-14)
    # a required diameter between two sizes rounds up to the next one
    b6 = restrained_wall_block("block6")
    td6 = tie_design(b6, mu=0.5, round_to_commercial=True)
    mm = td6.phi_required * 1000
    assert td6.phi_d * 1000 == pytest.approx(min(d for d in COMMERCIAL_DIAMETERS_MM if d >= mm))
    with pytest.raises(DesignError, match="exceeds the largest commercial size 36 mm"):
        tie_design(b6, mu=5.0, round_to_commercial=True)


def test_stable_wall_needs_no_tie_and_top_mass_uses_z_G():
    squat = RigidBlock(width=1.0, height=3.0, density=2000.0)  # tan(alpha) = 1/3 > mu = 0.2
    td = tie_design(squat)
    assert not td.needed and td.T_d < 0 and td.K_d == 0.0 and td.phi_d == 0.0
    assert "stable without a tie" in td.message
    # seismic force at the centre of gravity: with a top mass the lever is z_G, not h/2
    w = RigidBlock(width=0.3, height=3.0, density=2000.0, top_mass=1000.0)
    td = tie_design(w, 2.5)
    W = w.mass * G
    assert td.T_d * 2.5 + W * 0.15 == pytest.approx(0.2 * W * w.z_G, rel=1e-12)


@pytest.mark.parametrize(
    "kwargs, word",
    [
        ({"tie_height": 3.5}, "tie height 3.5 m is above the wall (h = 3.0 m)"),
        ({"mu": 0.0}, "mu must be a positive"),
        ({"f_uk": -1.0}, "f_uk must be a positive"),
        ({"length": float("nan")}, "tie length must be a finite number"),
        ({"E": 0.0}, "E must be a positive"),
    ],
)
def test_tie_design_validation(kwargs, word):
    with pytest.raises(DesignError) as exc:
        tie_design(restrained_wall_block("block1"), **kwargs)
    assert str(exc.value).startswith(word)


# -- eq. 13 ----------------------------------------------------------------------------------
@pytest.mark.parametrize("blk", BLOCKS)
def test_eq13_reference_damping(blk):
    b = restrained_wall_block(blk)
    for dt in (0.05, 0.1, 0.5):
        c_d = reference_damping(b, dt)
        assert c_d == pytest.approx(2 * b.mass * G * dt / b.height, rel=1e-12)
        # F_0 / v with F_0 = (s/h) W (static multiplier) and v = (s/2) / delta_t
        assert c_d == pytest.approx((b.width / b.height) * b.mass * G / (b.width / 2 / dt),
                                    rel=1e-12)
    for bad in (0.0, -0.1, float("nan"), None):
        with pytest.raises(DesignError, match="delta_t must be"):
            reference_damping(b, bad)


# -- report ----------------------------------------------------------------------------------
def test_design_report_defaults_and_sources():
    b = restrained_wall_block("block2")
    rep = design_report(b, delta_t=0.1, fractions=(0.01, 0.05))
    td = tie_design(b)
    assert rep["stiffness"]["K"] == pytest.approx(td.K_d, rel=1e-15)
    assert rep["stiffness"]["K_bed"] == pytest.approx(bed_stiffness_equal(b, td.K_d), rel=1e-15)
    assert rep["stiffness"]["K_bed_source"] == "eq. 11"
    assert rep["damping"]["c"][1]["c"] == pytest.approx(0.05 * rep["damping"]["c_d"], rel=1e-15)
    json.dumps(rep, allow_nan=False)
    rep2 = design_report(b, K_over_Kd=0.5, walls=(1.5e9, 0.3, 1.0))
    assert rep2["stiffness"]["K"] == pytest.approx(0.5 * td.K_d, rel=1e-15)
    assert rep2["stiffness"]["K_bed"] == pytest.approx(4.5e8, rel=1e-15)
    assert rep2["damping"] is None
    with pytest.raises(DesignError, match="either K or K_over_Kd"):
        design_report(b, K=1.0, K_over_Kd=1.0)


# -- CLI -------------------------------------------------------------------------------------
runner = CliRunner()


def _cli(*args):
    parent = typer.Typer()
    parent.add_typer(design_app, name="design")
    return runner.invoke(parent, ["design", *args])


def _err(r):
    return (r.stderr if r.stderr else r.output).strip()


def test_cli_tie_table_and_json():
    r = _cli("tie", "--block", "block1")
    assert r.exit_code == 0, r.output
    assert "945" in r.output and "2.04872" in r.output and "69226.7" in r.output
    assert "eq. 12" in r.output
    r = _cli("tie", "--width", "0.3", "--height", "3.0", "--commercial", "--json")
    assert r.exit_code == 0, r.output
    d = json.loads(r.output)
    assert d["tie"]["T_d"] == pytest.approx(945.0, rel=1e-12)
    assert d["tie"]["phi_d"] == 0.008


def test_cli_damper():
    r = _cli("damper", "--block", "block1", "--delta-t", "0.1", "--fraction", "0.01,0.05",
             "--fraction", "0.1")
    assert r.exit_code == 0, r.output
    assert "1260" in r.output and "12.6" in r.output and "63" in r.output and "126 " in r.output
    r = _cli("damper", "--block", "block1", "--delta-t", "0.1", "--json")
    assert json.loads(r.output)["c_d"] == pytest.approx(1260.0, rel=1e-12)


def test_cli_resonance():
    r = _cli("resonance", "--block", "block1")
    assert r.exit_code == 0, r.output
    assert "10.1052" in r.output and "eq. 8" in r.output and "eq. 11" in r.output
    r = _cli("resonance", "--block", "block1", "--K", "0", "--walls", "1.5e9,0.3,1.0", "--json")
    assert r.exit_code == 0, r.output
    d = json.loads(r.output)
    assert d["resonance"]["omega_plus"] is None  # no tie: no oscillation about O
    assert d["stiffness"]["K_bed"] == pytest.approx(4.5e8, rel=1e-15)
    b = restrained_wall_block("block1")
    ref = resonance_frequencies(b, K=0.0, K_bed=4.5e8)
    assert d["resonance"]["omega_minus"] == pytest.approx(ref.omega_minus, rel=1e-15)
    r = _cli("resonance", "--block", "block1", "--K-over-Kd", "0.5", "--bed-stiffness", "1e5",
             "--json")
    d = json.loads(r.output)
    assert d["stiffness"]["K"] == pytest.approx(0.5 * d["K_d"], rel=1e-15)
    r = _cli("resonance", "--block", "block1", "--K", "0")
    assert r.exit_code == 0 and "none" in r.output and "no oscillation" in r.output


@pytest.mark.parametrize(
    "args, word",
    [
        (["tie", "--block", "block1", "--tie-height", "4"], "above the wall (h = 3.0 m)"),
        (["resonance", "--block", "block1", "--K", "-1"], "K must be a non-negative"),
        (["tie", "--block", "block9"], "unknown EURODYN (2020) block 'block9'"),
        (["damper", "--block", "block1", "--delta-t", "0"], "--delta-t must be"),
        (["tie", "--width", "0.3"], "--width and --height"),
        (["tie", "--width", "-0.3", "--height", "3"], "width must be a positive"),
        (["tie", "--block", "block1", "--width", "0.3"], "not both"),
        (["resonance", "--block", "block1", "--K", "1", "--K-over-Kd", "1"], "not both"),
        (["resonance", "--block", "block1", "--walls", "1,2"], "--walls must be three"),
        (["damper", "--block", "block1", "--delta-t", "0.1", "--fraction", "x"], "--fraction"),
    ],
)
def test_cli_bad_input_exit_2_one_line(args, word):
    r = _cli(*args)
    assert r.exit_code == 2
    err = _err(r)
    assert len(err.splitlines()) == 1, err
    assert err.startswith("error: ") and word in err, err
