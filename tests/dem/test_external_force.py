"""External body forces of the DEM engine (``model.bext`` and the ``external`` callback)."""

from __future__ import annotations

import numpy as np

from murus.dem import Joint, Model
from murus.dem.engine import body_probe


def _block(force=0.0):
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=0.0))
    m.add_rectangle(4.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
    b = m.add_rectangle(0.4, 0.2, center=(0.0, 0.1))
    m.settle()
    return m, b


def test_constant_force_accelerates_at_F_over_m_and_energy_balances():
    m, b = _block()
    mass = m.bmass[b]
    F = 0.3 * mass  # a = 0.3 m/s²
    m.bext[b, 0] = F
    T = 1.0
    res = m.run(T, probes={"vx": body_probe(b, "vx"), "ux": body_probe(b, "ux")})
    a_v = res["vx"][-1] / res.t[-1]
    a_u = 2.0 * res["ux"][-1] / res.t[-1] ** 2
    assert abs(a_v / (F / mass) - 1.0) < 5e-3
    assert abs(a_u / (F / mass) - 1.0) < 5e-3
    e = m.energy()
    work = F * m.body_displacement()[b, 0]  # the state at the end of the run (m.time)
    assert abs(e["external_work"] / work - 1.0) < 5e-3
    assert abs(e["error"]) < 5e-3 * work


def test_callback_updates_the_force():
    m, b = _block()
    mass = m.bmass[b]
    calls = []

    def push(model):
        calls.append(model.time)
        model.bext[b, 0] = 0.2 * mass if model.time < 0.5 - 1e-9 else 0.0

    dt = m.stable_dt()
    res = m.run(1.0, external=push, external_every=int(round(0.05 / dt)),
                probes={"vx": body_probe(b, "vx")})
    # 0.2 m/s² during 0.5 s, then free sliding on the frictionless base
    assert abs(res["vx"][-1] / 0.1 - 1.0) < 2e-2
    assert len(calls) >= 19
    assert np.all(np.diff(calls) > 0)
    # a moment turns a free block
    m2 = Model(gravity=0.0)
    c = m2.add_rectangle(0.4, 0.2)
    m2.build()
    m2.bext[c, 2] = 10.0
    m2.run(0.1, probes={"w": body_probe(c, "omega")})
    assert abs(m2.bomg[c] / (10.0 / m2.binert[c] * 0.1) - 1.0) < 1e-2
