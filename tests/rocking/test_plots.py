"""Figures people read (issue 21, item 5): a free vibration draws no empty excitation panels,
the axes say what RC and theta/alpha are, the overturned convention is stated."""

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

from murus.rocking import RigidBlock, simulate  # noqa: E402
from murus.rocking.excitation import HarmonicPulse  # noqa: E402
from murus.rocking.plots import plot_response  # noqa: E402


def block():
    return RigidBlock(width=0.3, height=3.0, density=2140.67, name="b1")


def test_free_vibration_draws_only_the_rotation():
    r = simulate(block(), theta0_over_alpha=0.5, duration=3.0, out_dt=0.01)
    ax = plot_response(r)
    fig = ax[0].figure
    assert len(fig.axes) == 1
    assert "slenderness" in ax[0].get_ylabel()
    assert "free vibration from θ0/α = 0.5" in ax[0].get_title()
    plt.close(fig)


def test_forced_run_explains_rc_and_the_overturned_convention():
    b = block()
    # a rectangular pulse of 0.5 g (five times the uplift acceleration) for 2 s
    over = HarmonicPulse(amplitude=0.5 * 9.81, omega=0.0, phase=math.pi / 2, duration=2.0)
    r = simulate(b, over, duration=8.0, out_dt=0.01)
    assert r.overturned
    ax = plot_response(r)
    assert len(ax[0].figure.axes) == 3
    assert "z_G" in ax[1].get_ylabel() and "slenderness" in ax[2].get_ylabel()
    assert "π/(2α)" in ax[0].get_title()
    plt.close(ax[0].figure)
