"""Rocking spectra of EURODYN (2020), §4.1: the models built for each stiffness, the free-standing
reference, spectra against damping and pulse frequency, plots (issue 7, item 3)."""

import math

import matplotlib
import numpy as np
import pytest

from murus.rocking import Damper, RockingModel, SpringBed, Tie, restrained_wall_block, simulate
from murus.rocking.design import bed_stiffness_equal, reference_damping, tie_design
from murus.studies.spectrum import plot_overturning_map, plot_rocking_spectrum, rocking_spectrum

matplotlib.use("Agg")


@pytest.fixture(scope="module")
def spec(records):
    return rocking_spectrum(restrained_wall_block("block1"), records[:3], np.linspace(0, 1, 5),
                            executor="serial")


def test_models_follow_eurodyn2020(spec):
    b = restrained_wall_block("block1")
    Kd = tie_design(b).K_d
    K = spec["tie_stiffness"].values
    assert np.allclose(K, np.linspace(0, 1, 5) * Kd, rtol=1e-15)
    assert math.isnan(spec["bed_stiffness"].values[0])  # K = 0: free-standing, two-sided
    assert np.allclose(spec["bed_stiffness"].values[1:], [bed_stiffness_equal(b, k)
                                                          for k in K[1:]], rtol=1e-15)
    assert spec["theta_max_over_alpha"].dims == ("K_over_Kd", "record")


def test_values_are_those_of_simulate(spec, records):
    """Node K = 0.75 K_d under the second record, rebuilt by hand and run alone."""
    b = restrained_wall_block("block1")
    K = 0.75 * tie_design(b).K_d
    m = RockingModel(b, tie=Tie(K, b.height),
                     transverse_walls=SpringBed(bed_stiffness_equal(b, K), b.height),
                     motion_sides="one")
    r = simulate(m, records[1])
    assert spec["theta_max"].sel(K_over_Kd=0.75).isel(record=1).item() == r.theta_max
    assert spec["n_impacts"].sel(K_over_Kd=0.75).isel(record=1).item() == r.n_impacts
    # the free-standing reference is the K = 0 node (eq. 11 removes the walls with the tie)
    assert np.array_equal(spec["free_standing"].values,
                          spec["theta_max_over_alpha"].sel(K_over_Kd=0.0).values)


def test_rigid_walls_and_damping_spectrum(records):
    b = restrained_wall_block("block1")
    ds = rocking_spectrum(b, records[:2], 1.0, walls="rigid", c_over_cd=[0.0, 0.05, 0.2],
                          delta_t=10.0, executor="serial")
    assert ds["theta_max_over_alpha"].dims == ("restraint.damper.fraction", "record")
    assert float(ds["K_over_Kd"]) == 1.0  # a fixed value stays as a scalar coordinate
    assert np.all(np.isinf(ds["bed_stiffness"].values))
    cd = reference_damping(b, 10.0)
    assert np.allclose(ds["damper_coefficient"].values, [0.0, 0.05 * cd, 0.2 * cd])
    m = RockingModel(b, tie=Tie(tie_design(b).K_d, b.height),
                     transverse_walls=SpringBed(math.inf, b.height), motion_sides="one",
                     damper=Damper(0.2 * cd, b.height))
    r = simulate(m, records[0])
    assert ds["theta_max"].isel({"restraint.damper.fraction": 2, "record": 0}).item() \
        == r.theta_max
    with pytest.raises(ValueError, match="delta_t"):
        rocking_spectrum(b, records[:1], 1.0, c_over_cd=[0.1], executor="serial")


def test_pulse_frequency_spectrum():
    """Against omega_p / p for a one-cycle sine pulse (3 g tan alpha) on the free-standing
    block: long pulses overturn it, short ones barely rock it (Zhang and Makris 2001)."""
    b = restrained_wall_block("block1")
    ratios = np.array([1.0, 2.0, 4.0, 8.0, 16.0])
    ds = rocking_spectrum(b, {"type": "sine-pulse", "amplitude_g": 0.3}, 0.0,
                          omega_p_over_p=ratios, free_standing=False, executor="serial")
    assert ds["theta_max_over_alpha"].dims == ("omega_p_over_p", "record")
    assert ds.sizes["record"] == 1
    over = ds["overturned"].values[:, 0]
    assert list(over) == [1.0, 1.0, 1.0, 0.0, 0.0]
    th = ds["theta_max_over_alpha"].values[:, 0]
    assert th[-1] < th[-2] < 1.0


def test_plots(spec):
    ax = plot_rocking_spectrum(spec)
    ys = {round(ln.get_ydata()[0], 6) for ln in ax.lines if len(ln.get_ydata()) == 2}
    assert {0.1, 0.4} <= ys  # the limit states
    assert any("free-standing" in t.get_text() for t in ax.get_legend().get_texts())
    ax1 = plot_rocking_spectrum(spec, record=1)
    assert ax1.get_xlabel().startswith("$K/K_d$")
    ax2 = plot_overturning_map(spec)
    assert ax2.get_ylabel() == "record"
