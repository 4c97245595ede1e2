"""EN 1998-5 Annex E earth pressure against closed forms, a published value and a brute-force
trial-wedge maximisation written here independently of murus.

Brute force: the soil wedge between the back face (at psi to the horizontal, wall side) and a
plane through the heel at rho, under gamma A (-kh, -(1 - kv)), the wall reaction at delta and
the soil reaction at phi; the thrust is maximised over 200 001 values of rho (no optimiser),
then the peak is refined by a parabola through the three best points."""

import csv
import math

import numpy as np
import pytest

from murus.eurocode import ec8_5
from murus.eurocode.ec8_5 import (
    EC85Error,
    active_coefficient,
    application_heights,
    coulomb_coefficient,
    rankine_coefficient,
    seismic_angle,
    thrust_components,
    total_thrust,
)

R = math.radians


def brute_force_K(phi, beta, delta, psi, kh, kv, H=1.0, gamma=1.0, n=200_001):
    """K = 2 P_max / (gamma (1 - kv) H²) by a dense search over planar wedges."""
    C = np.array([-H * math.cos(psi) / math.sin(psi), H])  # top of the back face
    rho = np.linspace(beta + 1e-7, math.pi - psi - 1e-7, n)
    u = np.stack([np.cos(rho), np.sin(rho)])
    d = np.array([math.cos(beta), math.sin(beta)])
    # O + s u = C + t d  ->  s u - t d = C
    den = u[0] * (-d[1]) - u[1] * (-d[0])
    s = (C[0] * (-d[1]) - C[1] * (-d[0])) / den
    D = s * u
    area = 0.5 * np.abs(C[0] * D[1] - C[1] * D[0])
    W = gamma * area
    # unknown magnitudes P (wall on soil, along a) and R (soil below, along b)
    a = np.array([math.sin(psi - delta), math.cos(psi - delta)])
    b = np.stack([-np.sin(rho) * math.cos(phi) + np.cos(rho) * math.sin(phi),
                  np.cos(rho) * math.cos(phi) + np.sin(rho) * math.sin(phi)])
    rhs = np.stack([W * kh, W * (1.0 - kv)])
    det = a[0] * b[1] - a[1] * b[0]
    P = (rhs[0] * b[1] - rhs[1] * b[0]) / det
    P[(s <= 0) | ~np.isfinite(P)] = -np.inf
    i = int(np.argmax(P))
    assert 0 < i < n - 1, "maximum on the edge of the search"
    y0, y1, y2 = P[i - 1], P[i], P[i + 1]
    peak = y1 - 0.125 * (y2 - y0) ** 2 / (y2 - 2 * y1 + y0)
    return 2.0 * peak / (gamma * (1.0 - kv) * H * H)


CASES = [
    # phi, beta, delta, psi, kh, kv  (degrees for angles; kv positive upwards)
    (30, 0, 0, 90, 0.0, 0.0),
    (37.7, 0, 37.7, 90, 0.0, 0.0),
    (37.7, 0, 25.1333, 90, 0.16, 0.0),
    (37.7, 0, 25.1333, 90, 0.15, 0.075),
    (37.7, 0, 25.1333, 90, 0.15, -0.075),
    (35, 15, 20, 90, 0.10, 0.05),
    (32, -10, 10, 80, 0.20, -0.10),
    (40, 10, 26.67, 100, 0.12, 0.06),
    (45, 20, 30, 85, 0.25, 0.0),
    (30, 0, 15, 95, 0.30, 0.15),
]


@pytest.mark.parametrize("phi, beta, delta, psi, kh, kv", CASES)
def test_E2_against_brute_force_trial_wedge(phi, beta, delta, psi, kh, kv):
    theta = seismic_angle(kh, kv)
    assert R(beta) <= R(phi) - theta  # the branch (E.2)
    K = active_coefficient(R(phi), R(beta), R(delta), R(psi), theta)
    Kb = brute_force_K(R(phi), R(beta), R(delta), R(psi), kh, kv)
    assert K == pytest.approx(Kb, rel=1e-6)


def test_savalle2022_dsrw1_limit_state_coefficient():
    # the coefficient of the governing state of DSRW1 (kh = 0.1619, delta = 2/3 phi)
    K = active_coefficient(R(37.7), 0.0, R(37.7 * 2 / 3), R(90), seismic_angle(0.16191582, 0))
    assert K == pytest.approx(brute_force_K(R(37.7), 0, R(37.7 * 2 / 3), R(90), 0.16191582, 0),
                              rel=1e-6)
    assert 0.30 < K < 0.35


