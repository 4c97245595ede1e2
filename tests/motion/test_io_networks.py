"""Network formats: CSMIP/DMG V1 and V2 and COSMOS V0/V1/V2 (trimmed real files), K-NET/KiK-net
ASCII, COSMOS V0/V1 and multi-channel files written by the tests, channel selection, the
unrecognised-format message, fuzzing and round trips through the writers."""

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from murus import G
from murus.motion import GroundMotion, MotionFormatError, read, write
from murus.motion.io import detect_format, read_all

DATA = Path(__file__).resolve().parents[1] / "data"
CLC = DATA / "records" / "CICLC_trim.v1"
WLT = DATA / "records" / "CIWLT_trim.V2"
AKBMR = DATA / "records" / "AKBMR_trim.V2c"
NP8040 = DATA / "records" / "NP8040_HNZ_trim.V1c"
CE23837 = DATA / "records" / "CE23837_trim.V1C"
NP8040_V0 = DATA / "records" / "NP8040_HNE_trim.V0c"
COSMOS_V2 = DATA / "motion" / "sample_cosmos.V2"


def _file_values(path, chan):
    """The raw values of a channel of the trimmed DMG file, read independently (8F9.6)."""
    lines = path.read_text().splitlines()
    starts = [i for i, ln in enumerate(lines) if "Accelerogram points" in ln]
    k = starts[chan - 1]
    n = int(lines[k].split()[0])
    vals = []
    for ln in lines[k + 1:]:
        if ln.startswith("/&"):
            break
        vals += [float(ln[q:q + 9]) for q in range(0, len(ln), 9) if ln[q:q + 9].strip()]
    assert len(vals) == n
    return np.array(vals)


# ------------------------------------------------------------------------------ CSMIP/DMG V1


def test_dmg_v1_real_file_header_values():
    """Trimmed CGS file of station CLC, Ridgecrest 2019 (tests/data/records/README.md)."""
    assert detect_format(CLC) == "dmg"
    chans = read_all(CLC)
    assert [c.meta["channel"] for c in chans] == [1, 2, 3]
    assert [c.meta["component"] for c in chans] == ["90 Deg", "360 Deg", "Up"]
    assert [c.meta["azimuth_deg"] for c in chans] == [90.0, 0.0, None]
    assert [c.meta["vertical"] for c in chans] == [False, False, True]
    for k, c in enumerate(chans, start=1):
        assert c.meta["format"] == "dmg" and c.meta["level"] == "V1"
        assert c.meta["station"] == "CLC" and c.meta["units_in"] == "g"
        assert c.meta["record_id"] == "38457487.CI.CLC.--.HN"
        assert c.npts == 400 and c.dt == 0.01  # "at 100 pts/sec"; trimmed to 400 points
        assert np.array_equal(c.acc, _file_values(CLC, k) * G)
    # peaks: the header's "Max = .344 g" (.511, .347) vs the data, and real-header value 7
    # (.3442498 g, the unrounded peak of channel 1) vs the data's .344250
    assert [round(c.pga / G, 3) for c in chans] == [0.344, 0.511, 0.347]
    assert chans[0].pga / G == pytest.approx(0.3442498, abs=5e-7)
    assert chans[0].meta["pga_declared"] == pytest.approx(0.344 * G)


def test_dmg_channel_selection():
    assert read(CLC).meta["channel"] == 1  # the first horizontal channel
    assert read(CLC, channel=2).meta["component"] == "360 Deg"
    assert read(CLC, channel="360").meta["channel"] == 2
    assert read(CLC, channel="0").meta["channel"] == 2  # azimuth 0 = 360
    assert read(CLC, channel="N").meta["channel"] == 2
    assert read(CLC, channel="e").meta["channel"] == 1
    assert read(CLC, channel="90 deg").meta["channel"] == 1
    assert read(CLC, channel="up").meta["vertical"]
    assert read(CLC, channel=3).meta["vertical"]
    with pytest.raises(MotionFormatError) as e:
        read(CLC, channel=4)
    assert str(e.value) == ("CICLC_trim.v1: no channel matches channel '4' (channels: "
                            "1 (90 Deg), 2 (360 Deg), 3 (Up))")
    with pytest.raises(MotionFormatError, match="no channel matches channel 'west'"):
        read(CLC, channel="west")


