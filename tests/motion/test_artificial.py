"""Artificial EC8-compatible records and the EN 1998-1 §3.2.3.1.2 report."""

import numpy as np
import pytest

from murus.eurocode.ec8 import elastic_spectrum
from murus.motion.artificial import check_ec8, envelope, generate_ec8
from murus.motion.spectra import response_spectrum


@pytest.fixture(scope="module")
def records():
    return generate_ec8(2.5, "C", 1, n=3, seed=7)


def test_records_compatible_and_baseline(records):
    rep = check_ec8(records, 2.5, "C", 1, T1=0.4)
    assert rep.passed, rep.to_text()
    crit = {c.name: c for c in rep.criteria}
    spec = crit["mean 5 % spectrum >= 0.9 Se in range"]
    assert 0.08 <= spec.period <= 0.8 and spec.ratio >= 1.0
    for r in records:
        assert abs(r.velocity()[-1]) < 0.01  # m/s
        assert abs(r.displacement()[-1]) < 0.01  # m
        assert r.meta["stationary_duration"] >= 10
        assert r.pga >= 2.5 * 1.15 * (1 - 1e-12)  # ag S, ground C type 1
    # spectrum matched over the whole range within 15 % per record mean
    T = np.geomspace(0.05, 3.0, 60)
    mean = np.mean([response_spectrum(r, T).psa for r in records], axis=0)
    ratio = mean / elastic_spectrum(T, 2.5, "C", 1)
    assert 0.9 < ratio.min() and ratio.max() < 1.15


def test_records_start_and_end_at_rest(records):
    """The artificial records start and end at zero acceleration (EN 1998-1 records are applied
    from rest), with zero final velocity and displacement: the baseline vanishes at both ends."""
    for r in records:
        assert abs(r.acc[0]) <= 1e-12 * r.pga and abs(r.acc[-1]) <= 1e-12 * r.pga
        v, d = r.velocity(), r.displacement()
        assert abs(v[-1]) < 1e-12 * r.pga * r.duration
        assert abs(d[-1]) < 1e-12 * r.pga * r.duration ** 2
        assert "sin(pi t/T)" in r.meta["baseline"]


def test_reproducible_with_seed(records):
    again = generate_ec8(2.5, "C", 1, n=1, seed=7)
    assert np.array_equal(again[0].acc, records[0].acc)
    other = generate_ec8(2.5, "C", 1, n=1, seed=8)
    assert not np.array_equal(other[0].acc, records[0].acc)


def test_report_fails_with_reasons(records):
    rep = check_ec8(records[:2], 2.5, "C", 1, T1=0.4)
    crit = {c.name: c for c in rep.criteria}
    assert not rep.passed and not crit["number of records >= 3"].passed
    weak = [r.scaled(0.8) for r in records]
    rep = check_ec8(weak, 2.5, "C", 1, period_range=(0.1, 1.0))
    crit = {c.name: c for c in rep.criteria}
    assert not crit["mean PGA >= ag S"].passed
    assert crit["mean PGA >= ag S"].ratio == pytest.approx(
        np.mean([r.pga for r in weak]) / (2.5 * 1.15))
    s = crit["mean 5 % spectrum >= 0.9 Se in range"]
    assert not s.passed and 0.1 <= s.period <= 1.0
    assert "FAIL" in rep.to_text()


def test_envelope_shapes():
    t = np.linspace(0, 16, 1601)
    e = envelope(t, 2, 10, 4)
    assert e[0] == 0 and e[200] == 1 and e[1200] == 1 and e[-1] == 0
    j = envelope(t, 2, 10, 4, "jennings")
    assert j[100] == pytest.approx(0.25) and j[-1] == pytest.approx(0.05)
