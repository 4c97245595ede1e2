"""Response spectra against closed-form SDOF responses (Nigam and Jennings 1969 recurrence)."""

import math

import numpy as np
import pytest

from murus.motion import GroundMotion
from murus.motion._kernels import nj_coefficients
from murus.motion.spectra import response_spectrum


@pytest.mark.parametrize("omega,xi,h", [(7.3, 0.05, 0.013), (60.0, 0.0, 0.01), (2.0, 0.3, 0.2)])
def test_coefficients_equal_matrix_exponential(omega, xi, h):
    """The recurrence matrices are the exact transition of the augmented linear system
    (state u, u', a, a') over one step: they must equal expm(M h) to round-off."""
    from scipy.linalg import expm

    M = np.zeros((4, 4))
    M[0, 1] = 1
    M[1, 0] = -omega**2
    M[1, 1] = -2 * xi * omega
    M[1, 2] = -1
    M[2, 3] = 1
    E = expm(M * h)
    A = E[:2, :2]
    B = np.column_stack([E[:2, 2] - E[:2, 3] / h, E[:2, 3] / h])
    c = np.array(nj_coefficients(omega, xi, h))
    scale = np.abs(np.concatenate([A.ravel(), B.ravel()])).max()
    assert np.allclose(c[:4], A.ravel(), atol=1e-12 * scale)
    assert np.allclose(c[4:], B.ravel(), atol=1e-12 * scale)


def _step_peak(T, xi, a0):
    """Peak |u| of an oscillator at rest under a constant ground acceleration a0 (applied at
    t = 0): u = -(a0/w²)(1 - e^{-xi w t}(cos wd t + xi/sqrt(1-xi²) sin wd t)); first peak at
    t = pi/wd: (a0/w²)(1 + exp(-xi pi / sqrt(1 - xi²)))."""
    w = 2 * math.pi / T
    return a0 / w**2 * (1 + math.exp(-xi * math.pi / math.sqrt(1 - xi**2)))


@pytest.mark.parametrize("xi", [0.0, 0.05, 0.2])
def test_step_response_peak_all_periods(xi):
    dt = 0.01
    a0 = 1.7
    gm = GroundMotion(dt=dt, acc=np.full(2001, a0))  # 20 s constant: exact for linear input
    T = np.geomspace(0.005, 2.0, 40)  # from T = dt/2 (oversampled) to 200 dt
    sp = response_spectrum(gm, T, xi)
    exact = np.array([_step_peak(t, xi, a0) for t in T])
    assert np.max(np.abs(sp.sd / exact - 1)) < 2e-4
    # classical step-sampled peaks are biased low at short periods: the refinement matters
    coarse = response_spectrum(gm, T, xi, oversample=1, refine=False)
    short = T < 10 * dt
    assert np.max(np.abs(coarse.sd[short] / exact[short] - 1)) > 0.02


def _sine_response(t, T, xi, A, f):
    """Exact relative displacement of an oscillator at rest for a_g = A sin(2 pi f t)."""
    w = 2 * np.pi / T
    W = 2 * np.pi * f
    wd = w * np.sqrt(1 - xi**2)
    # particular: u = C sin Wt + D cos Wt with u'' + 2 xi w u' + w² u = -A sin Wt
    K = np.array([[w**2 - W**2, -2 * xi * w * W], [2 * xi * w * W, w**2 - W**2]])
    C, D = np.linalg.solve(K, [-A, 0.0])
    E = -D
    F = (xi * w * E - W * C) / wd
    return C * np.sin(W * t) + D * np.cos(W * t) + np.exp(-xi * w * t) * (
        E * np.cos(wd * t) + F * np.sin(wd * t))


def test_sine_input_against_closed_form():
    dt, A, f, dur = 0.001, 2.0, 2.0, 3.0
    t = np.arange(int(round(dur / dt)) + 1) * dt
    gm = GroundMotion(dt=dt, acc=A * np.sin(2 * np.pi * f * t))
    T = np.array([0.004, 0.008, 0.02, 0.1, 0.3, 0.5, 1.0, 2.0])
    xi = 0.05
    sp = response_spectrum(gm, T, xi)
    tf = np.linspace(0, dur, 600001)
    exact = np.array([np.max(np.abs(_sine_response(tf, Ti, xi, A, f))) for Ti in T])
    # input interpolation error (W dt)²/8 = 2e-5 and dense-grid peak error are below 1e-4
    assert np.max(np.abs(sp.sd / exact - 1)) < 1e-3


