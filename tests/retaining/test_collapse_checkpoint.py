"""Checkpoints of long collapse runs (murus.retaining.collapse, ``checkpoint=``): a run
interrupted (Ctrl-C, or a process killed right after a checkpoint) and started again resumes
from its checkpoint and gives the uninterrupted run's result bit for bit, also when the time
step changes during the run; a file that is not a checkpoint of the run is refused before any
computation and left as it is.

The runs are those of tests/retaining/test_collapse.py (the H/B = 1.3 mock-up with the thrust,
joint stiffness x 1e-4, a fast ramp: a collapse in about a second of model time) and short
stretches of the H/B = 2.7 mock-up on the continuum backfill. Most tests shorten the segments
between two pauses to one load update (``_SEGMENT``; the loads are updated ten times between two
samples), so that a run of a few seconds pauses hundreds of times, mostly between two samples.
"""

from __future__ import annotations

import json
import os
import signal

import numpy as np
import pytest

import murus.retaining.collapse as C
from murus.continuum.coupled import CoupledModel
from murus.dem.kernels import P_ALOCAL
from murus.retaining.collapse import CollapseError, collapse_run
from murus.retaining.geometry import preset

_ORIG_SAVE = C._save_checkpoint
KW = dict(stiffness_scale=1e-4, t_pseudo=0.5, backfill="thrust", t_max=2.0)
CKW = dict(backfill="continuum", A_rate=0.5, sample_dt=0.005)


@pytest.fixture(scope="module")
def wall():
    return preset("mockup-1.3", stone_height=0.011)


@pytest.fixture(scope="module")
def plain(wall):
    return collapse_run(wall, 5.0, **KW)


@pytest.fixture(scope="module")
def wall27():
    return preset("mockup-2.7", stone_height=0.011)


@pytest.fixture(params=["terminal", "background"])
def sigint_start(request):
    """SIGINT's handler when the run starts: Python's (a terminal) or ignored (a job started in
    the background by a shell, which the engine also takes Ctrl-C from: kill -INT)."""
    start = signal.default_int_handler if request.param == "terminal" else signal.SIG_IGN
    old = signal.signal(signal.SIGINT, start)
    yield start
    signal.signal(signal.SIGINT, old)


def _killed_after(monkeypatch, k: int) -> list:
    """The process "killed" (KeyboardInterrupt) right after the ``k``-th checkpoint."""
    orig = C._save_checkpoint
    n = [0]

    def save(*a, **kw):
        orig(*a, **kw)
        n[0] += 1
        if n[0] == k:
            raise KeyboardInterrupt

    monkeypatch.setattr(C, "_save_checkpoint", save)
    return n


def _resumed(monkeypatch) -> list:
    """The bookkeeping of each checkpoint a run resumes from."""
    seen = []
    orig = C._run_checkpointed

    def spy(m, kw, path, interval, digest, run):
        seen.append(run)
        return orig(m, kw, path, interval, digest, run)

    monkeypatch.setattr(C, "_run_checkpointed", spy)
    return seen


def _kill_and_resume(monkeypatch, ck, w, f: float, kw: dict, k: int):
    """The run, pausing at every load update, killed after its ``k``-th checkpoint, then run
    again: it must resume from the checkpoint (and remove it at the end)."""
    monkeypatch.setattr(C, "_SEGMENT", 1)
    n = _killed_after(monkeypatch, k)
    with pytest.raises(KeyboardInterrupt):
        collapse_run(w, f, checkpoint=ck, checkpoint_every=1e-9, **kw)
    assert n[0] == k and ck.exists()
    monkeypatch.setattr(C, "_save_checkpoint", _ORIG_SAVE)
    seen = _resumed(monkeypatch)
    res = collapse_run(w, f, checkpoint=ck, checkpoint_every=1e-9, **kw)
    assert len(seen) == 1 and seen[0]["steps"] > 0  # it did resume, from a run under way
    assert not ck.exists()  # removed when the run ended
    return res


