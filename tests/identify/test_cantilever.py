"""Timoshenko cantilever with a tip mass (murus.identify.cantilever) against closed forms.

- Euler-Bernoulli limit: f_n = (beta_n L)^2 / (2 pi H^2) sqrt(E I / (rho A)), beta_1 L =
  1.875104069, beta_2 L = 4.694091133 (Clough & Penzien, Table 18-1); the cubic Hermite
  element converges as h^4 for these (Strang & Fix), so 20 elements are within 1e-6 and halving
  the element size divides the error by about 16.
- Massless beam with a tip mass M: the element stiffness is exact, so f = sqrt(1/(F M)) / 2 pi
  with the static flexibility F = H^3/(3 E I) + H/(kappa G A) holds to round-off with any mesh;
  with a tip rotary inertia J the 2x2 flexibility of the tip (deflection, rotation) gives the
  two frequencies exactly.
- The exact Timoshenko cantilever with tip mass and tip inertia: the equations
  E I psi'' + kappa G A (w' - psi) + rho I w^2 psi = 0, kappa G A (w'' - psi') + rho A w^2 w = 0,
  clamped at the base, tip conditions E I psi' = J w^2 psi and kappa G A (w' - psi) = M w^2 w,
  solved by the transfer matrix expm(A H) and a root search on the 2x2 determinant (no
  discretisation): the finite elements converge to it from above as h^2.
- Sum of effective masses = total mass (all modes kept, consistent mass matrix).
- A massless beam with a tip mass under a base acceleration is a single-degree-of-freedom
  oscillator: the top displacement is the SDOF one and the base shear is M times the top
  absolute acceleration (to round-off).
"""

import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import brentq

from murus.identify.cantilever import Cantilever, CantileverError

# Mordant et al. (SERIES) short wall: 0.72 x 1.80 x 0.138 m, 5 t on top; E = 1000 fk (EN 1996-1-1
# §3.7.2) with the measured fk = 5.6 MPa (see validation/winkler.py); clay masonry 1800 kg/m3
# (assumed)
WALL = dict(height=1.8, length=0.72, thickness=0.138, modulus=5.6e9, density=1800.0)


def eb_frequency(beta_l, c):
    EI = c.modulus * c.inertia
    return beta_l**2 / (2 * math.pi * c.height**2) * math.sqrt(EI / (c.density * c.area))


def exact_timoshenko(c, fmax, n_scan=1500):
    """Natural frequencies [Hz] below fmax of the continuous Timoshenko cantilever ``c``."""
    EI, kGA = c.modulus * c.inertia, c.kappa * c.G * c.area
    rA, rI = c.density * c.area, c.density * c.inertia

    def det(f):
        w2 = (2 * math.pi * f) ** 2
        A = np.array([[0.0, 1.0, 0.0, 0.0],          # y = (w, w', psi, psi')
                      [-rA * w2 / kGA, 0.0, 0.0, 1.0],
                      [0.0, 0.0, 0.0, 1.0],
                      [0.0, -kGA / EI, (kGA - rI * w2) / EI, 0.0]])
        w, wp, psi, psip = expm(A * c.height)[:, [1, 3]]  # w(0) = psi(0) = 0
        r1 = EI * psip - c.tip_inertia * w2 * psi
        r2 = kGA * (wp - psi) - c.tip_mass * w2 * w
        return r1[0] * r2[1] - r1[1] * r2[0]

    fs = np.linspace(0.5, fmax, n_scan)
    d = np.array([det(f) for f in fs])
    k = np.nonzero(np.sign(d[:-1]) != np.sign(d[1:]))[0]
    return np.array([brentq(det, fs[i], fs[i + 1], xtol=1e-13) for i in k])


@pytest.mark.parametrize("tip", [dict(tip_mass=5000.0, tip_inertia=300.0), {}])
def test_timoshenko_against_the_exact_solution(tip):
    """Mordant et al. (SERIES) short wall (shear matters: H/L = 2.5), with and without the 5 t on
    top."""
    ref = exact_timoshenko(Cantilever(**WALL, **tip), 400.0)[:2]
    errs = []
    for n in (8, 16, 32):
        f = Cantilever(**WALL, **tip, elements=n).frequencies(2)
        errs.append(f / ref - 1.0)
        assert (f > ref).all()  # a consistent-mass model is stiffer than the continuum
    assert Cantilever(**WALL, **tip).frequencies(2) == pytest.approx(ref, rel=5e-4)
    # O(h^2): halving h divides the error by ~4
    for a, b in zip(errs[:-1], errs[1:], strict=True):
        assert a / b == pytest.approx(np.full(2, 4.0), rel=0.1)


def test_euler_bernoulli_limit_and_convergence_rate():
    errs = []
    for n in (2, 4, 8):
        c = Cantilever(**WALL, shear=False, rotary_inertia=False, elements=n)
        f = c.frequencies(2)
        errs.append(f[0] / eb_frequency(1.875104069, c) - 1.0)
    c = Cantilever(**WALL, shear=False, rotary_inertia=False, elements=20)
    f = c.frequencies(2)
    assert f[0] == pytest.approx(eb_frequency(1.875104069, c), rel=1e-6)
    assert f[1] == pytest.approx(eb_frequency(4.694091133, c), rel=1e-5)
    # O(h^4): halving h divides the error by ~16 (upper bound of the FE frequency: errors > 0)
    assert all(e > 0 for e in errs)
    for a, b in zip(errs[:-1], errs[1:], strict=True):
        assert 12.0 < a / b < 20.0


