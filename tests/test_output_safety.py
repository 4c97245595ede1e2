"""Output safety (issue 15, item 1): nothing of the user's is ever deleted, results appear
atomically, bad ``--out`` paths are refused up front, permissions follow the umask, Ctrl-C
exits 130; plus ``murus --version`` and the output extension check of ``motion ramp``."""

import json
import os
from importlib.metadata import version

import numpy as np
import pytest
from rocking_inputs import rocking_case, write_record
from typer.testing import CliRunner

from murus import outputs
from murus.cli import app
from murus.outputs import MANIFEST, OutputError, check_dir, check_file, write_dir, write_file

runner = CliRunner()

CASE = rocking_case(2.0)

RUN_FILES = ["response.png", "summary.json", "timeseries.csv"]


def snapshot(root):
    """Names, sizes, mtimes and contents of everything under ``root`` (and root's mode)."""
    snap = {".": os.stat(root).st_mode}
    for base, dirs, files in os.walk(root):
        for name in dirs + files:
            p = os.path.join(base, name)
            st = os.lstat(p)
            rel = os.path.relpath(p, root)
            data = open(p, "rb").read() if os.path.isfile(p) else None
            snap[rel] = (st.st_size, st.st_mtime_ns, st.st_mode, data)
    return snap


def project(tmp_path):
    """A user's folder: case file, record, notes."""
    proj = tmp_path / "proj"
    proj.mkdir()
    write_record(proj, seconds=1.5)
    (proj / "wall.toml").write_text(CASE)
    (proj / "notes.txt").write_text("my notes\n")
    return proj


def one_line_error(r, code=2):
    assert r.exit_code == code, r.output
    err = r.stderr.strip()
    assert len(err.splitlines()) == 1 and err.startswith("error: "), err
    assert "Traceback" not in r.output
    return err


def manifest(folder):
    return json.loads((folder / MANIFEST).read_text())


# ------------------------------------------------------------------------ murus run
def test_run_into_the_project_folder_keeps_the_users_files(tmp_path):
    proj = project(tmp_path)
    user = {n: (proj / n).read_bytes() for n in ("wall.toml", "record.csv", "notes.txt")}
    r = runner.invoke(app, ["run", str(proj / "wall.toml"), "--out", str(proj)])
    assert r.exit_code == 0, r.output
    for name, data in user.items():
        assert (proj / name).read_bytes() == data
    assert sorted(p.name for p in proj.iterdir()) == sorted(
        [*user, *RUN_FILES, MANIFEST])
    m = manifest(proj)
    assert m["files"] == RUN_FILES and m["command"].startswith("murus run")
    assert json.loads((proj / "summary.json").read_text())["theta_max"] > 0


def test_rerun_replaces_exactly_the_manifest_files(tmp_path):
    proj = project(tmp_path)
    out = proj / "out"
    assert runner.invoke(app, ["run", str(proj / "wall.toml"), "--out", str(out)]).exit_code == 0
    (out / "mine.txt").write_text("added by the user between runs\n")
    ino = (out / "summary.json").stat().st_ino
    mine = snapshot(out)["mine.txt"]
    r = runner.invoke(app, ["run", str(proj / "wall.toml"), "--out", str(out), "--no-figure"])
    assert r.exit_code == 0, r.output
    # response.png was murus's and is no longer written: removed; the user's file stays
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "mine.txt", "summary.json",
                                                     "timeseries.csv"]
    assert snapshot(out)["mine.txt"] == mine
    assert (out / "summary.json").stat().st_ino != ino  # replaced by a new file (os.replace)
    assert manifest(out)["files"] == ["summary.json", "timeseries.csv"]


def test_a_users_summary_json_in_out_is_refused_before_computing(tmp_path, monkeypatch):
    proj = project(tmp_path)
    (proj / "summary.json").write_text('{"mine": true}\n')
    before = snapshot(tmp_path)
    import murus.rocking.case as case

    def no_run(*a, **k):  # the error must come before any computation
        raise AssertionError("computed")

    monkeypatch.setattr(case, "run_case", no_run)
    err = one_line_error(runner.invoke(app, ["run", str(proj / "wall.toml"), "--out",
                                             str(proj)]))
    assert "summary.json" in err and "not written by murus" in err
    assert snapshot(tmp_path) == before


