"""Rotation of horizontal pairs, RotDnn spectra (Boore 2010) against closed forms, and the
three-component read that carries the vertical component."""

import math
from pathlib import Path

import numpy as np
import pytest

from murus.motion import GroundMotion, MotionFormatError
from murus.motion.components import horizontal_pair, read_components, rotate, rotd_spectrum
from murus.motion.io import read_all
from murus.motion.spectra import pseudo_spectrum

CLC = Path(__file__).resolve().parents[1] / "data" / "records" / "CICLC_trim.v1"
PERIODS = np.array([0.05, 0.2, 0.5, 1.0, 2.0])


def _sine(n=1500, dt=0.01, f=1.7, amp=2.0, phase=0.0, name="s"):
    t = np.arange(n) * dt
    env = np.minimum(1.0, t / 2.0) * np.minimum(1.0, (t[-1] - t) / 2.0)
    return GroundMotion(dt=dt, acc=amp * env * np.sin(2 * np.pi * f * t + phase), name=name)


def test_identical_in_phase_pair():
    """a = b: the displacement along theta is u (cos + sin); RotD100 = sqrt(2) Sa (theta =
    45 deg), RotD50 = sqrt(2) sin(45 deg) Sa = Sa (median of |sin| over the 1-degree grid)."""
    a = _sine()
    sa = pseudo_spectrum(a, PERIODS, 0.05)
    r = rotd_spectrum(a, a, PERIODS, 0.05)
    assert np.allclose(r[100], math.sqrt(2) * sa, rtol=2e-4)
    assert np.allclose(r[50], sa, rtol=2e-4)
    assert np.all(r.angle_max_deg == 45.0)


def test_single_component_record():
    """b = 0: RotD100 = Sa of a (theta = 0), RotD50 = sin(45 deg) Sa."""
    a = _sine(phase=0.3)
    z = GroundMotion(dt=a.dt, acc=np.zeros(a.npts))
    sa = pseudo_spectrum(a, PERIODS, 0.05)
    r = rotd_spectrum(a, z, PERIODS, 0.05, percentiles=(0, 50, 100))
    assert np.allclose(r[100], sa, rtol=2e-4)
    assert np.allclose(r[50], math.sin(math.pi / 4) * sa, rtol=2e-4)
    assert np.allclose(r[0], 0.0, atol=1e-9 * sa.max())  # theta = 90 deg: nothing
    r_swapped = rotd_spectrum(z, a, PERIODS, 0.05)
    assert np.allclose(r_swapped[100], sa, rtol=2e-4)


def test_rotd_is_orientation_independent_and_bounded():
    a = _sine(f=1.3, name="a")
    b = _sine(f=2.9, amp=1.2, phase=1.0, name="b")
    r = rotd_spectrum(a, b, PERIODS)
    a30, b30 = rotate(a, b, 30.0)
    r30 = rotd_spectrum(a30, b30, PERIODS)
    for nn in (50, 100):
        assert np.allclose(r30[nn], r[nn], rtol=1e-6)
    sa, sb = pseudo_spectrum(a, PERIODS), pseudo_spectrum(b, PERIODS)
    assert np.all(r[100] >= np.maximum(sa, sb) * (1 - 2e-4))
    assert np.all(r[50] <= r[100])


def test_rotate_closed_form_and_azimuths():
    a = _sine(name="a").with_meta(azimuth_deg=0.0)
    b = _sine(f=2.2, name="b").with_meta(azimuth_deg=90.0)
    r1, r2 = rotate(a, b, 90.0)
    assert np.allclose(r1.acc, b.acc, atol=1e-12) and np.allclose(r2.acc, -a.acc, atol=1e-12)
    assert r1.meta["azimuth_deg"] == 90.0 and r2.meta["azimuth_deg"] == 180.0
    q1, q2 = rotate(*rotate(a, b, 25.0), -25.0)
    assert np.allclose(q1.acc, a.acc, atol=1e-12) and np.allclose(q2.acc, b.acc, atol=1e-12)
    # b declared at a - 90 deg: turned into a right-handed pair
    bw = b.with_meta(azimuth_deg=270.0)
    w1, _ = rotate(a, bw, 90.0)
    assert np.allclose(w1.acc, -b.acc, atol=1e-12)  # the east component of a westward sensor
    with pytest.raises(ValueError, match="not perpendicular"):
        rotate(a, b.with_meta(azimuth_deg=45.0), 10.0)
    with pytest.raises(ValueError, match="1500 and 1400 samples"):
        rotate(a, GroundMotion(dt=0.01, acc=np.zeros(1400)), 10.0)


def test_rotd_of_the_real_clc_pair():
    h1, h2 = horizontal_pair(read_all(CLC))
    assert (h1.meta["azimuth_deg"], h2.meta["azimuth_deg"]) == (90.0, 0.0)
    r = rotd_spectrum(h1, h2, PERIODS)
    s1, s2 = pseudo_spectrum(h1, PERIODS), pseudo_spectrum(h2, PERIODS)
    assert np.all(r[100] >= np.maximum(s1, s2) * (1 - 1e-3))
    assert np.all(r[50] <= r[100])
    assert np.all(r[50] >= 0.5 * np.minimum(s1, s2))


def test_read_components_carries_the_vertical():
    gm = read_components(CLC)
    chans = read_all(CLC)
    assert gm.meta["channel"] == 1 and gm.meta["vertical_channel"] == 3
    assert np.array_equal(gm.acc, chans[0].acc) and np.array_equal(gm.acc_v, chans[2].acc)
    gm2 = read_components(CLC, horizontal="360", scale=2.0)
    assert np.array_equal(gm2.acc, 2 * chans[1].acc) and np.array_equal(gm2.acc_v,
                                                                         2 * chans[2].acc)
    with pytest.raises(MotionFormatError, match="channel 3 is vertical"):
        read_components(CLC, horizontal="up")
    assert read_components(CLC, vertical=False).acc_v is None


def test_read_components_of_separate_files(tmp_path):
    """K-NET: one file per channel; the vertical one (.UD) becomes acc_v."""
    from test_io_networks import _counts, _knet_text

    paths = []
    for k, (ext, d) in enumerate([("EW", "E-W"), ("NS", "N-S"), ("UD", "U-D")]):
        p = tmp_path / f"AKT013.{ext}"
        p.write_text(_knet_text(_counts(seed=k), direction=d))
        paths.append(p)
    gm = read_components(paths, horizontal="N")
    assert gm.meta["component"] == "N-S" and gm.meta["vertical_component"] == "U-D"
    assert np.array_equal(gm.acc_v, read_all(paths[2])[0].acc)
    with pytest.raises(MotionFormatError, match="0 vertical channels"):
        read_components(paths[:2])
