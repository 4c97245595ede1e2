"""Ctrl-C and a killed main process (issue 15, item 3), on real command-line runs in a
subprocess: SIGINT sent to the process group of ``murus study run`` (process pool, or serial)
after the first chunk is stored ends it with exit code 130, keeps the chunks stored, says how to
resume in command-line form, leaves no worker behind; the resume gives the Dataset of an
uninterrupted run. SIGKILL of the main process: the workers of the pool and of a local Dask
cluster exit by themselves (they watch their parent).

The study is the small one of ``studies_inputs`` made slow by a hook (``faults.Sleep``) that the
child process adds to every chunk, so that the run is still going when the signal comes."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import xarray as xr
from studies_inputs import SLOW_CHILD, SLOW_STUDY, alive, children, write_study
from typer.testing import CliRunner

from murus.studies.cli import app
from murus.studies.sweep import open_result, study_status


@pytest.fixture
def study(tmp_path, records):
    return write_study(tmp_path, records, SLOW_STUDY)


def start(args, sleep: float, tmp_path: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path), NUMBA_NUM_THREADS="1")
    return subprocess.Popen([sys.executable, "-c", SLOW_CHILD, str(sleep), *map(str, args)],
                            cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)




def wait_for(cond, timeout: float, what: str) -> None:
    end = time.monotonic() + timeout
    while not cond():
        if time.monotonic() > end:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}")
        time.sleep(0.05)


def stored(out: Path) -> int:
    return len(list((out / "chunks").glob("*.npz.sha256")))


pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc")


@pytest.mark.parametrize("executor", [["--workers", "2"], ["--serial"]])
def test_sigint_exits_130_keeps_chunks_and_resumes(study, tmp_path, executor):
    out = tmp_path / "out"
    p = start(["study", "run", study, "--out", out, *executor], 0.4, tmp_path)
    try:
        wait_for(lambda: stored(out) >= 1 or p.poll() is not None, 120, "the first chunk")
        assert p.poll() is None, p.communicate()
        workers = children(p.pid)
        os.killpg(p.pid, signal.SIGINT)  # Ctrl-C reaches the whole process group
        _, err = p.communicate(timeout=30)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
    assert p.returncode == 130, err
    st = study_status(out)
    n = len(st["done"])
    assert 1 <= n < st["total"] and not st["damaged"]
    assert f"interrupted after {n} of {st['total']} chunks" in err
    assert f"resume with: murus study run {study} --out {out}" in err
    assert "Traceback" not in err
    wait_for(lambda: not any(alive(w) for w in workers), 10, "the workers to exit")
    r = CliRunner().invoke(app, ["run", str(study), "--out", str(out), "--serial", "-q"])
    assert r.exit_code == 0, r.output
    clean = tmp_path / "clean"
    r = CliRunner().invoke(app, ["run", str(study), "--out", str(clean), "--serial", "-q"])
    assert r.exit_code == 0, r.output
    xr.testing.assert_identical(open_result(out / "result.nc"),
                                open_result(clean / "result.nc"))


@pytest.mark.parametrize("executor", [["--workers", "2"], ["--dask", "local", "--workers", "2"]])
def test_workers_exit_when_the_main_process_is_killed(study, tmp_path, executor):
    if "--dask" in executor:
        pytest.importorskip("distributed")
    out = tmp_path / "out"
    p = start(["study", "run", study, "--out", out, *executor], 1.0, tmp_path)
    workers: list[int] = []
    try:
        wait_for(lambda: stored(out) >= 1 or p.poll() is not None, 120, "the first chunk")
        assert p.poll() is None, p.communicate()
        workers = children(p.pid)
        assert len(workers) >= 2
        os.kill(p.pid, signal.SIGKILL)
        p.wait()
        # before this fix they ran on for more than a minute (orphans of a dead parent)
        wait_for(lambda: not any(alive(w) for w in workers), 10, "the orphaned workers to exit")
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
        for w in workers:  # only if the test failed: no orphan of ours is left running
            if alive(w):
                os.kill(w, signal.SIGKILL)
