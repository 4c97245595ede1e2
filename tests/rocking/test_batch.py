"""The batch entry point returns exactly what the cases return one by one (issue 2, item 5)."""

import math

import numpy as np
import pytest

from murus.rocking import (
    Constant,
    Record,
    RigidBlock,
    RockingModel,
    simulate,
    simulate_batch,
    sine_pulse,
)
from murus.rocking import kernels as K


def motions():
    rng = np.random.default_rng(7)
    out = []
    dt = 0.01
    for i, amp in enumerate((1.5, 2.5, 4.0)):
        n = 800
        a = np.convolve(rng.standard_normal(n + 20), np.ones(8) / 8, mode="same")[:n]
        a *= amp / np.abs(a).max()
        av = 0.3 * a[::-1].copy() if i == 1 else None  # one record with a vertical component
        out.append(Record(dt, a, av))
    out.append(sine_pulse(3.0, 1.5, cycles=2))
    return out


def models():
    return [
        RockingModel(RigidBlock(width=0.3, height=3.0, density=2140.7)),
        RockingModel(RigidBlock(width=0.72, height=1.8, top_mass=5000.0), Constant(0.85)),
        RockingModel(RigidBlock(width=0.2, height=1.0, density=2000.0)),
    ]


def test_batch_equals_one_by_one_bitwise():
    mods, mots = models(), motions()
    br = simulate_batch(mods, mots, duration=10.0)
    assert br.shape == (3, 4)
    for i, m in enumerate(mods):
        for j, x in enumerate(mots):
            r = simulate(m, x, duration=10.0)
            row = br.raw[i, j]
            assert row[K.S_THETA_MAX] == r.theta_max
            assert row[K.S_N_IMPACTS] == r.n_impacts
            assert bool(row[K.S_OVERTURNED]) == r.overturned
            assert row[K.S_E_DISSIPATED] == r.energy_dissipated
            up = row[K.S_T_UPLIFT]
            assert (math.isnan(up) and r.t_uplift is None) or up == r.t_uplift
    # the cases are not trivial: some rock, some do not, one overturns
    assert (br["theta_max"] > 0).sum() >= 4
    assert br.overturned.any() and not br.overturned.all()
    assert np.allclose(br.theta_max_over_alpha, br["theta_max"] / br.alpha[:, None])


def test_batch_free_vibration_initial_conditions():
    mods = models()[:1]
    br = simulate_batch(mods, [None], duration=3.0, theta0=0.5 * mods[0].body.alpha)
    r = simulate(mods[0], None, duration=3.0, theta0=0.5 * mods[0].body.alpha)
    assert br["theta_max"][0, 0] == r.theta_max == pytest.approx(0.5 * mods[0].body.alpha)
    assert br["n_impacts"][0, 0] == r.n_impacts
