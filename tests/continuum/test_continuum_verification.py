"""Verification of the continuum (zones) engine against closed forms and the energy balance
(issue 17 item 7). The cases live in murus.continuum.verify, shared with
``murus verify continuum``; each row states its tolerance, and these tests run the quick
variants (coarser meshes, same tolerances)."""

import math

import pytest

from murus.continuum import verify as V

KEYS = {"case", "expected", "obtained", "error", "tolerance", "passed"}


def _check(rows, n_available):
    """Every available row passes its tolerance; the rest are flagged as not yet available."""
    ok = [r for r in rows if r["passed"] is not None]
    assert len(ok) == n_available
    for r in rows:
        assert set(r) - {"available"} == KEYS
        if r["passed"] is None:
            assert r.get("available") is False and "not yet available" in r["case"]
            assert math.isnan(r["obtained"])
    bad = [r for r in ok if not r["passed"]]
    assert not bad, "\n".join(
        f"{r['case']}: expected {r['expected']:.6g}, obtained {r['obtained']:.6g}, "
        f"error {r['error']:.3g} > {r['tolerance']:g}" for r in bad)
    for r in ok:
        assert r["error"] <= r["tolerance"]


def test_shear_column_frequency_and_amplification():
    """f1 = Vs / 4H (1 %); steady amplification at f1 with 5 % mass-proportional damping
    against layer_transfer_rayleigh (5 %)."""
    _check(V.case_shear_column(quick=True), 2)


def test_quiet_base_absorbs_p_and_s_pulses():
    """Reflected energy of a P and an S pulse at normal incidence below 3 %."""
    _check(V.case_quiet_base(quick=True), 2)


def test_quiet_base_check_fails_without_the_dashpots(monkeypatch):
    """Control: with no dashpots the base is fixed and reflects the whole pulse."""
    monkeypatch.setattr(V.ContinuumModel, "add_quiet", lambda self, edges: None)
    assert V._pulse_energy_reflected("P", quick=True) > 0.95


def test_hole_in_mohr_coulomb_salencon():
    """Plastic radius 1.735 a (3 %), radial and tangential stresses to 5 a (3 % of P0)."""
    _check(V.case_hole(quick=True), 3)


def test_prandtl_strip_footing():
    """(2 + pi) c (5 %) and, with phi = 30 deg, N_c = 30.14 (10 %)."""
    _check(V.case_prandtl(quick=True), 2)


def test_rankine_thrust_on_a_smooth_wall_moving_away():
    """1/2 K_A gamma H² (5 %); a rough wall (a block through the interface) to Coulomb's
    P_A cos(delta) and, with tilted gravity, to Mononobe-Okabe's (10 %)."""
    _check(V.case_rankine(quick=True), 3)


def test_wall_thrust_control_a_smooth_interface_gives_rankine_not_coulomb():
    """Control of the rough-wall row: with a smooth interface the same model gives Rankine's
    thrust (5 %), which is 19 % above Coulomb's with delta = 20 deg, beyond the row's 10 %."""
    got, hist, cm = V.wall_thrust(0.0, 0.0, quick=True)
    want = V.cf.rankine_thrust(18e3, 4.0, math.radians(30.0))
    assert got == pytest.approx(want, rel=0.05)
    coulomb = V.cf.active_thrust(18e3, 4.0, math.radians(30.0), math.radians(20.0))
    assert got / (coulomb * math.cos(math.radians(20.0))) - 1.0 > 0.10
    assert hist[0] > got  # the thrust at rest is above the active one


def test_oedometric_settlement():
    """s t / M (2 %); a rigid block on the layer through the interface (2 %)."""
    _check(V.case_oedometer(quick=True), 2)


def test_energy_balance_of_a_shaken_plastic_soil():
    """The balance of ContinuumModel.energy closes within 1 % of its largest term, with the
    plastic work a large share of the energy; blocks, zones and interface together within
    1 % of the input work."""
    rows = V.case_energy(quick=True)
    _check(rows, 2)


def test_coupled_energy_balance_exercises_plasticity_and_slip():
    """The coupled balance closes (1 %) on a run where both dissipations matter: the plastic
    work and the interface slip are each more than 1 % of the input work, so that a missing
    term would show above the tolerance."""
    ratio, info, cm = V.coupled_energy(quick=True)
    assert ratio <= 0.01
    assert info["plastic_zones"] > 0
    assert info["plastic"] > 0.01 * info["input_work"]
    assert info["slip"] > 0.01 * info["input_work"]


def test_free_field_sides_follow_the_column():
    """Side and centre within 2 % of the 1D column; the column's amplitude the damped layer's
    (5 %)."""
    _check(V.case_free_field(quick=True), 3)
    assert set(V.CASES) >= {"shear_column", "quiet_base", "free_field", "hole", "prandtl",
                            "rankine", "oedometer", "energy"}


def test_verify_continuum_cli_prints_the_table_and_exits_1_on_a_failure(monkeypatch):
    from typer.testing import CliRunner

    from murus.cli import app

    r = CliRunner().invoke(app, ["verify", "continuum", "--quick", "-c", "oedometer"],
                           env={"COLUMNS": "200"})
    assert r.exit_code == 0, r.output
    assert "s t / M [m]" in r.output and "pass" in r.output
    assert "murus" in r.output and "tolerance" in r.output
    monkeypatch.setitem(V.CASES, "later", lambda quick: [V._not_available("later", 0.05, "x")])
    r = CliRunner().invoke(app, ["verify", "continuum", "-c", "later"], env={"COLUMNS": "200"})
    assert r.exit_code == 0 and "n/a" in r.output
    monkeypatch.setitem(V.CASES, "broken", lambda quick: [V._row("broken", 1.0, 1.1, 0.05)])
    r = CliRunner().invoke(app, ["verify", "continuum", "-c", "broken"], env={"COLUMNS": "200"})
    assert r.exit_code == 1
    assert "FAIL" in r.output
    r = CliRunner().invoke(app, ["verify", "continuum", "--case", "nope"])
    assert r.exit_code == 2
    assert "unknown case" in r.output


@pytest.mark.parametrize("name", ["oedometer"])
def test_rows_are_plain_numbers(name):
    for r in V.CASES[name](quick=True):
        for k in ("expected", "obtained", "error", "tolerance"):
            assert isinstance(r[k], float)


def test_public_functions_have_numpydoc_sections():
    import inspect
    import re

    for name in V.__all__:
        obj = getattr(V, name)
        if not inspect.isfunction(obj):
            continue
        doc = inspect.getdoc(obj) or ""
        for sec in ("Parameters", "Returns", "References"):
            assert re.search(rf"^{sec}\n-{{3,}}$", doc, re.M), (name, sec)
