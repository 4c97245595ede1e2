"""The shaking-table test format of murus.identify.testdata: round trip, units, one-line
errors naming file, line and column, and sequences (sequence.toml or naming convention)."""

import numpy as np
import pytest

from murus import G
from murus.identify.testdata import (
    ShakingTableTest,
    TestDataError,
    read_sequence,
    read_test,
    write_sequence,
    write_test,
)

HEADER = """# murus shaking-table test
# name: S01
# kind: seismic
# sampling_rate_hz: 100
# pga_g: 0.04
# wall_length_m: 0.72
# wall_height_m: 1.8
# lvdt_positions_m: 0.1, 0.62
# top_mass_kg: 5000
# operator: someone
"""


def _make(n=50, seed=0, kind="seismic", name="S01"):
    rng = np.random.default_rng(seed)
    ch = {"table_acc": rng.standard_normal(n), "top_acc": rng.standard_normal(n),
          "lvdt_1": 1e-5 * rng.standard_normal(n), "lvdt_2": 1e-5 * rng.standard_normal(n),
          "rot_bottom": 1e-4 * rng.standard_normal(n), "rot_top": 1e-4 * rng.standard_normal(n)}
    return ShakingTableTest(name=name, sampling_rate=200.0, wall_length=2.1, wall_height=1.8,
                            channels=ch, kind=kind, pga_g=0.15,
                            lvdt_positions=[0.05, 2.05], top_mass=5000.0,
                            meta={"note": "x"})


def test_round_trip(tmp_path):
    t = _make()
    p = write_test(t, tmp_path / "a.csv")
    r = read_test(p)
    assert r.name == "S01" and r.kind == "seismic" and r.pga_g == pytest.approx(0.15)
    assert r.sampling_rate == 200.0 and r.dt == pytest.approx(0.005)
    assert r.wall_length == 2.1 and r.top_mass == 5000.0 and r.meta == {"note": "x"}
    np.testing.assert_allclose(r.lvdt_positions, [0.05, 2.05])
    for k, v in t.channels.items():
        np.testing.assert_allclose(r.channels[k], v, rtol=1e-8, atol=1e-15)
    assert r.lvdt.shape == (2, 50) and r.has_lvdt and r.has_rotations


def test_units_converted_to_si(tmp_path):
    p = tmp_path / "u.csv"
    p.write_text(HEADER + "table_acc [g],top_acc [cm/s2],lvdt_1 [mm],lvdt_2 [m],"
                 "rot_bottom [mrad],rot_top [rad]\n"
                 "0.1,100,1,0.001,2,0.002\n0.2,-100,2,0.002,4,0.004\n")
    r = read_test(p)
    np.testing.assert_allclose(r.table_acc, [0.1 * G, 0.2 * G])
    np.testing.assert_allclose(r.top_acc, [1.0, -1.0])
    np.testing.assert_allclose(r.lvdt, [[1e-3, 2e-3], [1e-3, 2e-3]])
    np.testing.assert_allclose(r.rot_bottom, r.rot_top)
    assert r.meta == {"operator": "someone"}
    assert r.measured_pga_g == pytest.approx(0.2)


COLS = "time [s],table_acc [m/s2],top_acc [m/s2],lvdt_1 [m],lvdt_2 [m]\n"


