"""Coefficients of restitution: laws applied to the angular velocity at each impact.

A law is an object with declared parameters and limits (``PARAMS``) that tells the kernel which
code to run (``KIND``) and with which numbers (:meth:`kernel_value`). New laws (amplitude
dependent, free/forced, aspect ratio: seed 000 §3.3.2) are new classes with new kernel codes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from murus.rocking.body import RigidBlock


class RestitutionError(ValueError):
    """An invalid restitution law or parameter."""


@dataclass(frozen=True)
class Housner:
    """Housner's coefficient from conservation of angular momentum about the new pivot.

    ``e = 1 - 2 m R² sin²(alpha) / I_O`` for the actual body (seed 000 eq. 10): ``cos 2 alpha``
    for a mass at the top, ``1 - 3/2 sin²(alpha)`` for a uniform rectangle (seed 002 §4.3,
    Housner 1963).
    """

    KIND: ClassVar[int] = 0
    PARAMS: ClassVar[dict] = {}
    name: ClassVar[str] = "housner"

    def value(self, body: RigidBlock) -> float:
        e = body.housner_restitution()
        if not 0.0 <= e <= 1.0:  # pragma: no cover - impossible for a rectangle
            raise RestitutionError(f"Housner's e = {e:.4f} is outside [0, 1] for this body")
        return e

    def kernel_value(self, body: RigidBlock) -> float:
        return self.value(body)


@dataclass(frozen=True)
class Constant:
    """A constant coefficient ``e`` in [0, 1] given by the user (``e = 1``: elastic impacts,
    used by seed 002 §4.2 to isolate viscous damping)."""

    e: float
    KIND: ClassVar[int] = 0
    PARAMS: ClassVar[dict] = {"e": ("-", "0 <= e <= 1")}
    name: ClassVar[str] = "constant"

    def __post_init__(self) -> None:
        try:
            v = float(self.e)
        except (TypeError, ValueError):
            raise RestitutionError(f"restitution value must be a number, got {self.e!r}") from None
        if not (math.isfinite(v) and 0.0 <= v <= 1.0):
            raise RestitutionError(f"restitution value must be in [0, 1], got {self.e!r}")
        object.__setattr__(self, "e", v)

    def value(self, body: RigidBlock) -> float:
        return self.e

    def kernel_value(self, body: RigidBlock) -> float:
        return self.e


RestitutionLaw = Housner | Constant


def make_restitution(spec) -> RestitutionLaw:
    """A law from a name (``"housner"``), a number (constant) or a law object."""
    if isinstance(spec, Housner | Constant):
        return spec
    if isinstance(spec, int | float) and not isinstance(spec, bool):
        return Constant(float(spec))
    if isinstance(spec, str):
        if spec.lower() == "housner":
            return Housner()
        raise RestitutionError(
            f"unknown restitution law {spec!r}; expected 'housner' or 'constant'"
        )
    raise RestitutionError(f"cannot make a restitution law from {spec!r}")