def _same(a, b) -> None:
    for name in ("t", "d_top", "kh", "kv", "acc", "displacement", "rotation"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.status == b.status and a.dt == b.dt
    assert a.t_end == b.t_end and a.steps == b.steps
    if a.collapsed:
        assert a.t_col == b.t_col and a.A_col == b.A_col


def test_resumed_collapse_equals_the_uninterrupted_run(wall, plain, tmp_path, monkeypatch):
    assert plain.collapsed and plain.status == "stopped"
    _same(plain, _kill_and_resume(monkeypatch, tmp_path / "run.npz", wall, 5.0, KW, 3))


def test_ctrl_c_writes_a_checkpoint_and_the_run_resumes(wall, plain, tmp_path, monkeypatch,
                                                        sigint_start):
    # Ctrl-C (a real SIGINT) half way: taken at the next pause, where the checkpoint is written
    # although the interval (an hour) has not passed
    ck = tmp_path / "run.npz"
    sent = []

    def progress(t, t_end, info):
        if info == "run" and t > 0.5 * plain.t_col and not sent:
            sent.append(t)
            os.kill(os.getpid(), signal.SIGINT)

    saved = []
    orig = C._save_checkpoint
    monkeypatch.setattr(C, "_save_checkpoint", lambda m, *a: saved.append(m.time) or orig(m, *a))
    with pytest.raises(KeyboardInterrupt):
        collapse_run(wall, 5.0, checkpoint=ck, checkpoint_every=3600.0, progress=progress, **KW)
    # one checkpoint, written at the pause right after the Ctrl-C (within one segment)
    assert sent and ck.exists() and len(saved) == 1 and sent[0] <= saved[0] < plain.t_col
    assert signal.getsignal(signal.SIGINT) is sigint_start  # handler restored
    monkeypatch.undo()
    seen = _resumed(monkeypatch)
    res = collapse_run(wall, 5.0, checkpoint=ck, checkpoint_every=3600.0, **KW)
    assert len(seen) == 1 and seen[0]["steps"] > 0
    _same(plain, res)
    assert not ck.exists()


@pytest.mark.parametrize("segment", [1, C._SEGMENT])
def test_uninterrupted_checkpointed_run_equals_the_plain_run(wall, plain, tmp_path,
                                                             monkeypatch, segment):
    # many pauses (one per load update, or the default segments), a checkpoint at each: the
    # pauses do not change the run
    monkeypatch.setattr(C, "_SEGMENT", segment)
    ck = tmp_path / "run"  # the suffix .npz is added
    res = collapse_run(wall, 5.0, checkpoint=ck, checkpoint_every=1e-9, **KW)
    _same(plain, res)
    assert not (tmp_path / "run.npz").exists()


def test_continuum_run_resumes_bit_for_bit(wall27, tmp_path, monkeypatch):
    kw = dict(CKW, t_max=0.04)
    a = collapse_run(wall27, 10.0, **kw)
    b = _kill_and_resume(monkeypatch, tmp_path / "c.npz", wall27, 10.0, kw, 2)
    _same(a, b)
    assert not a.collapsed and a.status == "completed"
    assert np.array_equal(a.zone_xy, b.zone_xy) and np.array_equal(a.zone_state, b.zone_state)


def test_time_step_change_during_the_run(wall27, tmp_path, monkeypatch):
    # the zones' check of their critical step lowers the time step once, at 5 ms (forced
    # here; it happens when zones distort): the frame of the step count restarts there, and
    # the pauses must follow it
    orig = CoupledModel.after_chunk
    changes = []

    def after_chunk(self):
        out = orig(self)
        m = self.dem
        # at a sample that is not a load update (every = round(sample_dt / dt) is not a
        # multiple of the load updates' round(1e-3 / dt) here)
        rel = int(m.C[0]) - m.step_offset
        every, ext = round(kw["sample_dt"] / m.dt), round(1e-3 / m.dt)
        if (m.P[P_ALOCAL] == 0.0 and m.time >= 0.005 and m.dt >= 0.95 * self.stable_dt()
                and rel % every == 0 and rel % ext != 0):
            changes.append(m.time)
            self.set_dt(0.9 * m.dt)
        return out

    monkeypatch.setattr(CoupledModel, "after_chunk", after_chunk)
    kw = dict(CKW, t_max=0.03, sample_dt=0.0047)
    a = collapse_run(wall27, 10.0, **kw)
    b = _kill_and_resume(monkeypatch, tmp_path / "c.npz", wall27, 10.0, kw, 15)
    # the step changed once in the plain run and once in the interrupted one, before its
    # checkpoint (the resumed run goes on with the lower step)
    assert len(changes) == 2 and changes[0] == changes[1]
    _same(a, b)


def test_checkpoint_of_another_run_is_refused_and_kept(wall, tmp_path, monkeypatch):
    ck = tmp_path / "run.npz"
    monkeypatch.setattr(C, "_SEGMENT", 1)
    _killed_after(monkeypatch, 1)
    with pytest.raises(KeyboardInterrupt):
        collapse_run(wall, 5.0, checkpoint=ck, checkpoint_every=1e-9, **KW)
    monkeypatch.undo()
    before = ck.read_bytes()
    settled = []
    monkeypatch.setattr(C, "_run_checkpointed", lambda *a: settled.append(1))
    with pytest.raises(CollapseError, match="checkpoint of another run"):
        collapse_run(wall, 6.0, checkpoint=ck, **KW)
    assert ck.read_bytes() == before and not settled  # refused before the run


@pytest.mark.parametrize("content", [b"not a zip file", b""])
def test_damaged_checkpoint_is_refused_and_kept(wall, tmp_path, content):
    bad = tmp_path / "bad.npz"
    bad.write_bytes(content)
    with pytest.raises(CollapseError, match="not a checkpoint of a collapse run"):
        collapse_run(wall, 5.0, checkpoint=bad, **KW)
    assert bad.read_bytes() == content
    np.savez(bad, run=np.array(json.dumps([1, 2])))  # a zip, but no bookkeeping
    with pytest.raises(CollapseError, match="not a checkpoint of a collapse run"):
        collapse_run(wall, 5.0, checkpoint=bad, **KW)


def test_checkpoint_arguments_checked(wall, tmp_path):
    with pytest.raises(CollapseError, match="disc backfill"):
        collapse_run(wall, 5.0, **dict(KW, backfill="discrete"), checkpoint=tmp_path / "x")
    with pytest.raises(CollapseError, match="checkpoint_every"):
        collapse_run(wall, 5.0, checkpoint=tmp_path / "x", checkpoint_every=0.0, **KW)
    with pytest.raises(CollapseError, match="does not exist"):
        collapse_run(wall, 5.0, checkpoint=tmp_path / "no" / "x.npz", **KW)
    assert not list(tmp_path.iterdir())


def test_cli_interrupted_run_resumes_from_its_checkpoint(tmp_path, monkeypatch):
    from typer.testing import CliRunner

    from murus.cli import app

    runner = CliRunner()
    base = ["retaining", "collapse", "--preset", "mockup-1.3", "--stone-height", "0.011",
            "--stiffness-scale", "1e-4", "--t-max", "0.3", "--frequency", "5",
            "--backfill", "thrust"]
    ref = tmp_path / "ref"
    r = runner.invoke(app, base + ["--out", str(ref)])
    assert r.exit_code == 0, r.output
    out, ck = tmp_path / "run", tmp_path / "state"
    args = base + ["--out", str(out), "--checkpoint", str(ck), "--checkpoint-every", "1e-9"]
    monkeypatch.setattr(C, "_SEGMENT", 1)
    _killed_after(monkeypatch, 2)
    r = runner.invoke(app, args)
    assert r.exit_code == 130
    assert "checkpoint" in r.output and "resume" in r.output
    assert not out.exists() and (tmp_path / "state.npz").exists()
    monkeypatch.undo()
    r = runner.invoke(app, args)
    assert r.exit_code == 0, r.output
    assert not (tmp_path / "state.npz").exists()
    assert (out / "d_top.csv").read_bytes() == (ref / "d_top.csv").read_bytes()
    a, b = (json.loads((d / "summary.json").read_text()) for d in (ref, out))
    a.pop("wall_time"), b.pop("wall_time")
    assert a == b
    r = runner.invoke(app, base + ["--out", str(tmp_path / "x"), "--runs", "2",
                                   "--checkpoint", str(ck)])
    assert r.exit_code == 2 and "--checkpoint needs --runs 1" in r.output
    r = runner.invoke(app, base + ["--out", str(tmp_path / "y"), "--checkpoint",
                                   str(tmp_path / "none" / "c.npz")])
    assert r.exit_code == 2 and "does not exist" in r.output
    assert not (tmp_path / "y").exists()