def test_dmg_units_and_dt_checks(tmp_path):
    with pytest.raises(MotionFormatError, match=r"CICLC_trim.v1 line 28: the file declares "
                                                r"units g but units cm/s2 were given"):
        read(CLC, units="cm/s2")
    with pytest.raises(MotionFormatError, match="line 28: the file declares dt = 0.01 s"):
        read(CLC, dt=0.02)
    text = CLC.read_text()
    p = tmp_path / "x.v1"
    p.write_text(text.replace("No. of Points =    400", "No. of Points =    401", 1))
    with pytest.raises(MotionFormatError, match="x.v1 line 11: header declares 401 points"):
        read(p)
    p.write_text(text.replace("   400 Accelerogram points", "   401 Accelerogram points", 1)
                 .replace("No. of Points =    400", "No. of Points =    401", 1))
    with pytest.raises(MotionFormatError, match="x.v1 line 79: acceleration block ends after "
                                                "400 of its 401 values"):
        read(p)
    p.write_text(text.replace("in units of g.", "in units of furlongs.", 1))
    with pytest.raises(MotionFormatError, match="x.v1 line 28: unknown acceleration units"):
        read(p)
    p.write_text(text.replace("Max  =   .344 g", "Max  =   .444 g", 1))
    with pytest.warns(UserWarning, match="x.v1 line 12: declared peak .444 g differs"):
        read(p)


def test_dmg_full_length_channel_structure(tmp_path):
    """Blank lines at the end are accepted; a missing data header is named."""
    text = CLC.read_text()
    p = tmp_path / "y.v1"
    p.write_text(text + "\n\n")
    assert len(read_all(p)) == 3
    p.write_text(text.replace("   400 Accelerogram points at", "   400 Accelerogram pts at", 1))
    with pytest.raises(MotionFormatError, match="y.v1 line 79: channel 1 has no acceleration "
                                                "data header"):
        read(p)


# ------------------------------------------------------------------------------ CSMIP/DMG V2


def _dmg_v2_text(chans):
    """A CSMIP V2 file in the layout of the CGS corrected files (25 text lines, 7 lines of
    16I5, 13 lines of 8F10, acceleration / velocity / displacement blocks, '/&' line)."""
    out = []
    for k, (comp, acc, peak) in enumerate(chans, start=1):
        text = [
            "Corrected Accelerogram Data                Processed: 01/01/20, CGS",
            "Uncorrected Accelerogram Data",
            "Synthetic record for murus tests",
            "Station No. 12345  35.000N, 117.000W",
            "murus test station",
            f"Chan  {k}:  {comp}",
        ]
        text += [f"text line {r}" for r in range(7, 25)]
        text[10] = f"Peak acceleration = {peak} cm/sec2  at   .010 sec.  Peak velocity = 1 cm/sec"
        text.append("Instrument and baseline corrected; filter 0.1-25 Hz")
        ints = ["".join(f"{-999:5d}" for _ in range(16))] * 6 + ["".join(f"{-999:5d}"
                                                                       for _ in range(4))]
        reals = ["".join(f"{-999.0:10.3f}" for _ in range(8))] * 12 + [
            "".join(f"{-999.0:10.3f}" for _ in range(4))]
        n = len(acc)
        block = [f"{n:6d} points of accel data equally spaced at  .005 sec, in cm/sec2.  "
                 "(8f10.3)"]
        block += ["".join(f"{v:10.3f}" for v in acc[q:q + 8]) for q in range(0, n, 8)]
        block += [f"{n:6d} points of veloc data equally spaced at  .005 sec, in cm/sec.   "
                  "(8f10.3)"]
        block += ["".join(f"{0.0:10.3f}" for _ in acc[q:q + 8]) for q in range(0, n, 8)]
        block += [f"{n:6d} points of displ data equally spaced at  .005 sec, in cm.       "
                  "(8f10.3)"]
        block += ["".join(f"{0.0:10.3f}" for _ in acc[q:q + 8]) for q in range(0, n, 8)]
        block += [f"/&  ----------  End of data for channel  {k}  ----------"]
        out += text + ints + reals + block
    return "\n".join(out) + "\n"


