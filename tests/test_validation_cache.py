"""The cache of the long validation runs (validation/runcache.py) is keyed by the engine's
source (issue 18, item 6): a change of code recomputes a run, a change of documentation or
comments does not, and a record made by another engine is not read as current."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "validation"))
import runcache  # noqa: E402

CODE = '''"""Module doc."""


def f(x):
    """Doc of f."""
    return 2 * x  # a comment
'''


def test_source_key_follows_code_not_documentation(tmp_path):
    pkg = tmp_path / "eng"
    pkg.mkdir()
    (pkg / "a.py").write_text(CODE)
    k0 = runcache.source_key("eng", root=tmp_path)
    (pkg / "a.py").write_text(CODE.replace("Doc of f.", "Other words.")
                              .replace("# a comment", "# another"))
    assert runcache.source_key("eng", root=tmp_path) == k0
    (pkg / "a.py").write_text(CODE.replace("2 * x", "3 * x"))
    assert runcache.source_key("eng", root=tmp_path) != k0
    (pkg / "a.py").write_text(CODE)
    (pkg / "plots.py").write_text("Y = 1\n")  # not the engine
    assert runcache.source_key("eng", root=tmp_path) == k0
    (pkg / "b.py").write_text("Y = 1\n")
    assert runcache.source_key("eng", root=tmp_path) != k0
    assert runcache.source_key("eng/a.py", root=tmp_path) != runcache.source_key(
        "eng", root=tmp_path)


def _compute(key):  # writes the record, as a validation script's compute does
    path = Path(_compute.cache) / f"{key}.json"
    rec = {"key": key, "n": _compute.n}
    path.write_text(json.dumps(rec))
    _compute.n += 1
    return rec


def test_a_record_of_another_engine_is_recomputed(tmp_path, monkeypatch):
    monkeypatch.delenv("NUMBA_NUM_THREADS", raising=False)  # as it was, whatever ensure does
    _compute.cache, _compute.n = str(tmp_path), 0
    recs = runcache.ensure(["a"], _compute, tmp_path, engine="E1")
    assert recs["a"]["n"] == 0 and recs["a"][runcache.ENGINE_FIELD] == "E1"
    assert runcache.ensure(["a"], _compute, tmp_path, engine="E1")["a"]["n"] == 0  # cached
    again = runcache.ensure(["a"], _compute, tmp_path, engine="E2")["a"]
    assert again["n"] == 1 and again[runcache.ENGINE_FIELD] == "E2"


def _compute_under_ctrl_c(key):
    """Sends itself SIGINT inside the engine's Ctrl-C guard, as a long run interrupted by the
    user: the guard must take it as its flag (collapse_run then writes its checkpoint), not a
    handler of the caller raising at once. Key "bad" raises."""
    import os
    import signal

    from murus.dem.engine import _SigInt

    if key == "bad":
        raise ValueError("no such wall")
    with _SigInt() as ctrl:
        os.kill(os.getpid(), signal.SIGINT)
    return _compute(f"{key}" if ctrl.hit else f"{key}-preempted")


def test_a_serial_run_keeps_its_own_ctrl_c_and_failures_come_last(tmp_path):
    _compute.cache, _compute.n = str(tmp_path), 0
    try:
        with pytest.raises(RuntimeError, match="bad: ValueError: no such wall"):
            runcache.ensure(["a", "bad", "b"], _compute_under_ctrl_c, tmp_path)
    except KeyboardInterrupt:
        pytest.fail("ensure pre-empted the run's own Ctrl-C handling (a handler of its own)")
    # both good runs done (after the failure), each with the SIGINT as the guard's flag
    assert sorted(p.name for p in tmp_path.glob("*.json")) == ["a.json", "b.json"]


def test_the_real_engine_key_is_stable():
    k = runcache.source_key("dem", "continuum", "retaining", "motion/synthetic.py")
    assert len(k) == 16 and k == runcache.source_key("motion/synthetic.py", "retaining",
                                                     "continuum", "dem")
    with pytest.raises(FileNotFoundError):
        runcache.source_key("no_such_package_here")


def test_restamp_rekeys_only_the_old_engines_records(tmp_path):
    """``runcache.restamp`` moves the records of one engine to another, keeping where they came
    from and the evidence; records of other engines and unreadable files are left alone."""
    recs = {"a": {"x": 1, runcache.ENGINE_FIELD: "old"}, "b": {"x": 2, runcache.ENGINE_FIELD:
                                                                "other"}}
    for k, r in recs.items():
        (tmp_path / f"{k}.json").write_text(json.dumps(r))
    (tmp_path / "c.json").write_text("{not json")
    done = runcache.restamp(tmp_path, "old", "new", "a recomputed bit for bit")
    assert done == ["a"]
    a = json.loads((tmp_path / "a.json").read_text())
    assert a[runcache.ENGINE_FIELD] == "new" and a["_restamped_from"] == "old"
    assert a["_restamp_evidence"] == "a recomputed bit for bit" and a["x"] == 1
    assert json.loads((tmp_path / "b.json").read_text()) == recs["b"]
    assert (tmp_path / "c.json").read_text() == "{not json"


def test_restamp_leaves_the_records_a_change_does_change(tmp_path):
    """``skip`` names the records the engine's change does change (the subcycled runs of a
    change of the subcycled scheme alone): they keep the old key, so they are recomputed."""
    recs = {"a": {"spec": {"kw": {}}}, "s": {"spec": {"kw": {"subcycle": "auto"}}},
            "one": {"spec": {"kw": {"subcycle": 1}}}}
    for k, r in recs.items():
        r[runcache.ENGINE_FIELD] = "old"
        (tmp_path / f"{k}.json").write_text(json.dumps(r))
    done = runcache.restamp(tmp_path, "old", "new", "a recomputed",
                            skip=lambda r: (r["spec"]["kw"].get("subcycle") or 1) != 1)
    assert done == ["a", "one"]
    assert json.loads((tmp_path / "s.json").read_text()) == recs["s"]


def test_an_s1_check_at_another_median_is_stale():
    """An S1 check (Figure 14) is made at a ratio of the median A_col of the cached runs of
    DSRW1 at 5 Hz: a record made when that median was another (fewer runs then) is made again
    by the section (validation/retaining_continuum.py)."""
    import statistics

    import retaining_continuum as rc

    vals = [json.loads(p.read_text())["summary"]["A_col"]
            for p in sorted(rc.CACHE.glob("t7_DSRW1_5_none_r*.json"))]
    med = statistics.median(vals)
    rec = {"spec": {"ratio": 0.6}, "summary": {"a_peak": 0.6 * med}}
    assert rc._s1_current(rec)
    rec["summary"]["a_peak"] = 0.6 * med * (1 + 1e-9)
    assert not rc._s1_current(rec)


def test_a_disc_backfill_far_from_equilibrium_is_flagged():
    import retaining_continuum as rc

    def rec(msg):
        return {"summary": {"options": {"backfill_options": {"settle": msg}}}}

    recs = {"a": rec("not settled after 20000 steps, ratio 7.72e-01 > 0.01"),
            "b": rec("not settled after 20000 steps, ratio 6.69e-02 > 0.01"),
            "c": rec("settled in 14400 steps, ratio 8.33e-05")}
    assert rc._unsettled(recs, "a") == pytest.approx(0.772)
    assert rc._unsettled(recs, "b") is None and rc._unsettled(recs, "c") is None
    assert rc._unsettled(recs, "b", limit=0.0) == pytest.approx(0.0669)
    assert rc._unsettled(recs, "missing") is None


def test_every_continuum_run_has_one_twin_of_the_other_corner_rule():
    """Each run of the groups of validation/retaining_continuum.py that compare the corner
    rules has exactly one twin with the other ``corner_share`` and otherwise the same spec: no
    twin's key is another run's (a dict would silently drop one of them)."""
    import retaining_continuum as rc

    spec = rc.runs()
    tw = rc.TWIN_RULE
    base = [k for k, v in spec.items() if v["group"] in rc.TWIN_GROUPS]
    twins = [rc.twin_key(k) for k in base]
    assert len(set(twins)) == len(base) > 100
    assert not set(twins) & {k for k, v in spec.items() if not v["group"].startswith(tw)}
    for k, t in zip(base, twins, strict=True):
        a, b = dict(spec[k]), dict(spec[t])
        assert b.pop("kw") == dict(a.pop("kw"), corner_share=tw)
        assert b.pop("group") == f"{tw}_" + a.pop("group")
        assert a == b
    assert rc.twin_key("t7_DSRW1_5_none_r0", "shrink") == "shrink_DSRW1_5_r0"
    assert rc.twin_key("mock_1.7_k1_r0", "follow") == "follow_1.7_k1_r0"


def test_record_diff_names_what_changed_but_the_wall_time():
    """The comparison behind a re-keying (validation/restamp_check.py, promote_twins.py):
    exact equality of the histories, the mode and every summary value but the wall times (at
    any depth), including a summary value only one record has."""
    old = {"t": [0.0, 0.1], "d_top": [0.0, 1e-3], "mode": "T",
           "summary": {"A_col": 5.9, "wall_time": 10.0}}
    new = json.loads(json.dumps(old))
    new["summary"]["wall_time"] = 99.0
    assert runcache.record_diff(old, new) == []
    # a wall time deeper in the summary (the disc backfill's packing) is no difference either
    old["summary"]["options"] = {"backfill_options": {"packing_wall_time": 7.4, "n": 2053}}
    new["summary"]["options"] = {"backfill_options": {"packing_wall_time": 9.1, "n": 2053}}
    assert runcache.record_diff(old, new) == []
    new["summary"]["options"]["backfill_options"]["n"] = 2054
    assert runcache.record_diff(old, new) == ["summary.options"]
    new["summary"]["options"]["backfill_options"]["n"] = 2053
    new["d_top"][1] = 1e-3 * (1 + 1e-15)
    new["summary"]["corner_share"] = "shrink"
    assert runcache.record_diff(old, new) == ["d_top", "summary.corner_share"]


def test_the_campaign_is_made_of_runs_of_the_report():
    """``--campaign`` (validation/retaining_continuum.py) computes runs of the report, each
    once, beginning with the subcycling pairs at x 1 and the nominal run of every wall of
    Table 3; ``--lane I/N`` splits it into N disjoint lanes that cover it."""
    import retaining_continuum as rc

    from murus.retaining.geometry import MOCKUP_SLENDERNESS

    keys, spec = rc.campaign(), rc.runs()
    assert len(keys) == len(set(keys)) and all(k in spec for k in keys)
    assert keys[:3] == ["mock_2.7_k1_r0", "scale_DSRW1_5_k1_r0", "sub_DSRW1_5_k1_r0"]
    assert keys[3:3 + len(MOCKUP_SLENDERNESS)] == [f"sub_{s:g}_k1_r0" for s in
                                                     MOCKUP_SLENDERNESS]
    lanes = [keys[i::2] for i in range(2)]
    assert sorted(lanes[0] + lanes[1]) == sorted(keys) and not set(lanes[0]) & set(lanes[1])
    for argv in (["--campaign", "--lane", "2/2"], ["--keys", "mock_3_r0", "--lane", "0/2"]):
        with pytest.raises(SystemExit) as e:
            rc.main(argv)
        assert e.value.code == 2


def test_a_checkpoint_is_rekeyed_only_from_the_old_engines_digest(tmp_path):
    """``restamp_check.rekey_checkpoint`` (after a change shown not to change a run): the
    checkpoint of the old engine, its digest checked, is written under the new engine's name
    and digest with the same state, and ``collapse_run``'s check accepts it as the new run's;
    one of other arguments (another digest) is refused; the old file is left."""
    import numpy as np
    import restamp_check

    from murus.retaining.collapse import CollapseError, _check_checkpoint

    state = np.arange(64, dtype=np.uint8)
    run = {"left": 10, "steps": 5, "updates": 7, "wall": 1.5, "digest": "d-old"}
    old = tmp_path / "k_r0.aaaa.npz"
    np.savez(old, model=state, run=np.array(json.dumps(run)))
    new = restamp_check.rekey_checkpoint(tmp_path, "k_r0", {"digest": "d-old", "code": "aaaa"},
                                         {"digest": "d-new", "code": "bbbb"})
    assert new == tmp_path / "k_r0.bbbb.npz" and old.exists()
    got = _check_checkpoint(new, "d-new")
    assert got == dict(run, digest="d-new")
    with np.load(new) as z:
        assert np.array_equal(z["model"], state)
    with pytest.raises(CollapseError, match="another run"):
        _check_checkpoint(new, "d-old")
    with pytest.raises(SystemExit, match="not the old engine's"):
        restamp_check.rekey_checkpoint(tmp_path, "k_r0", {"digest": "d-other", "code": "aaaa"},
                                       {"digest": "d-new", "code": "cccc"})
    assert not (tmp_path / "k_r0.cccc.npz").exists()


def test_restamp_check_refuses_an_old_tree_that_is_no_checkout(tmp_path, capsys):
    """``--old-tree`` must be a checkout of murus, and ``--checkpoint`` comes with
    ``--old-tree`` and ``--apply``: said in one line, exit code 2, nothing run."""
    import restamp_check

    assert restamp_check.main(["old", "t7_DSRW1_5_none_r0", "--old-tree", str(tmp_path)]) == 2
    assert "not a checkout of murus" in capsys.readouterr().err
    # a checkpoint is re-keyed only with the evidence of both engines, applied
    assert restamp_check.main(["old", "t7_DSRW1_5_none_r0", "--checkpoint", "k_r0"]) == 2
    assert "--checkpoint needs --old-tree and --apply" in capsys.readouterr().err


def _fake_study(st, kind, workers=None, out=None):
    """Stands for run_behaviour_study: one case file per call, kept across calls (a resume)."""
    cases = Path(out) / "cases"
    cases.mkdir(parents=True, exist_ok=True)
    n = len(list(cases.iterdir()))
    (cases / f"case{n}.json").write_text("{}")
    (Path(out) / "behaviour_factor.csv").write_text("wall\n")
    return n


def test_a_behaviour_study_of_another_engine_is_recomputed(tmp_path, monkeypatch):
    """The behaviour studies' folders (validation/retaining_behaviour.py) are keyed by the
    engine as the records are: stamped before their first case, resumed by the same engine,
    recomputed from scratch by another (left out with ``--cached``, and named), refused
    without a stamp (one line, exit 2), re-keyed by restamp_check with its evidence."""
    import restamp_check
    import retaining_behaviour as rb

    import murus.retaining.study as S

    monkeypatch.delenv("NUMBA_NUM_THREADS", raising=False)
    monkeypatch.setattr(rb, "CACHE", tmp_path)
    monkeypatch.setattr(rb, "studies", lambda: {"W1": None})
    monkeypatch.setattr(S, "run_behaviour_study", _fake_study)
    monkeypatch.setattr(rb, "engine_key", lambda: "E1")
    assert rb.run_all() == {"W1": 0}
    stamp = json.loads((tmp_path / "W1" / rb.STAMP).read_text())
    assert stamp[runcache.ENGINE_FIELD] == "E1"
    assert stamp[runcache.PLATFORM_FIELD] == runcache.platform()
    assert rb.run_all() == {"W1": 1}  # resumed: the first case kept
    assert rb.stamp_state(tmp_path / "W1", "E1") == ("current", "E1")
    assert "_resumed_on" not in json.loads((tmp_path / "W1" / rb.STAMP).read_text())
    here = runcache.platform
    other = dict(here(), cpu="another CPU")
    monkeypatch.setattr(runcache, "platform", lambda: other)
    assert rb.run_all() == {"W1": 2}  # resumed on another machine: named in the stamp
    assert json.loads((tmp_path / "W1" / rb.STAMP).read_text())["_resumed_on"] == [other]
    monkeypatch.setattr(runcache, "platform", here)

    monkeypatch.setattr(rb, "engine_key", lambda: "E2")
    stale = {}
    assert rb.run_all(cached=True, stale=stale) == {} and stale == {"W1": "E1"}
    assert len(list((tmp_path / "W1" / "cases").iterdir())) == 3  # --cached wrote nothing
    assert rb.run_all() == {"W1": 0}  # recomputed from scratch
    assert rb.stamp_state(tmp_path / "W1", "E2") == ("current", "E2")

    assert restamp_check.restamp_studies("E2", "E3", "W1 cut at 1 s: bit for bit") == ["W1"]
    stamp = json.loads((tmp_path / "W1" / rb.STAMP).read_text())
    assert stamp[runcache.ENGINE_FIELD] == "E3" and stamp["_restamped_from"] == "E2"
    assert restamp_check.restamp_studies("E2", "E4", "none") == []  # E2's stamp is gone

    (tmp_path / "W1" / rb.STAMP).unlink()
    with pytest.raises(SystemExit) as exc:
        rb.main(["--out", str(tmp_path / "section.md")])
    assert exc.value.code == 2 and not (tmp_path / "section.md").exists()
    assert len(list((tmp_path / "W1" / "cases").iterdir())) == 1  # nothing removed
