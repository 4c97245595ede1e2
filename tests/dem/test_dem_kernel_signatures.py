"""The DEM kernels take named structures (issue 16, item 1): no numba kernel of
:mod:`murus.dem` takes more than 12 arguments, and the structures of :mod:`murus.dem._kdata`
name every array a model hands to the kernels."""

from __future__ import annotations

import inspect

import numpy as np
from numba.core.registry import CPUDispatcher

from murus.dem import Joint
from murus.dem import _kdata as kd
from murus.dem import kernels as K
from murus.dem.model import Model

#: the modules that define the DEM kernels
KERNEL_MODULES = (K,)
MAX_ARGS = 12
#: the per-pair body of the parallel contact loop, which takes bare arrays: numba compiles a
#: parallel loop whose body reads an array out of a tuple without its ``noalias`` attributes,
#: and the contact loop then runs 2.1 times slower (kernels.process_pair, benchmarks/ab_dem.py)
EXEMPT = {"murus.dem.kernels.process_pair": 24, "murus.dem.kernels._process": 23}


def _dispatchers():
    for mod in KERNEL_MODULES:
        for name, obj in vars(mod).items():
            if isinstance(obj, CPUDispatcher) and obj.py_func.__module__ == mod.__name__:
                yield f"{mod.__name__}.{name}", obj


def test_kernels_take_at_most_twelve_arguments():
    found = dict(_dispatchers())
    assert "murus.dem.kernels.run_chunk" in found  # the inspection sees the kernels
    assert len(found) >= 20
    too_long = {name: len(inspect.signature(d.py_func).parameters)
                for name, d in found.items()
                if len(inspect.signature(d.py_func).parameters) > MAX_ARGS}
    assert too_long == EXEMPT


def test_structures_are_the_saved_state():
    """Every field of the kernel structures is a model array saved by a checkpoint (one list
    of names)."""
    fields = set(kd.STATE_ARRAYS)
    assert len(fields) == len(kd.STATE_ARRAYS)  # no name in two structures
    assert fields <= set(Model._ARRAYS)


def _copies(nt):
    return type(nt)(*[a.copy() for a in nt])


def test_parallel_loops_write_the_state():
    """The parallel contact and body loops write the structures they are given, as the serial
    ones do (numba drops writes through a named-tuple attribute inside a prange loop, numba
    issue #7135: the kernels write by field position)."""
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=35), rounding=1e-3)
    m.add_rectangle(0.8, 0.2, center=(0.0, 0.1), kinematic="fixed")
    top = m.add_rectangle(0.4, 0.2, center=(0.17, 0.3))
    m.settle(tol=1e-3, max_steps=200)
    m.bvel[top] = (0.01, 0.0)  # sliding: the shear forces change
    m.bomg[top] = 0.01
    n = m.pairs.shape[0]
    out = {}
    for name, loop in (("ser", K._contacts_serial), ("par", K._contacts_parallel)):
        c = _copies(kd.pack(kd.Contacts, m))
        pw = np.zeros((n, K.NW))
        nact = np.zeros(n, np.int64)
        loop(c, pw, kd.pack(kd.Shapes, m), kd.pack(kd.Bodies, m), m.jprops, m.dt,
             m.thickness, m.P[K.P_REACH], nact)
        out[name] = c
    assert not np.array_equal(out["ser"].sf[..., K.F_FS], m.sf[..., K.F_FS])
    for a, b in zip(out["ser"], out["par"], strict=True):
        assert np.array_equal(a, b)
    fb = np.zeros((m.nbody, 3))
    fr = kd.Frame(0.0, 0.0, 0.0, 0.0, 0.0, -9.81, 0.0, 0.0)
    bsp, bsh = K.incidence(m.sbody, m.nbody)
    res = {}
    for name, loop in (("ser", K._update_bodies_ser), ("par", K._update_bodies_par)):
        bodies = _copies(kd.pack(kd.Bodies, m))
        shapes = kd.pack(kd.Shapes, m)._replace(wv=m.wv.copy())
        part = np.zeros((K.NBLK, K.NQ))
        loop(m.P, fr, fb, bodies, shapes, part, bsp, bsh)
        res[name] = (bodies, shapes.wv, part)
    assert res["ser"][0].bpos[top, 0] > m.bpos[top, 0]  # it moved
    for a, b in zip(res["ser"][0], res["par"][0], strict=True):
        assert np.array_equal(a, b)
    assert np.array_equal(res["ser"][1], res["par"][1])
    assert np.array_equal(res["ser"][2], res["par"][2])


def test_kernels_called_from_python_return_plain_tuples():
    """numba boxes a named tuple by calling its Python class; a Ctrl-C pending at that moment
    crashed the process with SIGSEGV (found by the behaviour-factor Ctrl-C test). The kernels
    that Python calls return their contact arrays as a plain tuple."""
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=35), rounding=1e-3)
    m.add_rectangle(0.8, 0.2, center=(0.0, 0.1), kinematic="fixed")
    m.add_rectangle(0.4, 0.2, center=(0.17, 0.3))
    m.settle(tol=1e-3, max_steps=50)
    empty = _copies(kd.pack(kd.Contacts, m))._replace(pairs=np.zeros((0, 2), np.int64))
    out = K.transfer_arrays(empty, m.pairs.copy(), m.sgroup, m.jtab, 1)
    assert type(out) is tuple and len(out) == len(kd.Contacts._fields)
    n = 3
    drive = kd.Drive(np.zeros((n, 2)), np.zeros((n, 2)), np.tile([0.0, -9.81], (n, 1)),
                     np.zeros((n, 2)))
    out = K.run_chunk(n, m.P, m.E, m.C, m.S, drive, kd.pack(kd.Bodies, m),
                      kd.pack(kd.Shapes, m), kd.pack(kd.Joints, m), kd.pack(kd.Contacts, m))
    assert type(out) is tuple and len(out) == len(kd.Contacts._fields)
