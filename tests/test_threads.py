"""Thread choice on a shared machine (murus.threads): the count from the load figures, the
governor's decisions from given timings, who decides, and DEM results that do not depend on
the split of a chunk nor on the thread count. No timings are asserted (benchmarks/)."""

import os
import subprocess
import sys

import numba
import numpy as np
import pytest

from murus import threads as T
from murus.dem import Joint, Model
from murus.dem import kernels as K
from murus.motion.synthetic import sine_pulse


@pytest.mark.parametrize(("cap", "cores", "others", "want"), [
    (2, 2, 0, 2),      # idle two-core machine: both threads
    (2, 2, 1, 1),      # one busy process on two cores: one thread (issue 15 item 6)
    (2, 2, 2, 1),
    (2, 2, 9.0, 1),    # heavy load: never below one
    (2, 2, 0.4, 2),    # a fraction rounds to the nearest thread
    (8, 8, 3, 5),      # the cores left free
    (4, 8, 1, 4),      # never above the cap
    (1, 8, 0, 1),
])
def test_choose_threads(cap, cores, others, want):
    assert T.choose_threads(cap, cores, others) == want


class Load:
    """Others running, as set by the test; the governor reads it at every part."""

    def __init__(self, x=0.0):
        self.x = x

    def __call__(self):
        return self.x


def _gov(load, **kw):
    return T.Governor(2, cores=2, load=load, load_every=0.0, **kw)


def test_governor_follows_the_load_with_hysteresis():
    load = Load(0.0)
    g = _gov(load, part=100)
    assert g.cur == 2 and g.next(1000) == (100, 2)  # idle: both threads, parts of 100 steps
    load.x = 1.0  # another process starts spinning
    assert g.next(1000) == (100, 2)  # smoothed over two readings: 0.5 rounds to 0
    assert g.next(1000) == (100, 1)  # 0.75: one thread
    assert g.next(1000) == (100, 1)
    load.x = 0.0  # it stops: 0.44 rounds to 0, both threads again
    assert g.next(1000) == (100, 2)
    assert g.switches == 2
    g = _gov(Load(3.0))
    assert g.cur == 1  # busy from the start


def test_governor_timing_overrides_the_load_after_two_probes():
    g = _gov(Load(0.0), base=2, longest=8, part=100)
    assert g.next(1000) == (100, 2)
    g.record(2, 100, 99.0)  # the first part may wake the threads: not counted
    for _ in range(2):
        assert g.next(1000) == (100, 2)
        g.record(2, 100, 1.0)  # 0.01 s per step on two threads
    assert g.next(1000) == (25, 1)  # probe: a quarter part on one thread
    g.record(1, 25, 0.175)  # 0.007 s per step: faster by more than 20 %
    assert g.cur == 2 and g.pending
    assert g.next(1000) == (25, 1)  # confirm at once
    g.record(1, 25, 0.175)
    assert g.cur == 1 and g.switches == 1
    for _ in range(2):
        assert g.next(1000) == (100, 1)
        g.record(1, 100, 0.7)
    assert g.next(1000) == (25, 2)  # probe of the many
    g.record(2, 25, 0.25)  # 0.01 s per step: slower, stay, probe half as often
    assert g.cur == 1 and g.interval == 4 and not g.pending
    g.record(1, 100, 0.7)
    g.record(1, 100, 0.7)
    assert g.next(1000) == (100, 1)  # 2 of 4 parts since the probe
    for _ in range(3):
        g.record(1, 100, 2.0)  # slowed down by more than 30 %: look again soon
    assert g.interval == 2
    assert g.next(10) == (10, 2)  # a probe of the many, cut to the steps left
    assert g.steps == {2: 325, 1: 750}


def test_governor_margin_and_a_single_probe_keep_the_choice():
    g = _gov(Load(0.0), base=1, part=100)
    g.record(2, 100, 5.0)
    g.record(2, 100, 1.0)
    assert g.next(100) == (25, 1)
    g.record(1, 25, 0.22)  # 12 % faster: inside the 20 % margin
    assert g.cur == 2 and not g.pending and g.interval == 2
    g.record(2, 100, 1.0)
    g.record(2, 100, 1.0)
    assert g.next(100) == (25, 1)
    g.record(1, 25, 0.15)  # one probe in favour...
    assert g.pending and g.next(100) == (25, 1)
    g.record(1, 25, 0.3)  # ...not confirmed
    assert g.cur == 2 and not g.pending


def test_fixed_governor_never_probes():
    g = T.Governor(2, fixed=True)
    for _ in range(50):
        assert g.next(500) == (500, 2)
        g.record(2, 500, 1.0)
    assert g.probes == 0 and g.steps == {2: 25000}