def _v2_chans():
    a1 = np.round(100 * np.sin(np.arange(21) * 0.7), 3)
    a2 = np.round(-50 * np.cos(np.arange(21) * 0.3), 3)
    a3 = np.round(20 * np.sin(np.arange(21) * 1.1), 3)
    return [("Up", a3, f"{np.max(np.abs(a3)):.3f}"), ("180 Deg", a1, f"{np.max(np.abs(a1)):.3f}"),
            ("270 Deg", a2, f"{np.max(np.abs(a2)):.3f}")]


def test_dmg_v2(tmp_path):
    chans = _v2_chans()
    p = tmp_path / "s.V2"
    p.write_text(_dmg_v2_text(chans))
    assert detect_format(p) == "dmg"
    got = read_all(p)
    assert len(got) == 3
    for gm, (comp, acc, _) in zip(got, chans, strict=True):
        assert gm.meta["level"] == "V2" and gm.meta["station"] == "12345"
        assert gm.meta["component"] == comp and gm.dt == 0.005 and gm.npts == 21
        assert np.allclose(gm.acc, acc * 0.01, rtol=1e-15, atol=0)
        assert gm.meta["units_in"] == "cm/s2"
    assert read(p).meta["component"] == "180 Deg"  # the first horizontal, not channel 1
    assert read(p, channel="180").meta["azimuth_deg"] == 180.0
    assert read(p, channel="Z").meta["channel"] == 1
    bad = _dmg_v2_text([("90 Deg", chans[1][1], "99.000")])
    p.write_text(bad)
    with pytest.warns(UserWarning, match="s.V2 line 11: declared peak 99.000 cm/sec2"):
        read(p)


def _v2_block(path, what):
    """The values of every '<what> data' block (accel, veloc, displ) of a CSMIP V2 file, read
    independently of murus (8 fields of 10 characters)."""
    lines = path.read_text().splitlines()
    out = []
    for k, ln in enumerate(lines):
        if f"points of {what} data" in ln:
            n = int(ln.split()[0])
            vals = []
            for row in lines[k + 1:]:
                if len(vals) == n:
                    break
                vals += [float(row[q:q + 10]) for q in range(0, len(row), 10)
                         if row[q:q + 10].strip()]
            assert len(vals) == n
            out.append(np.array(vals))
    return out


def test_dmg_v2_real_file_header_values():
    """Trimmed CGS V2 file of station WLT, La Habra 2014 (tests/data/records/README.md): what
    murus reads against the header of each channel."""
    assert detect_format(WLT) == "dmg"
    chans = read_all(WLT)
    assert [c.meta["channel"] for c in chans] == [1, 2, 3]
    assert [c.meta["component"] for c in chans] == ["90 Deg", "360 Deg", "Up"]
    assert [c.meta["azimuth_deg"] for c in chans] == [90.0, 0.0, None]
    assert [c.meta["vertical"] for c in chans] == [False, False, True]
    assert [c.npts for c in chans] == [184, 184, 440]
    for c, acc in zip(chans, _v2_block(WLT, "accel"), strict=True):
        assert c.meta["format"] == "dmg" and c.meta["level"] == "V2"
        assert c.meta["station"] == "WLT" and c.meta["units_in"] == "cm/s2"
        assert c.meta["record_id"] == "15481673.CI.WLT.--.HN"
        assert c.meta["event"].startswith("Rcrd of Fri Mar 28, 2014 21:09:34.0 PDT")
        assert c.dt == 0.02  # "equally spaced at .020 sec"
        assert np.allclose(c.acc, acc * 0.01, rtol=1e-15, atol=0)
    # "Peak acceleration = 82.584 cm/sec/sec at .440 sec" (-115.845 at .120, 69.662 at .060)
    # and real-header value 66, the unrounded peak (82.584260, -115.84550, 69.662250)
    for c, peak, printed, t in zip(chans, (82.58426, -115.8455, 69.66225),
                                   (82.584, 115.845, 69.662), (0.44, 0.12, 0.06), strict=True):
        i = int(np.argmax(np.abs(c.acc)))
        assert c.acc[i] == pytest.approx(peak * 0.01, rel=1e-12)
        assert abs(c.pga * 100 - printed) <= 0.0005 + 1e-9  # printed with 3 decimals
        assert i * c.dt == pytest.approx(t)
        assert c.meta["pga_declared"] == pytest.approx(printed * 0.01)
    assert read(WLT).meta["channel"] == 1 and read(WLT, channel="Z").meta["channel"] == 3
    # murus skips the velocity and displacement blocks; the stored file keeps them whole:
    # their peaks are those of the headers (-6.863 cm/s at .280 s, -.836 cm at 3.180 s, ...)
    for what, peaks, times in (("veloc", (-6.863001, -8.141052, -5.84483), (0.28, 0.22, 8.46)),
                               ("displ", (-0.8361315, -0.8323321, -0.9898853),
                                (3.18, 2.76, 8.70))):
        for x, peak, t in zip(_v2_block(WLT, what), peaks, times, strict=True):
            i = int(np.argmax(np.abs(x)))
            assert x[i] == pytest.approx(peak, abs=1e-7) and i * 0.02 == pytest.approx(t)