@pytest.mark.parametrize("elements", [1, 3, 10])
def test_tip_mass_on_massless_beam_is_exact(elements):
    c = Cantilever(**{**WALL, "density": 0.0}, tip_mass=5000.0, elements=elements)
    f = c.frequencies(1)[0]
    assert f == pytest.approx(1 / (2 * math.pi) / math.sqrt(c.tip_flexibility() * 5000.0),
                              rel=1e-10)
    # shear matters for this squat wall: the Euler-Bernoulli beam is stiffer
    eb = Cantilever(**{**WALL, "density": 0.0}, tip_mass=5000.0, shear=False)
    assert eb.frequencies(1)[0] > 1.05 * f


def test_tip_rotary_inertia_two_dof_closed_form():
    M, J = 5000.0, 800.0
    c = Cantilever(**{**WALL, "density": 0.0}, tip_mass=M, tip_inertia=J, elements=7)
    H, EI = c.height, c.modulus * c.inertia
    F = np.array([[H**3 / (3 * EI) + H / (c.kappa * c.G * c.area), H**2 / (2 * EI)],
                  [H**2 / (2 * EI), H / EI]])
    lam = np.sort(np.linalg.eigvals(np.linalg.solve(np.diag([M, J]), np.linalg.inv(F))).real)
    assert c.frequencies(2) == pytest.approx(np.sqrt(lam) / (2 * math.pi), rel=1e-9)


def test_effective_masses_sum_to_the_total_mass():
    """Over all modes the effective masses sum to the total mass less the part of the first
    element that the consistent mass attaches to the support (it moves with the base): that
    part is O(h), so it halves as the mesh is refined, and the base shear of a rigid wall
    accounts for it (test below)."""
    deficits = []
    for n in (4, 8, 16):
        c = Cantilever(**WALL, tip_mass=5000.0, tip_inertia=300.0, elements=n)
        md = c.modes()
        deficits.append(c.total_mass - md.effective_mass.sum())
        assert md.shape[-1] == pytest.approx(np.ones(md.frequency.size))
        assert md.effective_mass[0] / c.total_mass > 0.8  # the tip mass makes mode 1 dominant
    assert all(d > 0 for d in deficits)
    for a, b in zip(deficits[:-1], deficits[1:], strict=True):
        assert a / b == pytest.approx(2.0, rel=0.05)


def test_sdof_response_and_base_shear():
    from murus.motion._kernels import sdof_history

    M = 5000.0
    c = Cantilever(**{**WALL, "density": 0.0}, tip_mass=M, elements=4)
    dt = 0.005
    t = np.arange(0, 4, dt)
    acc = 2.0 * np.sin(2 * math.pi * 3.0 * t) * np.exp(-t)
    r = c.response((acc, dt), damping=0.05)
    w = 2 * math.pi * c.frequencies(1)[0]
    u, _ = sdof_history(acc, dt, w, 0.05)
    assert r.top_displacement == pytest.approx(u, abs=1e-12 * np.abs(u).max() + 1e-15)
    assert r.base_shear == pytest.approx(M * r.top_acceleration,
                                         abs=1e-9 * np.abs(r.base_shear).max())
    assert r.base_moment == pytest.approx(c.height * r.base_shear,
                                          abs=1e-9 * np.abs(r.base_moment).max())
    # equilibrium of the oscillator: M (u'' + a_g) = -k u - c u'
    k = 1 / c.tip_flexibility()
    assert np.abs(r.base_shear + k * u).max() < 0.1 * np.abs(k * u).max() + 1e-9 * k


@pytest.mark.parametrize("n_modes", [None, 2])
def test_rigid_wall_moves_with_the_base(n_modes):
    """A very stiff wall (E x 1e6, first frequency ~ 10 kHz against a 2 Hz input): every point
    has the base acceleration, so the base shear is the total mass x a_g and the base moment
    the total moment of the masses about the base x a_g, to O((f_input/f_1)^2) ~ 1e-7, with
    all modes or with two (the residual mass carries the rest)."""
    c = Cantilever(**{**WALL, "modulus": 5.6e15}, tip_mass=5000.0, elements=6)
    dt = 0.01
    t = np.arange(0, 2, dt)
    acc = 1.5 * np.sin(2 * math.pi * 2.0 * t)
    r = c.response((acc, dt), damping=0.05, n_modes=n_modes)
    mass = c.total_mass
    moment = 5000.0 * c.height + c.density * c.area * c.height**2 / 2
    assert r.base_shear == pytest.approx(mass * acc, abs=1e-5 * mass)
    assert r.base_moment == pytest.approx(moment * acc, abs=1e-5 * moment)


def test_fit_modulus_recovers_the_frequency():
    c = Cantilever(**WALL, tip_mass=5000.0)
    f1 = c.frequencies(1)[0]
    E = c.fit_modulus(0.7 * f1)
    assert E == pytest.approx(0.49 * c.modulus, rel=1e-12)
    c2 = Cantilever(**{**WALL, "modulus": E}, tip_mass=5000.0)
    assert c2.frequencies(1)[0] == pytest.approx(0.7 * f1, rel=1e-9)


@pytest.mark.parametrize("kw, word", [
    ({"height": -1.0}, "height"),
    ({"modulus": float("nan")}, "modulus"),
    ({"elements": 0}, "elements"),
    ({"density": 0.0}, "needs mass"),
])
def test_bad_parameters(kw, word):
    with pytest.raises(CantileverError, match=word):
        Cantilever(**{**WALL, **kw})