@pytest.mark.parametrize("phi", [20, 25, 30, 37.7, 45, 50])
def test_rankine_closed_form(phi):
    expected = math.tan(R(45 - phi / 2)) ** 2
    assert coulomb_coefficient(R(phi)) == pytest.approx(expected, rel=1e-14)
    assert active_coefficient(R(phi), 0, 0, R(90), 0) == pytest.approx(expected, rel=1e-14)
    assert rankine_coefficient(R(phi)) == pytest.approx(expected, rel=1e-15)
    assert expected == pytest.approx((1 - math.sin(R(phi))) / (1 + math.sin(R(phi))), rel=1e-13)


@pytest.mark.parametrize("phi, beta, delta, omega", [(30, 0, 20, 0), (35, 10, 23.3, 10),
                                                     (37.7, 0, 37.7, -5), (40, 15, 10, 5)])
def test_theta_zero_is_coulomb(phi, beta, delta, omega):
    # Coulomb (Mueller-Breslau) with the back at omega from the vertical (soil side positive
    # when the soil rests on the back face): psi = 90 - omega in EN 1998-5's convention
    p, b, d, w = R(phi), R(beta), R(delta), R(omega)
    ka = math.cos(p - w) ** 2 / (
        math.cos(w) ** 2 * math.cos(d + w)
        * (1 + math.sqrt(math.sin(p + d) * math.sin(p - b) / (math.cos(d + w) * math.cos(w - b))))
        ** 2)
    assert coulomb_coefficient(p, b, d, R(90) - w) == pytest.approx(ka, rel=1e-13)
    assert active_coefficient(p, b, d, R(90) - w, 0.0) == pytest.approx(ka, rel=1e-13)


@pytest.mark.parametrize("phi, beta, delta, omega, kh, kv", [(30, 0, 0, 0, 0.2, 0.0),
                                                             (35, 10, 17.5, 5, 0.15, 0.07),
                                                             (40, -5, 20, -8, 0.3, -0.1)])
def test_mononobe_okabe_textbook_form(phi, beta, delta, omega, kh, kv):
    # the cos form of Mononobe-Okabe (e.g. Kramer 1996, omega from the vertical)
    p, b, d, w = R(phi), R(beta), R(delta), R(omega)
    th = math.atan(kh / (1 - kv))
    kae = math.cos(p - th - w) ** 2 / (
        math.cos(th) * math.cos(w) ** 2 * math.cos(d + w + th)
        * (1 + math.sqrt(math.sin(p + d) * math.sin(p - b - th)
                         / (math.cos(d + w + th) * math.cos(b - w)))) ** 2)
    assert active_coefficient(p, b, d, R(90) - w, seismic_angle(kh, kv)) == pytest.approx(
        kae, rel=1e-13)


def test_published_values(data_dir):
    with open(data_dir / "retaining" / "en1998_5_mononobe_okabe.csv") as fh:
        rows = list(csv.DictReader(ln for ln in fh if not ln.startswith("#")))
    assert len(rows) == 4
    for r in rows:
        th = seismic_angle(float(r["kh"]), float(r["kv_up"]))
        assert th == pytest.approx(float(r["theta_rad"]), rel=1e-12, abs=1e-15)
        K = active_coefficient(R(float(r["phi_deg"])), R(float(r["beta_deg"])),
                               R(float(r["delta_deg"])), R(float(r["psi_deg"])), th)
        assert K == pytest.approx(float(r["K"]), rel=1e-9), r["source"]


def test_branches_meet_and_E3():
    phi, delta, psi = R(37.7), R(25), R(90)
    th = R(10)
    b0 = phi - th  # the limit of (E.2)
    hi = active_coefficient(phi, b0 + 1e-12, delta, psi, th)
    # continuous, with a square-root approach from the (E.2) side
    for eps in (1e-6, 1e-8, 1e-10):
        lo = active_coefficient(phi, b0 - eps, delta, psi, th)
        assert lo < hi and (hi - lo) / hi < 3 * math.sqrt(eps)
    # (E.3) beyond, and it is the E.2 form without the square-root term
    b = R(32.6)
    e3 = math.sin(psi + phi - th) ** 2 / (math.cos(th) * math.sin(psi) ** 2
                                          * math.sin(psi - th - delta))
    assert active_coefficient(phi, b, delta, psi, th) == pytest.approx(e3, rel=1e-14)