# ----------------------------------------------------------------------------- K-NET/KiK-net


def _knet_text(counts, direction="E-W", freq="100Hz", scale="2000(gal)/8388608",
               duration=None, max_acc=None):
    counts = np.asarray(counts)
    fac = 2000 / 8388608
    a = counts * fac
    a = a - a.mean()
    if max_acc is None:
        max_acc = f"{np.max(np.abs(a)):.3f}"
    if duration is None:
        duration = str(int(len(counts) / 100))
    hdr = [("Origin Time", "1996/08/11 03:12:00"), ("Lat.", "38.920"), ("Long.", "140.630"),
           ("Depth. (km)", "7"), ("Mag.", "5.9"), ("Station Code", "AKT013"),
           ("Station Lat.", "39.6069"), ("Station Long.", "140.3213"),
           ("Station Height(m)", "34"), ("Record Time", "1996/08/11 03:12:39"),
           ("Sampling Freq(Hz)", freq), ("Duration Time(s)", duration), ("Dir.", direction),
           ("Scale Factor", scale), ("Max. Acc. (gal)", max_acc),
           ("Last Correction", "1996/08/11 03:00:00"), ("Memo.", "")]
    lines = [f"{k:<18s}{v}" for k, v in hdr]
    lines += ["".join(f"{c:9d}" for c in counts[q:q + 8]) + " " for q in range(0, len(counts), 8)]
    return "\n".join(lines) + "\n"


def _counts(n=250, seed=1):
    rng = np.random.default_rng(seed)
    return (-18000 + np.round(3000 * rng.standard_normal(n))).astype(int)


def test_knet_scale_factor_and_mean(tmp_path):
    c = _counts()
    p = tmp_path / "AKT0139608110312.EW"
    p.write_text(_knet_text(c))
    assert detect_format(p) == "knet"
    gm = read(p)
    fac = 2000 / 8388608  # gal per count
    expect = (c * fac - np.mean(c * fac)) * 0.01
    assert np.allclose(gm.acc, expect, rtol=0, atol=1e-15)
    assert gm.dt == 0.01 and gm.npts == 250
    assert gm.meta["station"] == "AKT013" and gm.meta["component"] == "E-W"
    assert gm.meta["azimuth_deg"] == 90.0 and gm.meta["magnitude"] == 5.9
    assert gm.meta["pga_declared"] == pytest.approx(round(gm.pga * 100, 3) / 100)
    p2 = tmp_path / "AKT0139608110312.UD2"
    p2.write_text(_knet_text(c, direction="U-D"))
    assert read(p2).meta["vertical"]


@pytest.mark.parametrize("change,match", [
    (dict(scale="2000/8388608"), "line 14: scale factor '2000/8388608' is not 'A\\(gal\\)/B'"),
    (dict(freq="fast"), "line 11: sampling frequency 'fast' is not a number of Hz"),
    (dict(duration="9"), "line 12: Duration Time 9 s but the file has 250 values"),
    (dict(max_acc="99.000"), None),
])
def test_knet_header_errors(tmp_path, change, match):
    p = tmp_path / "k.NS"
    p.write_text(_knet_text(_counts(), **change))
    if match is None:
        with pytest.warns(UserWarning, match="k.NS line 15: declared peak 99.000 gal"):
            read(p)
        return
    with pytest.raises(MotionFormatError, match="k.NS " + match):
        read(p)


