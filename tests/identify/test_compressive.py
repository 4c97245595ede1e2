"""Contact length from base transducers (murus.identify.compressive) against closed forms:
rigid rotations about known points, the EN 1996-1-1 linear stress block on a Winkler bed, and
the Mordant et al. (SERIES), Table 2 layout."""

import math

import numpy as np
import pytest

from murus.eurocode.ec6 import compressive_length
from murus.identify.compressive import (
    CompressiveError,
    contact_length,
    fit_plane,
    test_contact,
)
from murus.identify.testdata import ShakingTableTest

L = 2.10
X = np.array([0.05, 0.55, 1.05, 1.55, 2.05])


@pytest.mark.parametrize("xp", [0.0, 0.3, 1.05, 1.7, L])
@pytest.mark.parametrize("theta", [1e-4, 3e-3, -2e-3])
def test_rigid_rotation_about_a_point(xp, theta):
    """A rigid rotation theta (clockwise positive: the left end lifts) about the point x_p of
    the base: d(x) = (x_p - x) sin(theta); contact where d <= 0: [x_p, L] for theta > 0 and
    [0, x_p] for theta < 0, exactly, whatever the transducer positions."""
    d = (xp - X) * math.sin(theta)
    lc = contact_length(X, d, L)
    expected = L - xp if theta > 0 else xp
    assert lc == pytest.approx(expected, abs=1e-12)


def test_rocking_about_corners_and_vectorised():
    th = np.array([0.0, 0.01, -0.01, 1e-6])
    d = np.where(th > 0, (L - X)[:, None] * np.sin(th), -X[:, None] * np.sin(th))
    lc = contact_length(X, d, L)
    np.testing.assert_allclose(lc, [L, 0.0, 0.0, 0.0], atol=1e-12)
    # a closure of 1 um keeps the contact under small uplifts: Lc = closure / sin(theta)
    lc = contact_length(X, d, L, closure=1e-6)
    np.testing.assert_allclose(lc, [L, 1e-6 / np.sin(0.01), 1e-6 / np.sin(0.01), 1.0],
                               rtol=1e-9)
    # uniform compression or uniform opening
    assert contact_length(X, -1e-5 * np.ones(5), L) == L
    assert contact_length(X, 1e-5 * np.ones(5), L) == 0.0


def test_plane_fit_is_least_squares():
    rng = np.random.default_rng(0)
    d = 1e-4 + 2e-4 * X + 1e-6 * rng.standard_normal(5)
    a, b = fit_plane(X, d)
    pa = np.polyfit(X, d, 1)
    assert a == pytest.approx(pa[1]) and b == pytest.approx(pa[0])


@pytest.mark.parametrize("e_over_L", [0.0, 0.1, 1 / 6, 0.25, 0.4, 0.49])
def test_winkler_bed_gives_the_ec6_linear_length(e_over_L):
    """A no-tension Winkler bed under N at eccentricity e: compression linear, zero at the end
    of the compressed length (whole length in the kern, 3 (L/2 - e) beyond). The transducers
    zeroed before loading read minus the compression, so the plane-section contact length is
    the EN 1996-1-1 linear stress-block length of murus.eurocode.ec6."""
    N, kb = 5000 * 9.81, 1e9
    e = e_over_L * L
    lc_ec6 = compressive_length(N, N * e, L, "linear")
    if e <= L / 6:
        c = N / (kb * L) + 12 * N * e * (X - L / 2) / (kb * L**3)
    else:
        cmax = 2 * N / (kb * lc_ec6)
        c = cmax * (X - (L - lc_ec6)) / lc_ec6
    lc = contact_length(X, -c, L)
    assert lc == pytest.approx(lc_ec6, rel=1e-9, abs=1e-12)


def test_test_contact_minimum_in_mm_and_percent():
    n = 200
    t = np.arange(n) / 100
    th = 1e-3 * np.sin(2 * np.pi * t)
    xp = np.where(th > 0, 1.5, 0.6)  # rotation points: contact 0.6 m either side
    d = (xp[None, :] - X[:, None]) * np.sin(th)[None, :]
    ch = {"table_acc": np.zeros(n), "top_acc": np.zeros(n)}
    ch.update({f"lvdt_{k + 1}": d[k] for k in range(5)})
    test = ShakingTableTest(name="S", sampling_rate=100.0, wall_length=L, wall_height=1.8,
                            channels=ch, lvdt_positions=X)
    tc = test_contact(test)
    assert tc.lc_min == pytest.approx(0.6, abs=1e-9)
    assert tc.lc_min_mm == pytest.approx(600.0, abs=1e-6)
    assert tc.lc_min_percent == pytest.approx(100 * 0.6 / L)
    assert tc.lifted.max() == pytest.approx(L - 0.6)


def test_errors():
    with pytest.raises(CompressiveError, match="distinct positions"):
        contact_length([1.0, 1.0], [0.0, 0.0], L)
    with pytest.raises(CompressiveError, match="2 positions but 3"):
        contact_length([0.0, 1.0], np.zeros(3), L)
    with pytest.raises(CompressiveError, match="closure"):
        contact_length(X, np.zeros(5), L, closure=-1.0)
