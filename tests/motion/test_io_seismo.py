"""SAC and miniSEED: detection from the first bytes (always), reading through ObsPy (the
optional extra; skipped when ObsPy is not installed)."""

import struct
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from murus.motion import MotionFormatError, read
from murus.motion.io import read_all
from murus.motion.seismo import sniff_binary


def _sac_bytes(data, delta=0.01, idep=8, cmpaz=90.0, cmpinc=90.0, kstnm="TST", kcmpnm="HNE"):
    """A little-endian SAC v6 file written from the header layout (70 floats, 40 ints, 192
    bytes of strings), independently of ObsPy."""
    f = [-12345.0] * 70
    f[0] = delta  # DELTA
    f[5] = 0.0  # B
    f[57], f[58] = cmpaz, cmpinc  # CMPAZ, CMPINC
    i = [-12345] * 40
    i[6] = 6  # NVHDR
    i[9] = len(data)  # NPTS
    i[15] = 1  # IFTYPE = ITIME
    i[16] = idep  # IDEP
    i[35] = 1  # LEVEN
    s = [b"-12345  "] * 24
    s[0] = kstnm.encode().ljust(8)
    s[20] = kcmpnm.encode().ljust(8)
    head = struct.pack("<70f", *f) + struct.pack("<40i", *i) + s[0] + b"-12345          " + \
        b"".join(s[3:])
    assert len(head) == 632
    return head + np.asarray(data, "<f4").tobytes()


def test_binary_formats_are_recognised(tmp_path):
    sac = _sac_bytes(np.arange(10.0))
    assert sniff_binary(sac[:1024], len(sac)) == "sac"
    assert sniff_binary(b"000001D " + b"\x00" * 600, 4096) == "mseed"
    assert sniff_binary(b"MS\x03" + b"\x00" * 60, 64) == "mseed"
    assert sniff_binary(b"Uncorrected Accelerogram Data" + b" " * 700, 729) is None


def test_without_obspy_the_message_says_what_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "obspy", None)  # import obspy -> ImportError
    p = tmp_path / "x.sac"
    p.write_bytes(_sac_bytes(np.arange(10.0)))
    with pytest.raises(MotionFormatError) as e:
        read(p)
    assert str(e.value) == ("x.sac: reading SAC files needs ObsPy: pip install "
                            "'murus[seismo]' (or pip install obspy)")


def test_sac_through_obspy(tmp_path):
    pytest.importorskip("obspy")
    a = np.sin(np.arange(200) * 0.1) * 1e8  # nm/s²
    p = tmp_path / "st.sac"
    p.write_bytes(_sac_bytes(a, idep=8))
    gm = read(p)
    assert gm.meta["format"] == "sac" and gm.dt == pytest.approx(0.01, rel=1e-7)
    assert np.allclose(gm.acc, a.astype("f4") * 1e-9, rtol=1e-7)
    assert gm.meta["azimuth_deg"] == 90.0 and not gm.meta["vertical"]
    p.write_bytes(_sac_bytes(a, idep=5, cmpinc=0.0))
    with pytest.raises(MotionFormatError, match="st.sac: SAC data carry no acceleration units"):
        read(p)
    gm = read(p, units="cm/s2")
    assert gm.meta["vertical"] and np.allclose(gm.acc, a.astype("f4") * 0.01, rtol=1e-7)
    p.write_bytes(_sac_bytes(a, idep=7))
    with pytest.raises(MotionFormatError, match="declares velocity \\(IDEP = 7\\)"):
        read(p)
    p.write_bytes(_sac_bytes(a)[:700])
    with pytest.raises(MotionFormatError, match="st.sac: "):
        read(p, format="sac")


def test_mseed_through_obspy(tmp_path):
    obspy = pytest.importorskip("obspy")
    t = np.arange(300) * 0.01
    traces = [obspy.Trace(data=(np.sin(2 * np.pi * t) * (k + 1)).astype("f4"),
                          header={"network": "XX", "station": "TST", "channel": f"HN{c}",
                                  "delta": 0.01}) for k, c in enumerate("ENZ")]
    p = tmp_path / "st.mseed"
    obspy.Stream(traces).write(str(p), format="MSEED")
    with pytest.raises(MotionFormatError, match="st.mseed: MSEED data carry no acceleration"):
        read(p)
    chans = read_all(p, units="m/s2")
    assert [c.meta["component"] for c in chans] == ["HNE", "HNN", "HNZ"]
    assert [c.meta["azimuth_deg"] for c in chans] == [90.0, 0.0, None]
    assert read(p, units="m/s2", channel="N").meta["component"] == "HNN"
    assert np.allclose(chans[2].acc, 3 * np.sin(2 * np.pi * t), atol=1e-6)
    from murus.motion.components import read_components

    gm = read_components(p, units="g")
    assert gm.acc_v is not None and gm.meta["component"] == "HNE"
    short = tmp_path / "short.mseed"
    short.write_bytes(p.read_bytes()[:700])  # a record cut in the middle
    with pytest.raises(MotionFormatError, match="short.mseed: not a (clean|readable) MSEED file"):
        read(short, units="m/s2")


def _mseed_bytes(tmp_path):
    obspy = pytest.importorskip("obspy")
    t = np.arange(500) * 0.01
    tr = obspy.Trace(data=np.sin(2 * np.pi * t).astype("f4"),
                     header={"station": "TST", "channel": "HNE", "delta": 0.01})
    p = tmp_path / "base.mseed"
    obspy.Stream([tr]).write(str(p), format="MSEED", reclen=512)
    return p.read_bytes()


@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(kind=st.sampled_from(["sac", "mseed"]), cut=st.integers(0, 2000),
       pos=st.integers(0, 2000), byte=st.integers(0, 255))
def test_corrupted_binary_refused_or_valid(tmp_path, kind, cut, pos, byte):
    """Truncated or overwritten SAC/miniSEED bytes: a one-line refusal naming the file, or a
    record with finite values (never a traceback)."""
    pytest.importorskip("obspy")
    data = bytearray(_sac_bytes(np.sin(np.arange(300) * 0.1) * 1e8) if kind == "sac"
                     else _mseed_bytes(tmp_path))
    if pos < len(data):
        data[pos] = byte
    data = bytes(data[:max(cut, 1) if cut < len(data) else len(data)])
    p = tmp_path / f"c.{kind}"
    p.write_bytes(data)
    try:
        chans = read_all(p, units=None if kind == "sac" else "m/s2")
    except MotionFormatError as e:
        assert "\n" not in str(e) and "c." + kind in str(e)
        return
    for gm in chans:
        assert gm.npts >= 2 and gm.dt > 0 and np.all(np.isfinite(gm.acc))
