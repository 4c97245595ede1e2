"""Coefficients of restitution: laws applied to the angular velocity at each impact.

A law is an object with declared parameters and limits (``PARAMS``) that writes the kernel's
law code and numbers into the parameter vector (:meth:`fill`); the kernel evaluates it at each
impact (:func:`murus.rocking.kernels.restitution`).

Mordant et al. (SERIES), §3.3.2 lost the text of its equations 13-18 in extraction; the laws below
reconstruct them from the physical description of the paper and the rocking literature (Housner 1963
for the momentum balance; the ``1 - k sin^2 alpha`` family, with ``k = 2`` for a mass on top and
``k = 3/2`` for a uniform rectangle, as in EURODYN (2020), §4.3). What was assumed is stated on
each.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from murus.errors import MurusError
from murus.rocking import kernels as K
from murus.rocking.body import RigidBlock


class RestitutionError(MurusError, ValueError):
    """An invalid restitution law or parameter."""


@dataclass(frozen=True)
class Housner:
    """Housner's coefficient from conservation of angular momentum about the new pivot.

    ``e = 1 - 2 m R² sin²(alpha) / I_O`` for the actual body (Mordant et al. (SERIES), eq. 10):
    ``cos 2 alpha`` for a mass at the top, ``1 - 3/2 sin²(alpha)`` for a uniform rectangle
    (EURODYN (2020), §4.3, Housner 1963).
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

    def fill(self, P: np.ndarray, body: RigidBlock, moving_pivot: bool) -> None:
        """With a moving pivot (Mordant et al. (SERIES), eq. 13) the coefficient follows the lever
        at each impact by the momentum balance about the new pivot; on the corner it is a
        constant."""
        P["e"] = self.value(body)
        P["e_kind"] = K.E_MOMENTUM if moving_pivot else K.E_CONSTANT


@dataclass(frozen=True)
class Constant:
    """A constant coefficient ``e`` in [0, 1] given by the user (``e = 1``: elastic impacts,
    used by EURODYN (2020), §4.2 to isolate viscous damping).

    Parameters
    ----------
    e : float
        Coefficient of restitution of the angular velocity [-], in [0, 1].
    """

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

    def fill(self, P: np.ndarray, body: RigidBlock, moving_pivot: bool) -> None:
        P["e"] = self.e
        P["e_kind"] = K.E_CONSTANT


def momentum_restitution(body: RigidBlock, b1: float, b2: float) -> float:
    """Coefficient of restitution when the pivot moves at the impact (Housner's angular
    momentum balance about the new pivot, Mordant et al. (SERIES), eq. 13 reconstructed) [-].

    ``b1``, ``b2``: lever of the weight about the pivot before and after the impact [m]:
    ``e = (I_G + m z_G^2 - m b1 b2) / (I_G + m z_G^2 + m b2^2)``, i.e.
    ``(H^2 - b1 b2) / (H^2 + b2^2)`` for a mass at the height H (``I_G = 0``), ``cos 2 alpha``
    when ``b1 = b2 = b/2``. The kernel evaluates it with ``b1 = b2`` = the lever of the pivot law
    at the instant of the impact (the law depends on ``|a_g|``, the same on both sides)."""
    ig = body.I_O - body.mass * body.R**2
    j = ig + body.mass * body.z_G**2
    return (j - body.mass * b1 * b2) / (j + body.mass * b2 * b2)


def _coef(owner: str, name: str, v, lo: float = 0.0) -> float:
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise RestitutionError(f"{owner} {name} must be a number, got {v!r}") from None
    if not (math.isfinite(x) and x >= lo):
        raise RestitutionError(f"{owner} {name} must be a finite number >= {lo}, got {v!r}")
    return x


