"""Checkpoints of long collapse runs (murus.retaining.collapse, ``checkpoint=``): a run
interrupted after a checkpoint and started again resumes from it and gives the uninterrupted
run's result bit for bit; a checkpoint of another run is refused and left as it is.

The runs are those of tests/retaining/test_collapse.py (the H/B = 1.3 mock-up with the thrust,
joint stiffness x 1e-4, a fast ramp: a collapse in about a second of model time) and a short
stretch of the H/B = 2.7 mock-up on the continuum backfill. The segments are shortened to one
load update (``_SEGMENT``; the loads are updated ten times between two samples), so that a run of
a few seconds writes hundreds of checkpoints, most of them between two samples.
"""

from __future__ import annotations

import numpy as np
import pytest

import murus.retaining.collapse as C
from murus.retaining.collapse import CollapseError, collapse_run
from murus.retaining.geometry import preset

KW = dict(stiffness_scale=1e-4, t_pseudo=0.5, backfill="thrust", t_max=2.0)


@pytest.fixture(scope="module")
def wall():
    return preset("mockup-1.3", stone_height=0.011)


@pytest.fixture(scope="module")
def plain(wall):
    return collapse_run(wall, 5.0, **KW)


def _interrupt_after(monkeypatch, k: int) -> list:
    """Ctrl-C right after the ``k``-th checkpoint is written."""
    orig = C._save_checkpoint
    n = [0]

    def save(*a, **kw):
        orig(*a, **kw)
        n[0] += 1
        if n[0] == k:
            raise KeyboardInterrupt

    monkeypatch.setattr(C, "_save_checkpoint", save)
    monkeypatch.setattr(C, "_SEGMENT", 1)
    return n


def _same(a, b) -> None:
    for name in ("t", "d_top", "kh", "acc", "displacement", "rotation"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.status == b.status
    assert a.t_end == b.t_end and a.steps == b.steps
    if a.collapsed:
        assert a.t_col == b.t_col and a.A_col == b.A_col


def test_resumed_collapse_equals_the_uninterrupted_run(wall, plain, tmp_path, monkeypatch):
    assert plain.collapsed and plain.status == "stopped"
    ck = tmp_path / "run.npz"
    n = _interrupt_after(monkeypatch, 3)
    with pytest.raises(KeyboardInterrupt):
        collapse_run(wall, 5.0, checkpoint=ck, checkpoint_every=1e-9, **KW)
    assert n[0] == 3 and ck.exists()
    monkeypatch.undo()
    res = collapse_run(wall, 5.0, checkpoint=ck, checkpoint_every=1e-9, **KW)
    _same(plain, res)
    assert not ck.exists()  # removed when the run ended


def test_uninterrupted_checkpointed_run_equals_the_plain_run(wall, plain, tmp_path,
                                                             monkeypatch):
    # many segments, a checkpoint after each: the segments do not change the run
    monkeypatch.setattr(C, "_SEGMENT", 1)
    ck = tmp_path / "run"  # the suffix .npz is added
    res = collapse_run(wall, 5.0, checkpoint=ck, checkpoint_every=1e-9, **KW)
    _same(plain, res)
    assert not (tmp_path / "run.npz").exists()


def test_continuum_run_resumes_bit_for_bit(tmp_path, monkeypatch):
    w = preset("mockup-2.7", stone_height=0.011)
    kw = dict(backfill="continuum", A_rate=0.5, t_max=0.04, sample_dt=0.005)
    a = collapse_run(w, 10.0, **kw)
    ck = tmp_path / "c.npz"
    _interrupt_after(monkeypatch, 2)
    with pytest.raises(KeyboardInterrupt):
        collapse_run(w, 10.0, checkpoint=ck, checkpoint_every=1e-9, **kw)
    monkeypatch.undo()
    b = collapse_run(w, 10.0, checkpoint=ck, checkpoint_every=1e-9, **kw)
    _same(a, b)
    assert not a.collapsed and a.status == "completed"
    assert np.array_equal(a.zone_xy, b.zone_xy) and np.array_equal(a.zone_state, b.zone_state)


def test_checkpoint_of_another_run_is_refused_and_kept(wall, tmp_path, monkeypatch):
    ck = tmp_path / "run.npz"
    _interrupt_after(monkeypatch, 1)
    with pytest.raises(KeyboardInterrupt):
        collapse_run(wall, 5.0, checkpoint=ck, checkpoint_every=1e-9, **KW)
    monkeypatch.undo()
    before = ck.read_bytes()
    with pytest.raises(CollapseError, match="checkpoint of another run"):
        collapse_run(wall, 6.0, checkpoint=ck, **KW)
    assert ck.read_bytes() == before
    bad = tmp_path / "bad.npz"
    bad.write_bytes(b"not a zip file")
    with pytest.raises(CollapseError, match="not a checkpoint of a collapse run"):
        collapse_run(wall, 5.0, checkpoint=bad, **KW)
    assert bad.read_bytes() == b"not a zip file"


def test_checkpoint_arguments_checked(wall, tmp_path):
    with pytest.raises(CollapseError, match="disc backfill"):
        collapse_run(wall, 5.0, **dict(KW, backfill="discrete"), checkpoint=tmp_path / "x")
    with pytest.raises(CollapseError, match="checkpoint_every"):
        collapse_run(wall, 5.0, checkpoint=tmp_path / "x", checkpoint_every=0.0, **KW)
    assert not list(tmp_path.iterdir())


def test_cli_interrupted_run_resumes_from_its_checkpoint(tmp_path, monkeypatch):
    import json

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
    _interrupt_after(monkeypatch, 2)
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