def test_monotonic_and_symmetric_behaviour():
    phi = R(35)
    Ks = [active_coefficient(phi, 0, R(20), R(90), seismic_angle(kh)) for kh in
          np.linspace(0, 0.4, 9)]
    assert all(b > a for a, b in zip(Ks, Ks[1:], strict=False))  # K grows with kh
    # delta lowers K (vertical wall, level backfill), beta and a soil-bearing back raise it
    assert active_coefficient(phi, 0, R(20)) < active_coefficient(phi, 0, 0)
    assert active_coefficient(phi, R(10), 0) > active_coefficient(phi, 0, 0)
    assert active_coefficient(phi, 0, 0, R(80)) > active_coefficient(phi, 0, 0, R(90))
    # kv: same theta, K identical; E_d scales with (1 - kv)
    th = seismic_angle(0.2, 0.1)
    assert th == pytest.approx(seismic_angle(0.2 / 0.9, 0.0), rel=1e-15)


def test_seismic_angle_signs_and_tilt():
    assert seismic_angle(0.0) == 0.0
    assert seismic_angle(0.2, 0.1) == pytest.approx(math.atan(0.2 / 0.9), rel=1e-15)
    assert seismic_angle(0.2, -0.1) == pytest.approx(math.atan(0.2 / 1.1), rel=1e-15)
    assert seismic_angle(0.2, 0.1) > seismic_angle(0.2, -0.1)  # upward inertia is worse
    for t in (0.05, 0.2, 0.6):
        assert seismic_angle(math.sin(t), 1 - math.cos(t)) == pytest.approx(t, rel=1e-14)


def test_total_thrust_and_components():
    g, H = 14.9e3, 2.5
    K = coulomb_coefficient(R(37.7), 0, R(25))
    assert total_thrust(g, H, K) == pytest.approx(0.5 * g * K * H * H, rel=1e-15)
    assert total_thrust(g, H, K, 0.1) == pytest.approx(0.9 * 0.5 * g * K * H * H, rel=1e-15)
    Es, dE = thrust_components(g, H, R(37.7), 0.0, 0.0, 0, R(25))
    assert Es == pytest.approx(0.5 * g * K * H * H, rel=1e-15) and dE == 0.0
    Es, dE = thrust_components(g, H, R(37.7), 0.16, 0.08, 0, R(25))
    Kd = active_coefficient(R(37.7), 0, R(25), R(90), seismic_angle(0.16, 0.08))
    assert Es + dE == pytest.approx(0.5 * g * 0.92 * Kd * H * H, rel=1e-14)
    assert dE > 0
    assert application_heights(3.0) == (1.0, 1.5)
    assert application_heights(3.0, "static") == (1.0, 1.0)


def test_seismic_coefficients_7_1_to_7_3():
    assert ec8_5.horizontal_coefficient(0.25, 1.2, 2.0) == pytest.approx(0.15, rel=1e-15)
    assert ec8_5.vertical_coefficient(0.15, 0.9) == pytest.approx(0.075, rel=1e-15)
    assert ec8_5.vertical_coefficient(0.15, 0.45) == pytest.approx(0.0495, rel=1e-15)
    assert set(ec8_5.R_FACTORS.values()) == {2.0, 1.5, 1.0}


@pytest.mark.parametrize("call, word", [
    (lambda: active_coefficient(R(95)), "phi must be in"),
    (lambda: active_coefficient(R(30), 0, R(35)), "wall friction delta"),
    (lambda: active_coefficient(R(30), 0, 0, R(190)), "psi"),
    (lambda: active_coefficient(R(30), R(95)), "beta"),
    (lambda: active_coefficient(R(30), 0, R(30), R(90), R(65)), "seismic angle is too large"),
    (lambda: coulomb_coefficient(R(30), R(35)), "no static active state"),
    (lambda: seismic_angle(-0.1), "kh must be >= 0"),
    (lambda: seismic_angle(0.1, 1.0), "kv must be < 1"),
    (lambda: seismic_angle("x"), "must be a number"),
    (lambda: total_thrust(1.0, -2.0, 0.3), "height H"),
    (lambda: application_heights(2.0, "top"), "mid-height"),
    (lambda: active_coefficient(float("nan")), "finite"),
])
def test_bad_input_one_line_errors(call, word):
    with pytest.raises(EC85Error) as exc:
        call()
    msg = str(exc.value)
    assert word in msg and "\n" not in msg