def test_knet_bad_values(tmp_path):
    text = _knet_text(_counts())
    p = tmp_path / "k.EW"
    lines = text.splitlines()
    lines[20] = lines[20].replace(lines[20].split()[3], "12.5", 1)
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(MotionFormatError, match="k.EW line 21: '12.5' is not a whole number"):
        read(p)
    lines[20] = lines[20].replace("12.5", "nan")
    p.write_text("\n".join(lines) + "\n")
    with pytest.raises(MotionFormatError, match="k.EW line 21: 'nan' is not a finite number"):
        read(p)
    p.write_text(text.replace("Scale Factor      2000(gal)/8388608\n", ""))
    with pytest.raises(MotionFormatError, match="k.EW line 16: K-NET header has no 'scale"):
        read(p)
    with pytest.raises(MotionFormatError, match="declares units cm/s2 but units g"):
        read(_write(tmp_path / "k2.EW", text), units="g")


def _write(p, text):
    p.write_text(text)
    return p


# -------------------------------------------------------------------------------- COSMOS V0/V1


def _cosmos_text(level=1, azimuth=90, units="cm/sec2 (04)", values=None):
    text = COSMOS_V2.read_text()
    lines = text.splitlines()
    title = {0: "Raw acceleration counts", 1: "Uncorrected acceleration",
             2: "Corrected acceleration"}[level]
    lines[0] = title + lines[0][len("Corrected acceleration"):]
    ints = [-999] * 100
    ints[0] = level
    ints[53] = azimuth
    k = next(i for i, ln in enumerate(lines) if "Integer-header" in ln)
    for r in range(10):
        lines[k + 1 + r] = "".join(f"{v:8d}" for v in ints[10 * r:10 * r + 10])
    d = next(i for i, ln in enumerate(lines) if "acceleration pts" in ln)
    lines[d] = lines[d].replace("units=cm/sec2 (04)", f"units={units}")
    return "\n".join(lines) + "\n"


def _cosmos_values(path):
    """The data of a one-channel COSMOS file with Format=(1E15.6), read independently."""
    lines = path.read_text().splitlines()
    k = next(i for i, ln in enumerate(lines) if "acceleration pts" in ln)
    n = int(lines[k].split()[0])
    vals = [float(ln) for ln in lines[k + 1:k + 1 + n]]
    assert lines[k + 1 + n].startswith("End-of-data")
    return np.array(vals)


@pytest.mark.parametrize(
    "path, level, station, comp, peak, printed",
    [  # real-header value 64 (6 decimals) and the text line "Max = -6.852 cm/sec2 at ..."
        (AKBMR, "V2", "BMR", "BNZ", -6.851512, -6.852),
        (NP8040, "V1", "8040", "400", -221.811408, -221.811),
    ])
def test_cosmos_real_files_header_values(path, level, station, comp, peak, printed):
    """Trimmed USGS COSMOS files of the 2018 Anchorage earthquake (tests/data/records/
    README.md): E-format data, vertical channels given by the SCNL comment (AK.BMR.BNZ, the
    orientation code is 0) or by integer header 55 (NP.8040, code 400 = up)."""
    import warnings

    assert detect_format(path) == "cosmos"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        chans = read_all(path)
    assert len(chans) == 1
    c = chans[0]
    assert c.meta["format"] == "cosmos" and c.meta["level"] == level
    assert c.meta["station"] == station and c.meta["component"] == comp
    assert c.meta["vertical"] and c.meta["azimuth_deg"] is None
    assert c.meta["units_in"] == "cm/s2" and c.meta["channel"] == 1
    assert c.meta["event"] == ("Record of Point MacKenzie Earthquake of Fri Nov 30, 2018 "
                               "17:29 UTC")
    assert c.dt == 0.005 and c.npts == 200  # real header 62: 5 ms; trimmed to 200 points
    assert np.allclose(c.acc, _cosmos_values(path) * 0.01, rtol=1e-15, atol=0)
    i = int(np.argmax(np.abs(c.acc)))
    assert c.acc[i] == pytest.approx(peak * 0.01, rel=5e-7)  # the data: 7 significant digits
    assert abs(c.acc[i] * 100 - printed) <= 0.0005 + 1e-9  # "Max = ..." with 3 decimals
    assert i * c.dt == pytest.approx(0.5)  # "... at 0.500 sec" after trimming
    assert c.meta["pga_declared"] == pytest.approx(abs(peak) * 0.01)


