"""Collapse protocol and behaviour factor (murus.retaining.collapse) on a cheap mock-up.

The mock-up of Savalle et al. (2022), §3 with H/B = 1.3 and 11 mm courses (four courses and a top
course); the joint stiffness of Savalle et al. (2022), Table 1 is scaled by 1e-4 (2.6e8 Pa/m: the
joint closure under the wall's weight, 2.5e-6 m, is 0.1 % of the 5 % H collapse threshold) and the
ramp reaches A_pseudo at 0.5 s instead of 2.5 s, so that each run takes a few seconds. (At 1e-5 the
crest stone presses 1.7 mm into the backstop at collapse, 10 % of its thickness: the engine stops
such a run as an interpenetration, issue 15.)
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from murus.retaining.collapse import (
    BehaviourTable,
    CollapseError,
    behaviour_factor,
    collapse_run,
    pseudo_static_resistance,
    ramp_rate,
)
from murus.retaining.geometry import preset

KW = dict(stiffness_scale=1e-4, t_pseudo=0.5, backfill="thrust")


@pytest.fixture(scope="module")
def wall():
    return preset("mockup-1.3", stone_height=0.011)


@pytest.fixture(scope="module")
def a_pseudo(wall):
    return pseudo_static_resistance(wall)


@pytest.fixture(scope="module")
def strong(wall, a_pseudo):
    return collapse_run(wall, 5.0, A_pseudo=a_pseudo, t_max=2.0, **KW)


def test_strong_ramp_collapses(strong, wall, a_pseudo):
    r = strong
    assert r.collapsed and r.status == "stopped"
    assert r.threshold == pytest.approx(0.05 * wall.height)  # mock-ups: 5 % H (§3.1)
    assert r.A_rate == pytest.approx(ramp_rate(a_pseudo, 0.5))
    assert r.A_col == pytest.approx(r.A_rate * r.t_col)
    # dynamic capacity above the pseudo-static one (Savalle et al. (2022), Table 8: r > 1)
    assert 1.0 < r.A_col / a_pseudo < 3.0
    # d_top crosses the threshold at t_col
    assert r.d_top[-1] > r.threshold
    assert np.interp(r.t_col, r.t, r.d_top) == pytest.approx(r.threshold, rel=1e-6)
    # the thrust followed the input: kh = a / g at the samples
    i = len(r.t) // 2
    assert r.kh[i] == pytest.approx(r.acc[i] / 9.81, abs=0.02 * abs(r.acc).max() / 9.81)
    s = r.summary()
    assert s["A_peak"] == pytest.approx(0.6 * r.A_col)
    assert s["r"] == pytest.approx(0.6 * r.A_col / a_pseudo)
    assert len(r.polygons) == len(r.displacement)


def test_weak_ramp_does_not_collapse(wall, a_pseudo):
    # the same slope stopped when the envelope reaches A_pseudo / 2
    r = collapse_run(wall, 5.0, A_pseudo=a_pseudo, t_max=0.25, **KW)
    assert not r.collapsed and r.status == "completed"
    assert np.isnan(r.A_col)
    assert r.d_top.max() < 0.25 * r.threshold


def test_A_col_decreases_with_the_thrust(wall, a_pseudo, strong):
    # more earth thrust, earlier collapse: A_col(no backfill) > A_col(Annex E) > A_col(2 x)
    free = collapse_run(wall, 5.0, A_pseudo=a_pseudo, t_max=2.0, thrust_scale=0.0, **KW)
    double = collapse_run(wall, 5.0, A_pseudo=a_pseudo, t_max=2.0, thrust_scale=2.0, **KW)
    assert free.A_col > strong.A_col > double.A_col


def test_behaviour_table_and_writers(wall, a_pseudo, strong, tmp_path):
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=1) as ex:
        tab = behaviour_factor(wall, [5.0], ["none"], executor=ex, t_max=2.0, **KW)
    assert isinstance(tab, BehaviourTable)
    row = tab.rows[0]
    assert row["A_col_m_s2"] == pytest.approx(strong.A_col, rel=1e-9)  # deterministic
    assert row["r"] == pytest.approx(0.6 * strong.A_col / a_pseudo)
    tab.to_csv(tmp_path / "t.csv")
    text = (tmp_path / "t.csv").read_text().splitlines()
    assert text[0].startswith("wall,frequency_Hz,vertical,t_col_s,A_col_m_s2")
    md = tab.to_markdown()
    assert "A_peak = 0.6 A_col" in md and "r = A_peak/A_pseudo" in md


def test_errors(wall):
    with pytest.raises(CollapseError, match="vertical mode"):
        collapse_run(wall, 5.0, "sideways", **KW)
    with pytest.raises(CollapseError, match="a_peak"):
        collapse_run(wall, 5.0, signal="S1", **KW)
    with pytest.raises(CollapseError, match="frequency"):
        collapse_run(wall, -1.0, **KW)
    for bad in (0, -2, 1.5, True, "fast"):
        with pytest.raises(CollapseError, match="subcycle must be"):
            collapse_run(wall, 5.0, backfill="continuum", subcycle=bad)
    with pytest.raises(CollapseError, match="only with the continuum backfill"):
        collapse_run(wall, 5.0, backfill="thrust", subcycle="auto")
    # refused above x 1e-1 with the corner rule "follow" (VALIDATION.md, Subcycling), before
    # anything is built; n = 1 is off; the default rule "shrink" subcycles at any stiffness
    nowhere = "/no/such/folder/ck.npz"  # the next check, also before anything is built
    follow = {"corner_share": "follow"}
    for scale in (1.0, 0.2):
        with pytest.raises(CollapseError, match="'follow': not validated above x 0.1"):
            collapse_run(wall, 5.0, backfill="continuum", subcycle="auto",
                         stiffness_scale=scale, backfill_options=follow, checkpoint=nowhere)
    for n, scale, opts in ((1, 1.0, follow), ("auto", 0.1, follow), ("auto", 1.0, None),
                           (3, 1.0, {"corner_share": "shrink"})):
        with pytest.raises(CollapseError, match="does not exist"):
            collapse_run(wall, 5.0, backfill="continuum", subcycle=n, stiffness_scale=scale,
                         backfill_options=opts, checkpoint=nowhere)



def test_the_refusal_assumes_the_backfills_default_corner_rule():
    """``subcycle_refused`` (and ``collapse_run``, which passes it the corner rule of
    ``backfill_options`` or this default) decides on the rule the continuum backfill and its
    interface run when none is given: the three defaults are one rule, so that a change of the
    backfill's default cannot leave the refusal judging another rule than the one run (all
    read ``murus.continuum.DEFAULT_CORNER_SHARE``)."""
    import inspect

    from murus.continuum import DEFAULT_CORNER_SHARE
    from murus.continuum.interface import Interface
    from murus.retaining.collapse import subcycle_refused
    from murus.retaining.continuum_backfill import ContinuumBackfill

    defaults = {inspect.signature(f).parameters["corner_share"].default
                for f in (Interface.__init__, ContinuumBackfill.__init__, subcycle_refused)}
    assert defaults == {DEFAULT_CORNER_SHARE} == {"shrink"}
    assert subcycle_refused("auto", 1.0) is None


def test_cli_collapse_and_errors(tmp_path):
    from murus.cli import app

    runner = CliRunner()
    out = tmp_path / "run"
    args = ["retaining", "collapse", "--preset", "mockup-1.3", "--stone-height", "0.011",
            "--stiffness-scale", "1e-5", "--t-max", "0.3", "--frequency", "5",
            "--backfill", "thrust", "--out", str(out)]
    res = runner.invoke(app, args)
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    assert s["collapsed"] is False and s["A_col"] is None and s["wall"].startswith("mockup")
    hist = np.loadtxt(out / "d_top.csv", delimiter=",", skiprows=1)
    assert hist.shape[1] == 6 and hist[-1, 0] == pytest.approx(0.3, abs=0.011)
    assert (out / "collapse.png").stat().st_size > 1000
    # errors: one line, exit code 2, nothing written
    bad = tmp_path / "bad"
    res = runner.invoke(app, ["retaining", "collapse", "--preset", "mockup-1.3", "--out",
                              str(bad)])
    assert res.exit_code == 2
    assert "courses are unknown" in res.output and len(res.output.strip().splitlines()) == 1
    assert not bad.exists()
    res = runner.invoke(app, ["retaining", "behaviour-factor", "--preset", "DSRW1",
                              "--frequencies", "5,x", "--out", str(bad)])
    assert res.exit_code == 2 and "--frequencies" in res.output
    assert not bad.exists()
    assert math.isfinite(1.0)


def test_peak_ratio_check_runs_s1_with_the_same_slope(wall, a_pseudo, strong):
    from murus.retaining.collapse import peak_ratio_check

    checks = peak_ratio_check(wall, 5.0, strong.A_col, (0.6, 1.2), A_pseudo=a_pseudo,
                              tail=0.2, **KW)
    low, high = checks[0.6], checks[1.2]
    for ratio, c in checks.items():
        assert c.signal == "S1" and c.a_peak == pytest.approx(ratio * strong.A_col)
        assert c.A_rate == pytest.approx(strong.A_rate)
    # Savalle et al. (2022), Figure 14: stable at 0.6 A_col; a peak above A_col collapses
    assert low.stable and low.t_end == pytest.approx(3 * low.a_peak / low.A_rate + 0.2, abs=2e-3)
    assert high.collapsed


def test_failure_mode_closed_form():
    from murus.retaining.collapse import failure_mode

    z = 0.09  # top stone centroid above the toe [m]
    # rigid toppling about the toe: d_top = theta z
    assert failure_mode(0.05 * z, 0.05, z) == "T"
    # rigid toppling about a joint at z_j = 0.05: d_top = theta (z - z_j), theta z > d_top
    assert failure_mode(0.05 * (z - 0.05), 0.05, z) == "T"
    # pure sliding: no rotation
    assert failure_mode(0.0046, 0.0, z) == "S"
    # sliding with a small tilt (rotation share 0.4 < 0.5)
    assert failure_mode(0.0046, 0.4 * 0.0046 / z, z) == "S"
    # tipping back into the slope is not toppling out of it
    assert failure_mode(0.0046, -0.05, z) == "S"
    assert failure_mode(-0.001, 0.05, z) == ""


def test_damping_frame_is_irrelevant_without_damping(wall, a_pseudo):
    # identity: with xi = 0 the frame of the damping cannot matter (same history bit for bit);
    # with xi > 0 it is recorded and changes the response
    kw = dict(KW, A_pseudo=a_pseudo, t_max=0.6)
    base = collapse_run(wall, 5.0, xi=0.0, damping_frame="base", **kw)
    absolute = collapse_run(wall, 5.0, xi=0.0, damping_frame="absolute", **kw)
    np.testing.assert_array_equal(base.d_top, absolute.d_top)
    damped = collapse_run(wall, 5.0, xi=0.5, damping_frame="absolute", **kw)
    assert damped.options["damping_frame"] == "absolute"
    assert base.options["damping_frame"] == "base"
    assert not np.array_equal(damped.d_top, base.d_top)
    with pytest.raises(CollapseError, match="damping_frame"):
        collapse_run(wall, 5.0, damping_frame="relative", **kw)


def test_mechanisms_follow_the_limit_analysis_on_a_fast_ramp(wall, a_pseudo, strong):
    # on a fast ramp (A_pseudo reached at 0.5 s) the DEM wall fails by the mechanism that
    # governs the pseudo-static limit analysis: sliding of the squat mock-up (H/B = 1.3),
    # overturning of the slender one (H/B = 3.3); the modes of Savalle et al. (2022), Table 3 (S, T)
    # in the experiment and in UDEC. (On the slow 10 Hz ramp of §3 the murus mock-ups all slide:
    # VALIDATION.md, dynamic collapse.)
    from murus.retaining.pseudostatic import critical_acceleration

    assert critical_acceleration(wall).mode == "sliding" and strong.mode == "S"
    slender = preset("mockup-3.3", stone_height=0.0112)
    assert critical_acceleration(slender).mode == "overturning"
    r = collapse_run(slender, 5.0, t_max=2.0, **KW)
    assert r.collapsed and r.mode == "T"
    assert r.rotation.size == len(r.polygons)


def test_table4_derived_values():
    # tests/data/retaining/savalle2022_table4.csv: UDEC A_fail = 3.2 m/s² (experiment, Table 3)
    # times (1 + error); 45 deg reproduces Table 3's 2.6 m/s² to its printed digits
    import csv
    from pathlib import Path

    path = Path(__file__).parents[1] / "data" / "retaining" / "savalle2022_table4.csv"
    with open(path) as fh:
        rows = list(csv.DictReader(ln for ln in fh if not ln.startswith("#")))
    assert [float(r["backfill_friction_deg"]) for r in rows] == [45.0, 50.0, 55.0]
    for r in rows:
        assert float(r["num_A_fail_m_s2"]) == pytest.approx(
            3.2 * (1 + float(r["error_pct"]) / 100), abs=0.006)
    assert float(rows[0]["num_A_fail_m_s2"]) == pytest.approx(2.6, abs=0.05)


def test_ensemble_perturbs_the_time_step_and_takes_the_median(wall, a_pseudo, strong):
    """Issue 18, item 6: the nominal run of an ensemble is the single run bit for bit (so the
    shipped command lies within the stated range), the others have their time step scaled by
    DT_FACTORS (the stable step is proportional to the safety factor), and the median and
    range are those of the runs' A_col."""
    from murus.retaining.collapse import DT_FACTORS, XI_SAVALLE, collapse_ensemble

    ens = collapse_ensemble(wall, 5.0, runs=3, A_pseudo=a_pseudo, t_max=2.0, **KW)
    assert ens.factors == DT_FACTORS[:3]
    nom = ens.nominal
    assert np.array_equal(nom.d_top, strong.d_top) and nom.A_col == strong.A_col
    for f, r in zip(ens.factors, ens.results, strict=True):
        assert r.dt == pytest.approx(f * nom.dt, rel=1e-12)
        assert r.collapsed
    a = sorted(r.A_col for r in ens.results)
    assert ens.median == a[1] and ens.range == (a[0], a[2])
    s = ens.summary()
    assert s["A_col"] == nom.A_col and s["A_col_median"] == a[1]
    assert [x["dt_factor"] for x in s["runs"]] == list(DT_FACTORS[:3])
    # the damping of Savalle et al. (2022), §3.1: 5 % of critical, unless given
    assert nom.options["xi"] == XI_SAVALLE == 0.05
    with pytest.raises(CollapseError, match="runs"):
        collapse_ensemble(wall, 5.0, runs=len(DT_FACTORS) + 1, **KW)
    with pytest.raises(CollapseError, match="xi"):
        collapse_run(wall, 5.0, xi=-0.1, **KW)


def test_cli_runs_option(tmp_path):
    from murus.cli import app

    runner = CliRunner()
    out = tmp_path / "run"
    args = ["retaining", "collapse", "--preset", "mockup-1.3", "--stone-height", "0.011",
            "--stiffness-scale", "1e-4", "--t-max", "0.2", "--frequency", "5",
            "--backfill", "thrust", "--out", str(out)]
    res = runner.invoke(app, args + ["--runs", "2"])
    assert res.exit_code == 0, res.output
    s = json.loads((out / "summary.json").read_text())
    assert [r["dt_factor"] for r in s["runs"]] == [1.0, 0.95]
    assert s["A_col_median"] is None and "median A_col" in res.output  # no collapse: inf
    for bad in ("0", "6"):
        res = runner.invoke(app, args[:-1] + [str(tmp_path / "bad"), "--runs", bad])
        assert res.exit_code == 2 and "--runs" in res.output
        assert len(res.output.strip().splitlines()) == 1 and not (tmp_path / "bad").exists()