@pytest.mark.parametrize("kind", ["file", "under_file", "dot", "cwd", "unwritable", "root"])
def test_bad_out_paths_exit_2_and_change_nothing(tmp_path, monkeypatch, kind):
    proj = project(tmp_path)
    (tmp_path / "afile").write_text("x")
    monkeypatch.chdir(tmp_path)
    out = {"file": "afile", "under_file": "afile/sub/out", "dot": ".",
           "cwd": f"../{tmp_path.name}", "unwritable": "locked/out", "root": "/"}[kind]
    if kind == "unwritable":
        (tmp_path / "locked").mkdir()
        real = os.access
        locked = str(tmp_path / "locked")
        # os.access semantics (root passes every permission check, so a chmod cannot be
        # used here: test_unwritable_parent_really_refused does it for other users)
        monkeypatch.setattr(os, "access", lambda p, m, *a, **k: False if
                            os.path.abspath(p) == locked else real(p, m, *a, **k))
    before = snapshot(tmp_path)
    err = one_line_error(runner.invoke(app, ["run", str(proj / "wall.toml"), "--out", out]))
    assert out.split("/")[0] in err or kind in ("cwd",)
    assert kind != "root" or "root of the file system" in err
    assert snapshot(tmp_path) == before


@pytest.mark.skipif(os.geteuid() == 0, reason="root passes every permission check")
def test_unwritable_parent_really_refused(tmp_path):
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        with pytest.raises(OutputError, match="not writable"):
            check_dir(locked / "out")
    finally:
        locked.chmod(0o700)


def test_manifest_that_is_not_ours_is_never_overwritten(tmp_path):
    out = tmp_path / "o"
    out.mkdir()
    (out / MANIFEST).write_text("my own file\n")
    with pytest.raises(OutputError, match="not a murus manifest"):
        check_dir(out)
    assert (out / MANIFEST).read_text() == "my own file\n"


# ------------------------------------------------------------------ the writer itself
def _write(files):
    def write(tmp):
        for rel, text in files.items():
            (tmp / rel).parent.mkdir(parents=True, exist_ok=True)
            (tmp / rel).write_text(text)
    return write


@pytest.mark.parametrize("mask, dmode, fmode", [(0o022, 0o755, 0o644), (0o077, 0o700, 0o600)])
def test_permissions_follow_the_umask(tmp_path, mask, dmode, fmode):
    old = os.umask(mask)
    try:
        out = write_dir(tmp_path / "a" / "b" / "out", _write({"x.csv": "1\n", "sub/y.txt": "2"}))
        # a folder that exists already gets new files and sub-folders with the same modes
        write_dir(tmp_path / "a" / "b" / "out",
                  _write({"x.csv": "1\n", "sub/y.txt": "2", "new/z.txt": "3"}))
        f = write_file(tmp_path / "c" / "one.csv", lambda p: p.write_text("1\n"))
    finally:
        os.umask(old)
    for d in (tmp_path / "a", tmp_path / "a" / "b", out, out / "sub", out / "new",
              tmp_path / "c"):
        assert d.stat().st_mode & 0o777 == dmode, d
    for p in (out / "x.csv", out / "sub" / "y.txt", out / "new" / "z.txt", out / MANIFEST, f):
        assert p.stat().st_mode & 0o777 == fmode, p


@pytest.mark.parametrize("exc", [RuntimeError, KeyboardInterrupt])
def test_failure_while_writing_leaves_out_unchanged(tmp_path, exc):
    out = write_dir(tmp_path / "out", _write({"a.csv": "old a", "b/c.csv": "old c"}))
    (out / "user.txt").write_text("mine")
    before = snapshot(tmp_path)

    def write(tmp):
        (tmp / "a.csv").write_text("new a")
        raise exc("boom")

    with pytest.raises(exc):
        write_dir(out, write)
    assert snapshot(tmp_path) == before
    # a new folder whose missing parents were created for it: all removed again
    with pytest.raises(exc):
        write_dir(tmp_path / "p" / "q" / "new", write)
    assert snapshot(tmp_path) == before


