"""The rocking model: a body, its restitution law and the options of the equation of motion.

The model compiles into the flat parameter vector that the numba kernels read
(:mod:`murus.rocking.kernels`); moment terms added later (ties, spring beds, dampers, variable
pivot) extend that vector, not the integrators.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from murus import G
from murus.rocking import kernels as K
from murus.rocking.body import RigidBlock
from murus.rocking.restitution import Housner, RestitutionLaw, make_restitution


class ModelError(ValueError):
    """An invalid model option."""


@dataclass(frozen=True)
class RockingModel:
    """A rigid body rocking on a rigid base (Housner 1963; seed 000 §3.1, seed 002 eq. 1).

    Parameters
    ----------
    body:
        The :class:`RigidBlock`.
    restitution:
        A law object, ``"housner"`` or a number in [0, 1] (constant law).
    linearised:
        Use the linearised equation ``sin x -> x, cos x -> 1`` (slender blocks; the equation of
        the closed-form pulse solutions).
    gravity:
        ``g`` [m/s²].
    rest_tol:
        After an impact the body returns to rest when ``|theta'| < rest_tol * p * alpha`` and the
        ground cannot lift it (ends the cascade of ever smaller impacts).
    """

    body: RigidBlock
    restitution: RestitutionLaw = field(default_factory=Housner)
    linearised: bool = False
    gravity: float = G
    rest_tol: float = 1e-3

    def __post_init__(self) -> None:
        if not isinstance(self.body, RigidBlock):
            raise ModelError("body must be a RigidBlock")
        object.__setattr__(self, "restitution", make_restitution(self.restitution))
        if not (math.isfinite(self.gravity) and self.gravity > 0.0):
            raise ModelError(f"gravity must be positive, got {self.gravity!r}")
        if not (math.isfinite(self.rest_tol) and 0.0 <= self.rest_tol < 1.0):
            raise ModelError(f"rest_tol must be in [0, 1), got {self.rest_tol!r}")

    @property
    def e(self) -> float:
        """The coefficient of restitution of the constant-valued laws [-]."""
        return self.restitution.value(self.body)

    @property
    def p(self) -> float:
        b = self.body
        return math.sqrt(b.mass * self.gravity * b.R / b.I_O)

    def params(self) -> np.ndarray:
        """The parameter vector ``P`` read by the kernels."""
        b = self.body
        P = np.zeros(K.P_SIZE)
        P[K.P_I] = b.I_O
        P[K.P_M] = b.mass
        P[K.P_R] = b.R
        P[K.P_ALPHA] = b.alpha
        P[K.P_G] = self.gravity
        P[K.P_LINEAR] = 1.0 if self.linearised else 0.0
        P[K.P_E_KIND] = float(self.restitution.KIND)
        P[K.P_E] = self.restitution.kernel_value(b)
        P[K.P_REST_TOL] = self.rest_tol
        return P

    def describe(self) -> dict:
        return {
            "body": self.body.describe(),
            "restitution": {"law": self.restitution.name, "e": self.e},
            "linearised": self.linearised,
            "gravity": self.gravity,
            "rest_tol": self.rest_tol,
        }


def as_model(model_or_body, restitution=None, linearised: bool | None = None) -> RockingModel:
    """A :class:`RockingModel` from a model or a body (with optional overrides)."""
    if isinstance(model_or_body, RockingModel):
        m = model_or_body
        if restitution is not None or linearised is not None:
            m = RockingModel(
                m.body,
                restitution if restitution is not None else m.restitution,
                m.linearised if linearised is None else linearised,
                m.gravity,
                m.rest_tol,
            )
        return m
    if isinstance(model_or_body, RigidBlock):
        return RockingModel(
            model_or_body,
            restitution if restitution is not None else Housner(),
            bool(linearised),
        )
    raise ModelError(f"expected a RockingModel or a RigidBlock, got {type(model_or_body).__name__}")
