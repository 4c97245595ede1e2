"""Structure of the continuum kernels and the engine's inputs: kernels take at most 12
arguments, the kernel structures are the model's arrays, the base follows a GroundMotion in both
directions, and the parallel loops give the serial loops' numbers bit for bit."""

from __future__ import annotations

import inspect
import math

import numpy as np
from continuum_inputs import rect_mesh, sides
from numba.core.registry import CPUDispatcher

from murus.continuum import ContinuumModel, Elastic, MohrCoulomb
from murus.continuum import _kdata as kd
from murus.continuum import kernels as K
from murus.motion.core import GroundMotion


def test_kernels_take_at_most_twelve_arguments():
    found = {n: d for n, d in vars(K).items()
             if isinstance(d, CPUDispatcher) and d.py_func.__module__ == K.__name__}
    assert "run_chunk" in found and "_zone" in found and len(found) >= 10
    too_long = {n: len(inspect.signature(d.py_func).parameters) for n, d in found.items()
                if len(inspect.signature(d.py_func).parameters) > 12}
    assert too_long == {}


def test_structures_are_model_arrays():
    xy, zones = rect_mesh(2, 2, 1.0, 1.0)
    m = ContinuumModel(xy, zones, Elastic(density=2000.0, E=1e7, nu=0.3))
    assert len(set(kd.STATE_ARRAYS)) == len(kd.STATE_ARRAYS)
    for name in kd.STATE_ARRAYS:
        a = getattr(m, name)
        assert isinstance(a, np.ndarray) and a.flags.c_contiguous, name
    assert m.state_bytes() == sum(getattr(m, f).nbytes for f in kd.STATE_ARRAYS)


def test_base_follows_a_ground_motion_in_both_directions():
    """A sine acceleration ``a(t) = A sin(2 pi t / T)`` from rest moves the base by
    ``A T² / (2 pi)`` over one period (vertical: half of it with acc_v = a / 2); the record is
    the sine sampled at 0.01 s (interpolation error ~ (2 pi dt)² / 8 = 5e-4)."""
    A, T, dts = 0.5, 1.0, 0.01
    t = np.arange(0.0, T + dts / 2, dts)
    a = A * np.sin(2 * np.pi * t / T)
    gm = GroundMotion(dt=dts, acc=a, acc_v=0.5 * a)
    xy, zones = rect_mesh(2, 2, 1.0, 1.0)
    m = ContinuumModel(xy, zones, Elastic(density=2000.0, E=1e7, nu=0.3), gravity=0.0)
    left, right, bottom, top = sides(xy)
    m.set_base(bottom)
    g = int(np.flatnonzero(bottom)[0])
    res = m.run(T, motion=gm, monitors={"ux": ("gp", g, "ux"), "uy": ("gp", g, "uy")})
    assert res.success
    want = A * T * T / (2 * np.pi)
    assert abs(m.time - T) < m.dt
    assert res["ux"][-1] == m.gdisp[g, 0]  # the monitor samples the end state
    # the model time ends within one step of T: compare at the model time
    tt = m.time
    wx = A * T / (2 * np.pi) * tt - A * (T / (2 * np.pi)) ** 2 * math.sin(2 * np.pi * tt / T)
    assert abs(m.gdisp[g, 0] - wx) < 1e-3 * want
    assert abs(m.gdisp[g, 1] - 0.5 * wx) < 1e-3 * want


def test_parallel_loops_give_the_serial_numbers():
    """Zone loop and gridpoint loop as numba parallel loops (prange) against the serial ones:
    each zone writes its own rows, each gridpoint gathers its corners in a fixed order and the
    partial sums are combined in a fixed block order, so the state is identical bit for bit."""
    xy, zones = rect_mesh(12, 8, 12.0, 8.0)
    out = []
    for parmin in (1e9, 0.0):
        m = ContinuumModel(xy, zones, MohrCoulomb(density=2000.0, E=1e7, nu=0.3,
                                                  friction_deg=25.0, cohesion=3e3,
                                                  dilation_deg=5.0))
        left, right, bottom, top = sides(xy)
        m.fix(left | right, x=True, y=False)
        m.set_base(bottom)
        m.P[K.P_PARMIN] = parmin
        m.settle(tol=1e-4, max_steps=2000)
        m.run(0.3, velocity=lambda t: 0.4 * np.sin(12.0 * t), xi=0.05, freq=2.0)
        out.append(m)
    a, b = out
    assert (a.zstate & K.ST_SHEAR_PAST).any()  # plastic flow happened
    for name in kd.STATE_ARRAYS:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert np.array_equal(a.E, b.E)
