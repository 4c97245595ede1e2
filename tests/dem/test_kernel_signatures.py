"""The DEM kernels take named structures (issue 16, item 1): no numba kernel of
:mod:`murus.dem` takes more than 12 arguments, and the structures of :mod:`murus.dem._kdata`
name every array a model hands to the kernels."""

from __future__ import annotations

import inspect

from numba.core.registry import CPUDispatcher

from murus.dem import _kdata as kd
from murus.dem import kernels as K
from murus.dem.model import Model

#: the modules that define the DEM kernels
KERNEL_MODULES = (K,)
MAX_ARGS = 12


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
    assert too_long == {}


def test_structures_are_the_saved_state():
    """Every field of the kernel structures is a model array saved by a checkpoint (one list
    of names)."""
    fields = set(kd.STATE_ARRAYS)
    assert len(fields) == len(kd.STATE_ARRAYS)  # no name in two structures
    assert fields <= set(Model._ARRAYS)