def test_cosmos_v1_real_cgs_three_channels():
    """Trimmed CGS COSMOS V1 file of station CE.23837 (Pomona), 29 Aug 2018: three channels,
    units "g." with a period, Format=(8f9.6), CRLF line ends (tests/data/records/README.md)."""
    assert detect_format(CE23837) == "cosmos"
    chans = read_all(CE23837)
    assert [c.meta["channel"] for c in chans] == [1, 2, 3]
    assert [c.meta["component"] for c in chans] == ["360", "400", "90"]
    assert [c.meta["azimuth_deg"] for c in chans] == [0.0, None, 90.0]
    assert [c.meta["vertical"] for c in chans] == [False, True, False]
    lines = CE23837.read_text().splitlines()
    heads = [k for k, ln in enumerate(lines) if "acceleration pts" in ln]
    # "Max = -.105 g at 1.575 sec" (.049 at .085, -.059 at 2.075) and real-header value 64
    # (-.105433, .048757, -.059022 g), which the data hold exactly (8f9.6, g)
    for c, k, peak, printed, t in zip(chans, heads, (-0.105433, 0.048757, -0.059022),
                                      (-0.105, 0.049, -0.059), (1.575, 0.085, 2.075),
                                      strict=True):
        assert c.meta["level"] == "V1" and c.meta["station"] == "23837"
        assert c.meta["units_in"] == "g" and c.dt == 0.005 and c.npts == 440
        vals = [float(ln[q:q + 9]) for ln in lines[k + 1:k + 56] for q in range(0, 72, 9)]
        assert np.array_equal(c.acc, np.array(vals) * G)
        i = int(np.argmax(np.abs(c.acc)))
        assert c.acc[i] / G == pytest.approx(peak, abs=1e-12)
        assert abs(c.acc[i] / G - printed) <= 0.0005 + 1e-12
        assert i * c.dt == pytest.approx(t)
        assert c.meta["pga_declared"] == pytest.approx(abs(peak) * G)
    assert read(CE23837).meta["channel"] == 1 and read(CE23837, channel="Z").meta["channel"] == 2
    assert read(CE23837, channel="E").meta["channel"] == 3


def test_cosmos_declared_maximum_checked(tmp_path):
    p = tmp_path / "m.V2c"
    p.write_text(AKBMR.read_text().replace("     -6.851512 ", "     -7.851512 ", 1))
    with pytest.warns(UserWarning, match=r"m.V2c line 53: declared maximum -7.85151 \(real "
                                         r"header 64\) differs from the data \(6.85151\)"):
        read(p)


def test_cosmos_v1_and_multichannel(tmp_path):
    p = tmp_path / "two.V1"
    p.write_text(_cosmos_text(1, 90) + _cosmos_text(1, 400))
    assert detect_format(p) == "cosmos"
    chans = read_all(p)
    assert len(chans) == 2
    assert chans[0].meta["level"] == "V1" and chans[0].meta["azimuth_deg"] == 90.0
    assert chans[1].meta["vertical"] and chans[1].meta["channel"] == 2
    ref = read(COSMOS_V2)
    assert np.array_equal(chans[0].acc, ref.acc) and np.array_equal(chans[1].acc, ref.acc)
    assert read(p, channel="up").meta["channel"] == 2
    # counts without the recorder LSB (real-header value 22: -999 in this file) are refused
    p0 = tmp_path / "raw.V0"
    p0.write_text(_cosmos_text(0, 90, units="counts (50)"))
    with pytest.raises(MotionFormatError, match=r"raw.V0 line \d+: raw counts \(COSMOS V0\) "
                                                r"need real-header value 22 \(recorder least"):
        read(p0)


