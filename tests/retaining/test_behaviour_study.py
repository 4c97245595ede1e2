"""The behaviour-factor study (murus.retaining.study, ``murus retaining behaviour-factor``) on
the study machinery: stored cases, resume after an interruption with an identical table and
no recomputation, S1 checks queued after their S2 run, bad case files (exit 2, one line naming
the key and line, nothing written), serial and process-pool runs identical (real DEM runs of
the tiny example: a mock-up at one frequency)."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import murus.retaining.study as bs
from murus.retaining.collapse import CollapseResult
from murus.retaining.study import behaviour_study, load_behaviour_study, run_behaviour_study
from murus.studies.faults import FailTimes, Interrupt, Touch
from murus.studies.sweep import StudyError, study_status

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "retaining" / \
    "mockup_behaviour_factor.toml"


# ----------------------------------------------------------------------------- a fake run --
class FakeRun:
    """Stands for collapse_run (no DEM): S2 collapses at t_col = 0.5 + 0.1 f (never at
    f >= 100 Hz); S1 collapses when its peak exceeds 0.65 A_col (peak time over the S2
    slope). Deterministic, run time included; records its calls."""

    def __init__(self):
        self.calls = []

    def __call__(self, wall, frequency, vertical="none", **kw):
        sig = kw.get("signal", "S2")
        self.calls.append((sig, frequency, vertical, kw.get("a_peak")))
        A_pseudo = kw["A_pseudo"]
        A = kw.get("A_rate") or A_pseudo / kw.get("t_pseudo", 2.5)
        thr = 0.05 * wall.height
        if sig == "S2":
            collapsed = frequency < 100
            t_col = 0.5 + 0.1 * frequency if collapsed else math.nan
            A_col = A * t_col
            ap = math.nan
        else:
            ap = kw["a_peak"]
            t_col_s2 = 0.5 + 0.1 * frequency
            collapsed = ap > 0.65 * A * t_col_s2
            t_col = ap / A if collapsed else math.nan
            A_col = ap if collapsed else math.nan
        t = np.linspace(0.0, 1.0, 11)
        d = thr * t * (1.5 if collapsed else 0.5)
        z = np.zeros_like(t)
        sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
        return CollapseResult(
            wall=wall.name, frequency=frequency, vertical=vertical, signal=sig, A_rate=A,
            A_pseudo=A_pseudo, a_peak=ap, threshold=thr, height=wall.height,
            collapsed=collapsed, t_col=t_col, A_col=A_col, t_end=1.0, t=t, d_top=d, acc=z,
            acc_v=z, kh=z, kv=z, polygons=[sq, sq + 1.0], displacement=np.array([0.0, 0.1]),
            wall_time=0.25 + frequency / 1000, steps=10, dt=1e-3, status="completed")


@pytest.fixture
def fake(monkeypatch):
    f = FakeRun()
    monkeypatch.setattr(bs, "collapse_run", f)
    return f


def small(frequencies=(3.0, 5.0), ratios=(0.6, 0.7), **numerics):
    return behaviour_study({
        "study": {"name": "t", "retries": 0},
        "wall": {"preset": "mockup-1.3", "stone_height": 0.011},
        "cases": {"frequencies": list(frequencies), "check_ratios": list(ratios)},
        "numerics": {"stiffness_scale": 1e-5, "t_pseudo": 0.5, "backfill": "thrust",
                     **numerics}})




def files(out):
    return {p.name: p.read_bytes() for p in sorted((out / "cases").iterdir())}


# ----------------------------------------------------------------------------- resume -----
def test_layout_and_stage_order(fake, tmp_path):
    st = small()
    names = [c.name for c in st.tasks()]
    assert names == ["S2_3Hz_none", "S2_5Hz_none", "S1_3Hz_none_0.6", "S1_3Hz_none_0.7",
                     "S1_5Hz_none_0.6", "S1_5Hz_none_0.7"]
    res = run_behaviour_study(st, "serial", out=tmp_path / "s")
    # each S1 check ran after its S2 run, with its slope and a_peak = ratio A_col
    s2 = {c[1]: c for c in fake.calls if c[0] == "S2"}
    assert [c[0] for c in fake.calls[:2]] == ["S2", "S2"] and len(fake.calls) == 6
    row = {r["frequency_Hz"]: r for r in res.table.rows}
    for sig, f, _v, ap in fake.calls:
        if sig == "S1":
            assert f in s2 and ap in (pytest.approx(0.6 * row[f]["A_col_m_s2"]),
                                      pytest.approx(0.7 * row[f]["A_col_m_s2"]))
    assert res.checks[(3.0, "none")] == {0.6: "stable", 0.7: "collapsed"}
    assert row[5.0]["r"] == pytest.approx(0.6 * row[5.0]["A_col_m_s2"] /
                                          row[5.0]["A_pseudo_m_s2"])
    out = tmp_path / "s"
    rec = json.loads((out / "cases" / "S2_5Hz_none.json").read_text())
    assert rec["summary"]["collapsed"] is True and rec["history"] == "S2_5Hz_none.csv"
    hist = np.loadtxt(out / "cases" / "S2_5Hz_none.csv", delimiter=",", skiprows=1)
    assert hist.shape == (11, 6)
    csv = (out / "behaviour_factor.csv").read_text().splitlines()
    assert csv[0].startswith("wall,frequency_Hz,vertical,t_col_s,A_col_m_s2")
    assert csv[0].endswith("S1_0.6_A_col,S1_0.7_A_col") and csv[1].endswith("stable,collapsed")
    md = (out / "behaviour_factor.md").read_text()
    assert "| S1 at 0.7 A_col | collapsed | collapsed |" in md
    s = study_status(out)
    assert s["complete"] and s["unit"] == "cases" and s["total"] == 6 and s["result"]


def test_interrupted_run_resumes_identically(fake, tmp_path):
    st = small()
    clean = tmp_path / "clean"
    run_behaviour_study(st, "serial", out=clean)
    out = tmp_path / "run"
    with pytest.raises(KeyboardInterrupt):
        run_behaviour_study(st, "serial", out=out, hook=Interrupt(3))
    s = study_status(out)
    assert s["done"] == [0, 1, 2] and s["missing"] == [3, 4, 5] and not s["result"]
    assert not list((out / "cases").glob(".*"))  # no temporary file left behind
    mtimes = {p.name: p.stat().st_mtime_ns for p in (out / "cases").iterdir()}
    n_before = len(fake.calls)
    marks = tmp_path / "marks"
    marks.mkdir()
    res = run_behaviour_study(st, "serial", out=out, hook=Touch(str(marks)))
    # only the missing cases ran; the stored ones were not touched
    assert sorted(int(p.name.split("-")[1]) for p in marks.iterdir()) == [3, 4, 5]
    assert len(fake.calls) - n_before == 3
    assert all((out / "cases" / n).stat().st_mtime_ns == m for n, m in mtimes.items())
    # the table of the uninterrupted run, byte for byte, and the same case files
    for name in ("behaviour_factor.csv", "behaviour_factor.md"):
        assert (out / name).read_bytes() == (clean / name).read_bytes()
    assert files(out) == files(clean)
    # a complete folder: nothing runs, same table
    n = len(fake.calls)
    again = run_behaviour_study(st, "serial", out=out)
    assert len(fake.calls) == n and again.to_markdown() == res.to_markdown()


def test_damaged_case_recomputed_and_other_study_refused(fake, tmp_path):
    st = small()
    out = tmp_path / "s"
    run_behaviour_study(st, "serial", out=out)
    (out / "cases" / "S1_5Hz_none_0.6.json").write_text("{damaged")
    (out / "cases" / "S2_3Hz_none.csv").unlink()  # a case without its history is redone
    n = len(fake.calls)
    run_behaviour_study(st, "serial", out=out)
    assert [c[:2] for c in fake.calls[n:]] == [("S2", 3.0), ("S1", 5.0)]
    with pytest.raises(StudyError, match="different study"):
        run_behaviour_study(small(ratios=(0.6,)), "serial", out=out)


def test_truncated_and_corrupt_case_files_reported_and_recomputed(fake, tmp_path):
    """Item 4 of issue 15 for the behaviour-factor study: a truncated history and a flipped
    byte in a snapshot are found by their checksums (status: damaged, naming the file); the
    resume recomputes those cases and gives the files and table of an uninterrupted run."""
    st = small()
    clean = tmp_path / "clean"
    run_behaviour_study(st, "serial", out=clean)
    out = tmp_path / "s"
    run_behaviour_study(st, "serial", out=out)
    cases = out / "cases"
    rec = json.loads((cases / "S2_5Hz_none.json").read_text())
    assert set(rec["sha256"]) == {"S2_5Hz_none.csv", "S2_5Hz_none.npz"}
    assert (cases / "S2_5Hz_none.json.sha256").exists()
    h = cases / "S2_3Hz_none.csv"
    h.write_bytes(h.read_bytes()[:-30])  # truncated history
    z = cases / "S1_5Hz_none_0.7.npz"
    data = bytearray(z.read_bytes())
    data[len(data) // 2] ^= 0x01  # one byte flipped in the snapshot
    z.write_bytes(bytes(data))
    s = study_status(out)
    assert sorted(s["damaged"]) == [0, 5] and s["done"] == [1, 2, 3, 4]
    assert "S2_3Hz_none.csv: checksum mismatch" in s["damaged"][0]
    assert "S1_5Hz_none_0.7.npz" in s["damaged"][5]
    n = len(fake.calls)
    run_behaviour_study(st, "serial", out=out)
    assert sorted(c[:2] for c in fake.calls[n:]) == [("S1", 5.0), ("S2", 3.0)]
    assert study_status(out)["complete"]
    assert files(out) == files(clean)
    for name in ("behaviour_factor.csv", "behaviour_factor.md"):
        assert (out / name).read_bytes() == (clean / name).read_bytes()


def test_no_collapse_skips_checks_and_failures_are_recorded(fake, tmp_path):
    st = small(frequencies=(5.0, 200.0))
    out = tmp_path / "s"
    # the S2 run at 5 Hz (task 0) fails every time: its checks cannot run
    res = run_behaviour_study(st, "serial", out=out, retries=1,
                              hook=FailTimes(str(tmp_path), chunk=0, times=-1))
    assert list(res.failures) == [0] and res.failures[0]["case"] == "S2_5Hz_none"
    assert res.checks[(200.0, "none")] == {0.6: "skipped", 0.7: "skipped"}
    assert res.checks[(5.0, "none")] == {0.6: "missing", 0.7: "missing"}
    assert res.table.rows[0]["collapsed"] == "failed"
    assert not res.table.rows[1]["collapsed"] and math.isnan(res.table.rows[1]["r"])
    s = study_status(out)
    assert list(s["failed"]) == [0] and s["missing"] == [2, 3]
    assert json.loads((out / "failures.json").read_text())["0"]["attempts"] == 2
    # skipped checks are stored (no DEM run): only the S2 run and its checks run again
    n = len(fake.calls)
    again = run_behaviour_study(st, "serial", out=out)
    assert [c[0] for c in fake.calls[n:]] == ["S2", "S1", "S1"]
    assert not again.failures and not (out / "failures.json").exists()
    assert study_status(out)["complete"]


# ----------------------------------------------------------------------------- case files -
BAD = [
    ("[cases]\nfrequencies = [5.0, -1.0]\n", "cases.frequencies", 7),
    ("[cases]\nfrequencies = [5.0]\nvertical = ['sideways']\n", "cases.vertical", 8),
    ("[cases]\nfrequencies = [5.0]\n[numerics]\nxi = 2.0\n", "numerics.xi", 9),
    ("[cases]\nfrequencies = [5.0]\n[numerics]\nstifness_scale = 1e-3\n",
     "numerics.stifness_scale", 9),
    ("[cases]\nfrequencies = [5.0]\n[executor]\nkind = 'threads'\n", "executor.kind", 9),
]


@pytest.mark.parametrize(("tail", "key", "line"), BAD)
def test_bad_case_file_exit_2_nothing_written(tmp_path, tail, key, line):
    from murus.cli import app

    case = tmp_path / "bad.toml"
    case.write_text("[study]\nname = 'bad'\n\n[wall]\npreset = 'mockup-1.3'\n" + tail)
    out = tmp_path / "out"
    res = CliRunner().invoke(app, ["retaining", "behaviour-factor", str(case), "--out",
                                   str(out)])
    assert res.exit_code == 2, res.output
    msg = res.output.strip()
    assert len(msg.splitlines()) == 1 and msg.startswith("error: bad.toml")
    assert f"line {line}: [{key}]" in msg
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_bad_wall_and_option_errors(tmp_path):
    from murus.cli import app

    runner = CliRunner()
    case = tmp_path / "bad.toml"
    case.write_text("[wall]\npreset = 'mockup-1.3'\nheight = -1.0\n[cases]\n"
                    "frequencies = [5.0]\n")
    out = tmp_path / "out"
    res = runner.invoke(app, ["retaining", "behaviour-factor", str(case), "--out", str(out)])
    assert res.exit_code == 2 and "line 3: [wall.height] height must be > 0" in res.output
    case.write_text("[wall]\npreset = 'mockup-1.3'\n[cases]\nfrequencies = [5.0]\n")
    res = runner.invoke(app, ["retaining", "behaviour-factor", str(case), "--out", str(out)])
    assert res.exit_code == 2 and "[wall.stone_height]" in res.output  # courses unknown
    res = runner.invoke(app, ["retaining", "behaviour-factor", str(EXAMPLE), "--preset",
                              "DSRW1", "--out", str(out)])
    assert res.exit_code == 2 and "not both" in res.output
    res = runner.invoke(app, ["retaining", "behaviour-factor", str(EXAMPLE), "--serial",
                              "--executor", "dask", "--out", str(out)])
    assert res.exit_code == 2 and "conflicts" in res.output
    res = runner.invoke(app, ["retaining", "behaviour-factor", "--preset", "DSRW1",
                              "--vertical", "sideways", "--out", str(out)])
    assert res.exit_code == 2 and "--vertical" in res.output
    assert not out.exists()


# ----------------------------------------------------------------------------- real runs --
@pytest.fixture(scope="module")
def serial_run(tmp_path_factory):
    """The example (three real DEM runs of a mock-up) through the CLI, serially."""
    from murus.cli import app

    out = tmp_path_factory.mktemp("bf") / "serial"
    res = CliRunner().invoke(app, ["retaining", "behaviour-factor", str(EXAMPLE), "--out",
                                   str(out), "--quiet"])
    assert res.exit_code == 0, res.output
    return out


def test_example_runs_and_reruns_nothing(serial_run):
    from murus.cli import app

    out = serial_run
    rows = (out / "behaviour_factor.csv").read_text().splitlines()
    head, row = rows[0].split(","), rows[1].split(",")
    r = dict(zip(head, row, strict=True))
    assert r["collapsed"] == "True" and 1.0 < float(r["A_col_m_s2"]) / \
        float(r["A_pseudo_m_s2"]) < 3.0  # dynamic capacity above the pseudo-static one
    assert r["S1_0.6_A_col"] == "stable"  # Savalle et al. (2022), Figure 14
    for name in ("S2_5Hz_none", "S1_5Hz_none_0.6", "S1_5Hz_none_0.7"):
        assert (out / "cases" / f"{name}.png").stat().st_size > 1000
        h = np.loadtxt(out / "cases" / f"{name}.csv", delimiter=",", skiprows=1)
        assert h.shape[1] == 6
    mt = {p.name: p.stat().st_mtime_ns for p in (out / "cases").iterdir()}
    table = (out / "behaviour_factor.md").read_bytes()
    res = CliRunner().invoke(app, ["retaining", "behaviour-factor", str(EXAMPLE), "--out",
                                   str(out), "--quiet"])
    assert res.exit_code == 0, res.output
    assert {p.name: p.stat().st_mtime_ns for p in (out / "cases").iterdir()} == mt
    assert (out / "behaviour_factor.md").read_bytes() == table
    status = CliRunner().invoke(app, ["study", "status", str(out)])
    assert "3/3 cases done" in status.output and "behaviour_factor.csv written" in \
        status.output


def test_process_pool_identical_to_serial(serial_run, tmp_path):
    st = load_behaviour_study(EXAMPLE)
    out = tmp_path / "pool"
    res = run_behaviour_study(st, "process", workers=2, out=out)
    assert not res.failures
    for p in sorted((serial_run / "cases").glob("*.json")):
        a = json.loads(p.read_text())
        b = json.loads((out / "cases" / p.name).read_text())
        for rec in (a, b):
            rec["summary"].pop("wall_time")
        assert a == b
        # the d_top histories, bit for bit
        h = p.with_suffix(".csv").name
        assert (out / "cases" / h).read_bytes() == (serial_run / "cases" / h).read_bytes()

    def table(folder):
        lines = (folder / "behaviour_factor.csv").read_text().splitlines()
        i = lines[0].split(",").index("wall_time_s")
        return [[x for k, x in enumerate(line.split(",")) if k != i] for line in lines]

    assert table(out) == table(serial_run)


def test_resume_of_a_real_run_after_deleting_a_case(serial_run, tmp_path):
    out = tmp_path / "copy"
    shutil.copytree(serial_run, out)
    for ext in ("json", "csv", "npz", "png"):
        (out / "cases" / f"S1_5Hz_none_0.7.{ext}").unlink()
    marks = tmp_path / "marks"
    marks.mkdir()
    st = load_behaviour_study(EXAMPLE)
    res = run_behaviour_study(st, "serial", out=out, hook=Touch(str(marks)))
    assert [p.name.split("-")[1] for p in marks.iterdir()] == ["2"]
    a = json.loads((out / "cases" / "S1_5Hz_none_0.7.json").read_text())
    b = json.loads((serial_run / "cases" / "S1_5Hz_none_0.7.json").read_text())
    a["summary"].pop("wall_time"), b["summary"].pop("wall_time")
    assert a == b
    assert res.checks[(5.0, "none")][0.7] == ("collapsed" if b["summary"]["collapsed"]
                                              else "stable")
    assert (out / "behaviour_factor.md").read_bytes() == \
        (serial_run / "behaviour_factor.md").read_bytes()  # the stored run times


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc")
@pytest.mark.parametrize("executor", [[], ["--workers", "2"]])
def test_ctrl_c_exits_130_and_the_resume_completes(serial_run, tmp_path, executor):
    """Issue 15 item 3: SIGINT to the process group of `murus retaining behaviour-factor`
    (serial: the DEM run in the main process; a pool of 2: the two S1 runs in the workers)
    once the S2 run is stored: exit code 130, the S2 case kept, the resume command in
    command-line form; before, the DEM engine caught SIGINT and the study ran on to the end.
    The resume computes the S1 checks and gives the files of an uninterrupted run."""
    import os
    import signal
    import subprocess
    import sys
    import time

    from murus.cli import app

    out = tmp_path / "out"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path), NUMBA_NUM_THREADS="1")
    p = subprocess.Popen([sys.executable, "-c", "from murus.cli import app; app()",
                          "retaining", "behaviour-factor",
                          str(EXAMPLE), "--out", str(out), *executor],
                         env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True)
    try:
        end = time.monotonic() + 300
        while not (out / "cases" / "S2_5Hz_none.json.sha256").exists():
            assert p.poll() is None and time.monotonic() < end, p.communicate()
            time.sleep(0.02)
        os.killpg(p.pid, signal.SIGINT)
        _, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
    assert p.returncode == 130, err
    s = study_status(out)
    assert s["done"] == [0] and not s["damaged"] and not s["result"]
    assert "interrupted after 1 of 3 cases" in err
    assert f"resume with: murus retaining behaviour-factor {EXAMPLE} --out {out}" in err
    assert "Traceback" not in err
    res = CliRunner().invoke(app, ["retaining", "behaviour-factor", str(EXAMPLE), "--out",
                                   str(out), "--quiet", "--no-snapshots"])
    assert res.exit_code == 0, res.output
    for p_ in sorted((serial_run / "cases").glob("*.json")):
        a = json.loads(p_.read_text())
        b = json.loads((out / "cases" / p_.name).read_text())
        a["summary"].pop("wall_time"), b["summary"].pop("wall_time")
        assert a == b
        h = p_.with_suffix(".csv").name
        assert (out / "cases" / h).read_bytes() == (serial_run / "cases" / h).read_bytes()
    assert not list((out / "cases").glob(".*"))  # no progress or temporary file left


def test_discrete_backfill_options_reach_collapse_run():
    """[numerics] backfill = "discrete" and its [numerics.backfill_options] go to every run's
    keyword arguments; options without backfill = "discrete" are refused with the key."""
    from murus.config import CaseError
    from murus.retaining.study import behaviour_study

    base = {"wall": {"preset": "mockup-1.3", "stone_height": 0.011},
            "cases": {"frequencies": [5.0]}}
    st = behaviour_study(dict(base, numerics={
        "backfill": "discrete", "backfill_options": {"W": 0.5, "boundary": "absorbing"}}))
    for case in st.tasks():
        kw = st.case_kwargs(case, {"summary": {"A_col": 1.0, "A_rate": 1.0}})
        assert kw["backfill"] == "discrete"
        assert kw["backfill_options"] == {"W": 0.5, "boundary": "absorbing"}
    with pytest.raises(CaseError, match=r"\[numerics\].*needs backfill = 'discrete' or"):
        behaviour_study(dict(base, numerics={"backfill_options": {"W": 0.5}}))
    with pytest.raises(CaseError, match=r"numerics.backfill_options.boundary"):
        behaviour_study(dict(base, numerics={"backfill": "discrete",
                                             "backfill_options": {"boundary": "wall"}}))


def test_continuum_backfill_options_reach_collapse_run():
    """[numerics] backfill = "continuum" (issue 18) and its options (W, size, boundary
    free-field or fixed) go to every run's keyword arguments; an option of the disc backfill,
    or its boundary, is refused with the key."""
    from murus.config import CaseError
    from murus.retaining.study import behaviour_study

    base = {"wall": {"preset": "mockup-1.3", "stone_height": 0.011},
            "cases": {"frequencies": [5.0]}}
    st = behaviour_study(dict(base, numerics={
        "backfill": "continuum", "backfill_options": {"W": 0.5, "size": 0.01,
                                                      "boundary": "fixed"}}))
    for case in st.tasks():
        kw = st.case_kwargs(case, {"summary": {"A_col": 1.0, "A_rate": 1.0}})
        assert kw["backfill"] == "continuum"
        assert kw["backfill_options"] == {"W": 0.5, "size": 0.01, "boundary": "fixed"}
    with pytest.raises(CaseError, match=r"radius: not an option of the continuum"):
        behaviour_study(dict(base, numerics={"backfill": "continuum",
                                             "backfill_options": {"radius": 0.01}}))
    with pytest.raises(CaseError, match=r"takes free-field or fixed"):
        behaviour_study(dict(base, numerics={"backfill": "continuum",
                                             "backfill_options": {"boundary": "absorbing"}}))
    with pytest.raises(CaseError, match=r"size: not an option of the discrete"):
        behaviour_study(dict(base, numerics={"backfill": "discrete",
                                             "backfill_options": {"size": 0.01}}))


@pytest.mark.parametrize("name", ["mockup_1.3", "mockup_1.7", "mockup_2.3", "mockup_2.7",
                                  "mockup_3", "mockup_3.3", "mockup_2.7_phi50",
                                  "mockup_2.7_phi55"])
def test_table3_case_files_are_the_validated_runs(name):
    """The case files of examples/retaining/savalle2022_table3/ (issue 18, item 7) resolve to
    the nominal runs of the continuum validation (validation/retaining_continuum.py): the
    same wall (preset, courses, backfill friction) and the same keywords of collapse_run."""
    import sys

    sys.path.insert(0, str(EXAMPLE.parents[2] / "validation"))
    try:
        import retaining_continuum as rc
    finally:
        sys.path.pop(0)
    spec = rc.runs()
    # the reference of the report: the printed stiffness, subcycled (rc.MOCK_COLUMNS)
    key = name.replace("mockup", "sub").replace("_phi", "_k1_phi")
    key = (key if "phi" in key else key + "_k1") + "_r0"
    s = spec[key]
    wall = rc._wall(s)
    ref = {"stiffness_scale": 1.0, "subcycle": "auto"}
    assert s["kw"] == ref and s["run"] == 0  # the nominal run, and
    kw = dict(ref, A_rate=rc.A_MOCK, t_max=rc.MOCK_TMAX)  # the mock-ups' slope and length
    st = load_behaviour_study(EXAMPLE.parent / "savalle2022_table3" / f"{name}.toml")
    assert st.wall.name == wall.name
    assert st.wall.stone_height == pytest.approx(wall.stone_height, rel=1e-12)
    assert st.wall.backfill_friction_deg == wall.backfill_friction_deg
    assert st.check_ratios == [] and st.cases[0] == (s["f"], "none")
    # Figure 7 (30 Hz) is the H/B = 2.3 wall's second case, the validation's mock30 run
    assert [c[0] for c in st.cases] == ([10.0, 30.0] if name == "mockup_2.3" else [10.0])
    if name == "mockup_2.3":
        s30 = spec["sub_2.3_k1_30Hz_r0"]
        assert s30["wall"] == s["wall"] and s30["f"] == 30.0 and s30["kw"] == ref
    got = st.case_kwargs(st.tasks()[0])
    for k in ("A_rate", "t_max", "stiffness_scale"):
        assert got[k] == pytest.approx(kw[k], rel=1e-12)
    assert got["subcycle"] == "auto"
    # the rest are collapse_run's defaults in both
    assert got["backfill"] == "continuum" and got["xi"] == 0.05
    assert set(got) - {"A_rate", "t_max", "backfill", "xi", "A_pseudo", "stiffness_scale",
                       "subcycle"} == set()


def test_a_rate_option_reaches_collapse_run():
    """--a-rate (command-line form) and [numerics] A_rate: the slope of the S2 envelope of
    every S2 run; the S1 checks keep their parent's slope."""
    from murus.retaining.cli import _options_case

    data = _options_case("mockup-1.3", "5", None, "0.6", 0.011, None, None, None, None, None,
                         a_rate=0.1307)
    st = behaviour_study(data)
    s2, s1 = st.tasks()[0], st.tasks()[1]
    assert st.case_kwargs(s2)["A_rate"] == 0.1307
    assert st.case_kwargs(s1, {"summary": {"A_col": 2.0, "A_rate": 0.5}})["A_rate"] == 0.5