def test_failure_while_moving_into_out_puts_everything_back(tmp_path, monkeypatch):
    out = write_dir(tmp_path / "out", _write({"a.csv": "old a", "b/c.csv": "old c",
                                              "gone.csv": "old"}))
    (out / "user.txt").write_text("mine")
    before = snapshot(tmp_path)
    real, calls = os.replace, []

    def flaky(src, dst, *a, **k):
        calls.append(dst)
        if len(calls) == 6:  # manifest, a (+ backup), b/c (+ backup): fail in the middle
            raise OSError("disk full")
        return real(src, dst, *a, **k)

    monkeypatch.setattr(outputs.os, "replace", flaky)
    with pytest.raises(OutputError, match="disk full"):
        write_dir(out, _write({"a.csv": "new a", "b/c.csv": "new c", "d/e.csv": "new e"}))
    monkeypatch.setattr(outputs.os, "replace", real)
    assert len(calls) > 6  # the failed move, then the moves back
    after = snapshot(tmp_path)
    # contents, names and modes as before (a restored file keeps its old inode and mtime)
    assert after == before


def test_collision_found_only_after_writing_moves_nothing(tmp_path):
    out = write_dir(tmp_path / "out", _write({"a.csv": "old a"}))
    (out / "rec_02.csv").write_text("the user's")
    before = snapshot(tmp_path)
    with pytest.raises(OutputError, match="rec_02.csv"):
        write_dir(out, _write({"a.csv": "new", "rec_01.csv": "1", "rec_02.csv": "2"}))
    assert snapshot(tmp_path) == before


def test_subfolders_murus_emptied_are_removed_but_user_files_kept(tmp_path):
    out = write_dir(tmp_path / "out", _write({"case1/s.json": "1", "case2/s.json": "2",
                                              "all.csv": "x"}))
    (out / "case2" / "mine.txt").write_text("mine")
    write_dir(out, _write({"all.csv": "y"}))
    assert not (out / "case1").exists()
    assert sorted(p.name for p in (out / "case2").iterdir()) == ["mine.txt"]
    assert (out / "all.csv").read_text() == "y"
    assert manifest(out)["files"] == ["all.csv"]


def test_check_file(tmp_path):
    assert check_file(tmp_path / "x.CSV", (".csv",)) == tmp_path / "x.CSV"
    with pytest.raises(OutputError, match=r"\.xlsx.*\.csv or \.at2"):
        check_file(tmp_path / "x.xlsx", (".csv", ".at2"))
    with pytest.raises(OutputError, match="is a folder"):
        check_file(tmp_path, (".csv",))
    (tmp_path / "f").write_text("")
    with pytest.raises(OutputError, match="is a file"):
        check_file(tmp_path / "f" / "x.csv", (".csv",))


# ------------------------------------------------------------------------ other commands
def test_motion_ramp_refuses_an_extension_it_cannot_write(tmp_path):
    before = snapshot(tmp_path)
    args = ["motion", "ramp", "--amplitude-rate", "1", "--frequency", "2", "--duration", "1"]
    err = one_line_error(runner.invoke(app, [*args, "--out", str(tmp_path / "x.xlsx")]))
    assert "x.xlsx" in err and ".csv or .at2" in err
    one_line_error(runner.invoke(app, [*args, "--out", str(tmp_path)]))
    assert snapshot(tmp_path) == before
    r = runner.invoke(app, [*args, "--out", str(tmp_path / "r.csv")])
    assert r.exit_code == 0, r.output
    assert os.listdir(tmp_path) == ["r.csv"]  # no temporary file left


