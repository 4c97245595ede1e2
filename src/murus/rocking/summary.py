"""What a rocking run reports, declared once (no numba here, so that studies and the CLI can read
it without loading the kernels).

- :data:`SUMMARY`: the summary of a run on a rigid base, one row per slot of the kernels'
  summary vector (:mod:`murus.rocking.kernels` takes its ``S_*`` slots from it), with its units
  and description; the same rows give the attributes of :class:`~murus.rocking.engine.
  RockingResult`, the entries of ``summary.json`` and the variables of the study Datasets
  (:mod:`murus.studies.sweep`).
- :data:`WINKLER_SUMMARY`: the same for the body on an elastic (Winkler) layer
  (:mod:`murus.rocking.winkler_kernels`).
- :data:`LIMIT_STATES`: the limit states on ``theta_max / alpha``.
- :data:`FREE_TAIL` and :data:`FREE_VIBRATION_DURATION`: default durations.

References
----------
EURODYN (2020), "Mitigation of amplified response of restrained rocking walls through
horizontal dampers", doi:10.47964/1120.9351.20156, §4 (limit states).
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple


class Quantity(NamedTuple):
    """One declared summary quantity.

    ``name``: attribute of the result and key of ``summary.json``; ``units`` (``"1"``:
    dimensionless or a count); ``description`` (the ``long_name`` of a Dataset variable);
    ``kind``: how the slot reads as a Python value (``"float"``, ``"int"``, ``"bool"``,
    ``"time"``: a time that may not be reached, ``None`` then); ``dataset``: a variable of the
    study Datasets; ``aliases``: earlier names, still readable."""

    name: str
    units: str
    description: str
    kind: str = "float"
    dataset: bool = True
    aliases: tuple = ()


#: The summary of a rocking run on a rigid base, in the order of the kernels' slots.
SUMMARY = (
    Quantity("theta_max", "rad", "largest absolute rotation"),
    Quantity("theta_signed_max", "rad", "signed rotation at the largest absolute rotation"),
    Quantity("t_theta_max", "s", "time of the largest absolute rotation"),
    Quantity("n_impacts", "1", "number of impacts", "int", aliases=("impacts",)),
    Quantity("t_uplift", "s", "time of first uplift (NaN: never)", "time",
             aliases=("uplift_time",)),
    Quantity("overturned", "1", "1 if the wall overturned, 0 if not (NaN: failed case)", "bool"),
    Quantity("t_overturn", "s", "time of overturning (NaN: none)", "time"),
    Quantity("t_exceed_alpha", "s", "first time |theta| > alpha (NaN: never)", "time"),
    Quantity("energy_dissipated", "J", "energy dissipated at impacts"),
    Quantity("n_uplifts", "1", "number of uplift intervals", "int", dataset=False),
    Quantity("status", "1", "0 ok, 1 step size underflow, 2 step budget exhausted", "int"),
    Quantity("n_steps", "1", "Runge-Kutta steps", "int"),
    Quantity("t_final", "s", "time the integration reached", dataset=False),
    Quantity("theta_pos", "rad", "largest positive rotation"),
    Quantity("theta_neg", "rad", "largest negative rotation"),
    Quantity("n_peaks", "1", "number of peaks of the rotation while rocking", "int",
             dataset=False),
)

#: The summary of a run on an elastic (Winkler) layer, in the order of its kernel's slots.
WINKLER_SUMMARY = (
    Quantity("theta_max", "rad", "largest absolute rotation"),
    Quantity("theta_signed_max", "rad", "signed rotation at the largest absolute rotation"),
    Quantity("t_theta_max", "s", "time of the largest absolute rotation"),
    Quantity("overturned", "1", "1 if the wall overturned", "bool"),
    Quantity("t_overturn", "s", "time of overturning (NaN: none)", "time"),
    Quantity("n_crossings", "1", "crossings of theta = 0", "int", aliases=("crossings",)),
    Quantity("n_peaks", "1", "half-cycle peaks", "int"),
    Quantity("peak_contact_force", "N", "largest contact resultant (at step ends)"),
    Quantity("t_peak_contact_force", "s", "time of the largest contact resultant"),
    Quantity("peak_pressure", "Pa", "largest contact pressure (at step ends)"),
    Quantity("peak_angular_acceleration", "rad/s2", "largest |theta''| (at step ends)"),
    Quantity("min_contact_length", "m", "smallest contact length"),
    Quantity("status", "1", "0 ok, 1 step size underflow, 2 step budget exhausted", "int"),
    Quantity("n_steps", "1", "accepted Runge-Kutta steps", "int"),
    Quantity("t_final", "s", "time the integration reached"),
    Quantity("n_rejected", "1", "rejected Runge-Kutta steps", "int"),
)


def slots(table) -> dict[str, int]:
    """Slot of each quantity of a summary table in the kernel's summary vector."""
    return {q.name: i for i, q in enumerate(table)}


def _time(x: float):
    return None if math.isnan(x) else x


@functools.cache
def _readers(table) -> tuple:
    """(name, converter) of each quantity of a summary table."""
    conv = {"int": int, "bool": bool, "time": _time}
    return tuple((q.name, conv.get(q.kind, float)) for q in table)


def values(table, S) -> dict:
    """The summary vector ``S`` of a kernel read through its table: name -> Python value
    (``float``, ``int``, ``bool``, or ``None`` for a time not reached)."""
    readers = _readers(tuple(table))
    xs = S.tolist() if hasattr(S, "tolist") else [float(x) for x in S]
    if len(xs) != len(readers):
        raise ValueError(f"a summary vector of {len(xs)} values for a table of {len(readers)}")
    return {name: f(float(x)) for (name, f), x in zip(readers, xs, strict=True)}


def table_summary(result, table, fields) -> dict:
    """The entries of ``summary.json`` that come from a summary table: each quantity of
    ``table`` kept by the result as an attribute (``fields``), under its name and its earlier
    names (``aliases``).

    Parameters
    ----------
    result : object
        A result with the attributes ``fields``.
    table : tuple of Quantity
        :data:`SUMMARY` or :data:`WINKLER_SUMMARY`.
    fields : tuple of str
        The quantities the result keeps.

    Returns
    -------
    dict
    """
    out = {}
    for q in table:
        if q.name in fields:
            out[q.name] = getattr(result, q.name)
            for a in q.aliases:
                out[a] = out[q.name]
    return out


#: Limit states on the normalised rotation ``theta_max / alpha`` (EURODYN (2020), §4): limited
#: and moderate rocking; overturning is the third.
LIMIT_STATES = {"limited": 0.1, "moderate": 0.4}

#: Default free motion after the end of an input [s].
FREE_TAIL = 5.0

#: Default duration of a free vibration (no input) [s], from the API and from a case file alike.
FREE_VIBRATION_DURATION = 20.0
