"""One rocking front end and one result protocol (issue 16, item 2): ``simulate`` dispatches on
the model, the rocking, Winkler and DEM results share one base, one declared summary table feeds
the kernels, the results, summary.json and the study Datasets, and a free vibration lasts as long
from the API as from a case file."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from murus.dem.engine import RunResult, SettleResult
from murus.results import Result
from murus.rocking import (
    ModelError,
    RigidBlock,
    RockingModel,
    WinklerBase,
    WinklerModel,
    WinklerResult,
    simulate,
    simulate_batch,
    simulate_winkler,
    sine_pulse,
)
from murus.rocking import kernels as K
from murus.rocking import winkler_kernels as WK
from murus.rocking.engine import SUMMARY_FIELDS, RockingResult
from murus.rocking.summary import (
    FREE_VIBRATION_DURATION,
    LIMIT_STATES,
    SUMMARY,
    WINKLER_SUMMARY,
)

BLOCK = RigidBlock(width=0.25, height=1.0, density=2000.0)
G = 9.81


def test_results_share_one_base():
    for cls in (RockingResult, WinklerResult, RunResult, SettleResult):
        assert issubclass(cls, Result)
    settle = SettleResult(converged=False, steps=3, ratio=0.5, message="not yet")
    assert settle.success is False and settle.status == "not converged"
    run = RunResult(t=np.zeros(1), status="interrupted")
    assert run.success is False and RunResult(t=np.zeros(1), status="completed").success


def test_simulate_dispatches_on_the_model():
    base = WinklerBase(5e7)
    pulse = sine_pulse(3.0 * G * math.tan(BLOCK.alpha), 2.0)
    a = simulate(WinklerModel(BLOCK, base), pulse, duration=1.0)
    b = simulate_winkler(BLOCK, base, pulse, duration=1.0)
    assert isinstance(a, WinklerResult) and a.success and a.status == 0 and a.message == "ok"
    np.testing.assert_array_equal(a.theta, b.theta)
    r = simulate(RockingModel(BLOCK), pulse, duration=1.0)
    assert isinstance(r, RockingResult) and r.success
    # the CLI's line comes from the result class, not from the keys of its summary
    assert "impacts" in r.headline() and "zero crossings" in a.headline()
    with pytest.raises(ModelError, match="rigid base"):
        simulate(WinklerModel(BLOCK, base), pulse, method="newmark", dt=1e-3)


def test_uplift_time_is_the_closed_form_under_every_name():
    """A sine pulse of amplitude 2 g tan(alpha) lifts the block when it first reaches the uplift
    acceleration g tan(alpha) (Housner 1963): at t0 + asin(1/2) / (2 pi f). The same time under
    every name (attribute, deprecated alias, summary.json keys, batch field)."""
    t0 = 0.3
    exc = sine_pulse(2.0 * G * math.tan(BLOCK.alpha), 1.0, t0=t0)
    r = simulate(BLOCK, exc, duration=1.0)
    s = r.summary()
    t_up = t0 + math.asin(0.5) / (2.0 * math.pi * 1.0)
    assert r.t_uplift == pytest.approx(t_up, abs=1e-9)
    with pytest.warns(DeprecationWarning):
        assert r.uplift_time == r.t_uplift
    assert s["t_uplift"] == s["uplift_time"] == r.t_uplift
    assert s["n_impacts"] == s["impacts"] == r.n_impacts
    assert s["theta_pos"] == r.theta_pos and s["status"] == r.message == "ok"
    br = simulate_batch([BLOCK], [exc], duration=1.0, threads=1)
    assert br["t_uplift"][0, 0] == br["uplift_time"][0, 0] == r.t_uplift


def test_one_summary_table():
    assert len(SUMMARY) == K.S_SIZE and len(WINKLER_SUMMARY) == WK.S_SIZE
    assert [SUMMARY_FIELDS[q.name] for q in SUMMARY] == list(range(K.S_SIZE))
    assert all(q.units and q.description for q in SUMMARY + WINKLER_SUMMARY)
    from murus.studies.sweep import SUMMARY_VARS

    assert [v[:3] for v in SUMMARY_VARS] == [(q.name, i, q.units) for i, q in enumerate(SUMMARY)
                                             if q.dataset]
    from murus.studies.fragility import LIMIT_STATES as FRAG
    from murus.studies.spectrum import LIMIT_STATES as SPEC

    assert SPEC == LIMIT_STATES == {k: v for k, v in FRAG.items() if v is not None}


def test_free_vibration_lasts_as_long_from_the_api_as_from_a_case_file(tmp_path):
    from murus.rocking.case import build, load_case

    r = simulate(BLOCK, theta0_over_alpha=0.2, out_dt=0.5)
    assert r.t[-1] == FREE_VIBRATION_DURATION
    case = tmp_path / "free.toml"
    case.write_text("[body]\nwidth = 0.25\nheight = 1.0\ndensity = 2000.0\n"
                    "[motion]\ntype = \"free\"\ntheta0_over_alpha = 0.2\n")
    cfg, path, text = load_case(case)
    _, _, kwargs = build(cfg, path, text)
    assert kwargs["duration"] == FREE_VIBRATION_DURATION


def test_deprecated_winkler_alias():
    r = simulate_winkler(BLOCK, WinklerBase(5e7), theta0_over_alpha=0.5, duration=0.8,
                         out_dt=1e-2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        t = r.t_first_crossing
    with pytest.warns(DeprecationWarning):
        assert r.first_crossing == t
    assert r.summary()["n_crossings"] == r.summary()["crossings"] == r.crossings.shape[0]
