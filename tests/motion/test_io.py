"""Readers and writers: sample files of each format, round trips, refusals and property-based
corruption tests (never a traceback, never a silently wrong record)."""

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from murus import G
from murus.motion import GroundMotion, MotionFormatError, read, write

DATA = Path(__file__).resolve().parents[1] / "data" / "motion"


def test_at2_sample_last_line_and_dt_not_rounded():
    gm = read(DATA / "sample.AT2")
    assert gm.meta["format"] == "at2"
    assert gm.npts == 13
    assert gm.dt == 0.005  # '.0050' parsed exactly, not rounded
    assert gm.acc[-1] == pytest.approx(-0.13 * G, rel=1e-15)  # the last (partial) line is read
    assert gm.acc[0] == pytest.approx(0.01 * G, rel=1e-15)
    assert gm.meta["component"] == "090"
    old = read(DATA / "sample_old.AT2")
    assert old.npts == 6 and old.dt == 0.02 and old.acc[-1] == pytest.approx(-0.006 * G)


def test_esm_sample():
    gm = read(DATA / "sample_esm.ASC")
    assert gm.meta["format"] == "esm"
    assert gm.npts == 8 and gm.dt == 0.005
    assert gm.pga == pytest.approx(0.45, rel=1e-15)  # 45 cm/s²
    assert gm.meta["station"] == "TST" and gm.meta["magnitude"] == 6.0


def test_cosmos_sample():
    gm = read(DATA / "sample_cosmos.V2")
    assert gm.meta["format"] == "cosmos"
    assert gm.npts == 11 and gm.dt == 0.01
    assert np.allclose(gm.acc, 0.01 * np.array(
        [1.0, -2.5, 3.25, -4.0, 5.5, -6.0, 7.0, -8.0, 9.0, -10.0, 11.0]), rtol=1e-15)


def test_units_conflict_is_refused():
    with pytest.raises(MotionFormatError, match="sample.AT2 line 3"):
        read(DATA / "sample.AT2", units="cm/s2")


def _roundtrip_motion(n=57, dt=0.0123456789, vertical=False, seed=0):
    rng = np.random.default_rng(seed)
    a = rng.standard_normal(n) * 2.0
    return GroundMotion(dt=dt, acc=a, acc_v=0.4 * a if vertical else None, name="rt",
                        meta={"event": "E, with comma", "station": "S"})


@pytest.mark.parametrize("vertical", [False, True])
def test_csv_roundtrip_exact(tmp_path, vertical):
    gm = _roundtrip_motion(vertical=vertical)
    p = write(gm, tmp_path / "r.csv")
    back = read(p)
    assert back.dt == gm.dt
    assert np.array_equal(back.acc, gm.acc)
    if vertical:
        assert np.array_equal(back.acc_v, gm.acc_v)
    gm_g = read(write(gm, tmp_path / "g.csv", units="g"))
    assert np.allclose(gm_g.acc, gm.acc, rtol=1e-15, atol=1e-15)


def test_at2_roundtrip(tmp_path):
    gm = _roundtrip_motion(n=23)  # 4 full lines and a partial one
    back = read(write(gm, tmp_path / "r.AT2"))
    assert back.dt == gm.dt and back.npts == gm.npts
    assert np.allclose(back.acc, gm.acc, rtol=1e-9, atol=1e-9 * gm.pga)


def test_two_column_units_and_errors(tmp_path):
    p = tmp_path / "record.csv"
    p.write_text("time,acc\n0,1\n0.01,2\n0.02,abc\n")
    with pytest.raises(MotionFormatError) as e:
        read(p, units="g")
    assert str(e.value) == "record.csv line 4: 'abc' is not a number"
    p.write_text("0 1\n0.01 2\n0.02 3\n")
    with pytest.raises(MotionFormatError, match="units not declared"):
        read(p)
    gm = read(p, units="cm/s2")
    assert gm.dt == 0.01 and gm.acc[-1] == pytest.approx(0.03)
    p.write_text("0 1\n0.01 2\n0.01 3\n")
    with pytest.raises(MotionFormatError, match="record.csv line 3: time"):
        read(p, units="g")
    p.write_text("0 1\n0.01 nan\n")
    with pytest.raises(MotionFormatError, match="line 2: 'nan' is not a finite number"):
        read(p, units="g")
    p.write_text("1\n2\n3\n")
    with pytest.raises(MotionFormatError, match="without a time step"):
        read(p, units="g")
    gm = read(p, units="g", dt=0.02)
    assert gm.npts == 3 and gm.dt == 0.02
    p.write_text("# npts: 4\n# units: g\n# dt: 0.01\n1\n2\n3\n")
    with pytest.raises(MotionFormatError, match="npts = 4 but the file has 3"):
        read(p)


def test_non_uniform_time_resampled_with_warning(tmp_path):
    p = tmp_path / "nu.csv"
    p.write_text("0 0\n0.01 1\n0.03 3\n0.04 4\n")
    with pytest.warns(UserWarning, match="non-uniform"):
        gm = read(p, units="m/s2")
    assert np.allclose(gm.acc, 100 * gm.time)  # linear data: resampling exact


