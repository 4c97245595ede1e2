"""Analyses built on :func:`murus.rocking.simulate`: minimum overturning amplitudes."""

from __future__ import annotations

import math
from collections.abc import Callable

from murus.rocking.engine import simulate
from murus.rocking.model import ModelError, as_model


def overturns(model, excitation, *, without_impact: bool = False, tail: float | None = None,
              rtol: float = 1e-11) -> bool:
    """Whether the body overturns under ``excitation`` (optionally: before any impact).

    The run lasts until ``tail`` seconds after the end of the input (default ``40 / p``: a body
    left just above the separatrix needs ~ln(1/distance)/p to fall).

    Parameters
    ----------
    model : RockingModel or RigidBlock
        The body and its laws.
    excitation : Record, HarmonicPulse or GroundMotion
        The input.
    without_impact : bool
        Count only overturning before the first impact.
    tail : float, optional
        Seconds simulated after the end of the input [s] (default ``40 / p``).
    rtol : float
        Relative tolerance of the integrator.

    Returns
    -------
    bool
    """
    mdl = as_model(model)
    tail = 40.0 / mdl.p if tail is None else tail
    r = simulate(mdl, excitation, duration=excitation.end_time + tail, rtol=rtol,
                 out_dt=max(excitation.end_time + tail, 1e-3))
    if without_impact:
        return r.overturned and r.n_impacts == 0
    return r.overturned


def critical_amplitude(
    model,
    make_excitation: Callable[[float], object],
    lo: float,
    hi: float,
    *,
    without_impact: bool = True,
    xtol: float = 1e-9,
    rtol: float = 1e-11,
) -> float:
    """Smallest amplitude (in the units of ``make_excitation``'s argument) that overturns the
    body, by bisection between ``lo`` (must not overturn) and ``hi`` (must overturn).

    With ``without_impact`` only overturning before the first impact counts (the "mode 2"
    overturning of the closed-form pulse solutions, e.g. Zhang and Makris 2001).

    Parameters
    ----------
    model : RockingModel or RigidBlock
        The body and its laws.
    make_excitation : callable
        ``amplitude -> excitation``.
    lo, hi : float
        Bracket of the amplitude (in the units of ``make_excitation``'s argument).
    without_impact : bool
        Count only overturning before the first impact.
    xtol : float
        Absolute tolerance of the bisection.
    rtol : float
        Relative tolerance of the integrator.

    Returns
    -------
    float
        The critical amplitude.
    """
    mdl = as_model(model)

    def ok(a):
        return overturns(mdl, make_excitation(a), without_impact=without_impact, rtol=rtol)

    if ok(lo):
        raise ModelError(f"the lower bound {lo!r} already overturns the body")
    if not ok(hi):
        raise ModelError(f"the upper bound {hi!r} does not overturn the body")
    n = int(math.ceil(math.log2(max(hi - lo, 1e-300) / (xtol * max(abs(hi), 1e-300))))) + 1
    for _ in range(max(n, 1)):
        mid = 0.5 * (lo + hi)
        if ok(mid):
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)
