"""The one builder of a motion from a case file's [motion] table (murus.motion.case), shared by
the rocking, DEM and study case files."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from murus import G
from murus.config import CaseError
from murus.dem.case import MotionCfg as DemMotion
from murus.motion.case import amplitude_si, build_motion
from murus.rocking.case import MotionCfg as RockingMotion


def test_pulse_amplitude_in_si_units():
    m = RockingMotion(type="sine-pulse", amplitude_g=0.3, frequency=2.0, scale=0.5)
    assert amplitude_si(m) == pytest.approx(0.3 * G * 0.5, rel=1e-15)
    m = RockingMotion(type="sine-pulse", amplitude=2.0, frequency=2.0, scale=0.5)
    assert amplitude_si(m) == pytest.approx(1.0, rel=1e-15)


def test_analytic_and_sampled_pulses_agree_with_the_closed_form():
    kw = dict(type="cosine-pulse", amplitude=1.5, frequency=2.0, cycles=1.5)
    analytic = build_motion(RockingMotion(**kw), None)
    sampled = build_motion(DemMotion(**kw), None, sampled_dt=0.001)
    assert analytic.amplitude == 1.5 and analytic.duration == pytest.approx(0.75, rel=1e-15)
    t = np.arange(sampled.npts) * sampled.dt
    ref = np.where(t <= 0.75 + 1e-12, 1.5 * np.cos(2 * math.pi * 2.0 * t), 0.0)
    np.testing.assert_allclose(sampled.acc, ref, rtol=0, atol=1e-12)
    # a study sweeping the frequency
    swept = build_motion(RockingMotion(**kw), None, frequency=4.0)
    assert swept.omega == pytest.approx(2 * math.pi * 4.0, rel=1e-15)


def test_harmonic_ramp_and_no_motion():
    m = DemMotion(type="harmonic-ramp", A=0.5, frequency=4.0, scale=2.0)
    gm = build_motion(m, None, sampled_dt=0.002, duration=1.0)
    t = np.arange(gm.npts) * gm.dt
    np.testing.assert_allclose(gm.acc, 1.0 * t * np.sin(2 * math.pi * 4.0 * t), atol=1e-12)
    assert build_motion(DemMotion(type="tilt", rate_deg_per_s=1.0), None) is None
    assert build_motion(DemMotion(), None) is None


def test_record_errors_carry_the_key(tmp_path):
    case = tmp_path / "case.toml"
    text = "[motion]\nfile = 'nowhere.csv'\n"
    case.write_text(text)
    with pytest.raises(CaseError) as info:
        build_motion(RockingMotion(file="nowhere.csv"), case, text)
    assert info.value.key == ("motion", "file")
    assert str(info.value) == "case.toml line 2: [motion.file] motion file 'nowhere.csv' not found"
    (tmp_path / "rec.csv").write_text("0.0,0.1\n0.01,0.2\n0.02,-0.1\n")
    gm = build_motion(DemMotion(file="rec.csv", units="g", scale=2.0), Path(case), text)
    np.testing.assert_allclose(gm.acc, np.array([0.1, 0.2, -0.1]) * G * 2.0, rtol=1e-12)