def test_cosmos_v0_real_file_counts_to_acceleration():
    """Trimmed USGS COSMOS V0 file (raw counts) of NP.8040 HNE, 2018 Anchorage earthquake
    (tests/data/records/README.md). Real header: LSB 0.298024 uV/count (value 22),
    sensitivity 1.2553 V/g (value 42), gain 1.0 (value 47); maximum 1033406 counts (value 64)
    at 45.580 s of the full record, 1.000 s of the trimmed one."""
    import warnings

    assert detect_format(NP8040_V0) == "cosmos"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        chans = read_all(NP8040_V0)
    assert len(chans) == 1
    c = chans[0]
    factor = 0.298024 * 1e-6 / 1.0 / 1.2553 * G  # by hand from the header values
    assert c.meta["level"] == "V0" and c.meta["units_in"] == "counts"
    assert c.meta["conversion"] == pytest.approx(factor, rel=1e-15)
    assert c.meta["conversion"] == pytest.approx(2.329017e-6, rel=1e-6)
    assert (c.meta["lsb_uv"], c.meta["sensitivity_v_per_g"], c.meta["gain"]) == (
        0.298024, 1.2553, 1.0)
    assert c.meta["station"] == "8040" and c.meta["azimuth_deg"] == 90.0
    assert c.dt == 0.005 and c.npts == 400
    lines = NP8040_V0.read_text().splitlines()
    k = next(i for i, ln in enumerate(lines) if "raw accel." in ln)
    counts = np.array([int(ln) for ln in lines[k + 1:k + 401]])
    assert lines[k + 401].startswith("End-of-data")
    assert np.allclose(c.acc, counts * factor, rtol=1e-14, atol=0)  # no offset removed
    i = int(np.argmax(np.abs(c.acc)))
    assert counts[i] == -1033406 and i * c.dt == pytest.approx(1.0)  # "Max = 1033406 counts"
    assert c.acc[i] == pytest.approx(-1033406 * factor, rel=1e-14)  # -2.40682 m/s2
    assert c.meta["pga_declared"] == pytest.approx(1033406 * factor, rel=1e-14)
    with pytest.raises(MotionFormatError, match="holds raw counts"):
        read(NP8040_V0, units="g")


@pytest.mark.parametrize("old,new,msg", [
    ("       1.255300", "    -999.000000", r"line 34: raw counts \(COSMOS V0\) need real-header "
                                           r"value 42 \(sensor sensitivity, volts/g\) to give "
                                           r"acceleration, but it is -999"),
    ("       0.298024", "       0.000000", r"line 30: .* value 22 \(recorder least significant "
                                           r"bit, microvolts/count\) .* but it is 0$"),
    ("    -999.000000       1.000000", "    -999.000000       0.000000",
     r"line 35: .* value 47 \(gain\) .* but it is 0$"),
])
def test_cosmos_v0_missing_conversion_values(tmp_path, old, new, msg):
    from typer.testing import CliRunner

    from murus.cli import app

    p = tmp_path / "raw.V0c"
    text = NP8040_V0.read_text()
    assert text.count(old) == 1
    p.write_text(text.replace(old, new))
    with pytest.raises(MotionFormatError, match="raw.V0c " + msg):
        read(p)
    r = CliRunner().invoke(app, ["motion", "info", str(p)])
    assert r.exit_code == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "raw.V0c line" in r.stderr


# --------------------------------------------------------------------- unrecognised formats


@pytest.mark.parametrize("text,first", [
    ("Uncorrected seismogram of somewhere\nRcrd of Fri Jul  5\n1 2 3\n",
     "'Uncorrected seismogram of somewhere'"),
    ("<html><body>404</body></html>\n", "'<html><body>404</body></html>'"),
    ("Station: ABC\nRcrd 12\n", "'Station: ABC'"),
])
def test_unrecognised_format(tmp_path, text, first):
    p = tmp_path / "rec.v1"
    p.write_text(text)
    with pytest.raises(MotionFormatError) as e:
        read(p)
    msg = str(e.value)
    assert msg.startswith(f"rec.v1: unrecognised record format (first line: {first})")
    assert "not a number" not in msg and "\n" not in msg


# ------------------------------------------------------------------------------- round trips


@pytest.mark.parametrize("fmt", ["csv", "at2"])
def test_network_records_roundtrip_through_writers(tmp_path, fmt):
    for gm in read_all(CLC):
        back = read(write(gm, tmp_path / f"c.{fmt}", format=fmt))
        assert back.npts == gm.npts and back.dt == gm.dt
        tol = 0.0 if fmt == "csv" else 1e-9 * gm.pga
        assert np.max(np.abs(back.acc - gm.acc)) <= tol
        if fmt == "csv":
            assert back.meta["station"] == "CLC"


# ----------------------------------------------------------------------------------- fuzzing

_settings = settings(max_examples=40, deadline=None,
                     suppress_health_check=[HealthCheck.function_scoped_fixture])


def _fuzz_sources(tmp_path):
    return {
        "CICLC_trim.v1": CLC.read_text(),
        "s.V2": _dmg_v2_text(_v2_chans()),
        "k.EW": _knet_text(_counts()),
        "two.V1": _cosmos_text(1, 90) + _cosmos_text(1, 400),
    }


