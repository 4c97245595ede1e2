"""GroundMotion operations, synthetic signals (Savalle et al. (2022) ramps) and processing, against
closed forms and convergence rates."""

import math
import warnings

import numpy as np
import pytest

from murus.motion import GroundMotion, processing, synthetic
from murus.motion.core import integrate


def test_ramp_velocity_displacement_closed_form_second_order():
    """Numerical integration of the sampled ramp converges to the closed forms at O(dt²)."""
    A, f, D = 0.7, 3.0, 5.0
    errs = []
    for dt in (0.004, 0.002, 0.001):
        gm = synthetic.harmonic_ramp(A, f, D, dt)
        t = gm.time
        ev = np.max(np.abs(gm.velocity() - synthetic.ramp_velocity(A, f, t)))
        ed = np.max(np.abs(gm.displacement() - synthetic.ramp_displacement(A, f, t)))
        errs.append((ev, ed))
    errs = np.array(errs)
    rates = np.log2(errs[:-1] / errs[1:])
    assert np.all(rates > 1.9) and np.all(rates < 2.1)
    vmax = np.max(np.abs(synthetic.ramp_velocity(A, f, np.linspace(0, D, 5001))))
    assert errs[-1, 0] < 1e-4 * vmax


def test_two_ramp_S1_shape():
    A, f, ap = 0.4, 5.0, 2.0
    gm = synthetic.two_ramp(A, f, ap, dt=0.001, vertical="opposition")
    tp = ap / A
    assert gm.duration == pytest.approx(3 * tp, abs=0.001)
    # envelope peak a_peak at t_p; the carrier peaks within a quarter period of t_p, where the
    # envelope is lower by at most A / (4 f)
    assert ap - A / (4 * f) - 1e-9 <= gm.pga <= ap
    i = np.argmax(np.abs(gm.acc))
    assert abs(gm.time[i] - tp) < 1 / f
    assert np.allclose(gm.acc_v, -0.5 * gm.acc)
    # decreasing part twice as long: the envelope halves at t_p + t_p
    t = gm.time
    late = (t > 2 * tp - 0.5 / f) & (t < 2 * tp + 0.5 / f)
    assert np.max(np.abs(gm.acc[late])) == pytest.approx(ap / 2, rel=0.1)


def test_truncated_ramp_S2_and_vertical_in_phase():
    gm = synthetic.truncated_ramp(0.5, 3.0, 1.5, dt=0.001, vertical="in_phase")
    assert gm.duration == pytest.approx(3.0, abs=1e-9)
    assert gm.pga <= 1.5 + 1e-12
    assert np.allclose(gm.acc_v, 0.5 * gm.acc)


def test_pulses():
    s = synthetic.sine_pulse(3.0, 2.0, cycles=1, dt=0.001, duration=1.0)
    assert s.pga == pytest.approx(3.0, rel=1e-5)
    assert s.velocity()[-1] == pytest.approx(0.0, abs=1e-9)  # full sine cycle: no net velocity
    c = synthetic.sine_pulse(3.0, 2.0, cycles=0.25, dt=0.001, kind="cosine")
    # quarter cosine: velocity A / W; trapezoidal error (W dt)²/12 relative
    W = 2 * math.pi * 2.0
    assert c.velocity()[-1] == pytest.approx(3.0 / W, rel=2 * (W * 0.001) ** 2 / 12)
    r = synthetic.rectangular_pulse(4.905, 0.2, dt=0.001, total=1.0)
    assert r.velocity()[-1] == pytest.approx(4.905 * 0.2, rel=1e-12)
    rk = synthetic.ricker(2.0, 5.0, dt=0.0005)
    i = np.argmax(rk.acc)
    assert rk.acc[i] == pytest.approx(2.0, rel=1e-12)
    # zero crossings at t0 +- 1/(pi f sqrt 2)
    tz = rk.meta["t0"] + 1 / (math.pi * 5.0 * math.sqrt(2))
    k = int(round(tz / rk.dt))
    assert abs(rk.acc[k]) < 2.0 * 4 * math.pi * 5.0 * rk.dt


def test_white_noise_band_and_rms():
    gm = synthetic.white_noise(20.0, 0.005, rms=0.3, band=(1.0, 10.0), seed=42)
    assert np.sqrt(np.mean(gm.acc**2)) == pytest.approx(0.3, rel=1e-12)
    X = np.abs(np.fft.rfft(gm.acc))
    f = np.fft.rfftfreq(gm.npts, gm.dt)
    assert np.max(X[(f < 1.0) | (f > 10.0)]) < 1e-9 * np.max(X)
    again = synthetic.white_noise(20.0, 0.005, rms=0.3, band=(1.0, 10.0), seed=42)
    assert np.array_equal(gm.acc, again.acc)


def test_groundmotion_operations():
    acc = np.sin(np.arange(101) * 0.3)
    gm = GroundMotion(dt=0.01, acc=acc, acc_v=0.5 * acc, name="x")
    assert gm.npts == 101 and gm.duration == pytest.approx(1.0)
    assert gm.time[0] == 0.0
    assert gm.scaled(2).pga == pytest.approx(2 * gm.pga)
    p = gm.padded(0.5)
    assert p.npts == 151 and np.all(p.acc[101:] == 0)
    s = gm.sliced(0.2, 0.5)
    assert s.npts == 31 and s.acc[0] == acc[20]
    r = gm.resampled(0.005)
    assert r.npts == 201 and np.allclose(r.acc[::2], acc)
    assert np.allclose(r.acc[1::2], 0.5 * (acc[:-1] + acc[1:]))
    with pytest.raises(ValueError):
        GroundMotion(dt=0.0, acc=acc)
    with pytest.raises(ValueError):
        GroundMotion(dt=0.01, acc=[1.0, np.nan])
    with pytest.raises(ValueError):
        GroundMotion(dt=0.01, acc=acc, acc_v=acc[:-1])


