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


#: the contact loop run by the interpreter (NUMBA_DISABLE_JIT=1: the loop body as Python, the
#: parallel loop a plain one) on the state pickled by the test, its outputs pickled back
_INTERPRETED = """
import pickle, sys
from murus.dem import kernels as K
args = pickle.load(open(sys.argv[1], "rb"))
K._contacts_parallel(*args)
pickle.dump((args[0], args[1], args[-1]), open(sys.argv[2], "wb"))
"""


def test_parallel_loops_write_the_state(tmp_path):
    """The parallel contact and body loops write the structures they are given, as the serial
    ones do (numba drops writes through a named-tuple attribute inside a prange loop, numba
    issue #7135: the kernels write by field position). The reference of the contact loop is
    the same code run by the interpreter in a fresh process (``NUMBA_DISABLE_JIT=1``), to the
    last bit: a compiled serial copy of the loop would cost the suite minutes of compilation
    (``_contacts_serial``, kept for the benchmarks)."""
    import os
    import pickle
    import subprocess
    import sys

    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=35), rounding=1e-3)
    m.add_rectangle(0.8, 0.2, center=(0.0, 0.1), kinematic="fixed")
    top = m.add_rectangle(0.4, 0.2, center=(0.17, 0.3))
    m.settle(tol=1e-3, max_steps=200)
    m.bvel[top] = (0.01, 0.0)  # sliding: the shear forces change
    m.bomg[top] = 0.01
    n = m.pairs.shape[0]
    args = (_copies(kd.pack(kd.Contacts, m)), np.zeros((n, K.NW)), kd.pack(kd.Shapes, m),
            kd.pack(kd.Bodies, m), m.jprops, m.dt, m.thickness, m.P[K.P_REACH],
            np.zeros(n, np.int64))
    (tmp_path / "in.pkl").write_bytes(pickle.dumps(args))
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    run = subprocess.run([sys.executable, "-c", _INTERPRETED, str(tmp_path / "in.pkl"),
                          str(tmp_path / "out.pkl")], env=env, capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr
    ref = pickle.loads((tmp_path / "out.pkl").read_bytes())
    K._contacts_parallel(*args)
    out = (args[0], args[1], args[-1])
    assert not np.array_equal(ref[0].sf[..., K.F_FS], m.sf[..., K.F_FS])
    assert np.any(ref[2] > 0) and np.any(ref[1] != 0.0)
    for a, b in zip(ref[0], out[0], strict=True):
        assert np.array_equal(a, b)
    assert np.array_equal(ref[1], out[1]) and np.array_equal(ref[2], out[2])
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
