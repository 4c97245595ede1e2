"""Intensity measures against closed forms."""

import math

import numpy as np
import pytest

from murus import G
from murus.motion import GroundMotion, measures
from murus.motion.synthetic import harmonic_ramp, ramp_velocity, sine_pulse


def _sine(A=2.0, f=2.5, cycles=10, dt=0.0005):
    return sine_pulse(A, f, cycles=cycles, dt=dt)


def test_arias_of_sine():
    """I_A = pi/(2g) * A² D / 2 over whole cycles; piecewise-linear a² integral error is
    O((W dt)²) = (2 pi 2.5 0.0005)²/6 ~ 1e-5."""
    A, f, cycles = 2.0, 2.5, 10
    gm = _sine(A, f, cycles)
    D = cycles / f
    assert measures.arias(gm) == pytest.approx(math.pi / (2 * G) * A**2 * D / 2, rel=1e-4)


def test_cav_of_sine_exact_with_zero_crossings():
    """CAV = integral |A sin| = 2 A D / pi; the piecewise-linear interpolant's integral differs
    by O((W dt)²)."""
    A, f, cycles = 2.0, 2.5, 10
    gm = _sine(A, f, cycles, dt=0.0005)
    assert measures.cav(gm) == pytest.approx(2 * A * (cycles / f) / math.pi, rel=1e-4)
    # a linear segment through zero: exact integral of |a| is (a0² + a1²) / (2 (|a0|+|a1|)) dt
    gm2 = GroundMotion(dt=1.0, acc=np.array([1.0, -3.0]))
    assert measures.cav(gm2) == pytest.approx((1 + 9) / (2 * 4), rel=1e-15)


def test_significant_duration_of_ramp():
    """For S = A t sin(W t) the Arias build-up is ~ t³ (Husid (t/D)³ up to an oscillating term of
    relative size ~3/(2 W t)), so D5-95 ~ D (0.95^(1/3) - 0.05^(1/3))."""
    D = 20.0
    gm = harmonic_ramp(0.5, 5.0, D, dt=0.002)
    exact = D * (0.95 ** (1 / 3) - 0.05 ** (1 / 3))
    exact75 = D * (0.75 ** (1 / 3) - 0.05 ** (1 / 3))
    # bound of the oscillation effect: a time error of ~1/(2 W) at each end
    tol = 2 / (2 * 2 * math.pi * 5.0)
    assert abs(measures.d5_95(gm) - exact) < tol
    assert abs(measures.d5_75(gm) - exact75) < tol


def test_pgv_of_ramp_closed_form():
    A, f, D = 0.8, 3.0, 6.0
    gm = harmonic_ramp(A, f, D, dt=0.0005)
    t = gm.time
    exact = np.max(np.abs(ramp_velocity(A, f, t)))
    assert measures.pgv(gm) == pytest.approx(exact, rel=1e-5)


def test_mean_period_of_pure_tone():
    """A whole number of cycles puts all Fourier energy in one bin: Tm = 1/f exactly (up to the
    tiny leakage of the sampled end points)."""
    gm = _sine(1.0, 4.0, cycles=40, dt=0.005)
    assert measures.mean_period(gm) == pytest.approx(0.25, rel=1e-3)


def test_summary_keys_and_pga():
    gm = _sine(1.5, 2.0, cycles=3, dt=0.001)
    s = measures.summary(gm)
    assert s["pga"] == pytest.approx(1.5, rel=1e-5)
    assert {"npts", "dt", "pgv", "pgd", "arias", "d5_75", "d5_95", "cav", "tm"} <= set(s)