@dataclass(frozen=True)
class AmplitudeDependent:
    """The restitution laws of Mordant et al. (SERIES), §3.3.2 (eqs. 14-18, reconstructed), all of
    the form

    ``e_n = 1 - (k0 + k1 r_n) sin^2(alpha_n)``

    - eqs. 14-15 (the alternative formulation of its reference [8], "different options
      are possible regarding the coefficient of sin^2 alpha"): ``k1 = 0`` and ``k0`` free;
      ``k0 = 2`` is Housner's value for a mass on top (Mordant et al. (SERIES), eq. 10), ``k0 =
      3/2`` the value for a uniform rectangle, the default of :meth:`coefficient`;
    - eq. 16, amplitude dependence ("the largest the amplitude, the stronger the impact, the
      lower the restitution"): ``r_n = theta_max,n / theta_abs,max``, the largest rotation of
      the half-cycle before the impact over the largest rotation of the response, with
      ``k1 > 0``. The largest rotation of the whole response is not known while integrating:
      ``variant = "causal"`` (default) uses the running maximum (deterministic, one run);
      ``"iterated"`` re-runs the analysis with the previous run's maximum until it is stable
      (:func:`murus.rocking.simulate`, at most ``max_iterations``), which is the paper's
      definition when it converges;
    - eq. 17: once the input has ended (free vibration) ``(k0_free, k1_free)`` replace
      ``(k0, k1)`` (the paper observed less dissipation then); ``None``: the same law;
    - eq. 18: the energy lost at each impact is multiplied by ``f = (lambda / A0)^2``,
      ``lambda = h / b`` the aspect ratio of the wall and ``A0`` the calibrated reference aspect
      ratio ("proportional to the square of the proportion of the aspect ratios"), so that
      ``e' = sqrt(1 - f (1 - e^2))``; ``None``: off.

    ``alpha_n`` is the slenderness about the current pivot (Mordant et al. (SERIES), eq. 12).
    Defaults ``k0 = k1 = 1``: the largest half-cycle dissipates as Housner's top-mass wall (``k =
    2``), small ones half as much — a starting point for calibration (``murus.identify``), not a
    published value.

    Parameters
    ----------
    k0, k1 : float
        Coefficients of ``e_n = 1 - (k0 + k1 r_n) sin^2(alpha_n)`` [-].
    k0_free, k1_free : float, optional
        The coefficients once the input has ended (eq. 17); ``None``: ``k0``, ``k1``.
    A0 : float, optional
        Slenderness scale of the aspect factor of eq. 18 [-]; ``None``: off.
    variant : str
        ``"causal"`` (running maximum) or ``"iterated"`` (eq. 16 iterated to a fixed point).
    max_iterations : int
        Largest number of runs of the ``"iterated"`` variant.

    References
    ----------
    Mordant et al. (SERIES), §3.3.2, eqs. 14-18 (reconstructed); Housner (1963).
    """

    k0: float = 1.0
    k1: float = 1.0
    k0_free: float | None = None
    k1_free: float | None = None
    A0: float | None = None
    variant: str = "causal"
    max_iterations: int = 20
    KIND: ClassVar[int] = K.E_COEFFICIENT
    PARAMS: ClassVar[dict] = {
        "k0": ("-", ">= 0"), "k1": ("-", ">= 0"), "k0_free": ("-", ">= 0"),
        "k1_free": ("-", ">= 0"), "A0": ("-", "> 0"), "variant": ("", "causal | iterated"),
    }
    name: ClassVar[str] = "amplitude-dependent"

    def __post_init__(self) -> None:
        n = self.name
        object.__setattr__(self, "k0", _coef(n, "k0", self.k0))
        object.__setattr__(self, "k1", _coef(n, "k1", self.k1))
        for f in ("k0_free", "k1_free"):
            v = getattr(self, f)
            if v is not None:
                object.__setattr__(self, f, _coef(n, f, v))
        if self.A0 is not None:
            a0 = _coef(n, "A0", self.A0)
            if a0 <= 0.0:
                raise RestitutionError(f"{n} A0 must be positive, got {self.A0!r}")
            object.__setattr__(self, "A0", a0)
        if self.variant not in ("causal", "iterated"):
            raise RestitutionError(
                f"{n} variant must be 'causal' or 'iterated', got {self.variant!r}")
        if not (isinstance(self.max_iterations, int) and self.max_iterations >= 1):
            raise RestitutionError(f"{n} max_iterations must be a positive integer")

    @classmethod
    def coefficient(cls, k: float = 1.5, **kw) -> AmplitudeDependent:
        """Eqs. 14-15: ``e_n = 1 - k sin^2(alpha_n)``."""
        return cls(k0=k, k1=0.0, **kw)

    @property
    def free_law(self) -> bool:
        return self.k0_free is not None or self.k1_free is not None

    def aspect_factor(self, body: RigidBlock) -> float:
        if self.A0 is None:
            return 1.0
        return (body.height / body.width / self.A0) ** 2

    def value(self, body: RigidBlock) -> float:
        """The coefficient of the largest half-cycle on the corner, during the input [-]."""
        e = 1.0 - (self.k0 + self.k1) * math.sin(body.alpha) ** 2
        f = self.aspect_factor(body)
        return math.sqrt(max(0.0, 1.0 - f * (1.0 - e * e))) if f != 1.0 else max(0.0, e)

    def kernel_value(self, body: RigidBlock) -> float:
        return self.value(body)

    def fill(self, P: np.ndarray, body: RigidBlock, moving_pivot: bool) -> None:
        P["e"] = self.value(body)
        P["e_kind"] = K.E_COEFFICIENT
        P["e_k0"] = self.k0
        P["e_k1"] = self.k1
        if self.free_law:
            P["e_free"] = 1.0
            P["e_k0f"] = self.k0 if self.k0_free is None else self.k0_free
            P["e_k1f"] = self.k1 if self.k1_free is None else self.k1_free
        P["e_aspect"] = self.aspect_factor(body)

    def describe(self) -> dict:
        return {"k0": self.k0, "k1": self.k1, "k0_free": self.k0_free, "k1_free": self.k1_free,
                "A0": self.A0, "variant": self.variant}


RestitutionLaw = Housner | Constant | AmplitudeDependent


def make_restitution(spec) -> RestitutionLaw:
    """A law from a name (``"housner"``), a number (constant) or a law object."""
    if isinstance(spec, Housner | Constant | AmplitudeDependent):
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