def test_at2_npts_mismatch_and_missing_dt(tmp_path):
    text = (DATA / "sample.AT2").read_text()
    p = tmp_path / "bad.AT2"
    p.write_text(text.replace("NPTS=   13", "NPTS=   14"))
    with pytest.raises(MotionFormatError, match="bad.AT2 line 7: header declares NPTS = 14"):
        read(p)
    p.write_text(text.replace("DT=   .0050 SEC", "SEC"))
    with pytest.raises(MotionFormatError, match="bad.AT2 line 4"):
        read(p)
    lines = text.splitlines()
    p.write_text("\n".join(lines[:-1]) + "\n")  # dropped last line
    with pytest.raises(MotionFormatError, match="NPTS = 13 but the file has 10"):
        read(p)


def test_missing_file_and_binary(tmp_path):
    with pytest.raises(MotionFormatError, match="no such file"):
        read(tmp_path / "none.csv")
    b = tmp_path / "b.csv"
    b.write_bytes(b"\x00\x01\x02")
    with pytest.raises(MotionFormatError, match="binary"):
        read(b)


# ------------------------------------------------------------------ property-based tests

_settings = settings(max_examples=60, deadline=None,
                     suppress_health_check=[HealthCheck.function_scoped_fixture])


@_settings
@given(data=st.binary(max_size=400), ext=st.sampled_from([".csv", ".AT2", ".ASC", ".V2", ".txt"]))
def test_random_bytes_never_traceback(tmp_path, data, ext):
    p = tmp_path / f"f{ext}"
    p.write_bytes(data)
    try:
        gm = read(p, units="g", dt=0.01)
    except MotionFormatError as e:
        assert "\n" not in str(e) and p.name in str(e)
        return
    assert np.all(np.isfinite(gm.acc)) and gm.dt > 0 and gm.npts >= 2


_fmt_text = st.sampled_from(["sample.AT2", "sample_esm.ASC", "sample_cosmos.V2",
                             "sample_old.AT2"])


@_settings
@given(name=_fmt_text, data=st.data())
def test_corrupted_sample_refused_or_identical(tmp_path, name, data):
    """Mutate one character or line of a valid file: the reader either refuses with a one-line
    message or returns exactly the original record (a harmless change such as a blank)."""
    text = (DATA / name).read_text()
    ref = read(DATA / name)
    lines = text.splitlines()
    kind = data.draw(st.sampled_from(["char", "drop_line", "dup_line", "insert_text"]))
    i = data.draw(st.integers(0, len(lines) - 1))
    if kind == "char":
        j = data.draw(st.integers(0, max(0, len(lines[i]) - 1)))
        c = data.draw(st.sampled_from(list("x9.-+ eE,:N") + ["nan", "1e999"]))
        lines[i] = lines[i][:j] + c + lines[i][j + 1:]
    elif kind == "drop_line":
        del lines[i]
    elif kind == "dup_line":
        lines.insert(i, lines[i])
    else:
        lines.insert(i, data.draw(st.sampled_from(["abc", "1 2 x", "nan", "", "NPTS=3"])))
    p = tmp_path / name
    p.write_text("\n".join(lines) + "\n")
    try:
        gm = read(p)
    except MotionFormatError as e:
        assert "\n" not in str(e) and name in str(e)
        return
    # accepted: it must be the same record, or a different one only if the change was in a
    # number (a value changed but still valid) -- then the count and dt still match the header
    assert gm.npts == ref.npts
    assert gm.dt > 0 and np.all(np.isfinite(gm.acc))
    changed = np.flatnonzero(gm.acc != ref.acc)
    assert changed.size <= 1 or gm.dt != ref.dt or kind == "char"


@_settings
@given(
    acc=st.lists(st.floats(-50, 50, allow_nan=False), min_size=2, max_size=40),
    dt=st.floats(1e-4, 0.1),
    fmt=st.sampled_from(["csv", "at2"]),
)
def test_roundtrip_property(tmp_path, acc, dt, fmt):
    gm = GroundMotion(dt=dt, acc=np.array(acc))
    back = read(write(gm, tmp_path / f"r.{fmt}", format=fmt))
    assert back.npts == gm.npts
    assert back.dt == gm.dt
    tol = 0 if fmt == "csv" else 1e-9 * max(gm.pga, 1e-300) + 1e-300
    assert np.max(np.abs(back.acc - gm.acc)) <= tol


def test_esm_declared_pga_mismatch_warns(tmp_path):
    text = (DATA / "sample_esm.ASC").read_text().replace("PGA_CM/S^2: -45.000000",
                                                          "PGA_CM/S^2: -55.000000")
    p = tmp_path / "x.ASC"
    p.write_text(text)
    with pytest.warns(UserWarning, match="x.ASC line 19: declared PGA_CM/S\\^2"):
        read(p)


def test_cli_module_import_is_light():
    import subprocess
    import sys

    code = ("import sys, murus.cli; heavy = [m for m in ('scipy', 'matplotlib', 'h5py') "
            "if m in sys.modules]; print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
