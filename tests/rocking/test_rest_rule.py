"""The end of a cascade of impacts (issue 15, item 7): the wall comes to rest at the
accumulation point of the impact times, never before, and only when the ground cannot lift it;
a run whose integration stops early says so (item 2)."""

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from murus import G
from murus.cli import app
from murus.rocking import (
    Constant,
    Damper,
    Record,
    RockingModel,
    SpringBed,
    Tie,
    restrained_wall_block,
    simulate,
)
from murus.rocking.design import reference_damping, tie_design

BLOCK = restrained_wall_block("block2")
E = 0.8


def accumulation_time(model, w0, gamma):
    """Closed form of the rest time of the linearised block (Housner 1963): launched from
    ``theta = 0`` with ``w0`` about pivot +1 under a constant ground acceleration
    ``gamma * alpha * g``, each flight about pivot ``s`` lasts ``T = (2/p) atanh(w / (p |c|))``
    with ``c = s alpha - gamma alpha`` (``theta'' = p^2 (theta - c)``), returns with ``w``, and
    the impact multiplies ``w`` by ``e``: the rest time is the sum of the series."""
    p, a = model.p, model.body.alpha
    t, s, w = 0.0, 1.0, w0
    for _ in range(5000):
        t += 2.0 / p * math.atanh(w / (p * abs(s * a - gamma * a)))
        w *= E
        s = -s
    return t


def linear(rest_tol=1e-3):
    return RockingModel(BLOCK, Constant(E), linearised=True, rest_tol=rest_tol)


@pytest.mark.parametrize("gamma", [0.0, 0.4])
def test_rest_at_the_accumulation_point(gamma):
    mdl = linear()
    w0 = 0.3 * mdl.p * BLOCK.alpha
    exact = accumulation_time(mdl, w0, gamma)
    motion = Record(0.01, np.full(2001, gamma * BLOCK.alpha * G)) if gamma else None
    res = simulate(mdl, motion, omega0=w0, duration=10.0)
    assert res.success
    # the cascade was summed from the first impact below 1e-3 p alpha, not integrated on
    assert res.n_impacts == math.ceil(math.log(1e-3 / 0.3) / math.log(E))
    t_rest = res.uplift_intervals[0, 1]
    # the summed tail (several ms) is exact to the integration error of the integrated part
    assert t_rest == pytest.approx(exact, abs=1e-7)
    last = res.impacts[-1, 0]
    assert exact - last > 1e-3  # what putting the wall at rest at the last impact would miss
    # the tight reference, integrated impact by impact down to 1e-12 p alpha
    ref = simulate(linear(1e-12), motion, omega0=w0, duration=10.0, rtol=1e-12)
    assert ref.uplift_intervals[0, 1] == pytest.approx(exact, abs=1e-10)
    assert ref.n_impacts > 100


def test_no_rest_while_the_ground_lifts_the_wall_during_the_cascade():
    """The ground crosses the uplift threshold 4 ms before the accumulation point: the cascade is
    integrated on and the wall lifts off from it, as in the tight reference (a wall put at rest
    at the first impact below 1e-3 p alpha lifts off from rest: theta_max 0.3 % lower)."""
    mdl = linear()
    w0 = 0.1 * mdl.p * BLOCK.alpha
    gamma = 0.4
    t_inf = accumulation_time(mdl, w0, gamma)
    dt = 1e-3
    t = np.arange(0.0, 12.0, dt)
    acc = np.where(t < t_inf - 4e-3, gamma, 0.0) * BLOCK.alpha * G
    acc = np.where((t >= t_inf - 4e-3) & (t < t_inf + 0.4), 1.4 * BLOCK.alpha * G, acc)
    rec = Record(dt, acc)
    res = simulate(mdl, rec, omega0=w0, duration=10.0)
    ref = simulate(linear(1e-12), rec, omega0=w0, duration=10.0, rtol=1e-12)
    assert res.success and ref.success
    # one uplift interval: the wall never came to rest between the two excursions
    assert res.uplift_intervals.shape[0] == ref.uplift_intervals.shape[0] == 1
    assert res.uplift_intervals[0, 1] == pytest.approx(ref.uplift_intervals[0, 1], abs=1e-6)
    assert res.theta_max > 1.5 * w0 ** 2 / (2 * mdl.p ** 2 * BLOCK.alpha)  # the second one
    assert res.theta_max == pytest.approx(ref.theta_max, rel=1e-6)