def test_who_decides(monkeypatch):
    monkeypatch.delenv("MURUS_THREADS", raising=False)
    monkeypatch.delenv("NUMBA_NUM_THREADS", raising=False)
    assert T.resolve() is None  # auto
    assert T.resolve(1) == 1
    assert T.resolve(10**6) == numba.config.NUMBA_NUM_THREADS
    for bad in (0, -1, 1.5):
        with pytest.raises(ValueError, match="threads must be an integer"):
            T.resolve(bad)
    monkeypatch.setenv("MURUS_THREADS", "1")
    assert T.resolve() == 1
    assert T.resolve(2) == min(2, numba.config.NUMBA_NUM_THREADS)  # the argument wins
    monkeypatch.setenv("MURUS_THREADS", "auto")
    assert T.resolve() is None
    for bad in ("two", "0"):
        monkeypatch.setenv("MURUS_THREADS", bad)
        with pytest.raises(ValueError, match="MURUS_THREADS"):
            T.resolve()


def test_an_explicit_numba_num_threads_is_kept():
    """NUMBA_NUM_THREADS set by the user: the count as it is set, a fixed governor. In a fresh
    interpreter: numba refuses a changed NUMBA_NUM_THREADS once its threads run, which they do
    in this one as soon as any test before has run a parallel kernel."""
    code = ("import numba\n"
            "from murus import threads as T\n"
            "assert T.resolve() == numba.get_num_threads() == 1, T.resolve()\n"
            "g = T.Governor.for_run()\n"
            "assert g.fixed and g.cap == 1, (g.fixed, g.cap)\n")
    env = {k: v for k, v in os.environ.items() if k != "MURUS_THREADS"}
    env["NUMBA_NUM_THREADS"] = "1"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 0, out.stderr


def test_wait_policy_set_unless_the_user_chose(monkeypatch):
    for k in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT", "KMP_BLOCKTIME"):
        monkeypatch.delenv(k, raising=False)
    T.configure_layer()
    import os
    assert os.environ["OMP_WAIT_POLICY"] == "passive"
    monkeypatch.setenv("OMP_WAIT_POLICY", "active")
    T.configure_layer()
    assert os.environ["OMP_WAIT_POLICY"] == "active"
    monkeypatch.delenv("OMP_WAIT_POLICY")
    monkeypatch.setenv("GOMP_SPINCOUNT", "1000")
    T.configure_layer()
    assert "OMP_WAIT_POLICY" not in os.environ


def test_others_running_reads_the_machine():
    x = T.others_running()
    assert x >= 0.0
    assert T.usable_cores() >= 1


def _stack():
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=25))
    m.add_rectangle(3.0, 0.2, center=(0.0, -0.1), kinematic="base")
    for i in range(3):
        m.add_rectangle(0.3, 0.6, center=(0.0, 0.3 + 0.6 * i))
    m.settle(tol=1e-8, threads=1)
    m.set_base_motion(sine_pulse(0.6 * 9.81, 3.0, cycles=2, dt=0.001, duration=0.5))
    m.P[K.P_PARMIN] = 0  # the governed path (and the parallel loop) for these few pairs
    return m


def test_dem_results_do_not_depend_on_parts_nor_threads(monkeypatch):
    ref = _stack()
    r1 = ref.run(0.2, every=20, threads=1)
    cap = numba.config.NUMBA_NUM_THREADS
    govs = []

    def many_parts(threads=None):
        govs.append(T.Governor(cap, start=cap, base=1, longest=2, part=7))
        return govs[-1]

    monkeypatch.setattr(T.Governor, "for_run", staticmethod(many_parts))
    m = _stack()
    r2 = m.run(0.2, every=20)
    assert r2.steps == r1.steps and sum(govs[-1].steps.values()) == r1.steps
    if cap > 1:
        assert govs[-1].probes > 0 and set(govs[-1].steps) == {1, cap}
    for a, b in zip([ref.bpos, ref.bang, ref.bvel, ref.bomg, ref.sf, ref.E, ref.C, ref.pairs],
                    [m.bpos, m.bang, m.bvel, m.bomg, m.sf, m.E, m.C, m.pairs], strict=True):
        assert np.array_equal(a, b)
    for k in r1.values:
        assert np.array_equal(r1[k], r2[k], equal_nan=True), k


def test_rocking_batch_threads_argument():
    from murus.rocking import RockingModel, restrained_wall_block, simulate_batch, sine_pulse

    models = [RockingModel(restrained_wall_block(f"block{i}")) for i in (1, 2)]
    motions = [sine_pulse(a * 9.81, 2.0) for a in (0.3, 0.6)]
    before = numba.get_num_threads()
    a = simulate_batch(models, motions, duration=3.0, threads=1)
    assert numba.get_num_threads() == before  # restored after the call
    b = simulate_batch(models, motions, duration=3.0)
    assert np.array_equal(a.raw, b.raw, equal_nan=True)
    assert np.nanmax(a.theta_max_over_alpha) > 0  # the pulses rock the blocks