@pytest.mark.parametrize("body, match", [
    ("time [s],table_acc [m/s2],lvdt_1 [m],lvdt_2 [m]\n0,1,2,3\n0.01,1,2,3\n",
     r"u\.csv:11: missing required channel 'top_acc'"),
    ("time [s],table_acc [ft/s2],top_acc [m/s2]\n0,1,2\n0.01,1,2\n",
     r"u\.csv:11: column 2 \(table_acc\): bad unit 'ft/s2'"),
    ("time [s],table_acc,top_acc [m/s2]\n0,1,2\n0.01,1,2\n",
     r"u\.csv:11: column 2 'table_acc' is not 'name \[unit\]'"),
    ("time [s],table_acc [m/s2],top_acc [m/s2],strain [m]\n0,1,2,3\n0.01,1,2,3\n",
     r"u\.csv:11: column 4: unknown channel 'strain'"),
    (COLS + "0,1,2,3,4\n0.01,1,2,nan,4\n", r"u\.csv:13: column 4 \(lvdt_1\): NaN"),
    (COLS + "0,1,2,3,4\n0.01,1,x2,3,4\n", r"u\.csv:13: column 3 \(top_acc\): not a number"),
    (COLS + "0,1,2,3,4\n0.01,1,2,3\n", r"u\.csv:13: 4 values, expected 5"),
    (COLS + "0,1,2,3,4\n0.01,1,2,3,4\n0.03,1,2,3,4\n",
     r"u\.csv:14: column 1 \(time\): non-uniform sampling"),
])
def test_errors_name_file_line_column(tmp_path, body, match):
    p = tmp_path / "u.csv"
    p.write_text(HEADER + body)
    with pytest.raises(TestDataError, match=match) as exc:
        read_test(p)
    assert "\n" not in str(exc.value)


def test_header_errors(tmp_path):
    p = tmp_path / "h.csv"
    p.write_text(HEADER.replace("# sampling_rate_hz: 100\n", "") + COLS + "0,1,2,3,4\n"
                 "0.01,1,2,3,4\n")
    with pytest.raises(TestDataError, match="missing header key 'sampling_rate_hz'"):
        read_test(p)
    p.write_text(HEADER.replace("0.1, 0.62", "0.1") + COLS + "0,1,2,3,4\n0.01,1,2,3,4\n")
    with pytest.raises(TestDataError, match=r"h\.csv:8: lvdt_positions_m has 1 values"):
        read_test(p)
    p.write_text(HEADER.replace("kind: seismic", "kind: quake") + COLS + "0,1,2,3,4\n"
                 "0.01,1,2,3,4\n")
    with pytest.raises(TestDataError, match=r"h\.csv:3: kind must be one of"):
        read_test(p)
    with pytest.raises(TestDataError, match="no such file"):
        read_test(tmp_path / "missing.csv")


def test_sequence_toml_and_naming_convention(tmp_path):
    tests = [_make(kind="white_noise", name="WN01"), _make(name="S01"),
             _make(kind="white_noise", name="WN02")]
    tests[1].pga_g = 0.04
    write_sequence(tmp_path / "a", tests, name="short wall")
    seq = read_sequence(tmp_path / "a")
    assert seq.name == "short wall" and len(seq) == 3
    assert [e.kind for e in seq] == ["white_noise", "seismic", "white_noise"]
    assert [e.label for e in seq.seismic] == ["S01"]
    assert seq.table1()[0]["pga_nominal_g"] == pytest.approx(0.04)
    # naming convention: no sequence.toml, natural order, WN in the name = white noise
    b = tmp_path / "b"
    b.mkdir()
    for fname, t in (("10_S02.csv", _make(name="S02")), ("2_WN02.csv", _make(name="WN02")),
                     ("1_S01.csv", _make(name="S01"))):
        write_test(t, b / fname)
        txt = (b / fname).read_text().replace("# kind: seismic\n", "")
        (b / fname).write_text(txt)
    seq = read_sequence(b)
    assert [e.file for e in seq] == ["1_S01.csv", "2_WN02.csv", "10_S02.csv"]
    assert [e.kind for e in seq] == ["seismic", "white_noise", "seismic"]
    # errors in sequence.toml name the file
    (b / "sequence.toml").write_text('[[test]]\nfile = "1_S01.csv"\nkind = "quake"\n')
    with pytest.raises(TestDataError, match=r"sequence\.toml: \[\[test\]\] number 1: kind"):
        read_sequence(b)
    (b / "sequence.toml").write_text('[[test]]\nfile = "nope.csv"\n')
    with pytest.raises(TestDataError, match=r"nope\.csv: no such file"):
        read_sequence(b)
