"""Blocks and zones in one time loop (issue 17, item 5): a rigid block resting on an elastic
layer through the zone-block interface. Closed forms: the interface carries the block's weight;
the layer between smooth rigid walls is oedometric, so the block settles by
``rho g H^2 / (2 M) + p H / M + p / kn`` (self-weight, the block's pressure p = weight / width
of the layer, the interface spring), ``M = E (1 - nu) / ((1 + nu)(1 - 2 nu))``. The block
overhangs the layer by 0.1 m on each side, so that its flat face (not its rounded corners)
covers every top gridpoint. The model and the settlement row are those of ``murus verify
continuum`` (:func:`murus.continuum.verify.block_on_layer`)."""

from __future__ import annotations

import numpy as np
import pytest

from murus.continuum import verify as V
from murus.continuum.coupled import CoupledError
from murus.dem.engine import body_probe

G_ACC, RHO, E, NU = 9.81, 2000.0, 1e7, 0.25
W, H, HB, KN, OVER = 2.0, 1.0, 0.5, 1e9, 0.1


def _block_on_layer():
    return V.block_on_layer(4, 4)


def test_block_on_an_elastic_layer_settles_to_the_closed_form():
    row, cm = V.block_settlement(quick=True)
    assert row["passed"], row
    weight = RHO * (W + 2 * OVER) * HB * G_ACC
    assert cm.iface.normal_force() == pytest.approx(weight, rel=0.005)
    M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
    p = weight / W
    want = RHO * G_ACC * H * H / (2 * M) + p * H / M + p / KN
    assert row["expected"] == pytest.approx(want, rel=1e-12)
    assert row["obtained"] == pytest.approx(want, rel=0.02)


def test_one_time_step_for_all():
    cm, dm, zm, iface = _block_on_layer()
    assert cm.dt <= zm.stable_dt() and cm.dt <= iface.critical_dt() * dm.safety
    with pytest.raises(CoupledError):
        cm.set_dt(2 * cm.stable_dt())


def test_a_settled_block_stays_at_rest_in_a_run():
    """The dynamic loop from a settled state with no base motion: nothing moves (the static
    solution is an equilibrium of the dynamic equations), and the time advances."""
    cm, dm, zm, iface = _block_on_layer()
    assert cm.settle(tol=1e-7, max_steps=400_000).converged
    y1 = float(dm.bpos[0, 1])
    res = cm.run(0.05, xi=0.05, freq=5.0, every=50,
                 probes={"y": body_probe(0, "y"), "N": lambda m: iface.normal_force()})
    weight = RHO * (W + 2 * OVER) * HB * G_ACC
    assert res.status == "completed"
    assert res.t[-1] == pytest.approx(0.05, abs=cm.dt)
    # the layer's settlement is ~1.7 mm: rest within a thousandth of it
    assert np.abs(res["y"] - y1).max() < 2e-6
    assert np.allclose(res["N"], weight, rtol=0.005)