def _models(block, rest_tol):
    k_d = tie_design(block).K_d
    c = 0.05 * reference_damping(block, 10.186)
    return {
        "free": RockingModel(block, rest_tol=rest_tol),
        "tie": RockingModel(block, tie=Tie(k_d, block.height), rest_tol=rest_tol),
        "damper": RockingModel(block, damper=Damper(c, block.height), rest_tol=rest_tol),
        "one-sided": RockingModel(block, tie=Tie(k_d, block.height),
                                  damper=Damper(c, block.height),
                                  transverse_walls=SpringBed(math.inf, block.height),
                                  motion_sides="one", rest_tol=rest_tol),
    }


def _significant(res):
    return int(np.sum(np.abs(res.impacts[:, 1]) >= 1e-2 * res.p * res.alpha))


def test_default_agrees_with_the_accurate_solver_on_real_records():
    """FEMA P695 far-field records at 1.5 g tan(alpha): where the reference (rtol 1e-12,
    rest_tol 1e-9) is not chaotic (it moves by < 0.1 % under the record x (1 + 1e-6) and
    rtol 1e-11), the default agrees within 0.1 % on theta_max, and on the count of significant
    impacts (|theta'| >= 1e-2 p alpha before the impact) where that count is stable too."""
    from murus.motion import suite

    block = restrained_wall_block("block1")
    thr = G * math.tan(block.alpha)
    recs = [m.sliced(0.0, 10.0) for m in suite("farfield")[0:8:2]]
    default = _models(block, 1e-3)
    tight = _models(block, 1e-9)
    stable = 0
    for r in recs:
        a = r.acc * (1.5 * thr / r.pga)
        for name in default:
            d = simulate(default[name], Record(r.dt, a), duration=13.0, out_dt=0.1)
            ref = simulate(tight[name], Record(r.dt, a), duration=13.0, rtol=1e-12, out_dt=0.1)
            pert = simulate(tight[name], Record(r.dt, a * (1 + 1e-6)), duration=13.0,
                            rtol=1e-12, out_dt=0.1)
            loose = simulate(tight[name], Record(r.dt, a), duration=13.0, rtol=1e-11,
                             out_dt=0.1)
            assert d.success and ref.success
            th = ref.theta_max
            if (th == 0.0 or ref.overturned or abs(pert.theta_max / th - 1) >= 1e-3
                    or abs(loose.theta_max / th - 1) >= 1e-3):
                continue
            stable += 1
            assert d.theta_max == pytest.approx(th, rel=1e-3), (r.name, name)
            n = _significant(ref)
            if n == _significant(pert) == _significant(loose):  # the count itself is stable
                assert _significant(d) == n, (r.name, name)
    assert stable >= 8


def test_rest_tol_zero_reports_the_underflow(tmp_path):
    """Without a rest rule the cascade is a Zeno point: the integration stops, the result says
    so, and ``murus run`` writes its outputs with that status and exits non-zero."""
    mdl = RockingModel(BLOCK, Constant(0.7), rest_tol=0.0)
    res = simulate(mdl, theta0_over_alpha=0.5, duration=20.0)
    assert not res.success
    assert res.message.startswith("step size underflow")
    assert "rest_tol = 0" in res.message
    assert res.summary()["status"] != "ok"
    case = """
[body]
width = 0.3
height = 3.0
thickness = 1.0
density = 2000.0
[restitution]
law = "constant"
value = 0.7
[motion]
type = "free"
theta0_over_alpha = 0.5
[solver]
duration = 20.0
rest_tol = 0.0
"""
    (tmp_path / "case.toml").write_text(case)
    r = CliRunner().invoke(app, ["run", str(tmp_path / "case.toml"), "--out",
                                 str(tmp_path / "out"), "--no-figure"])
    assert r.exit_code == 1  # ran, did not succeed (2 is for bad input)
    assert "step size underflow" in r.output and len(r.output.strip().splitlines()) == 1
    s = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert s["status"] != "ok"
    # the default rule ends the same cascade: success
    (tmp_path / "case.toml").write_text(case.replace("rest_tol = 0.0", "rest_tol = 1e-3"))
    r = CliRunner().invoke(app, ["run", str(tmp_path / "case.toml"), "--out",
                                 str(tmp_path / "out2"), "--no-figure"])
    assert r.exit_code == 0, r.output
    assert json.loads((tmp_path / "out2" / "summary.json").read_text())["status"] == "ok"


