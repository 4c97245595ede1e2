"""Rigid-body rocking of walls and blocks (Housner's model and its extensions).

Sign convention (Mordant et al. (SERIES), §3.1.1, EURODYN (2020), Figure 1): ``theta > 0`` is a
clockwise rotation about the right corner O; a positive ground acceleration drives a positive
rotation (EURODYN (2020) eq. 1); the vertical ground acceleration is positive upward. SI units.

The names below are imported on first use (PEP 562), so that ``murus --help`` and the design
commands do not load numba.

>>> from murus.rocking import RigidBlock, simulate
>>> res = simulate(RigidBlock(width=0.25, height=1.0, density=2000.0), theta0_over_alpha=0.5,
...                duration=1.0)
>>> res.n_impacts >= 1
True
"""

from murus._lazy import lazy_exports

_EXPORTS = {
    "BodyError": "body",
    "RigidBlock": "body",
    "series_clay_wall": "body",
    "restrained_wall_block": "body",
    "ExcitationError": "excitation",
    "HarmonicPulse": "excitation",
    "Record": "excitation",
    "as_excitation": "excitation",
    "cosine_pulse": "excitation",
    "free_vibration": "excitation",
    "rectangular_pulse": "excitation",
    "sine_pulse": "excitation",
    "ModelError": "model",
    "RockingModel": "model",
    "AmplitudeDependent": "restitution",
    "Constant": "restitution",
    "Housner": "restitution",
    "RestitutionError": "restitution",
    "Damper": "restraints",
    "Pivot": "restraints",
    "RestraintError": "restraints",
    "SpringBed": "restraints",
    "Tie": "restraints",
    "BatchResult": "engine",
    "RockingResult": "engine",
    "simulate": "engine",
    "simulate_batch": "engine",
    "WinklerBase": "winkler",
    "WinklerError": "winkler",
    "WinklerModel": "winkler",
    "WinklerResult": "winkler",
    "simulate_winkler": "winkler",
    "critical_amplitude": "analysis",
    "overturns": "analysis",
}

__all__ = sorted(_EXPORTS)

#: Deprecated names (DeprecationWarning on call; removed in the next release).
_EXPORTS.update({"seed000_wall": "body", "seed002_block": "body"})

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())