@_settings
@given(name=st.sampled_from(["CICLC_trim.v1", "s.V2", "k.EW", "two.V1"]), data=st.data())
def test_corrupted_network_files_refused_or_consistent(tmp_path, name, data):
    """Truncate, drop or duplicate a line, change a character, insert text, NaN or a huge
    value: the reader refuses with a one-line message naming the file, or returns channels
    whose counts and steps match the original (a harmless change)."""
    import warnings

    text = _fuzz_sources(tmp_path)[name]
    ref_path = tmp_path / ("ref_" + name)
    ref_path.write_text(text)
    ref = read_all(ref_path)
    lines = text.splitlines()
    kind = data.draw(st.sampled_from(["char", "drop_line", "dup_line", "insert", "truncate"]))
    i = data.draw(st.integers(0, len(lines) - 1))
    if kind == "char":
        j = data.draw(st.integers(0, max(0, len(lines[i]) - 1)))
        c = data.draw(st.sampled_from(list("x9.- eE,N") + ["nan", "1e999", "-999"]))
        lines[i] = lines[i][:j] + c + lines[i][j + 1:]
    elif kind == "drop_line":
        del lines[i]
    elif kind == "dup_line":
        lines.insert(i, lines[i])
    elif kind == "insert":
        lines.insert(i, data.draw(st.sampled_from(["abc", "1 2 x", "nan", "", "/&"])))
    else:
        lines = lines[:i]
    p = tmp_path / name
    p.write_text("\n".join(lines) + "\n")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            got = read_all(p)
    except MotionFormatError as e:
        msg = str(e)
        assert "\n" not in msg and name in msg
        return
    for gm in got:
        assert gm.dt > 0 and gm.npts >= 2 and np.all(np.isfinite(gm.acc))
        assert np.max(np.abs(gm.acc)) <= 1e6
    if kind in ("drop_line", "truncate", "dup_line") and name != "k.EW":
        # a lost or repeated data line must never pass silently: same channels, same counts
        same = [(g.npts, g.dt) for g in got] == [(g.npts, g.dt) for g in ref[:len(got)]]
        assert same
    if name == "k.EW" and kind in ("drop_line", "dup_line"):
        assert abs(got[0].npts - ref[0].npts) <= 8  # the format declares no count
    assert math.isfinite(sum(g.pga for g in got))


@_settings
@given(data=st.binary(max_size=300), ext=st.sampled_from([".v1", ".V2", ".EW", ".UD1", ".V0"]))
def test_random_bytes_network_extensions(tmp_path, data, ext):
    p = tmp_path / f"f{ext}"
    p.write_bytes(data)
    try:
        gm = read(p, units="g", dt=0.01)
    except MotionFormatError as e:
        assert "\n" not in str(e) and p.name in str(e)
        return
    assert np.all(np.isfinite(gm.acc)) and gm.dt > 0 and isinstance(gm, GroundMotion)


def test_cut_files_are_refused(tmp_path):
    """A file cut at a channel boundary is caught by the V1 channel count; one cut inside a
    channel by the missing '/&' line (DMG) or the broken next channel (COSMOS)."""
    lines = CLC.read_text().splitlines()
    p = tmp_path / "cut.v1"
    p.write_text("\n".join(lines[:158]) + "\n")  # channels 1 and 2 only
    with pytest.raises(MotionFormatError, match="cut.v1 line 5: the header declares 3 channels "
                                                "but the file has 2"):
        read_all(p)
    v2 = _dmg_v2_text(_v2_chans()).splitlines()
    end = [i for i, ln in enumerate(v2) if ln.startswith("/&")][0]
    q = tmp_path / "cut.V2"
    q.write_text("\n".join(v2[:end - 3]) + "\n")  # inside the displacement block
    with pytest.raises(MotionFormatError, match=r"cut.V2 line \d+: file ends before the end "
                                                "of channel 1"):
        read_all(q)
    two = (_cosmos_text(1, 90) + _cosmos_text(1, 400)).splitlines()
    r = tmp_path / "cut.V1"
    r.write_text("\n".join(two[:55]) + "\n")  # inside the text header of channel 2
    with pytest.raises(MotionFormatError, match="cut.V1 line 50: text after channel 1 is not a "
                                                "COSMOS channel"):
        read_all(r)
