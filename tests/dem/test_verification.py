"""Verification of murus.dem against closed forms, murus.rocking, conservation laws and a
published collapse limit (issue 5). The case builders live in murus.dem.verify, shared with
``murus verify dem``; each row states its tolerance."""

import pytest

from murus.dem import verify as V


def _check(rows):
    bad = [r for r in rows if not r["passed"]]
    assert not bad, "\n".join(
        f"{r['case']}: expected {r['expected']:.6g}, obtained {r['obtained']:.6g}, "
        f"error {r['error']:.3g} > {r['tolerance']:g}" for r in bad)


def test_inclined_plane():
    """30 deg plane, friction 25 deg: a = 0.9434 m/s² (1 %); at 20 deg: no motion (1e-6 m)."""
    _check(V.case_inclined_plane())


def test_newmark_sliding_block():
    """Friction 0.3, 0.5 g x 0.2 s pulse: slip 0.0654 m (2 %), stops at 0.3333 s (2 %)."""
    _check(V.case_newmark())


def test_rocking_block():
    """Onset at g tan(alpha) (2 %), first impact from alpha/2 at 0.349 s (2 %), one-sine pulse
    max rotation before the first impact as murus.rocking (5 %)."""
    _check(V.case_rocking())


def test_tilting_table():
    """Toppling at atan(0.25) = 14.04 deg (0.1 deg), sliding at 30 deg (1 deg)."""
    _check(V.case_tilting())


def test_stack_at_rest():
    """Each joint carries the weight above (1e-6 rel.), no drift over 1e5 undamped steps."""
    _check(V.case_stack())


def test_energy():
    """Undamped free rocking: energy conserved to 0.1 %; balance with slip to 0.1 %; with base
    work and mass damping to 1 %."""
    _check(V.case_energy())


def test_semicircular_arch_minimum_thickness():
    """Stands at 1.05 x 0.1075 R, collapses at 0.95 x 0.1075 R (Milankovitch / Ochsendorf)."""
    _check(V.case_arch())


def test_rolling_resistance():
    """A disc with rolling resistance mu_r rolls at tan(beta) = mu_r (0.2 deg)."""
    _check(V.case_rolling())


def test_run_verification_rows():
    rows = V.run_verification.__doc__
    assert rows
    assert set(V.CASES) >= {"inclined_plane", "newmark", "rocking", "tilting", "stack",
                            "energy", "arch"}


@pytest.mark.parametrize("name", ["newmark"])
def test_quick_rows_have_the_table_keys(name):
    for r in V.CASES[name](quick=True):
        assert set(r) == {"case", "expected", "obtained", "error", "tolerance", "passed"}


def test_verify_cli_prints_the_table_and_rejects_unknown_cases():
    """``murus verify dem``: one case through the CLI, units in brackets survive the markup."""
    from typer.testing import CliRunner

    from murus.cli import app

    r = CliRunner().invoke(app, ["verify", "dem", "--quick", "--case", "inclined_plane"],
                           env={"COLUMNS": "200"})
    assert r.exit_code == 0, r.output
    assert "[m/s2]" in r.output and "pass" in r.output
    r = CliRunner().invoke(app, ["verify", "dem", "--case", "nope"])
    assert r.exit_code == 2
    assert "unknown case" in r.output
