"""Overturning under pulses against closed forms (issue 2, item 8).

For the linearised equation the minimum overturning acceleration without impact, in
``beta = a_p / (g alpha)`` and ``Omega = omega_p / p``, is:
rectangular pulse of duration t1: ``beta = 1 / (1 - exp(-p t1))`` (derived in the test below);
one-sine pulse: 2.34990, 5.23896, 9.41697 at Omega = 2, 4, 6 (Zhang and Makris 2001, values of the
issue); one-cosine pulse: ``beta = (1 + Omega^2) / (1 - exp(-2 pi / Omega))``.
"""

import math

import numpy as np
import pytest

from murus import G
from murus.rocking import (
    RigidBlock,
    RockingModel,
    cosine_pulse,
    critical_amplitude,
    rectangular_pulse,
    simulate,
    sine_pulse,
)

BLOCK = RigidBlock(width=0.25, height=1.0, density=2000.0)
LIN = RockingModel(BLOCK, linearised=True)


def beta_crit(model, make, lo, hi):
    a = model.body.alpha
    return critical_amplitude(model, lambda b: make(b * G * a), lo, hi, xtol=1e-8)


def test_rectangular_pulse_closed_form():
    # linearised: theta + (beta - 1) alpha = (beta - 1) alpha cosh(p t) during the pulse; after it
    # the body overturns iff theta' >= p (alpha - theta), i.e. (beta - 1)(exp(p t1) - 1) >= 1
    p = LIN.p
    t1 = 0.5 / p
    beta = beta_crit(LIN, lambda amp: rectangular_pulse(amp, t1), 1.5, 5.0)
    exact = 1.0 / (1.0 - math.exp(-0.5))
    assert exact == pytest.approx(2.541494, abs=1e-6)
    assert beta == pytest.approx(exact, rel=1e-4)


@pytest.mark.parametrize("Omega, expected", [(2, 2.34990), (4, 5.23896), (6, 9.41697)])
def test_one_sine_pulse(Omega, expected):
    f = Omega * LIN.p / (2 * math.pi)
    beta = beta_crit(LIN, lambda amp: sine_pulse(amp, f), 1.01, 30.0)
    assert beta == pytest.approx(expected, rel=1e-4)


@pytest.mark.parametrize("Omega", [2, 4])
def test_one_cosine_pulse(Omega):
    expected = (1 + Omega**2) / (1 - math.exp(-2 * math.pi / Omega))
    f = Omega * LIN.p / (2 * math.pi)
    beta = beta_crit(LIN, lambda amp: cosine_pulse(amp, f), 1.01, 60.0)
    assert beta == pytest.approx(expected, rel=1e-4)


@pytest.mark.parametrize("Omega, expected", [(2, 2.34990), (4, 5.23896), (6, 9.41697)])
def test_one_sine_nonlinear_slender(Omega, expected):
    """The nonlinear equation tends to the linearised one as alpha -> 0, with an error O(alpha²)
    (sin x = x - x³/6): within 0.3 % at alpha = 0.05; halving alpha divides the gap by 4."""
    gaps = []
    for width in (0.2, 0.1):  # height 2 m: alpha = 0.0997 and 0.0500
        slender = RigidBlock(width=width, height=2.0, density=2000.0)
        f = Omega * slender.p / (2 * math.pi)
        beta = beta_crit(RockingModel(slender), lambda amp, f=f: sine_pulse(amp, f), 1.01, 30.0)
        gaps.append(beta / expected - 1.0)
    assert slender.alpha <= 0.1
    assert abs(gaps[1]) <= 3e-3
    assert 3.5 <= gaps[0] / gaps[1] <= 4.5


def test_uplift_at_g_tan_alpha():
    # a slow ramp a_g = k t: the body lifts when k t = g tan(alpha) (Mordant et al. (SERIES), eq. 9)
    k = 1.0  # m/s3
    dt = 0.01
    t = np.arange(0, 4.0, dt)
    for sign in (1.0, -1.0):
        res = simulate(BLOCK, (dt, sign * k * t), duration=3.0)
        assert res.t_uplift * k == pytest.approx(2.4525, rel=5e-3)
        assert res.t_uplift * k == pytest.approx(G * math.tan(BLOCK.alpha), rel=1e-9)
        # in the direction of the ground acceleration (EURODYN (2020), eq. 1 sign convention)
        assert np.sign(res.theta[-1]) == sign
        nm = simulate(BLOCK, (dt, sign * k * t), duration=3.0, method="newmark", dt=0.01)
        assert nm.t_uplift == pytest.approx(res.t_uplift, rel=1e-9)


def test_no_uplift_below_threshold():
    dt = 0.01
    t = np.arange(0, 5.0, dt)
    acc = 0.99 * G * math.tan(BLOCK.alpha) * np.sin(2 * math.pi * t)
    res = simulate(BLOCK, (dt, acc))
    assert res.t_uplift is None and res.theta_max == 0.0 and res.n_impacts == 0
    assert res.rocking_criterion.max() == pytest.approx(0.99, rel=1e-3)


def test_vertical_acceleration_adds_to_gravity():
    # with a constant upward a_v the threshold becomes (g + a_v) tan(alpha)
    from murus.rocking import Record

    dt = 0.01
    t = np.arange(0, 6.0, dt)
    av = np.full_like(t, 0.3 * G)
    res = simulate(BLOCK, Record(dt, t.copy(), av), duration=5.0)
    assert res.t_uplift == pytest.approx(1.3 * G * math.tan(BLOCK.alpha), rel=1e-9)
