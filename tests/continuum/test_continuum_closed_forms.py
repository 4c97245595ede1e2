"""Closed forms of the continuum verification (issue 17 item 7): published tables, REFERENCE.md
formulas written again here independently, and internal consistency (equilibrium, continuity,
flow rule, energy, modal sums)."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from murus.continuum import closed_forms as cf

DATA = Path(__file__).parent.parent / "data" / "continuum"
D = math.radians


def _rows(name):
    with open(DATA / name, newline="") as fh:
        return list(csv.DictReader(line for line in fh if not line.startswith("#")))


# ----------------------------------------------------------------------------- layer

VS, H = 200.0, 20.0


def test_layer_frequencies():
    assert cf.layer_frequency(VS, H) == pytest.approx(2.5, rel=1e-15)
    f = cf.layer_frequency(VS, H, np.arange(1, 5))
    np.testing.assert_allclose(f, [2.5, 7.5, 12.5, 17.5], rtol=1e-15)
    with pytest.raises(cf.ClosedFormError):
        cf.layer_frequency(VS, H, 0)


@pytest.mark.parametrize("kind", ["hysteretic", "relative", "absolute"])
def test_transfer_peaks_at_the_natural_frequencies(kind):
    """Local maxima of |u_top/u_base| at f_n: within 0.1 % for 2 % damping at f_1 (the
    shift is O(xi²))."""
    xi = 0.02
    f1 = cf.layer_frequency(VS, H)
    alpha = cf.mass_damping_alpha(xi, f1)
    for n in (1, 2, 3):
        fn = cf.layer_frequency(VS, H, n)
        f = np.linspace(0.9 * fn, 1.1 * fn, 20001)
        if kind == "hysteretic":
            t = cf.layer_transfer_hysteretic(f, VS, H, xi)
        else:
            t = cf.layer_transfer_rayleigh(f, VS, H, alpha, relative=kind == "relative")
        assert f[np.argmax(t)] == pytest.approx(fn, rel=1e-3)


def test_hysteretic_transfer_limits():
    """xi = 0: 1 / |cos(w H / Vs)| exactly; at f = 0 the layer moves with the base; the peak
    at f_n is 2 / ((2n - 1) pi xi) to O(xi) (Kramer 1996, §7.2.1)."""
    f = np.linspace(0.0, 6.0, 13)
    np.testing.assert_allclose(cf.layer_transfer_hysteretic(f, VS, H, 0.0),
                               1.0 / np.abs(np.cos(2 * np.pi * f * H / VS)), rtol=1e-12)
    assert cf.layer_transfer_hysteretic(0.0, VS, H, 0.05) == pytest.approx(1.0, abs=1e-15)
    for xi in (0.01, 0.02):
        for n in (1, 2):
            peak = cf.layer_transfer_hysteretic(cf.layer_frequency(VS, H, n), VS, H, xi)
            assert peak == pytest.approx(2.0 / (math.pi * xi * (2 * n - 1)), rel=2 * xi)


@pytest.mark.parametrize("relative", [True, False])
def test_rayleigh_transfer_is_the_sum_of_all_modes(relative):
    """The exact 1D solutions equal the modal superposition (error of 4000 modes ~ 1e-10)."""
    alpha = cf.mass_damping_alpha(0.05, cf.layer_frequency(VS, H))
    f = np.array([0.3, 1.0, 2.5, 4.0, 7.5, 9.0, 20.0])
    exact = cf.layer_transfer_rayleigh(f, VS, H, alpha, relative, complex_output=True)
    modal = cf.layer_transfer_modal(f, VS, H, alpha, 4000, relative, complex_output=True)
    np.testing.assert_allclose(exact, modal, rtol=1e-7)


@pytest.mark.parametrize("xi", [0.02, 0.05, 0.10])
def test_rayleigh_resonance_matches_modal_damping(xi):
    """At f_1 both damping forms give the single-mode (modal damping) peak
    Gamma_1 / (2 xi_1) = 2 / (pi xi_1), xi_1 = alpha / (2 w_1), within (pi xi / 2)² (the
    other modes add a real O(1) part in quadrature), and the hysteretic layer with xi = xi_1
    within the same bound."""
    f1 = cf.layer_frequency(VS, H)
    alpha = cf.mass_damping_alpha(xi, f1)
    assert cf.mass_damping_ratio(alpha, f1) == pytest.approx(xi, rel=1e-15)
    single = cf.layer_transfer_modal(f1, VS, H, alpha, 1)
    # 1 + Gamma_1 w_1² / (i alpha w_1): the base motion plus the resonant mode
    assert single == pytest.approx(math.hypot(1.0, 2.0 / (math.pi * xi)), rel=1e-12)
    single = 2.0 / (math.pi * xi)
    bound = (math.pi * xi / 2) ** 2
    for relative in (True, False):
        assert cf.layer_transfer_rayleigh(f1, VS, H, alpha, relative) == pytest.approx(
            single, rel=bound)
    assert cf.layer_transfer_hysteretic(f1, VS, H, xi) == pytest.approx(single, rel=bound)


def test_rayleigh_undamped_limit_and_the_two_forms_meet_at_high_frequency():
    """alpha = 0: both forms are 1 / |cos(kH)|; they differ by O(alpha / w) (the factor
    w / (w - i alpha) on the relative part), so they meet as w >> alpha."""
    alpha = cf.mass_damping_alpha(0.05, cf.layer_frequency(VS, H))
    f = np.array([0.5, 3.7, 11.0])
    for relative in (True, False):
        np.testing.assert_allclose(cf.layer_transfer_rayleigh(f, VS, H, 0.0, relative),
                                   1.0 / np.abs(np.cos(2 * np.pi * f * H / VS)), rtol=1e-12)
    for fh in (50.0, 200.0, 1000.0):
        rel = cf.layer_transfer_rayleigh(fh, VS, H, alpha, True)
        ab = cf.layer_transfer_rayleigh(fh, VS, H, alpha, False)
        w = 2 * math.pi * fh
        assert abs(rel / ab - 1.0) < alpha / w
        assert rel != ab


# ----------------------------------------------------------------------------- quiet boundary

VP, VSW = 1732.0, 1000.0


@pytest.mark.parametrize("wave", ["P", "S"])
def test_quiet_boundary_normal_incidence_reflects_nothing(wave):
    r = cf.quiet_boundary_reflection(0.0, VP, VSW, wave)
    assert abs(r.same) < 1e-14 and abs(r.converted) < 1e-14
    assert r.energy_absorbed == pytest.approx(1.0, abs=1e-14)


@pytest.mark.parametrize("wave", ["P", "S"])
@pytest.mark.parametrize("theta_deg", [10, 30, 45, 60, 80])
@pytest.mark.parametrize("ab", [(1.0, 1.0), (0.5, 2.0), (0.0, 0.0)])
def test_quiet_boundary_energy_balance(wave, theta_deg, ab):
    """Incident flux = reflected fluxes + dashpot power (computed from the total velocity at
    the boundary), to round-off, at any angle (also beyond the critical angle of SV)."""
    r = cf.quiet_boundary_reflection(D(theta_deg), VP, VSW, wave, *ab)
    assert r.energy_reflected + r.energy_absorbed == pytest.approx(1.0, abs=1e-12)
    assert min(r.energy_same, r.energy_converted, r.energy_absorbed) >= -1e-15


def test_quiet_boundary_oblique_incidence_reflects_a_little():
    """With a = b = 1, a P wave at 30 deg keeps less than 0.1 % of its energy and one at 60 deg
    reflects some per cent (Lysmer & Kuhlemeyer 1969: good absorption at small angles, not
    perfect at large ones); the reflection grows with the angle."""
    e = [cf.quiet_boundary_reflection(D(t), VP, VSW, "P").energy_reflected
         for t in (0, 30, 60, 80)]
    assert e[0] < 1e-28 < e[1] < 1e-3 < e[2] < e[3]


def _aki_richards(theta, alpha, beta, wave):
    """Free-surface P-SV coefficients, Aki & Richards (2002), §5.2 (written again here)."""
    if wave == "P":
        i = theta
        p = math.sin(i) / alpha
        j = math.asin(p * beta)
    else:
        j = theta
        p = math.sin(j) / beta
        i = math.asin(p * alpha)
    ci, cj = math.cos(i), math.cos(j)
    a = (1 / beta**2 - 2 * p**2) ** 2
    b = 4 * p**2 * ci / alpha * cj / beta
    den = a + b
    if wave == "P":
        return (-a + b) / den, 4 * alpha / beta * p * ci / alpha * (1 / beta**2 - 2 * p**2) / den
    return (a - b) / den, 4 * beta / alpha * p * cj / beta * (1 / beta**2 - 2 * p**2) / den


@pytest.mark.parametrize("wave,theta_deg", [("P", 10), ("P", 40), ("P", 70), ("S", 10),
                                            ("S", 25), ("S", 33)])
def test_free_surface_limit_is_aki_richards(wave, theta_deg):
    same, conv = _aki_richards(D(theta_deg), VP, VSW, wave)
    r = cf.quiet_boundary_reflection(D(theta_deg), VP, VSW, wave, a=0.0, b=0.0)
    assert abs(r.same) == pytest.approx(abs(same), rel=1e-10)
    assert abs(r.converted) == pytest.approx(abs(conv), rel=1e-10)
    assert r.energy_reflected == pytest.approx(1.0, abs=1e-12)


# ----------------------------------------------------------------------------- hole

HOLE = dict(a=1.0, p0=30e6, pi=0.0, c=3.45e6, phi=D(30.0))
G, K = 2.8e9, 3.9e9


def test_hole_against_the_itasca_problem():
    want = {r["quantity"]: (float(r["value"]), float(r["tolerance"]))
            for r in _rows("hole_mohr_coulomb.csv")}
    phi, c = HOLE["phi"], HOLE["c"]
    kp = (1 + math.sin(phi)) / (1 - math.sin(phi))
    r0 = cf.hole_plastic_radius(**HOLE)
    sr, st = cf.hole_stresses([HOLE["a"], r0], **HOLE)
    got = {"K_p": kp, "q_MPa": 2 * c * math.tan(math.pi / 4 + phi / 2) / 1e6,
           "R0_over_a": r0 / HOLE["a"], "sigma_r_R0_MPa": sr[1] / 1e6,
           "sigma_t_a_MPa": st[0] / 1e6, "sigma_t_R0_MPa": st[1] / 1e6}
    assert set(got) == set(want)
    for k, (v, tol) in want.items():
        assert got[k] == pytest.approx(v, abs=tol), k


def test_hole_stresses_equilibrium_continuity_and_yield():
    phi = HOLE["phi"]
    kp = (1 + math.sin(phi)) / (1 - math.sin(phi))
    q = 2 * HOLE["c"] * math.tan(math.pi / 4 + phi / 2)
    r0 = cf.hole_plastic_radius(**HOLE)
    # continuity at R0
    sr, st = cf.hole_stresses([r0 * (1 - 1e-12), r0 * (1 + 1e-12)], **HOLE)
    assert sr[0] == pytest.approx(sr[1], rel=1e-9) and st[0] == pytest.approx(st[1], rel=1e-9)
    # equilibrium d(sigma_r)/dr = (sigma_t - sigma_r)/r, central differences, both zones
    h = 1e-5
    for r in (1.1, 1.5, 1.7, 1.8, 2.5, 6.0):
        (sm, sp), _ = cf.hole_stresses([r - h, r + h], **HOLE)
        s_r, s_t = cf.hole_stresses(r, **HOLE)
        assert (sp - sm) / (2 * h) == pytest.approx((s_t - s_r) / r, rel=1e-6)
    # plastic stresses on the yield line sigma_t = Kp sigma_r + q, elastic ones inside it
    r = np.linspace(1.0, 5.0, 81)
    s_r, s_t = cf.hole_stresses(r, **HOLE)
    f = s_t - kp * s_r - q
    np.testing.assert_allclose(f[r < r0], 0.0, atol=1e-6 * HOLE["p0"])
    assert np.all(f[r > r0] < 0)
    # far field
    s_r, s_t = cf.hole_stresses(1e4, **HOLE)
    assert s_r == pytest.approx(HOLE["p0"], rel=1e-6) and s_t == pytest.approx(HOLE["p0"],
                                                                             rel=1e-6)


@pytest.mark.parametrize("psi_deg", [0.0, 15.0, 30.0])
def test_hole_displacement_follows_hooke_and_the_flow_rule(psi_deg):
    """u continuous at R0; in the elastic zone the strains are elastic; in the plastic zone
    the plastic strains (total - elastic, from the stresses) satisfy e_r^p + Kpsi e_t^p = 0
    and the hoop plastic strain is a contraction."""
    psi = D(psi_deg)
    kpsi = (1 + math.sin(psi)) / (1 - math.sin(psi))
    nu = (3 * K - 2 * G) / (2 * (3 * K + G))
    r0 = cf.hole_plastic_radius(**HOLE)
    u = cf.hole_displacement([r0 * (1 - 1e-12), r0 * (1 + 1e-12)], **HOLE, G=G, K=K, psi=psi)
    assert u[0] == pytest.approx(u[1], rel=1e-9)
    h = 1e-6
    for r in (1.05, 1.3, 1.6, 2.0, 3.0):
        um, up = cf.hole_displacement([r - h, r + h], **HOLE, G=G, K=K, psi=psi)
        e_r = (up - um) / (2 * h)
        e_t = cf.hole_displacement(r, **HOLE, G=G, K=K, psi=psi) / r
        s_r, s_t = cf.hole_stresses(r, **HOLE)
        d_r, d_t = -(s_r - HOLE["p0"]), -(s_t - HOLE["p0"])  # tension-positive changes
        ee_r = ((1 - nu) * d_r - nu * d_t) / (2 * G)
        ee_t = ((1 - nu) * d_t - nu * d_r) / (2 * G)
        p_r, p_t = e_r - ee_r, e_t - ee_t
        scale = abs(e_t)
        if r < r0:
            assert p_t < -1e-3 * scale
            assert p_r + kpsi * p_t == pytest.approx(0.0, abs=1e-6 * scale)
        else:
            assert abs(p_r) < 1e-6 * scale and abs(p_t) < 1e-6 * scale


def test_hole_more_dilation_more_convergence_and_elastic_limit():
    u = [cf.hole_displacement(1.0, **HOLE, G=G, K=K, psi=D(p)) for p in (0, 15, 30)]
    assert u[0] < 0 and u[2] < u[1] < u[0]
    # no plastic zone: Kirsch's hydrostatic case, u(a) = -(P0 - Pi) a / (2G)
    strong = dict(HOLE, c=30e6)
    assert cf.hole_plastic_radius(**strong) == 1.0
    assert cf.hole_displacement(1.0, **strong, G=G, K=K) == pytest.approx(-30e6 / (2 * G),
                                                                          rel=1e-12)
    with pytest.raises(cf.ClosedFormError):
        cf.hole_displacement(1.0, **HOLE, G=G, K=K, psi=D(35))
    with pytest.raises(cf.ClosedFormError):
        cf.hole_stresses(0.5, **HOLE)


# ----------------------------------------------------------------------------- footing


def test_bearing_capacity_factors_against_das_table():
    rows = _rows("bearing_capacity_factors.csv")
    assert len(rows) == 10
    for row in rows:
        nc, nq = cf.bearing_capacity_factors(D(float(row["phi_deg"])))
        assert nc == pytest.approx(float(row["N_c"]), abs=0.01), row
        assert nq == pytest.approx(float(row["N_q"]), abs=0.01), row


def test_prandtl_cohesive_and_continuity_at_zero_friction():
    assert cf.strip_footing_capacity(50e3) == pytest.approx((2 + math.pi) * 50e3, rel=1e-15)
    assert cf.strip_footing_capacity(50e3, 0.0, 10e3) == pytest.approx(
        (2 + math.pi) * 50e3 + 10e3, rel=1e-15)
    # N_c -> 2 + pi as phi -> 0 with slope 2 + 2 pi + pi²/2 (Taylor series of the formula)
    for phi in (1e-12, 1e-8, 1e-5):
        assert cf.bearing_capacity_factors(phi)[0] == pytest.approx(
            2 + math.pi + (2 + 2 * math.pi + math.pi**2 / 2) * phi, rel=1e-9)
    nc, nq = cf.bearing_capacity_factors(D(30))
    assert cf.strip_footing_capacity(10e3, D(30), 5e3) == pytest.approx(10e3 * nc + 5e3 * nq)


# ----------------------------------------------------------------------------- oedometer


def test_oedometric_modulus_and_settlement():
    E, nu = 30e6, 0.3
    Kb, Gs = E / (3 * (1 - 2 * nu)), E / (2 * (1 + nu))
    M = cf.oedometric_modulus(E, nu)
    assert M == pytest.approx(Kb + 4 * Gs / 3, rel=1e-14)
    assert M == pytest.approx(E * 0.7 / (1.3 * 0.4), rel=1e-15)
    assert cf.oedometric_settlement(100e3, 2.0, E, nu) == pytest.approx(100e3 * 2.0 / M,
                                                                        rel=1e-15)
    with pytest.raises(cf.ClosedFormError):
        cf.oedometric_modulus(E, 0.5)


# ----------------------------------------------------------------------------- thrusts

GAMMA, HW = 18e3, 4.0


@pytest.mark.parametrize("phi_deg", [25.0, 30.0, 36.0])
def test_thrust_wrappers_agree_with_the_reference_formulas(phi_deg):
    """REFERENCE.md, 'Continuum zones': Rankine, Coulomb (vertical wall, level backfill) and
    Mononobe-Okabe, written again here."""
    phi = D(phi_deg)
    ka = (1 - math.sin(phi)) / (1 + math.sin(phi))
    assert cf.rankine_thrust(GAMMA, HW, phi) == pytest.approx(0.5 * ka * GAMMA * HW**2,
                                                              rel=1e-13)
    assert cf.active_thrust(GAMMA, HW, phi) == pytest.approx(0.5 * ka * GAMMA * HW**2,
                                                             rel=1e-13)
    delta = 2 * phi / 3
    kc = math.cos(phi) ** 2 / (math.cos(delta) * (
        1 + math.sqrt(math.sin(phi + delta) * math.sin(phi) / math.cos(delta))) ** 2)
    assert cf.active_thrust(GAMMA, HW, phi, delta) == pytest.approx(0.5 * kc * GAMMA * HW**2,
                                                                    rel=1e-13)
    for kh, kv in ((0.15, 0.0), (0.2, 0.1), (0.2, -0.1)):
        for dl in (0.0, delta):
            th = math.atan(kh / (1 - kv))
            kae = math.cos(phi - th) ** 2 / (math.cos(th) * math.cos(dl + th) * (1 + math.sqrt(
                math.sin(phi + dl) * math.sin(phi - th) / math.cos(dl + th))) ** 2)
            assert cf.active_thrust(GAMMA, HW, phi, dl, kh, kv) == pytest.approx(
                0.5 * GAMMA * HW**2 * (1 - kv) * kae, rel=1e-12)
