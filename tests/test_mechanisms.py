"""Kinematic checks of local mechanisms (murus.mechanisms, Circolare 2019 §C8.7.1.2.1) and the
NTC 2018 spectrum (murus.eurocode.ntc): closed forms, a hand-calculated worked example, the
command line."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from murus.cli import app
from murus.eurocode.ntc import NTCError, NTCSpectrum, soil_coefficients
from murus.mechanisms import (
    Building,
    CornerOverturning,
    Floor,
    MechanismError,
    Seismic,
    SimpleOverturning,
    Storey,
    VerticalFlexure,
    alpha,
    analyse,
    capacity_curve,
    displacement_demand,
    floor_spectrum,
    overturning,
    participation,
    vertical_flexure,
)

G = 9.81
DATA = Path(__file__).parent / "data" / "mechanisms"
EXAMPLE = Path(__file__).parents[1] / "examples" / "mechanisms" / "two_storey_facade.toml"


def _site(ag_g=0.2, F0=2.4, Tc=0.31, soil="B"):
    return NTCSpectrum(ag_g * G, F0, Tc, soil)


# --- NTC 2018 spectrum -------------------------------------------------------------------------

def test_ntc_plateau_and_corners():
    sp = NTCSpectrum(0.25 * G, 2.5, 0.30, "A")
    assert sp.S == 1.0 and sp.CC == 1.0
    assert sp.TC == pytest.approx(0.30) and sp.TB == pytest.approx(0.10)
    assert sp.TD == pytest.approx(4.0 * 0.25 + 1.6)
    # plateau ag S F0 (eta = 1 at 5 %), T = 0: ag S; descending branch ag S F0 TC / T
    assert sp.Se(0.2) == pytest.approx(0.25 * G * 2.5, rel=1e-12)
    assert sp.Se(0.0) == pytest.approx(0.25 * G, rel=1e-12)
    assert sp.Se(1.0) == pytest.approx(0.25 * G * 2.5 * 0.30 / 1.0, rel=1e-12)
    assert sp.Se(3.0) == pytest.approx(0.25 * G * 2.5 * 0.30 * 2.6 / 9.0, rel=1e-12)
    # eta at 10 %: sqrt(10 / 15)
    assert sp.Se(0.2, 0.10) == pytest.approx(0.25 * G * 2.5 * math.sqrt(10 / 15), rel=1e-12)
    assert sp.SDe(1.0) == pytest.approx(sp.Se(1.0) / (2 * math.pi) ** 2, rel=1e-12)


def test_ntc_soil_table():
    # Table 3.2.IV, clamped S_S for B (1.00..1.20) and D (0.90..1.80)
    assert soil_coefficients("B", 0.1 * G, 2.5, 0.3)[0] == pytest.approx(1.2)
    assert soil_coefficients("B", 0.4 * G, 2.5, 0.3)[0] == pytest.approx(1.0)
    assert soil_coefficients("C", 0.2 * G, 2.5, 0.3)[0] == pytest.approx(1.70 - 0.60 * 0.5)
    assert soil_coefficients("D", 0.3 * G, 2.5, 0.3)[0] == pytest.approx(2.40 - 1.50 * 0.75)
    assert soil_coefficients("E", 0.2 * G, 2.5, 0.3)[1] == pytest.approx(1.15 * 0.3 ** -0.40)
    assert NTCSpectrum(0.1 * G, 2.5, 0.3, "A", "T4").S == pytest.approx(1.4)
    with pytest.raises(NTCError) as e:
        NTCSpectrum(0.1 * G, 9.0, 0.3)
    assert e.value.key == ("F0",)
    with pytest.raises(NTCError):
        NTCSpectrum(0.1 * G, 2.5, 0.3, "S1")


# --- closed forms -------------------------------------------------------------------------------

def test_single_block_closed_forms():
    t, h, rho = 0.5, 4.0, 1800.0
    wall = SimpleOverturning([Storey(h, t, density=rho)], [])
    assert alpha(wall) == pytest.approx(t / h, rel=1e-7)   # alpha0 = b / h
    part = participation(wall)
    # one lumped weight: e* = (W dx)^2 / (W W dx^2) = 1, M* = W / g
    assert part["e_star"] == pytest.approx(1.0, rel=1e-9)
    assert part["M_star"] == pytest.approx(rho * t * h, rel=1e-9)
    # large displacements: alpha(theta) = tan(beta - theta), d0* = t / 2 at theta0 = beta
    beta = math.atan(t / h)
    for th in (0.02, 0.05, 0.1):
        assert alpha(wall, th) == pytest.approx(math.tan(beta - th), rel=1e-6)
    cur = capacity_curve(wall, FC=1.0)
    assert cur["theta0"] == pytest.approx(beta, rel=1e-6)
    assert cur["d0_star"] == pytest.approx(t / 2, rel=1e-6)
    # a tie at the top: alpha0 = (W t/2 + T h) / (W h / 2)
    W = rho * G * t * h
    tied = SimpleOverturning([Storey(h, t, density=rho)], [Floor(1, tie=0.1 * W)])
    assert alpha(tied) == pytest.approx((W * t / 2 + 0.1 * W * h) / (W * h / 2), rel=1e-7)


@pytest.mark.parametrize("n", [1, 2, 5, 40])
def test_slices_approach_the_continuous_mass(n):
    # n slices of one storey: e* = 3 n^2 / (4 n^2 - 1) (1 -> 3/4), d0* = t/2 (4/3 - 1/(3 n^2))
    t, h = 0.5, 4.0
    wall = SimpleOverturning([Storey(h, t, density=1800.0)], [], slices=n)
    assert alpha(wall) == pytest.approx(t / h, rel=1e-7)
    assert participation(wall)["e_star"] == pytest.approx(3 * n * n / (4 * n * n - 1), rel=1e-9)
    d0 = capacity_curve(wall)["d0_star"]
    assert d0 == pytest.approx(t / 2 * (4 / 3 - 1 / (3 * n * n)), rel=1e-6)


def test_two_blocks_participation_closed_form():
    # two equal weights at heights 1 and 3 (lumped): e* = (W + 3W)^2 / (2W (W + 9W)) = 0.8
    st = [Storey(2.0, 0.4, weight=1000.0), Storey(2.0, 0.4, weight=1000.0)]
    part = participation(SimpleOverturning(st, []))
    assert part["e_star"] == pytest.approx(16 / 20, rel=1e-9)


def test_vertical_flexure_closed_form():
    t, h, h1, W, N = 0.4, 3.0, 1.2, 1000.0, 700.0
    h2 = h - h1
    vf = VerticalFlexure(height=h, thickness=t, weight=W, h1=h1, top_load=N)
    W1, W2 = W * h1 / h, W * h2 / h
    # virtual work with theta2 = theta h1 / h2: lower centroid dy = t/2, upper dy = t + t h1/(2
    # h2), top load (at mid-thickness) dy = t + t h1/(2 h2); both centroids dx = h1 / 2
    num = W1 * t / 2 + (W2 + N) * (t + t * h1 / (2 * h2))
    assert alpha(vf) == pytest.approx(num / (W * h1 / 2), rel=1e-7)
    # the hinge height minimising alpha0 is found
    s = Seismic({"SLV": _site()}, FC=1.0)
    res = vertical_flexure(h, t, W, s, top_load=N)
    hs = np.linspace(0.05, 2.95, 300)
    best = min(alpha(VerticalFlexure(height=h, thickness=t, weight=W, h1=x, top_load=N))
               for x in hs)
    assert res.alpha0 <= best + 1e-9
    assert res.e_star == pytest.approx(1.0)


def test_corner_wedge_closed_form():
    h, t, rho, phi = 3.0, 0.5, 1800.0, 30.0
    L = h * math.tan(math.radians(phi))
    r2 = math.sqrt(2.0)
    W = rho * G * t * L * h / 2            # each triangle
    s1, s2 = (L / 3 + t / 2) / r2, (t / 2 + t + L / 3) / r2   # distances along the bisector
    c = CornerOverturning(height=h, t1=t, t2=t, density=rho, crack_angle_deg=phi)
    assert alpha(c) == pytest.approx((s1 + s2) / (2 * 2 * h / 3), rel=1e-7)
    assert participation(c)["e_star"] == pytest.approx(1.0)
    # a thrust F at the top along the bisector: alpha0 falls by F h / (2 W 2h/3)
    F = 0.05 * W
    ct = CornerOverturning(height=h, t1=t, t2=t, density=rho, crack_angle_deg=phi, thrust=F)
    assert alpha(ct) == pytest.approx((W * (s1 + s2) - F * h) / (2 * W * 2 * h / 3), rel=1e-7)


def test_floor_spectrum_and_displacement_demand():
    sp = _site()
    b = Building(T1=0.25, height=6.7, storeys=2)
    aZ_top = sp.Se(0.25) * 1.2 * math.sqrt(1.01)
    # T -> 0: the peak floor acceleration; plateau a T1 .. b T1: 1.1 xi1^-0.5 eta a_Z
    assert floor_spectrum(sp, b, 6.7, 1e-9, 0.05) == pytest.approx(aZ_top, rel=1e-6)
    assert floor_spectrum(sp, b, 6.7, 0.25, 0.05) == pytest.approx(1.1 / math.sqrt(0.05)
                                                                   * aZ_top, rel=1e-9)
    # ground level: SDe of the ground spectrum
    assert displacement_demand(sp, 1.5, 0.08) == pytest.approx(sp.SDe(1.5, 0.08))
    # above b T1 the demand is not below S_eZ(T1) b^2 T1^2 / 4 pi^2 (eq. C8.7.1.12)
    d = displacement_demand(sp, 2.0, 0.08, b, 6.7)
    floor = floor_spectrum(sp, b, 6.7, 0.25, 0.08) * (1.1 * 0.25) ** 2 / (4 * math.pi ** 2)
    assert d >= floor - 1e-12 and d >= sp.SDe(2.0, 0.08) - 1e-12


def test_nonlinear_check_single_block():
    t, h = 0.5, 4.0
    wall = SimpleOverturning([Storey(h, t, density=1800.0)], [])
    sp = _site()
    res = analyse(wall, Seismic({"SLV": sp}, FC=1.0))
    lin, nl = res.checks
    assert lin.demand == pytest.approx(sp.pga / 2)
    assert lin.capacity == pytest.approx(t / h * G, rel=1e-6)
    # d_SLV = 0.4 d0 = 0.2 t; a(d) from theta: -t/2 cos th + h/2 sin th + t/2 = 0.2 t
    d = 0.2 * t
    beta = math.atan(t / h)
    R = math.hypot(t, h) / 2
    th = beta + math.asin((d - t / 2) / R)
    a = math.tan(beta - th) * G
    T = 1.68 * math.pi * math.sqrt(d / a)
    assert nl.capacity == pytest.approx(d, rel=1e-6)
    assert nl.details["T"] == pytest.approx(T, rel=2e-3)     # curve sampled at 101 points
    assert nl.demand == pytest.approx(sp.SDe(T, 0.08), rel=5e-3)


def test_ntc_displacement_spectrum_beyond_TE():
    # NTC 2018 §3.2.3.2.3: SDe = Se (T / 2 pi)^2 up to T_E, eq. 3.2.11 from T_E to T_F, then
    # d_g = 0.025 ag S TC TD (eq. 3.2.12); Table 3.2.VII: soil A T_E = 4.5 s, T_F = 10 s
    ag, F0, Tc = 0.25 * G, 2.5, 0.30
    sp = NTCSpectrum(ag, F0, Tc, "A")
    TC, TD = 0.30, 4.0 * 0.25 + 1.6
    dg = 0.025 * ag * 1.0 * TC * TD
    assert (sp.TE, sp.TF) == (4.5, 10.0) and sp.dg == pytest.approx(dg, rel=1e-12)
    eta = math.sqrt(10 / 13)   # 8 %
    assert sp.SDe(4.4, 0.08) == pytest.approx(ag * eta * F0 * TC * TD / (4 * math.pi ** 2),
                                              rel=1e-12)
    assert sp.SDe(7.0, 0.08) == pytest.approx(
        dg * (F0 * eta + (1 - F0 * eta) * (7.0 - 4.5) / (10.0 - 4.5)), rel=1e-12)
    assert sp.SDe(12.0, 0.08) == pytest.approx(dg, rel=1e-12)
    assert NTCSpectrum(ag, F0, Tc, "C").TE == 6.0 and NTCSpectrum(ag, F0, Tc, "B").TE == 5.0


# --- full chains reproduced by hand (vertical flexure, corner) ------------------------------------
#
# Both cases are written so that the capacity curve has a closed form; every number below comes
# from the formulas of the Circolare 2019 §C8.7.1.2.1 and NTC 2018 §3.2.3.2 evaluated with plain
# arithmetic in the test (murus supplies only the results compared). Tolerances: 1e-9 for what
# murus evaluates in closed form (alpha0, e*, M*, a0*, floor acceleration: its virtual
# displacements are central differences, error ~1e-10), 1e-6 for d0* (bisection) and for what it
# reads from its capacity curve sampled at n = 2001 points (a(d), T, demand: linear interpolation
# between points 5e-4 d0 apart, relative error of order (5e-4)^2 / 8 = 3e-8). Measured: <= 1.4e-8.

def _ntc_by_hand(ag, F0, Tc_star, soil):
    """Se(T, xi) and SDe(T, xi) of NTC 2018 eqs. 3.2.2-3.2.12 for soils A and B (T1 topography)."""
    a = ag / G
    SS = {"A": 1.0, "B": min(max(1.40 - 0.40 * F0 * a, 1.0), 1.20)}[soil]
    CC = {"A": 1.0, "B": 1.10 * Tc_star ** -0.20}[soil]
    TE, TF = {"A": (4.5, 10.0), "B": (5.0, 10.0)}[soil]
    TC = CC * Tc_star
    TB, TD = TC / 3, 4.0 * a + 1.6

    def Se(T, xi):
        eta = max(math.sqrt(10 / (5 + 100 * xi)), 0.55)
        if T < TB:
            return ag * SS * eta * F0 * (T / TB + (1 - T / TB) / (eta * F0))
        if T < TC:
            return ag * SS * eta * F0
        if T < TD:
            return ag * SS * eta * F0 * TC / T
        return ag * SS * eta * F0 * TC * TD / T ** 2

    def SDe(T, xi):
        eta = max(math.sqrt(10 / (5 + 100 * xi)), 0.55)
        dg = 0.025 * ag * SS * TC * TD
        if T <= TE:
            return Se(T, xi) * T ** 2 / (4 * math.pi ** 2)
        if T <= TF:
            return dg * (F0 * eta + (1 - F0 * eta) * (T - TE) / (TF - TE))
        return dg

    return Se, SDe, ag * SS


def test_vertical_flexure_at_height_by_hand():
    # A wall of the second storey, restrained at both floors (z0 = 3.5 m in a two-storey
    # building, H = 6.7 m, T1 = 0.25 s), hinge at mid-height h1 = h/2, the floor above bearing
    # N at mid-thickness (no horizontal inertia: it loads the top restraint).
    h, t, rho, N, z0 = 3.2, 0.45, 2000.0, 15.0e3, 3.5
    h1 = h / 2
    W = rho * G * t * h
    FC = 1.35
    # Kinematics (x outward, y up, origin at the outer face of the base A): the lower block turns
    # by theta about A, B = (-t cos + h1 sin, t sin + h1 cos); with h1 = h2 the upper block is the
    # mirror of the lower one about the horizontal through B, so C = (0, 2 yB), both centroids
    # have x = xB / 2, and N (mirror of the mid-bottom point (-t/2, 0)) has y = 2 yB - t/2 sin.
    def yB_d(th):                                                # d yB / d theta
        return t * math.cos(th) - h1 * math.sin(th)

    def xB_d(th):                                                # d xB / d theta
        return t * math.sin(th) + h1 * math.cos(th)

    # virtual work, eq. [C8.7.1.1]: alpha (W xB'/2) = (W/2)(yB'/2) + (W/2)(3 yB'/2)
    #                                                  + N (2 yB' - t/2 cos)
    def alpha(th):
        return (W * yB_d(th) + N * (2 * yB_d(th) - 0.5 * t * math.cos(th))) / (W * xB_d(th) / 2)

    a0 = alpha(0.0)
    assert a0 == pytest.approx((W * t + 1.5 * N * t) / (W * h1 / 2), rel=1e-12)
    # e* (eq. C8.7.1.5): both masses move by h1/2 per unit rotation -> e* = 1, M* = W / g
    e, M = 1.0, W / G
    a0s = a0 * G / (e * FC)                                      # eq. [C8.7.1.8]
    # collapse where alpha = 0: tan theta0 = t (W + 1.5 N) / ((W + 2 N) h1)
    th0 = math.atan(t * (W + 1.5 * N) / ((W + 2 * N) * h1))
    assert alpha(th0) == pytest.approx(0.0, abs=1e-12)
    # control point: centroid of the masses, x = xB/2; eq. [C8.7.1.4] factor = 1
    def dstar(th):
        return 0.5 * (t - t * math.cos(th) + h1 * math.sin(th))

    d0 = dstar(th0)
    # SLV: d = 0.4 d0 -> h1 sin - t cos = 2 d - t -> theta = beta + asin((2 d - t) / R)
    R, beta = math.hypot(t, h1), math.atan(t / h1)
    d_slv = 0.4 * d0
    th = beta + math.asin((2 * d_slv - t) / R)
    assert dstar(th) == pytest.approx(d_slv, rel=1e-12)
    a_slv = alpha(th) * G / (e * FC)
    T_slv = 1.68 * math.pi * math.sqrt(d_slv / a_slv)            # eq. [C8.7.1.10]
    # demand at z0 (Circolare 2019 §C7.2.3, first mode, n = 2: gamma1 = 6/5, psi1 = z0 / H,
    # xi1 = 5 %): a_Z = Se(T1) gamma psi sqrt(1 + 0.0004 xi1%^2)     eqs. [C7.2.7], [C7.2.10]
    Se, SDe, pga = _ntc_by_hand(0.2 * G, 2.4, 0.31, "B")
    T1, H, n = 0.25, 6.7, 2
    aZ = Se(T1, 0.05) * 3 * n / (2 * n + 1) * (z0 / H) * math.sqrt(1 + 0.0004 * 25)
    # floor spectrum eq. [C7.2.6] (a = 0.8, b = 1.1; amplification 1.1 xi1^-0.5 eta(xi) with
    # xi1 = 0.05 as a fraction, the reading documented in murus.mechanisms.demand)
    def SeZ(T, xi):
        eta = math.sqrt(10 / (5 + 100 * xi))
        A = 1.1 * 0.05 ** -0.5 * eta
        if T < 0.8 * T1:
            v = A * aZ / (1 + (A - 1) * (1 - T / (0.8 * T1)) ** 1.6)
        elif T < 1.1 * T1:
            v = A * aZ
        else:
            v = A * aZ / (1 + (A - 1) * (T / (1.1 * T1) - 1) ** 1.2)
        return max(v, Se(T, xi)) if T > T1 else v             # eq. [C7.2.5]

    k = 1 / (4 * math.pi ** 2)
    assert T_slv > 1.1 * T1
    # eq. [C8.7.1.12]: S_eZ(T) T^2 / 4 pi^2, not below S_eZ(T1)(b T1)^2 / 4 pi^2 beyond b T1; murus
    # also keeps the ground SDe(T) as a floor
    dem = max(SeZ(T_slv, 0.08) * T_slv ** 2 * k, SeZ(T1, 0.08) * (1.1 * T1) ** 2 * k,
              SDe(T_slv, 0.08))
    # nonlinear SLV check (§C8.7.1.2.1.8): ratio = d / demand, not below the activation ratio
    act = a0s / max(pga, aZ)
    ratio = max(d_slv / dem, act)

    sp = NTCSpectrum(0.2 * G, 2.4, 0.31, "B")
    vf = VerticalFlexure(height=h, thickness=t, weight=W, h1=h1, top_load=N, z0=z0)
    res = analyse(vf, Seismic({"SLV": sp}, Building(T1=T1, height=H, storeys=n), FC=FC),
                  n=2001)
    lin, nl = res.checks
    assert res.alpha0 == pytest.approx(a0, rel=1e-9)
    assert res.e_star == pytest.approx(e, rel=1e-9)
    assert res.M_star == pytest.approx(M, rel=1e-9)
    assert res.a0_star == pytest.approx(a0s, rel=1e-9)
    assert res.d0_star == pytest.approx(d0, rel=1e-6)            # bisection on theta0
    assert lin.details["a_floor"] == pytest.approx(aZ, rel=1e-9)
    assert lin.demand == pytest.approx(max(pga, aZ) / 2, rel=1e-9)
    assert nl.capacity == pytest.approx(d_slv, rel=1e-6)
    assert nl.details["a_at_d"] == pytest.approx(a_slv, rel=1e-6)
    assert nl.details["T"] == pytest.approx(T_slv, rel=1e-6)
    assert nl.demand == pytest.approx(dem, rel=1e-6)
    assert nl.details["displacement_ratio"] == pytest.approx(d_slv / dem, rel=1e-6)
    assert nl.ratio == pytest.approx(ratio, rel=1e-6)


def test_corner_wedge_nonlinear_by_hand():
    # Corner wedge at ground level with a roof load P at the top (at the centroid of the
    # wedge's weights in plan, moving with it), soil A: its long periods reach the reduced
    # displacement spectrum of NTC 2018 eq. 3.2.11 at the SLC.
    h, t, rho, phi, P, FC = 6.7, 0.45, 2000.0, 30.0, 6.0e3, 1.35
    L = h * math.tan(math.radians(phi))
    r2 = math.sqrt(2.0)
    Wi = rho * G * t * L * h / 2                                 # each triangle
    s1, s2 = (L / 3 + t / 2) / r2, (t / 2 + t + L / 3) / r2    # distances along the bisector
    W, s = 2 * Wi, (s1 + s2) / 2
    k = 2 * h / 3                                                # height of the triangles' G
    yb = (W * k + P * h) / (W + P)                               # centroid height of all masses
    # all masses at the same distance s from the hinge line: the wedge is a block of half-width
    # s and centroid height yb: alpha(theta) = tan(beta - theta), tan(beta) = s / yb
    beta = math.atan(s / yb)
    e = (W * k + P * h) ** 2 / ((W + P) * (W * k ** 2 + P * h ** 2))    # eq. [C8.7.1.5]
    M = e * (W + P) / G
    a0 = s / yb
    a0s = a0 * G / (e * FC)
    # control point = centroid of the masses: dC(theta) = s - s cos + yb sin; eq. [C8.7.1.4]
    # factor sum W dx^2 / (dx_C sum W dx) = 1 / e*; dC(beta) = s -> d0* = s / e*
    d0 = s / e
    def dstar(th):
        return (s - s * math.cos(th) + yb * math.sin(th)) / e

    Rr = math.hypot(s, yb)
    Se, SDe, pga = _ntc_by_hand(0.25 * G, 2.5, 0.30, "A")
    out = {}
    for ls, frac, c, xi in (("SLV", 0.4, 1.68, 0.08), ("SLC", 0.6, 1.56, 0.10)):
        d = frac * d0
        th = beta - math.asin((1 - e * d / s) * s / Rr)   # s - s cos + yb sin = e d
        assert dstar(th) == pytest.approx(d, rel=1e-12)
        a = math.tan(beta - th) * G / (e * FC)
        T = c * math.pi * math.sqrt(d / a)                # eqs. [C8.7.1.10], [C8.7.1.11]
        out[ls] = (d, a, T, SDe(T, xi))
    assert out["SLC"][2] > 4.5 > out["SLV"][2]           # SLC beyond T_E (eq. 3.2.11)

    sp = NTCSpectrum(0.25 * G, 2.5, 0.30, "A")
    c = CornerOverturning(height=h, t1=t, t2=t, density=rho, crack_angle_deg=phi, roof_load=P)
    res = analyse(c, Seismic({"SLV": sp, "SLC": sp}, FC=FC), n=2001)
    assert res.alpha0 == pytest.approx(a0, rel=1e-9)
    assert res.e_star == pytest.approx(e, rel=1e-9)
    assert res.M_star == pytest.approx(M, rel=1e-9)
    assert res.a0_star == pytest.approx(a0s, rel=1e-9)
    assert res.d0_star == pytest.approx(d0, rel=1e-6)
    lin = res.checks[0]
    assert lin.demand == pytest.approx(pga / 2, rel=1e-12)
    for ch in res.checks[1:]:
        d, a, T, dem = out[ch.limit_state]
        assert ch.capacity == pytest.approx(d, rel=1e-6), ch.limit_state
        assert ch.details["a_at_d"] == pytest.approx(a, rel=1e-6), ch.limit_state
        assert ch.details["T"] == pytest.approx(T, rel=1e-6), ch.limit_state
        assert ch.demand == pytest.approx(dem, rel=1e-6), ch.limit_state
        assert ch.ratio == pytest.approx(max(d / dem, a0s / pga), rel=1e-6), ch.limit_state


# --- worked example (hand calculation) ------------------------------------------------------------

def test_hand_example_two_storey():
    data = json.loads((DATA / "hand_example_two_storey.json").read_text())
    inp, exp, tol = data["input"], data["expected"], data["relative_tolerance"]
    site = inp["site_SLV"]
    sp = NTCSpectrum(site["ag_g"] * G, site["F0"], site["Tc_star"], site["soil"],
                     site["topography"])
    for k, v in exp["spectrum"].items():
        got = sp.Se(0.25) if k == "Se_plateau" else getattr(sp, k)
        assert got == pytest.approx(v, rel=tol), k
    s = Seismic({"SLV": sp}, Building(**inp["building"]), inp["FC"], inp["q"])
    r1, r2 = overturning(inp["storeys"], inp["floors"], s)
    for res, key in ((r1, "hinge_1"), (r2, "hinge_2")):
        e = exp[key]
        for name in ("alpha0", "e_star", "M_star", "a0_star"):
            assert getattr(res, name) == pytest.approx(e[name], rel=tol), (key, name)
        lin = [c for c in res.checks if c.method == "linear" and c.limit_state == "SLV"][0]
        assert lin.ratio == pytest.approx(e["ratio_SLV_linear"], rel=tol), key
    assert [c for c in r1.checks if c.method == "linear"][0].demand == pytest.approx(
        exp["hinge_1"]["demand_SLV_linear"], rel=tol)
    assert r2.checks[0].details["a_floor"] == pytest.approx(exp["hinge_2"]["a_floor"], rel=tol)


def test_errors_carry_keys():
    with pytest.raises(MechanismError) as e:
        Storey(height=-1.0, thickness=0.5, density=1800.0)
    assert e.value.key == ("height",)
    with pytest.raises(MechanismError) as e:
        Seismic({"SLV": _site()}, FC=1.5)
    assert e.value.key == ("FC",)
    with pytest.raises(MechanismError):   # a mechanism above the ground needs the building
        analyse(SimpleOverturning([Storey(3, 0.5, density=1800.0)] * 2, [], hinge=1),
                Seismic({"SLV": _site()}))


# --- command line --------------------------------------------------------------------------------

def test_cli_json_and_out(tmp_path):
    runner = CliRunner()
    res = runner.invoke(app, ["mechanism", str(EXAMPLE), "--json", "--out", str(tmp_path / "o")])
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert {m["name"] for m in out["mechanisms"]} == {
        "overturning from storey 1", "overturning from storey 2", "vertical flexure of storey 1",
        "vertical flexure of storey 2", "corner overturning 1"}
    assert out["governing"]["ratio"] == min(m["ratio"] for m in out["mechanisms"])
    saved = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert saved["governing"] == out["governing"]
    assert (tmp_path / "o" / "capacity_overturning_from_storey_1.png").stat().st_size > 0
    res = runner.invoke(app, ["mechanism", str(EXAMPLE)])
    assert res.exit_code == 0 and "governing:" in res.stdout


@pytest.mark.parametrize("edit, where", [
    (("FC = 1.35", "FC = 1.50"), "line"),
    (("thickness = 0.45", "thickness = -0.45"), "storeys"),
    (("level = 2", "level = 5"), "level"),
    (("F0 = 2.40", "F0 = 9.0"), "F0"),
    (("crack_angle_deg = 30.0", "crack_angle_deg = 80.0"), "corners"),
    (("T1 = 0.25", "T1 = 0.0"), "T1"),
    (("x = 0.30", "x = 0.60"), "floors.x"),
])
def test_cli_bad_input_one_line(tmp_path, edit, where):
    text = EXAMPLE.read_text(encoding="utf-8").replace(*edit)
    case = tmp_path / "bad.toml"
    case.write_text(text, encoding="utf-8")
    res = CliRunner().invoke(app, ["mechanism", str(case), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and where in lines[0], lines
    assert not (tmp_path / "o").exists()


def test_cli_ec8_single_storey(tmp_path):
    # a one-storey wall on EN 1998-1 ground B: the linear SLV demand is ag S / q (S = 1.2)
    case = tmp_path / "wall.toml"
    case.write_text(
        'title = "free-standing wall"\n'
        '[site]\nspectrum = "ec8"\nground = "B"\n[site.SLV]\nag = 2.0\n'
        '[analysis]\nFC = 1.0\nmechanisms = ["overturning"]\n'
        '[[storeys]]\nheight = 4.0\nthickness = 0.5\ndensity = 1800.0\n', encoding="utf-8")
    res = CliRunner().invoke(app, ["mechanism", str(case), "--json"])
    assert res.exit_code == 0, res.output
    m = json.loads(res.stdout)["mechanisms"][0]
    lin = [c for c in m["checks"] if c["method"] == "linear"][0]
    assert m["alpha0"] == pytest.approx(0.125, rel=1e-6)
    assert lin["demand"] == pytest.approx(2.0 * 1.2 / 2.0, rel=1e-9)
    assert lin["ratio"] == pytest.approx(0.125 * G / 1.2, rel=1e-6)


def test_public_api_docstrings():
    # numpydoc sections, by the rule of tests/test_docstrings.py (errors exempt)
    import importlib
    import inspect
    import re

    bad = []
    for modname in ("murus.mechanisms", "murus.eurocode.ntc", "murus.mechanisms.demand",
                    "murus.mechanisms.checks", "murus.mechanisms.facade",
                    "murus.mechanisms.kinematics", "murus.mechanisms.case",
                    "murus.mechanisms.cli"):
        mod = importlib.import_module(modname)
        for name in mod.__all__:
            obj = getattr(mod, name)
            if not (inspect.isfunction(obj) or inspect.isclass(obj)):
                continue
            if inspect.isclass(obj) and issubclass(obj, BaseException):
                continue
            doc = inspect.getdoc(obj) or ""
            params = [p for p in inspect.signature(obj).parameters if p not in ("self", "cls")]
            sections = "Parameters|Attributes" if inspect.isclass(obj) else "Parameters"
            if not doc or (params and not re.search(rf"^({sections})\n-{{3,}}", doc, re.M)):
                bad.append(f"{modname}.{name}")
    assert not bad, bad


def test_ties_in_the_curve():
    # by default the ties act in alpha0 but not in the capacity curve (d0* = t / 2 of the free
    # block); with ties_in_curve the tie keeps the wall up to a larger rotation
    t, h, rho = 0.5, 4.0, 1800.0
    W = rho * G * t * h
    wall = SimpleOverturning([Storey(h, t, density=rho)], [Floor(1, tie=0.2 * W)])
    s = Seismic({"SLV": _site()}, FC=1.0)
    res = analyse(wall, s)
    assert res.alpha0 == pytest.approx((W * t / 2 + 0.2 * W * h) / (W * h / 2), rel=1e-7)
    assert res.d0_star == pytest.approx(t / 2, rel=1e-6)
    assert res.info["ties_in_curve"] is False
    tied = analyse(wall, s, ties_in_curve=True)
    assert tied.d0_star > res.d0_star and tied.info["ties_in_curve"] is True
    assert tied.curve["alpha"][0] == pytest.approx(res.alpha0)


def test_verdict_code_and_all():
    # "code": the SLV verdict is the nonlinear check, the linear SLV check is for information;
    # "all": every check governs
    t, h = 0.5, 4.0
    wall = SimpleOverturning([Storey(h, t, density=1800.0)], [])
    s = Seismic({"SLV": _site(ag_g=0.3)}, FC=1.0)
    code, every = analyse(wall, s), analyse(wall, s, verdict="all")
    lin_c = [c for c in code.checks if c.method == "linear"][0]
    nl_c = [c for c in code.checks if c.method == "nonlinear"][0]
    assert not lin_c.governs and nl_c.governs
    assert code.ratio == pytest.approx(nl_c.ratio)
    assert every.ratio == pytest.approx(min(lin_c.ratio, nl_c.ratio))
    with pytest.raises(MechanismError):
        analyse(wall, s, verdict="strict")
