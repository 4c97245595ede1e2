"""The code's kinematic checks (murus.mechanisms) and the rocking engine (murus.rocking) describe
the same façade: their statics agree, two implementations written apart (issue 19, item 4)."""

from __future__ import annotations

import math

import pytest

from murus import G
from murus.mechanisms import Floor, SimpleOverturning, Storey, alpha
from murus.rocking import restrained_wall_block
from murus.rocking.body import RigidBlock
from murus.rocking.design import tie_design


@pytest.mark.parametrize("label", [f"block{k}" for k in range(1, 7)])
def test_the_tie_of_eq12_gives_alpha0_mu(label):
    """EURODYN (2020), eq. 12 sizes the tie for the collapse multiplier mu = 0.2:
    T_d h + W s/2 = mu W h/2. The virtual work of the Circolare with that tie at the top gives
    alpha0 = mu (round-off)."""
    b = restrained_wall_block(label)
    td = tie_design(b, mu=0.2)
    mech = SimpleOverturning([Storey(height=b.height, thickness=b.width,
                                     weight=b.mass * G)],
                             [Floor(level=1, load=0.0, tie=td.T_d)])
    assert alpha(mech, 0.0) == pytest.approx(0.2, rel=1e-6)


def test_uplift_of_a_facade_with_floors_is_its_activation_multiplier():
    """A façade of one thickness with floor loads on its centreline: the rocking body's uplift
    acceleration g tan(alpha) = g (s/2) / z_G and the Circolare's alpha0 g (no tie) are the
    same number (both the ratio of the restoring to the overturning moment of the weights)."""
    s, h1, h2, rho = 0.5, 3.5, 3.2, 2000.0
    loads = (6000.0, 4500.0)  # N per metre of wall
    body = RigidBlock(width=s, height=h1 + h2, density=rho,
                      masses=((loads[0] / G, h1), (loads[1] / G, h1 + h2)))
    mech = SimpleOverturning([Storey(height=h1, thickness=s, weight=rho * G * s * h1),
                              Storey(height=h2, thickness=s, weight=rho * G * s * h2)],
                             [Floor(level=1, load=loads[0], x=s / 2),
                              Floor(level=2, load=loads[1], x=s / 2)], hinge=0)
    assert alpha(mech, 0.0) * G == pytest.approx(body.uplift_acceleration, rel=1e-6)
    # and at a finite rotation both follow tan(alpha - theta) for a rigid block on its toe
    th = 0.3 * body.alpha
    assert alpha(mech, th) == pytest.approx(math.tan(body.alpha - th), rel=1e-5)


def test_the_facade_example_runs(capsys):
    """examples/mechanisms/facade_code_vs_dynamics.py, as a user runs it: the code's limits and
    the records' overturning intensities, printed."""
    import runpy
    from pathlib import Path

    ex = Path(__file__).parents[1] / "examples" / "mechanisms" / "facade_code_vs_dynamics.py"
    ns = runpy.run_path(str(ex), run_name="__main__")
    out = capsys.readouterr().out
    assert "SLV fails at agR" in out and "four of seven overturn it" in out
    # the statics of the example: alpha0 = tan(alpha) of the rocking body plus the tie's
    # moment T h1 over the overturning moment of the weights, m g z_G
    b = ns["body"]
    expected = math.tan(b.alpha) + ns["tie"] * ns["h1"] / (b.mass * G * b.z_G)
    assert ns["base"].alpha0 == pytest.approx(expected, rel=1e-6)
    assert ns["limits"]["nonlinear"] < ns["limits"]["linear"]
