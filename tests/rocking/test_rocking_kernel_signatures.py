"""The rocking kernels pass named data (issue 16, item 1): no numba kernel of the rocking engines
takes more than 12 arguments, the parameters are read by name from one declared table, and both
engines share one Dormand-Prince tableau."""

from __future__ import annotations

import inspect

import numpy as np
from numba.core.registry import CPUDispatcher

from murus.rocking import kernels as K
from murus.rocking import winkler_kernels as WK

MAX_ARGS = 12


def _dispatchers(module):
    return {name: obj for name, obj in vars(module).items()
            if isinstance(obj, CPUDispatcher) and obj.py_func.__module__ == module.__name__}


def test_no_rocking_kernel_takes_more_than_12_arguments():
    found = {}
    for module in (K, WK):
        disp = _dispatchers(module)
        assert len(disp) >= 10, module.__name__  # the inspection sees the kernels
        for name, d in disp.items():
            found[f"{module.__name__}.{name}"] = len(inspect.signature(d.py_func).parameters)
    too_long = {k: n for k, n in found.items() if n > MAX_ARGS}
    assert not too_long, too_long


def test_parameter_records_are_declared_once():
    for module, size in ((K, 40), (WK, 12)):
        names = [row[0] for row in module.PARAMS]
        assert len(set(names)) == len(names) == size
        assert module.PARAM_DTYPE.names == tuple(names)
        assert module.PARAM_DTYPE.itemsize == 8 * size
        assert all(len(row) == 3 and row[1] for row in module.PARAMS)  # units declared


def test_one_dormand_prince_tableau():
    # consistency of the shared tableau: rows of A sum to the nodes, the 5th-order weights
    # sum to 1, the error weights to 0 (both solutions are consistent)
    assert WK._A is K.DP_A and WK._C is K.DP_C and WK._E is K.DP_E
    assert np.allclose(K.DP_A.sum(axis=1), K.DP_C, rtol=0, atol=1e-15)
    assert abs(K.DP_A[6].sum() - 1.0) < 1e-15
    assert abs(K.DP_E.sum()) < 1e-16


def test_params_record_by_name():
    """The parameter record is built from fields given by name; the others are 0 and an
    unknown name is refused (a typo would otherwise be a silent zero)."""
    import pytest

    from murus.rocking import kernels as K

    P = K.params_record({"m": 2.0, "alpha": 0.1})
    assert P["m"] == 2.0 and P["alpha"] == 0.1 and P["g"] == 0.0
    assert P.dtype == K.PARAM_DTYPE
    with pytest.raises(KeyError, match="tie_kk"):
        K.params_record({"tie_kk": 1.0})


def test_a_restraint_class_plugs_in_without_a_model_field():
    """The extension point of the rocking moment (issue 16, item 1): a restraint class that the
    model takes through ``restraints`` runs the same kernel term as the model's own field. A
    user-defined class that writes the damper's parameters gives the identical history (bit for
    bit) to ``damper = Damper(...)``; a class without ``fill``/``describe`` is refused with its
    position."""
    import pytest

    from murus.motion.synthetic import sine_pulse
    from murus.rocking import Damper, ModelError, RockingModel, simulate
    from murus.rocking import restrained_wall_block as block

    class MyDamper:
        def __init__(self, c, h):
            self.c, self.h = c, h

        def fill(self, P, body):
            P["dmp_c"], P["dmp_y"], P["dmp_x"] = self.c, self.h, 0.0

        def describe(self):
            return {"c": self.c, "h": self.h}

    b = block("block1")
    pulse = sine_pulse(3.0, 2.0, dt=0.002)
    ref = simulate(RockingModel(b, damper=Damper(2e4, 0.8 * b.height)), pulse)
    mine = simulate(RockingModel(b, restraints=[MyDamper(2e4, 0.8 * b.height)]), pulse)
    free = simulate(RockingModel(b), pulse)
    assert ref.theta_max != free.theta_max  # the damper acts
    assert np.array_equal(ref.theta, mine.theta)
    assert mine.meta["model"]["restraints"] == [{"c": 2e4, "h": 0.8 * b.height}]
    with pytest.raises(ModelError, match=r"restraints\[0\]") as err:
        RockingModel(b, restraints=[object()])
    assert err.value.key == ("restraints", 0)