def test_subcycle_in_numerics():
    """[numerics] subcycle ("auto" or an integer >= 1, continuum backfill only) reaches every
    run and the study's digest; other values and other backfills are refused with the key;
    without it the numerics hold no such key, so the digest of a study written before the key
    existed is unchanged (its stored cases stay valid)."""
    from murus.config import CaseError
    from murus.retaining.study import behaviour_study

    base = {"wall": {"preset": "mockup-1.3", "stone_height": 0.011},
            "cases": {"frequencies": [5.0]}}
    plain = behaviour_study(dict(base, numerics={"backfill": "continuum"}))
    assert "subcycle" not in plain.numerics
    for val in ("auto", 3):
        st = behaviour_study(dict(base, numerics={"backfill": "continuum", "subcycle": val}))
        for case in st.tasks():
            assert st.case_kwargs(case, None if case.signal == "S2" else
                                  {"summary": {"A_col": 1.0, "A_rate": 1.0}})["subcycle"] == val
        assert st.digest() != plain.digest()
    for bad in (0, "fast", 2.5, True):
        with pytest.raises(CaseError, match="subcycle"):
            behaviour_study(dict(base, numerics={"backfill": "continuum", "subcycle": bad}))
    with pytest.raises(CaseError, match="subcycle needs backfill = 'continuum'"):
        behaviour_study(dict(base, numerics={"backfill": "thrust", "subcycle": "auto"}))
    # at the printed stiffness too (the case files' corner rule is the default, "shrink")
    st = behaviour_study(dict(base, numerics={"backfill": "continuum", "subcycle": "auto",
                                              "stiffness_scale": 1.0}))
    got = st.case_kwargs(st.tasks()[0])
    assert got["subcycle"] == "auto" and got["stiffness_scale"] == 1.0