def test_from_samples_non_uniform_warns_and_resamples():
    t = np.array([0.0, 0.01, 0.02, 0.035, 0.04])
    a = 2.0 * t  # linear: resampling is exact
    with pytest.warns(UserWarning, match="non-uniform"):
        gm = GroundMotion.from_samples(t, a)
    assert np.allclose(gm.acc, 2.0 * gm.time)
    with pytest.raises(ValueError, match="not increasing at sample 2"):
        GroundMotion.from_samples([0, 0.1, 0.1], [0, 1, 2])


def test_integrate_exact_for_linear_acc():
    dt = 0.1
    t = np.arange(11) * dt
    v, d = integrate(3.0 * t, dt)
    assert np.allclose(v, 1.5 * t**2, atol=1e-14)
    assert np.allclose(d, 0.5 * t**3, atol=1e-14)


def test_baseline_removes_polynomial_exactly():
    dt = 0.01
    t = np.arange(2001) * dt
    gm = GroundMotion(dt=dt, acc=0.02 + 0.003 * t)
    out = processing.baseline_correct(gm, order=2, fit="velocity")
    assert np.max(np.abs(out.acc)) < 1e-10
    out0 = processing.baseline_correct(gm, order=1, fit="acceleration")
    assert np.max(np.abs(out0.acc)) < 1e-12


def test_end_correction_zero_final_velocity_displacement():
    rng = np.random.default_rng(0)
    gm = GroundMotion(dt=0.01, acc=rng.standard_normal(3000) + 0.05)
    out = processing.end_correction(gm)
    assert abs(out.velocity()[-1]) < 1e-10
    assert abs(out.displacement()[-1]) < 1e-9


def test_end_correction_zero_ends_keeps_end_samples():
    """With zero_ends the baseline vanishes at t = 0 and t = T: the first and last samples are
    unchanged, and the final velocity and displacement are zero to round-off."""
    rng = np.random.default_rng(1)
    a = rng.standard_normal(3001) + 0.05
    a[0] = a[-1] = 0.0
    out = processing.end_correction(GroundMotion(dt=0.01, acc=a), zero_ends=True)
    assert out.acc[0] == 0.0 and out.acc[-1] == 0.0
    assert abs(out.velocity()[-1]) < 1e-10
    assert abs(out.displacement()[-1]) < 1e-9
    assert np.max(np.abs(out.acc - a)) > 1e-3  # a baseline was removed


@pytest.mark.parametrize("f", [0.05, 0.1, 0.2, 1.0])
def test_zero_phase_highpass_gain(f):
    """Steady sine through a zero-phase Butterworth high-pass of order n: gain
    |H|² = 1/(1 + (fc/f)^(2n)), no phase shift."""
    fc, n, dt = 0.1, 4, 0.01
    t = np.arange(int(200 / f / dt) + 1) * dt  # 200 cycles
    gm = GroundMotion(dt=dt, acc=np.sin(2 * np.pi * f * t))
    out = processing.highpass(gm, fc, order=n)
    mid = slice(t.size // 3, 2 * t.size // 3)
    gain = np.max(np.abs(out.acc[mid]))
    assert gain == pytest.approx(1 / (1 + (fc / f) ** (2 * n)), rel=2e-3, abs=1e-4)
    # zero phase: correlation with the input at zero lag is maximal
    if f >= fc:
        assert np.corrcoef(out.acc[mid], gm.acc[mid])[0, 1] > 0.999


def test_bandpass_lowpass_taper_trim():
    gm = synthetic.white_noise(30.0, 0.005, band=None, seed=1)
    bp = processing.bandpass(gm, 1.0, 10.0)
    X = np.abs(np.fft.rfft(bp.acc))
    f = np.fft.rfftfreq(bp.npts, bp.dt)
    inside = X[(f > 2) & (f < 8)].mean()
    assert X[f > 40].mean() < 1e-3 * inside  # 4th order zero phase: (10/40)^16
    lp = processing.lowpass(gm, 5.0)
    assert lp.npts == gm.npts
    tp = processing.taper(gm, 0.1)
    assert tp.acc[0] == 0.0 and tp.acc[-1] == pytest.approx(0.0, abs=1e-12)
    assert np.array_equal(tp.acc[gm.npts // 2], gm.acc[gm.npts // 2])
    burst = GroundMotion(dt=0.01, acc=np.concatenate([np.zeros(500), np.ones(300),
                                                       np.zeros(500)]))
    tr = processing.trim_arias(burst, 0.0001, 0.9999)
    assert tr.duration == pytest.approx(3.0, abs=0.03)


def test_scaling():
    gm = synthetic.ricker(1.0, 2.0, dt=0.005)
    assert processing.scale_to_pga(gm, 3.0).pga == pytest.approx(3.0, rel=1e-14)
    from murus.motion.spectra import psa

    s = processing.scale_to_sa(gm, 0.5, 4.0)
    assert psa(s, 0.5) == pytest.approx(4.0, rel=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        processing.highpass(gm, 0.5)
