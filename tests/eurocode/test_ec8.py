"""EN 1998-1 §3.2.2 spectra against hand values at the corner periods.

Hand values: recommended Tables 3.2 and 3.3 typed here independently of the module, with
Se(TB..TC) = 2.5 ag S eta, Se(TD) = 2.5 ag S eta TC / TD, Se(0) = ag S (eqs 3.2-3.5)."""

import math

import numpy as np
import pytest

from murus.eurocode import ec8

# EN 1998-1:2004 Table 3.2 (Type 1) and Table 3.3 (Type 2): S, TB, TC, TD
HAND = {
    1: {"A": (1.00, 0.15, 0.40, 2.0), "B": (1.20, 0.15, 0.50, 2.0), "C": (1.15, 0.20, 0.60, 2.0),
        "D": (1.35, 0.20, 0.80, 2.0), "E": (1.40, 0.15, 0.50, 2.0)},
    2: {"A": (1.00, 0.05, 0.25, 1.2), "B": (1.35, 0.05, 0.25, 1.2), "C": (1.50, 0.10, 0.25, 1.2),
        "D": (1.80, 0.10, 0.30, 1.2), "E": (1.60, 0.05, 0.25, 1.2)},
}


@pytest.mark.parametrize("stype", [1, 2])
@pytest.mark.parametrize("ground", list("ABCDE"))
def test_elastic_corner_values(stype, ground):
    S, TB, TC, TD = HAND[stype][ground]
    ag = 2.5
    Se = ec8.elastic_spectrum([0.0, TB, TC, TD, 4.0], ag, ground, stype)
    expected = [ag * S, 2.5 * ag * S, 2.5 * ag * S, 2.5 * ag * S * TC / TD,
                2.5 * ag * S * TC * TD / 16.0]
    assert np.allclose(Se, expected, rtol=1e-14)
    # continuity at the corners (the branches meet)
    eps = 1e-9
    for Tc in (TB, TC, TD):
        lo, hi = ec8.elastic_spectrum([Tc - eps, Tc + eps], ag, ground, stype)
        assert lo == pytest.approx(hi, rel=1e-7)


def test_type2_ground_d_soil_factor_is_1_80():
    assert ec8.parameters("D", 2).S == 1.80
    assert ec8.elastic_spectrum(0.2, 1.0, "D", 2) == pytest.approx(2.5 * 1.80)


def test_eta_and_damping():
    assert ec8.eta(0.05) == 1.0
    assert ec8.eta(0.10) == pytest.approx(math.sqrt(10 / 15))
    assert ec8.eta(0.5) == 0.55  # lower bound, eq (3.6)
    Se = ec8.elastic_spectrum(0.3, 1.0, "A", 1, damping=0.02)
    assert Se == pytest.approx(2.5 * math.sqrt(10 / 7))


def test_importance_and_national_annex_override():
    assert ec8.elastic_spectrum(0.3, 2.0, "B", 1, importance="III") == pytest.approx(
        1.2 * 2.5 * 2.0 * 1.2)
    assert ec8.elastic_spectrum(0.3, 2.0, "B", 1, importance=1.4) == pytest.approx(
        1.4 * 2.5 * 2.0 * 1.2)
    na = ec8.with_overrides(ec8.parameters("B", 1), S=1.25, TC=0.6)
    assert ec8.elastic_spectrum(0.6, 1.0, params=na) == pytest.approx(2.5 * 1.25)
    with pytest.raises(ValueError, match="ground type"):
        ec8.parameters("S1", 1)
    with pytest.raises(ValueError):
        ec8.parameters("A", 3)


@pytest.mark.parametrize("stype,avg", [(1, 0.90), (2, 0.45)])
def test_vertical_spectrum_table_3_4(stype, avg):
    ag = 3.0
    Sv = ec8.vertical_spectrum([0.0, 0.05, 0.15, 1.0, 2.0], ag, stype)
    a = avg * ag
    assert np.allclose(Sv, [a, 3.0 * a, 3.0 * a, 3.0 * a * 0.15, 3.0 * a * 0.15 * 1.0 / 4.0])


def test_design_spectrum_eqs_3_13_to_3_16():
    ag, q = 2.0, 3.0
    S, TB, TC, TD = HAND[1]["C"]
    Sd = ec8.design_spectrum([0.0, TB, TC, 1.0, TD, 3.0, 10.0], ag, q, "C", 1)
    exp = [ag * S * 2 / 3, ag * S * 2.5 / q, ag * S * 2.5 / q, ag * S * 2.5 / q * TC / 1.0,
           ag * S * 2.5 / q * TC / TD, max(ag * S * 2.5 / q * TC * TD / 9, 0.2 * ag),
           0.2 * ag]
    assert np.allclose(Sd, exp, rtol=1e-14)
    assert Sd[-1] == pytest.approx(0.2 * ag)  # lower bound beta ag governs at long periods
    Sdv = ec8.design_spectrum_vertical(0.1, ag, 1.5, 1)
    assert Sdv == pytest.approx(0.9 * ag * 2.5 / 1.5)
