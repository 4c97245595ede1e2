"""The modified rocking model of Mordant et al. (SERIES), §3.3: compressive-length pivot (eqs.
11-13) and the restitution laws (eqs. 14-18), each against its closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from murus import G
from murus.eurocode.ec6 import compressive_length
from murus.rocking import (
    AmplitudeDependent,
    Housner,
    Pivot,
    RockingModel,
    rectangular_pulse,
    series_clay_wall,
    simulate,
    sine_pulse,
)
from murus.rocking import kernels as K
from murus.rocking.restitution import RestitutionError
from murus.rocking.restraints import RestraintError

SHORT = series_clay_wall("short")  # B = 0.72 m, mass 5 t at H = 1.8 m
B, H = SHORT.width, SHORT.z_G
ONSET = {  # ground acceleration that starts rocking [m/s2], from a_g H = g * lever(a_g)
    "corner": G * B / (2 * H),
    "kern": G * B / (6 * H),
    "effective-width": 0.3 * G * B / H,  # lever Lc/2 = 1.5 (B/2 - e) = e at e = 0.3 B
    "neutral-axis": G * B / (4 * H),  # lever B - 3e = e at e = B/4
}


def _pivot(reading):
    if reading == "corner":
        return Pivot()
    return Pivot("compressive-length", reading)


@pytest.mark.parametrize("reading", ["kern", "effective-width", "neutral-axis"])
def test_kernel_lever_matches_python_and_ec6(reading):
    mdl = RockingModel(SHORT, pivot=_pivot(reading))
    P = mdl.params()
    ag = np.linspace(-6.0, 6.0, 121)
    py = mdl.pivot.lever(SHORT, ag)
    kern = np.array([K.lever(a, 0.0, P) for a in ag])
    np.testing.assert_allclose(kern, py, rtol=1e-14)
    N = SHORT.mass * G
    lc = compressive_length(np.full_like(ag, N), SHORT.mass * np.abs(ag) * H, B, "linear")
    expected = {"kern": np.full_like(ag, B / 6), "effective-width": lc / 2,
                "neutral-axis": lc - B / 2}[reading]
    np.testing.assert_allclose(py, np.clip(expected, 0.05 * B / 2, B / 2), rtol=1e-14)


@pytest.mark.parametrize("reading", sorted(ONSET))
def test_rocking_starts_at_the_modified_criterion(reading):
    """Mordant et al. (SERIES), eq. 11: rocking starts when m a_g H > m g lever; a rectangular pulse
    just below the onset acceleration never lifts the wall, just above lifts it at once."""
    mdl = RockingModel(SHORT, pivot=_pivot(reading))
    a = ONSET[reading]
    below = simulate(mdl, rectangular_pulse(a * (1 - 1e-7), 0.5), duration=0.6)
    above = simulate(mdl, rectangular_pulse(a * (1 + 1e-7), 0.5), duration=0.6)
    assert below.t_uplift is None
    assert above.t_uplift == pytest.approx(0.0, abs=1e-12)
    rc = above.rocking_criterion
    assert rc[1] == pytest.approx(1.0, rel=1e-6)


def test_housner_with_a_moving_pivot_is_the_momentum_balance():
    """Eq. 13: with the kern pivot the coefficient is (H^2 - b^2) / (H^2 + b^2), b = B/6 (mass
    on top); on the corner it is cos 2 alpha (Mordant et al. (SERIES), eq. 10)."""
    for pivot, lever in ((Pivot(), B / 2), (Pivot("compressive-length", "kern"), B / 6)):
        r = simulate(RockingModel(SHORT, Housner(), pivot=pivot), theta0_over_alpha=0.5,
                     duration=4.0)
        ratio = r.impacts[:3, 2] / r.impacts[:3, 1]
        np.testing.assert_allclose(ratio, (H**2 - lever**2) / (H**2 + lever**2), rtol=1e-12)


def test_momentum_restitution_with_a_moving_pivot():
    """e = (H^2 - b1 b2) / (H^2 + b2^2) for the mass on top; cos 2 alpha for b1 = b2 = B/2;
    the uniform block's Housner value 1 - 3/2 sin^2 alpha at its corners."""
    from murus.rocking import restrained_wall_block
    from murus.rocking.restitution import momentum_restitution

    for b1, b2 in ((0.36, 0.36), (0.36, 0.12), (0.2, 0.3)):
        assert momentum_restitution(SHORT, b1, b2) == pytest.approx(
            (H**2 - b1 * b2) / (H**2 + b2**2), rel=1e-14)
    assert momentum_restitution(SHORT, B / 2, B / 2) == pytest.approx(
        math.cos(2 * SHORT.alpha), rel=1e-14)
    blk = restrained_wall_block("block1")
    hb = blk.width / 2
    assert momentum_restitution(blk, hb, hb) == pytest.approx(
        1 - 1.5 * math.sin(blk.alpha) ** 2, rel=1e-13)


