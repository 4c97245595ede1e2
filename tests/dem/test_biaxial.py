"""Biaxial test of a disc assembly and calibration of the rolling resistance (issue 6, 2a)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from murus.dem import Joint
from murus.dem import biaxial as B

# a small assembly: 100 discs, 8 % axial strain, a few seconds per test after compilation
SMALL = {"n": 100, "max_strain": 0.08, "inertial": 2e-3, "sigma3": 50e3, "seed": 1}


def _joint(friction_deg=30.0, rolling=0.0):
    return Joint(kn=1e9, ks=1e9, friction_deg=friction_deg, rolling=rolling)


@pytest.fixture(scope="module")
def rolling_series():
    return {mu: B.biaxial_test(_joint(rolling=mu), **SMALL) for mu in (0.0, 0.1, 0.3)}


def test_assembly_has_no_initial_overlap():
    c, r, w, h = B.disc_assembly(300, (0.02, 0.03), seed=3)
    d = np.hypot(*(c[:, None, :] - c[None, :, :]).transpose(2, 0, 1))
    np.fill_diagonal(d, np.inf)
    assert np.all(d >= r[:, None] + r[None, :])
    assert np.all(c - r[:, None] > 0) and np.all(c[:, 0] + r < w) and np.all(c[:, 1] + r < h)


def test_frictionless_discs_have_a_small_friction_angle():
    # Without contact friction and rolling resistance the only source of shear strength is the
    # geometric (fabric) anisotropy the loading builds: simulations of frictionless assemblies
    # give a macroscopic friction coefficient of about 0.1 (Peyneau & Roux 2008, Phys. Rev. E 78,
    # 011307), i.e. 6 deg. The stress ratio of a frictionless 100-disc sample fluctuates
    # strongly (rearrangements without friction to stop them): its mean over the test after 1 %
    # strain is below 10 deg, its largest sample below 20 deg, against 25-35 deg with friction.
    r = B.biaxial_test(_joint(friction_deg=0.0), **dict(SMALL, max_strain=0.05))
    after = r.axial_strain > 0.01
    phi_mean = math.degrees(math.asin(np.mean(r.stress_ratio[after])))
    assert -2.0 < phi_mean < 10.0
    assert r.phi_peak_deg < 20.0


def test_friction_angle_increases_with_rolling_resistance(rolling_series):
    phis = [rolling_series[mu].phi_peak_deg for mu in sorted(rolling_series)]
    assert all(b > a for a, b in zip(phis, phis[1:], strict=False)), phis
    # friction 30 deg alone: a disc assembly is weaker than its contacts (the discs roll)
    assert 12.0 < phis[0] < 30.0


def test_confining_stress_is_held(rolling_series):
    for r in rolling_series.values():
        s3 = r.sigma3
        # the mean over the second half of the test within 5 % of the target (servo with
        # integral action; the samples are averages over 0.2 % of axial strain)
        assert abs(np.mean(s3[len(s3) // 2:]) / r.sigma3_target - 1.0) < 0.05
        assert np.all(r.sigma1 > 0)


def test_peak_is_at_least_the_critical_state_angle(rolling_series):
    for r in rolling_series.values():
        assert r.phi_peak_deg >= r.phi_cs_deg
        assert r.phi_peak_deg == pytest.approx(np.max(r.phi_deg), abs=1e-9)
        assert 0.15 < r.porosity0 < 0.3  # a 2D disc packing (random close packing ~0.16-0.2)


def test_calibration_root_finding(monkeypatch):
    # the root finder on a smooth monotone phi(mu): converged in a few runs
    calls = []

    def fake(joint, **kw):
        phi = 20.0 + 25.0 * joint.rolling / (joint.rolling + 0.2)
        calls.append(joint.rolling)
        return B.BiaxialResult(
            axial_strain=np.zeros(1), sigma1=np.ones(1), sigma3=np.ones(1),
            volumetric_strain=np.zeros(1), sigma3_target=1.0, phi_peak_deg=phi,
            phi_cs_deg=phi - 3, strain_at_peak=0.0, porosity0=0.2, n=1,
            rolling=joint.rolling, friction_deg=30.0, strain_rate=1.0, dt=1.0, steps=1,
            wall=0.0)

    monkeypatch.setattr(B, "biaxial_test", fake)
    res = B.calibrate_rolling(37.7, bracket=(0.0, 1.0), tol_deg=0.1)
    exact = 0.2 * 17.7 / (25.0 - 17.7)
    assert res.converged and len(calls) <= 8
    assert res.rolling == pytest.approx(exact, rel=0.02)
    # a target above what the bracket reaches: not converged, closest run returned
    res = B.calibrate_rolling(60.0, bracket=(0.0, 1.0))
    assert not res.converged and res.rolling == 1.0


def test_input_checks_and_plot(rolling_series):
    with pytest.raises(ValueError, match="sigma3"):
        B.biaxial_test(_joint(), sigma3=-1.0)
    with pytest.raises(ValueError, match="radius"):
        B.disc_assembly(10, (0.03, 0.02))
    import matplotlib

    matplotlib.use("Agg")
    ax = B.plot_biaxial(rolling_series[0.1])
    assert ax.get_xlabel().startswith("axial strain")
    r = rolling_series[0.1]
    assert math.isclose(math.sin(math.radians(r.phi_peak_deg)), r.stress_ratio.max())


def test_calibration_through_the_scatter_of_the_assemblies(monkeypatch):
    # each (assembly, mu_r) draws its peak angle from truth(mu_r) + N(0, 3.5 deg), independent
    # from one mu_r to the next (the scatter of 200-disc samples): one assembly's phi(mu_r) is
    # not monotone, the search over the means of 8 assemblies still converges, and the
    # scatter it reports at the calibrated mu_r is the 3.5 deg of the draw (sample standard
    # deviation of 8 values: within 0.5-1.5 sigma at 97 % probability)
    def truth(mu):
        return 27.5 + 30.0 * (1.0 - math.exp(-mu / 0.25))

    def fake(joint, seed=0, **kw):
        rng = np.random.default_rng([seed, int(round(joint.rolling * 1e9))])
        phi = truth(joint.rolling) + 3.5 * rng.standard_normal()
        return B.BiaxialResult(
            axial_strain=np.zeros(1), sigma1=np.ones(1), sigma3=np.ones(1),
            volumetric_strain=np.zeros(1), sigma3_target=1.0, phi_peak_deg=phi,
            phi_cs_deg=phi - 3, strain_at_peak=0.0, porosity0=0.2, n=1,
            rolling=joint.rolling, friction_deg=30.0, strain_rate=1.0, dt=1.0, steps=1,
            wall=0.0)

    monkeypatch.setattr(B, "biaxial_test", fake)
    res = B.calibrate_rolling(37.7, seeds=range(8))
    assert res.converged and res.status == "converged", res.message
    assert len(res.history) <= 8 and len(res.phi_seeds) == 8
    assert 0.5 * 3.5 < res.std_deg < 1.5 * 3.5
    root = 0.25 * -math.log(1.0 - (37.7 - 27.5) / 30.0)  # truth(root) = 37.7
    # within 3 standard errors (of the mean of the 3 x 8 tests around the target: 0.7 deg)
    assert abs(truth(res.rolling) - 37.7) < 3 * 3.5 / math.sqrt(24)
    assert res.rolling == pytest.approx(root, abs=0.05)
