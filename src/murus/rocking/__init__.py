"""Rigid-body rocking of walls and blocks (Housner's model and its extensions).

Sign convention (seed 000 §3.1.1, seed 002 Figure 1): ``theta > 0`` is a clockwise rotation
about the right corner O; a positive ground acceleration drives a positive rotation (seed 002
eq. 1); the vertical ground acceleration is positive upward. SI units.

>>> from murus.rocking import RigidBlock, simulate
>>> res = simulate(RigidBlock(width=0.25, height=1.0, density=2000.0), theta0_over_alpha=0.5,
...                duration=1.0)
>>> res.n_impacts >= 1
True
"""

from murus.rocking.body import BodyError, RigidBlock, seed000_wall, seed002_block
from murus.rocking.excitation import (
    ExcitationError,
    HarmonicPulse,
    Record,
    as_excitation,
    cosine_pulse,
    free_vibration,
    rectangular_pulse,
    sine_pulse,
)
from murus.rocking.model import ModelError, RockingModel
from murus.rocking.restitution import Constant, Housner, RestitutionError
from murus.rocking.simulate import BatchResult, RockingResult, simulate, simulate_batch

__all__ = [
    "BatchResult",
    "BodyError",
    "Constant",
    "ExcitationError",
    "HarmonicPulse",
    "Housner",
    "ModelError",
    "Record",
    "RestitutionError",
    "RigidBlock",
    "RockingModel",
    "RockingResult",
    "as_excitation",
    "cosine_pulse",
    "free_vibration",
    "rectangular_pulse",
    "seed000_wall",
    "seed002_block",
    "simulate",
    "simulate_batch",
    "sine_pulse",
]

from murus.rocking.analysis import critical_amplitude, overturns  # noqa: E402

__all__ += ["critical_amplitude", "overturns"]
