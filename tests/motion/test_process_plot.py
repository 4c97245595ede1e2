"""Record processing from the command line (``murus motion process``) and the record at a
glance (``murus motion plot``): each operation against a closed form, the processing recorded
in the written file, and the intensity measures against closed forms (sines, a velocity
step)."""

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from murus import G
from murus.cli import app
from murus.motion import GroundMotion, read
from murus.motion.measures import (
    d5_95,
    fourier_amplitude,
    housner_intensity,
    intensity_measures,
    predominant_period,
)
from murus.motion.processing import process, resample
from murus.motion.spectra import psa

runner = CliRunner()


def sine(A=1.5, f=2.0, dt=0.005, T=10.0, offset=0.0):
    t = dt * np.arange(int(round(T / dt)))
    return GroundMotion(acc=A * np.sin(2 * np.pi * f * t) + offset, dt=dt, name="sine")


def middle(x):
    n = x.size
    return x[n // 4: 3 * n // 4]


# ------------------------------------------------------------------ the operations
def test_baseline_order0_removes_an_offset_exactly():
    """A sine of whole cycles plus a constant: the mean removed leaves the sine (round-off)."""
    m = sine(offset=0.37)
    p = process(m, baseline=0)
    assert np.max(np.abs(p.acc - sine().acc)) < 1e-12
    assert p.meta["processing"] == ["baseline: polynomial of degree 0 fitted to the "
                                    "acceleration removed"]


def test_bandpass_keeps_a_mid_band_sine_and_records_it():
    """Zero-phase Butterworth of order n: |H| = 1 / (1 + (fc / f)^(2n)) for the high-pass (and
    the low-pass alike): 1 - |H| < 1e-7 at 1 to 4 Hz for 0.1-20 Hz, order 4. A 2 Hz sine under
    a Hann window of T = 10 s has its spectrum there, but for side lobes falling as
    (1 / (T |f - 2 Hz|))^3, about 1e-4 of the amplitude at the high-pass corner: the record
    passes unchanged to 1e-4 of its amplitude (2e-5 measured)."""
    dt, T = 0.005, 10.0
    t = dt * np.arange(int(round(T / dt)) + 1)
    m = GroundMotion(acc=1.5 * np.sin(2 * np.pi * 2.0 * t) * np.sin(np.pi * t / T) ** 2, dt=dt)
    p = process(m, highpass_hz=0.1, lowpass_hz=20.0)
    assert np.max(np.abs(p.acc - m.acc)) < 1e-4 * 1.5
    assert p.meta["processing"] == ["filter: acausal Butterworth band-pass 0.1-20 Hz, order 4, "
                                    "zero pads (Boore 2005)"]
    t = process(m, taper_fraction=0.05, highpass_hz=0.1)
    assert t.meta["processing"][0] == "taper: cosine over 0.05 of the duration at both ends"
    assert t.meta["processing"][1].startswith("filter: acausal Butterworth high-pass 0.1 Hz")


def test_highpass_removes_a_sine_below_the_corner():
    """A 0.05 Hz sine through a 1 Hz order-4 zero-phase high-pass: |H| = 1/(1 + 20^8) ~ 4e-11."""
    m = sine(A=1.0, f=0.05, dt=0.01, T=200.0)
    p = process(m, highpass_hz=1.0)
    assert np.max(np.abs(middle(p.acc))) < 1e-6


def test_resample_down_filters_what_would_alias():
    """A 40 Hz sine sampled at 200 Hz, resampled to 50 Hz (Nyquist 25 Hz): without a filter it
    folds back to 10 Hz at full amplitude; the anti-alias low-pass at 0.4 / dt = 20 Hz, order 4,
    zero phase, leaves 1 / (1 + (40/20)^8) = 1/257 of it."""
    m = sine(A=1.0, f=40.0, dt=0.005, T=10.0)
    aliased = m.resampled(0.02)
    assert np.max(np.abs(middle(aliased.acc))) > 0.5
    r = resample(m, 0.02)
    assert r.dt == 0.02
    assert np.max(np.abs(middle(r.acc))) < 1.05 / 257
    # up-sampling: linear interpolation only, the samples kept where the grids meet
    u = resample(m, 0.0025)
    assert np.allclose(u.acc[::2], m.acc[: u.acc[::2].size], atol=1e-12)


def test_trim_and_scale():
    m = sine()
    p = process(m, trim_s=(2.0, 6.0), pga=3.0)
    assert p.duration == pytest.approx(4.0, abs=1e-9)
    assert p.pga == pytest.approx(3.0, rel=1e-12)
    q = process(m, sa=(0.3, 4.0))
    assert psa(q, 0.3) == pytest.approx(4.0, rel=1e-9)
    a = process(m, trim_arias_fractions=(0.05, 0.95))
    # a stationary sine: the Husid curve is linear, so 90 % of the duration is kept
    assert a.duration == pytest.approx(0.9 * m.duration, abs=0.25 / 2.0)
    assert a.meta["processing"][0].startswith("trim: 0.05 to 0.95 of the Arias intensity")


@pytest.mark.parametrize("kw, msg", [
    (dict(trim_s=(1, 2), trim_arias_fractions=(0.1, 0.9)), "not both"),
    (dict(pga=1.0, sa=(0.2, 1.0)), "not both"),
    (dict(baseline=-1), "baseline order"),
    (dict(taper_fraction=0.7), "taper fraction"),
    (dict(highpass_hz=-1.0), "must be positive"),
    (dict(trim_s=(20.0, 30.0)), "not inside the record"),
    (dict(resample_dt=100.0), "longer than the record"),
    (dict(filter_order=0), "filter order"),
])
def test_process_rejects_bad_values(kw, msg):
    with pytest.raises(ValueError, match=msg):
        process(sine(), **kw)


# ------------------------------------------------------------------ the command
def write_sine(path, **kw):
    from murus.motion.io import write

    write(sine(**kw), path)
    return path


def test_process_command_records_each_operation_in_the_header(tmp_path):
    src = write_sine(tmp_path / "in.csv")
    out = tmp_path / "out.csv"
    r = runner.invoke(app, ["motion", "process", str(src), "--out", str(out), "--baseline", "0",
                            "--taper", "0.05", "--highpass", "0.1", "--lowpass", "20",
                            "--resample", "0.01", "--trim", "1,9", "--pga-g", "0.3"])
    assert r.exit_code == 0, r.output
    head = [ln for ln in out.read_text().splitlines() if ln.startswith("# processing")]
    assert [h.split(":")[0] for h in head] == [f"# processing {i}" for i in range(1, 7)]
    assert "baseline" in head[0] and "taper" in head[1] and "band-pass" in head[2]
    assert "resample" in head[3] and "trim" in head[4] and "scale" in head[5]
    back = read(out)
    assert back.dt == pytest.approx(0.01) and back.duration == pytest.approx(8.0)
    assert back.pga == pytest.approx(0.3 * G, rel=1e-9)
    # AT2: the operations on the title line, the record read back the same
    at2 = tmp_path / "out.at2"
    r = runner.invoke(app, ["motion", "process", str(src), "--out", str(at2), "--pga", "2.0"])
    assert r.exit_code == 0, r.output
    first = at2.read_text().splitlines()[0]
    assert "processing: 1. scale: x" in first
    assert read(at2).pga == pytest.approx(2.0, rel=1e-9)


@pytest.mark.parametrize("args, msg", [
    (["--trim", "1"], "--trim 1: expected two numbers"),
    (["--pga", "1", "--pga-g", "0.1"], "not both"),
    (["--baseline-fit", "jerk"], "--baseline-fit jerk"),
    (["--taper", "0.9"], "taper fraction"),
    (["--sa", "0.2,nan"], "not finite"),
])
def test_process_command_bad_input_one_line_exit_2_nothing_written(tmp_path, args, msg):
    src = write_sine(tmp_path / "in.csv")
    out = tmp_path / "out.csv"
    r = runner.invoke(app, ["motion", "process", str(src), "--out", str(out), *args])
    assert r.exit_code == 2, r.output
    assert msg in r.output and len(r.output.strip().splitlines()) == 1
    assert not out.exists()


def test_process_command_never_overwrites_the_input(tmp_path):
    src = write_sine(tmp_path / "in.csv")
    before = src.read_text()
    r = runner.invoke(app, ["motion", "process", str(src), "--out", str(src), "--pga", "1"])
    assert r.exit_code == 2 and "is the input file" in r.output
    assert src.read_text() == before


# ------------------------------------------------------------------ the measures
def test_fourier_amplitude_of_a_sine():
    """A sine of amplitude A over whole cycles, at a grid frequency: |C| = A T_d / 2."""
    m = sine(A=1.5, f=2.0, dt=0.005, T=10.0)
    f, c = fourier_amplitude(m)
    k = int(np.argmin(np.abs(f - 2.0)))
    assert f[k] == pytest.approx(2.0) and c[k] == pytest.approx(1.5 * 10.0 / 2, rel=1e-9)


def test_husid_duration_and_predominant_period_of_a_sine():
    m = sine(A=1.0, f=2.0, dt=0.005, T=20.0)
    # the Husid curve of sin² rises linearly with a ripple of at most 1/(4 pi f) in time
    assert d5_95(m) == pytest.approx(0.9 * 20.0, abs=1 / (4 * math.pi * 2.0))
    # the grid of predominant_period is 1.3 % apart
    assert predominant_period(m) == pytest.approx(0.5, rel=0.014)


def test_housner_intensity_of_a_velocity_step():
    """A ground-velocity step dv (one-sample acceleration spike of area dv): the relative
    displacement of an oscillator is -(dv / w_d) exp(-xi w t) sin(w_d t), whose first peak gives
    PSV = w SD = dv exp(-xi phi / sqrt(1 - xi²)), phi = atan(sqrt(1 - xi²) / xi), the same at
    every period; so SI = (2.5 - 0.1) dv exp(...). The spike of width 2 dt differs from an
    impulse by O((w dt)²) < 1e-4 at T = 0.1 s."""
    dt, dv, xi = 1e-4, 0.3, 0.05
    acc = np.zeros(int(3.0 / dt))
    acc[10] = dv / dt
    m = GroundMotion(acc=acc, dt=dt, name="step")
    phi = math.atan(math.sqrt(1 - xi**2) / xi)
    expected = 2.4 * dv * math.exp(-xi * phi / math.sqrt(1 - xi**2))
    assert housner_intensity(m, xi) == pytest.approx(expected, rel=1e-3)


def test_plot_command_writes_the_figure_and_the_measures(tmp_path):
    src = write_sine(tmp_path / "in.csv", T=8.0)
    out = tmp_path / "plot"
    r = runner.invoke(app, ["motion", "plot", str(src), "--out", str(out), "--json"])
    assert r.exit_code == 0, r.output
    got = json.loads(r.stdout)
    im = intensity_measures(read(src))
    assert got == pytest.approx(im, rel=1e-12)
    assert got["pga"] == pytest.approx(1.5, rel=1e-12)
    for name in ("record.png", "measures.json", "measures.csv", "spectra.csv", "fourier.csv"):
        assert (out / name).stat().st_size > 0
    assert (out / "spectra.csv").read_text().splitlines()[0] == (
        "period_s,psa_0.02_m_s2,psa_0.05_m_s2,psa_0.1_m_s2,psa_0.2_m_s2")
    rows = (out / "measures.csv").read_text().splitlines()
    assert rows[0] == "measure,label,value,units" and rows[1].startswith("pga,PGA,1.5,m/s²")
    r = runner.invoke(app, ["motion", "plot", str(src), "--out", str(tmp_path / "p2"),
                            "--damping", "1.5"])
    assert r.exit_code == 2 and "--damping" in r.output
    assert not (tmp_path / "p2").exists()


def test_rotd_command_closed_forms(tmp_path):
    """Two identical perpendicular components (a sine): the resultant along 45° is sqrt(2)
    times each, so RotD100 = sqrt(2) PSA, and RotD50 = PSA (the median over 0-179° of
    |cos t + sin t| PSA); the columns of the components are their own spectra."""
    a = write_sine(tmp_path / "a.csv", T=6.0)
    b = write_sine(tmp_path / "b.csv", T=6.0)
    out = tmp_path / "rotd"
    r = runner.invoke(app, ["motion", "rotd", str(a), str(b), "--out", str(out),
                            "--n-periods", "12"])
    assert r.exit_code == 0, r.output
    rows = np.loadtxt(out / "rotd.csv", delimiter=",", skiprows=1)
    head = (out / "rotd.csv").read_text().splitlines()[0]
    assert head == "period_s,rotd50_m_s2,rotd100_m_s2,angle_rotd100_deg,psa_a_m_s2,psa_b_m_s2"
    T, d50, d100, ang, pa, pb = rows.T
    assert np.allclose(pa, pb, rtol=1e-12)
    assert np.allclose(d100, math.sqrt(2) * pa, rtol=2e-4)
    assert np.allclose(d50, pa, rtol=2e-4)
    assert np.all(np.abs(ang - 45.0) <= 1.0)
    assert (out / "rotd.png").stat().st_size > 0
    r = runner.invoke(app, ["motion", "rotd", str(a), "--out", str(tmp_path / "r2")])
    assert r.exit_code == 2 and "horizontal channels" in r.output
    assert not (tmp_path / "r2").exists()