def test_undamped_sa_equals_psa_and_definitions():
    rng = np.random.default_rng(3)
    gm = GroundMotion(dt=0.01, acc=rng.standard_normal(1500))
    T = np.geomspace(0.02, 5, 30)
    sp = response_spectrum(gm, T, 0.0)
    # undamped: absolute acceleration = -w² u exactly, so SA = PSA (to the peak refinement)
    assert np.allclose(sp.sa, sp.psa, rtol=1e-3)
    w = 2 * np.pi / T
    assert np.allclose(sp.psa, w**2 * sp.sd, rtol=1e-14)
    assert np.allclose(sp.psv, w * sp.sd, rtol=1e-14)
    assert sp["psa"] is sp.psa


def test_linearity_and_zero_period():
    rng = np.random.default_rng(4)
    gm = GroundMotion(dt=0.005, acc=rng.standard_normal(800))
    s1 = response_spectrum(gm, [0.0, 0.1, 1.0])
    s2 = response_spectrum(gm.scaled(-3.0), [0.0, 0.1, 1.0])
    assert np.allclose(s2.psa, 3 * s1.psa, rtol=1e-12)
    assert s1.psa[0] == pytest.approx(gm.pga, rel=1e-15)


def test_long_period_sd_tends_to_pgd():
    """A very flexible oscillator stays still in absolute terms: SD -> PGD (relative motion
    = -ground displacement)."""
    dt = 0.01
    t = np.arange(1001) * dt
    gm = GroundMotion(dt=dt, acc=np.sin(2 * np.pi * 2 * t) * np.sin(np.pi * t / 10) ** 2)
    sp = response_spectrum(gm, [500.0], 0.0)
    pgd = np.max(np.abs(gm.displacement()))
    assert sp.sd[0] == pytest.approx(pgd, rel=2e-3)


def test_bad_damping():
    gm = GroundMotion(dt=0.01, acc=np.ones(10))
    with pytest.raises(ValueError):
        response_spectrum(gm, [1.0], 1.0)
    with pytest.raises(ValueError):
        response_spectrum(gm, [-1.0])


def test_pseudo_spectrum_matches_response_spectrum():
    from murus.motion.spectra import psa, pseudo_spectrum

    rng = np.random.default_rng(5)
    gm = GroundMotion(dt=0.01, acc=rng.standard_normal(1000))
    T = np.geomspace(0.01, 5, 25)
    # same method; trajectories differ only by round-off (record step vs sub-steps)
    assert np.allclose(pseudo_spectrum(gm, T), response_spectrum(gm, T).psa, rtol=1e-11)
    assert psa(gm, 0.3) == pytest.approx(response_spectrum(gm, [0.3]).psa[0], rel=1e-11)


@pytest.mark.parametrize("xi", [0.0, 0.05, 0.3])
@pytest.mark.parametrize("refine", [True, False])
def test_fast_sd_kernel_equals_reference_kernel(xi, refine):
    """The PSA-only kernel (all oscillators advanced together, sub-stepping only the steps that
    may hold a new peak) must give the SD of the straightforward kernel to round-off (sub-steps
    no longer than T/10 in both cases, where the Hermite refinement is accurate)."""
    from murus.motion._kernels import sdof_peaks, sdof_sd_peaks

    rng = np.random.default_rng(11)
    acc = np.cumsum(rng.standard_normal(3000)) * 0.1 + rng.standard_normal(3000)
    T = np.geomspace(0.002, 8.0, 60)
    w = 2 * np.pi / T
    for m in (np.maximum(np.ceil(10 * 0.01 / T), 1), np.maximum(np.ceil(10 * 0.01 / T), 3)):
        m = m.astype(np.int64)
        ref = sdof_peaks(acc, 0.01, w, xi, m, refine)[0]
        fast = sdof_sd_peaks(acc, 0.01, w, xi, m, refine)
        assert np.allclose(fast, ref, rtol=1e-10, atol=0)