def test_summary_states_the_method_and_what_to_trust_it_for():
    nm = simulate(BLOCK, theta0_over_alpha=0.5, method="newmark", dt=1e-3, duration=1.0)
    ev = simulate(BLOCK, theta0_over_alpha=0.5, duration=1.0)
    assert nm.summary()["method"] == "newmark" and ev.summary()["method"] == "event"
    assert "method = 'event'" in nm.summary()["method_note"]
    assert "verdicts" in ev.summary()["method_note"]


def test_rest_at_the_accumulation_point_against_rigid_transverse_walls():
    """One-sided motion: every bounce about pivot +1 ends with an impact into the walls and one
    out of them, so the launch speed falls by ``e^2`` per bounce and the rest time is
    ``sum_n (2/p) atanh(e^(2n) w0 / (p alpha))`` (linearised, no ground motion)."""
    walls = {"transverse_walls": SpringBed(math.inf, BLOCK.height), "motion_sides": "one"}
    mdl = RockingModel(BLOCK, Constant(E), linearised=True, **walls)
    p, a = mdl.p, BLOCK.alpha
    w0 = 0.3 * p * a
    exact = sum(2.0 / p * math.atanh(E ** (2 * n) * w0 / (p * a)) for n in range(3000))
    res = simulate(mdl, None, omega0=w0, duration=10.0)
    assert res.success
    assert res.n_impacts == math.ceil(math.log(1e-3 / 0.3) / math.log(E * E))
    assert res.uplift_intervals[0, 1] == pytest.approx(exact, abs=1e-7)
    assert exact - res.impacts[-1, 0] > 1e-3
    tight = RockingModel(BLOCK, Constant(E), linearised=True, rest_tol=1e-12, **walls)
    ref = simulate(tight, None, omega0=w0, duration=10.0, rtol=1e-12)
    assert ref.uplift_intervals[0, 1] == pytest.approx(exact, abs=1e-10)


def test_rest_tol_on_a_winkler_base_is_refused(tmp_path):
    case = """
[body]
width = 0.72
height = 1.80
thickness = 0.138
top_mass = 5000.0
[base]
model = "winkler"
stiffness = 1.0e9
[motion]
type = "free"
theta0_over_alpha = 0.5
[solver]
duration = 2.0
rest_tol = 1e-3
"""
    (tmp_path / "case.toml").write_text(case)
    r = CliRunner().invoke(app, ["run", str(tmp_path / "case.toml"), "--out",
                                 str(tmp_path / "out"), "--no-figure"])
    assert r.exit_code == 2
    assert "line 15: [solver.rest_tol] a Winkler base has no rest rule" in r.output
    assert not (tmp_path / "out").exists()


def test_elastic_impacts_with_a_damper_come_to_rest():
    """e = 1 with a damper (EURODYN (2020), Figures 7-8, the validation's model): the bounce times
    form a divergent series (each bounce loses a vanishing fraction of its speed to the damper), so
    the cascade has no accumulation point; the body is put at rest once its speed after an
    impact is below rest_tol p alpha, as before the accumulation rule (334 impacts in 10 s at
    5 % c_d in VALIDATION.md; the accumulation rule alone gave 22.9 million)."""
    from murus.rocking import Constant, Damper, RockingModel, simulate
    from murus.rocking.body import restrained_wall_block
    from murus.rocking.design import reference_damping

    b = restrained_wall_block("block1")
    c = 0.05 * reference_damping(b, 10.186)
    r = simulate(RockingModel(b, Constant(1.0), damper=Damper(c, b.height)),
                 theta0_over_alpha=0.9, duration=10.0, out_dt=0.01)
    assert r.success
    assert r.n_impacts < 1000
    assert r.theta[-1] == 0.0 and r.omega[-1] == 0.0