def test_single_file_outputs_replace_only_murus_files(tmp_path):
    """A user's file is never overwritten by a single-file output; murus's own file is (its
    signature, or the folder's list of files murus wrote); an output naming one of its
    inputs is refused."""
    args = ["motion", "ramp", "--amplitude-rate", "1", "--frequency", "2", "--duration", "1"]
    mine = tmp_path / "mine.csv"
    mine.write_text("my precious data\n")
    before = snapshot(tmp_path)
    err = one_line_error(runner.invoke(app, [*args, "--out", str(mine)]))
    assert "was not written by murus" in err
    assert snapshot(tmp_path) == before
    ramp = tmp_path / "r.csv"
    assert runner.invoke(app, [*args, "--out", str(ramp)]).exit_code == 0
    assert runner.invoke(app, [*args, "--duration", "2", "--out", str(ramp)]).exit_code == 0
    # a CSV without a signature: recorded in the folder's list, so a re-run may replace it
    h = tmp_path / "s1.csv"
    t = np.linspace(0.0, 2.0, 41)
    np.savetxt(h, np.column_stack([t, 0.01 * t]), delimiter=",", header="t_s,d_top_m",
               comments="")
    wr = ["retaining", "weighted-response", str(h), str(h), "--weights", "1,1"]
    err = one_line_error(runner.invoke(app, [*wr, "--out", str(h)]))
    assert "is one of the input histories" in err
    out = tmp_path / "w.csv"
    assert runner.invoke(app, [*wr, "--out", str(out)]).exit_code == 0
    assert outputs.owned_file(out)
    assert runner.invoke(app, [*wr, "--out", str(out)]).exit_code == 0


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs Linux /proc")
def test_write_errors_are_one_line(tmp_path):
    """A location where nothing can be written (a pseudo file system) gives one line, exit 2."""
    proj = project(tmp_path)
    err = one_line_error(runner.invoke(app, ["run", str(proj / "wall.toml"), "--out",
                                             "/proc/murus-out", "--no-figure"]))
    assert "/proc/murus-out" in err


def test_oversized_input_is_one_line_without_output(tmp_path):
    """An input asking for more memory than the machine has: one line, exit 2, no output."""
    err = one_line_error(runner.invoke(app, ["lab", "synthesize", str(tmp_path / "syn"),
                                             "--wn-duration", "1e12"]))
    assert "more memory than this machine has" in err
    assert not (tmp_path / "syn").exists()


def test_version():
    r = runner.invoke(app, ["--version"])
    assert r.exit_code == 0
    assert r.output.strip() == f"murus {version('murus')}"


def test_ctrl_c_exits_130_with_one_line_and_outputs_as_before(tmp_path, monkeypatch):
    proj = project(tmp_path)
    out = proj / "out"
    assert runner.invoke(app, ["run", str(proj / "wall.toml"), "--out", str(out)]).exit_code == 0
    before = snapshot(tmp_path)
    import murus.rocking.output as ro

    def interrupted(result, folder, figure=True):
        (folder / "summary.json").write_text("half")
        raise KeyboardInterrupt

    monkeypatch.setattr(ro, "write_result_files", interrupted)
    r = runner.invoke(app, ["run", str(proj / "wall.toml"), "--out", str(out)])
    assert r.exit_code == 130
    assert r.stderr.strip() == "interrupted"
    assert snapshot(tmp_path) == before


def test_atomic_write_flushes_and_cleans_up(tmp_path, monkeypatch):
    synced = []
    real_fsync = os.fsync
    monkeypatch.setattr(outputs.os, "fsync", lambda fd: (synced.append(fd), real_fsync(fd)))
    p = outputs.atomic_write(tmp_path / "a.bin", lambda t: t.write_bytes(b"new"))
    assert p.read_bytes() == b"new" and len(synced) == 2  # the file, then its folder
    # a piece of a study: its own temporary name; a failed write leaves nothing behind
    name = outputs.process_tmp_name(p)
    assert name == f".a.bin.tmp-{os.getpid()}"

    def fail(t):
        assert t.name == name
        t.write_bytes(b"half")
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        outputs.atomic_write(p, fail, tmp_name=name)
    assert p.read_bytes() == b"new" and sorted(os.listdir(tmp_path)) == ["a.bin"]