def test_coefficient_law_eq14_15():
    """e = 1 - k sin^2(alpha); k = 2 is Housner's top-mass value."""
    for k in (1.5, 2.0):
        r = simulate(RockingModel(SHORT, AmplitudeDependent.coefficient(k)),
                     theta0_over_alpha=0.5, duration=4.0)
        ratio = r.impacts[:3, 2] / r.impacts[:3, 1]
        np.testing.assert_allclose(ratio, 1 - k * math.sin(SHORT.alpha) ** 2, rtol=1e-12)
    assert AmplitudeDependent.coefficient(2.0).value(SHORT) == pytest.approx(
        SHORT.housner_restitution(), rel=1e-14)


def test_amplitude_dependent_causal_eq16():
    """r_n = max rotation of the half-cycle before the impact / max rotation so far: 1 at the
    first impact of a free rocking, then the ratio of the peaks."""
    k0, k1 = 1.0, 1.5
    r = simulate(RockingModel(SHORT, AmplitudeDependent(k0, k1)), theta0_over_alpha=0.6,
                 duration=4.0)
    s2 = math.sin(SHORT.alpha) ** 2
    ratio = r.impacts[:4, 2] / r.impacts[:4, 1]
    assert ratio[0] == pytest.approx(1 - (k0 + k1) * s2, rel=1e-12)
    theta0 = 0.6 * SHORT.alpha
    for n in (1, 2, 3):  # peak between impacts n-1 and n
        pk = r.peaks[(r.peaks[:, 0] > r.impacts[n - 1, 0]) & (r.peaks[:, 0] < r.impacts[n, 0])]
        rn = abs(pk[0, 1]) / theta0
        assert ratio[n] == pytest.approx(1 - (k0 + k1 * rn) * s2, rel=1e-9)


def test_iterated_variant_is_self_consistent():
    """Iterated eq. 16: r uses the largest rotation of the whole response; a sine pulse whose
    largest rotation comes after the first impact makes the two variants differ."""
    law = AmplitudeDependent(1.0, 1.0, variant="iterated")
    mdl = RockingModel(SHORT, law)
    motion = sine_pulse(1.5 * ONSET["corner"], 1.0, cycles=3.0)
    r = simulate(mdl, motion, duration=6.0)
    causal = simulate(RockingModel(SHORT, AmplitudeDependent(1.0, 1.0)), motion, duration=6.0)
    assert 2 <= r.meta["solver"]["restitution_iterations"] <= law.max_iterations
    s2 = math.sin(SHORT.alpha) ** 2
    pk = r.peaks[r.peaks[:, 0] < r.impacts[0, 0]]
    r1 = np.abs(pk[:, 1]).max() / r.theta_max
    assert r1 < 0.999
    assert r.impacts[0, 2] / r.impacts[0, 1] == pytest.approx(1 - (1 + r1) * s2, rel=1e-7)
    assert causal.impacts[0, 2] / causal.impacts[0, 1] == pytest.approx(1 - 2 * s2, rel=1e-12)


def test_free_vibration_law_eq17():
    """After the end of the input the free-vibration coefficients apply."""
    law = AmplitudeDependent(2.0, 0.0, k0_free=0.5, k1_free=0.0)
    motion = sine_pulse(2.0 * ONSET["corner"], 2.0, cycles=3.0)
    r = simulate(RockingModel(SHORT, law), motion, duration=8.0)
    assert not r.overturned
    s2 = math.sin(SHORT.alpha) ** 2
    ratio = r.impacts[:, 2] / r.impacts[:, 1]
    forced = r.impacts[:, 0] <= motion.end_time
    assert forced.any() and (~forced).any()
    np.testing.assert_allclose(ratio[forced], 1 - 2.0 * s2, rtol=1e-12)
    np.testing.assert_allclose(ratio[~forced], 1 - 0.5 * s2, rtol=1e-12)


def test_aspect_ratio_factor_eq18():
    """The energy lost at an impact is scaled by (lambda / A0)^2, lambda = h / b."""
    A0 = 3.0
    law = AmplitudeDependent.coefficient(2.0, A0=A0)
    r = simulate(RockingModel(SHORT, law), theta0_over_alpha=0.5, duration=3.0)
    f = (SHORT.height / SHORT.width / A0) ** 2
    e = 1 - 2.0 * math.sin(SHORT.alpha) ** 2
    assert r.impacts[0, 2] / r.impacts[0, 1] == pytest.approx(math.sqrt(1 - f * (1 - e * e)),
                                                              rel=1e-12)


def test_bad_laws_are_refused():
    with pytest.raises(RestitutionError, match="variant"):
        AmplitudeDependent(variant="sometimes")
    with pytest.raises(RestitutionError, match="k1"):
        AmplitudeDependent(k1=-1.0)
    with pytest.raises(RestraintError, match="pivot reading"):
        Pivot("compressive-length", "middle")
    with pytest.raises(RestraintError, match="pivot law"):
        Pivot("zero-stress")
