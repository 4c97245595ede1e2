"""The virtual test sequence (murus.identify.synth): readable in the documented format,
deterministic, and identified by murus.identify.modal within 2 % of the synthesized
frequencies (issue 8, item 8)."""

import json

import numpy as np
import pytest

from murus.identify.classify import classify_sequence
from murus.identify.compressive import compressive_table
from murus.identify.modal import evolution
from murus.identify.synth import SynthWall, synthesize_sequence, synthesize_tests
from murus.identify.testdata import read_sequence

KW = {"levels": (0.04, 0.12, 0.32), "wn_duration": 60.0, "seismic_duration": 15.0}


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return synthesize_sequence(tmp_path_factory.mktemp("seq") / "virtual", seed=7, **KW)


def test_readable_and_ordered(folder):
    seq = read_sequence(folder)
    assert [e.label for e in seq] == ["WN01", "S01", "WN02", "S02", "WN03", "S03", "WN04"]
    assert [e.kind for e in seq][:2] == ["white_noise", "seismic"]
    rows = seq.table1()
    np.testing.assert_allclose([r["pga_nominal_g"] for r in rows], KW["levels"])
    # the measured PGA of the table channel equals the nominal one up to sensor noise
    np.testing.assert_allclose([r["pga_measured_g"] for r in rows], KW["levels"], rtol=0.03)
    t = seq.entries[1].test
    assert t.has_lvdt and t.has_rotations and t.top_mass == 5000.0
    assert t.meta["lvdt_zero"] == "unloaded"


def test_identified_frequencies_follow_the_synthesized_ones(folder):
    seq = read_sequence(folder)
    truth = [t for t in json.loads((folder / "truth.json").read_text())["tests"]
             if t["kind"] == "white_noise"]
    evo = evolution(seq)
    f_true = np.array([t["frequency_hz"] for t in truth])
    z_true = np.array([t["damping"] for t in truth])
    print("\nf identified", evo.frequency[:, 0], "true", f_true)
    print("zeta identified", evo.damping[:, 0], "true", z_true)
    np.testing.assert_allclose(evo.frequency[:, 0], f_true, rtol=0.02)
    np.testing.assert_allclose(evo.damping[:, 0], z_true, rtol=0.15)
    assert np.all(np.diff(evo.frequency[:, 0]) < 0)  # damage: the frequency drops
    assert evo.reliable.all()


def test_classes_and_compressive_lengths(folder):
    seq = read_sequence(folder)
    labels = [c.label for c in classify_sequence(seq)]
    assert labels[0] == "cantilever" and labels[-1] == "rocking"
    truth = json.loads((folder / "truth.json").read_text())["tests"]
    assert [t["rocked"] for t in truth if t["kind"] == "seismic"] == [False, False, True]
    table = compressive_table(seq)
    lc = [r["lc_percent"] for r in table.rows]
    assert lc[0] > 50.0 and lc[-1] < 1.0 and lc == sorted(lc, reverse=True)
    md = table.to_markdown()
    assert "Assessment (linear)" in md and "| virtual wall | S01 |" in md


def test_deterministic_for_a_seed():
    kw = dict(levels=(0.3,), wn_duration=25.0, seismic_duration=5.0)
    a, ta = synthesize_tests(seed=3, **kw)
    b, tb = synthesize_tests(seed=3, **kw)
    c, _ = synthesize_tests(seed=4, **kw)
    assert ta == tb
    for x, y, z in zip(a, b, c, strict=True):
        for k in x.channels:
            np.testing.assert_array_equal(x.channels[k], y.channels[k])
        assert not np.array_equal(x.channels["top_acc"], z.channels["top_acc"])


def test_elastic_base_is_the_ec6_linear_block():
    """The synthetic base joint reproduces the EN 1996-1-1 linear stress block: the
    plane-section contact length of its readings equals 3 (L/2 - e) beyond the kern."""
    from murus import G
    from murus.eurocode.ec6 import compressive_length
    from murus.identify.compressive import contact_length

    w = SynthWall()
    a_top = np.array([0.0, 0.5, -1.0, 1.5])  # m/s2
    d, _ = w.base_joint(a_top)
    lc = contact_length(w.lvdt_positions, d, w.length)
    N = w.top_mass * G
    expected = compressive_length(N * np.ones(4), w.top_mass * a_top * w.height, w.length)
    np.testing.assert_allclose(lc, expected, rtol=1e-9)


def test_bad_levels():
    with pytest.raises(ValueError, match="levels"):
        synthesize_tests(levels=(-0.1,))
