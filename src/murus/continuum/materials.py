"""Zone materials of the continuum engine: linear elastic and Mohr-Coulomb (Itasca FLAC,
Constitutive Models, "Mohr-Coulomb model").

Moduli in Pa, density in kg/m³, angles in degrees, stresses in Pa (tension positive inside the
engine, strengths positive). Give the elastic constants as ``E`` and ``nu`` or as ``K`` and
``G``. Errors are :class:`MaterialError` with the key of the offending parameter.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus.continuum import kernels as K
from murus.errors import MurusError

__all__ = ["MaterialError", "Elastic", "MohrCoulomb", "elastic_constants"]


class MaterialError(MurusError, ValueError):
    """Invalid zone-material parameters (``key``: the parameter)."""


def _finite(name, v, lo=None, strict=False):
    try:
        v = float(v)
    except (TypeError, ValueError):
        raise MaterialError(f"{name} must be a number, got {v!r}", key=(name,)) from None
    if not math.isfinite(v):
        raise MaterialError(f"{name} must be finite, got {v!r}", key=(name,))
    if lo is not None and (v <= lo if strict else v < lo):
        op = ">" if strict else ">="
        raise MaterialError(f"{name} must be {op} {lo:g}, got {v!r}", key=(name,))
    return v


def elastic_constants(E=None, nu=None, K=None, G=None) -> tuple[float, float]:
    """Bulk and shear moduli from (E, nu) or (K, G), validated.

    Parameters
    ----------
    E : float, optional
        Young's modulus [Pa].
    nu : float, optional
        Poisson's ratio [-], ``-1 < nu < 0.5``.
    K, G : float, optional
        Bulk and shear moduli [Pa].

    Returns
    -------
    tuple of float
        ``(K, G)`` [Pa].

    Raises
    ------
    MaterialError
        Neither or both pairs given, or a value out of range (key: the parameter).

    References
    ----------
    ``K = E / (3 (1 - 2 nu))``, ``G = E / (2 (1 + nu))`` (isotropic elasticity).
    """
    pair1 = E is not None or nu is not None
    pair2 = K is not None or G is not None
    if pair1 == pair2:
        raise MaterialError("give the elastic constants as E and nu, or as K and G",
                            key=("E",) if pair1 else ())
    if pair1:
        if E is None or nu is None:
            raise MaterialError("give both E and nu", key=("nu" if E is not None else "E",))
        E = _finite("E", E, 0.0, strict=True)
        nu = _finite("nu", nu)
        if not (-1.0 < nu < 0.5):
            raise MaterialError(f"nu must be in (-1, 0.5), got {nu!r}", key=("nu",))
        return E / (3.0 * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))
    if K is None or G is None:
        raise MaterialError("give both K and G", key=("G" if K is not None else "K",))
    return _finite("K", K, 0.0, strict=True), _finite("G", G, 0.0, strict=True)


@dataclass(frozen=True)
class Elastic:
    """Linear elastic, isotropic zone material.

    Parameters
    ----------
    density : float
        Mass density [kg/m³], > 0.
    E, nu : float, optional
        Young's modulus [Pa] and Poisson's ratio [-].
    K, G : float, optional
        Bulk and shear moduli [Pa] (instead of E and nu).

    Attributes
    ----------
    bulk, shear : float
        K and G [Pa].
    """

    density: float
    E: float | None = None
    nu: float | None = None
    K: float | None = None
    G: float | None = None

    def __post_init__(self) -> None:
        _finite("density", self.density, 0.0, strict=True)
        k, g = elastic_constants(self.E, self.nu, self.K, self.G)
        object.__setattr__(self, "bulk", k)
        object.__setattr__(self, "shear", g)

    @property
    def young(self) -> float:
        """Young's modulus [Pa]."""
        return 9.0 * self.bulk * self.shear / (3.0 * self.bulk + self.shear)

    @property
    def poisson(self) -> float:
        """Poisson's ratio [-]."""
        return (3.0 * self.bulk - 2.0 * self.shear) / (2.0 * (3.0 * self.bulk + self.shear))

    @property
    def constrained(self) -> float:
        """Constrained (oedometric) modulus ``M = K + 4 G / 3`` [Pa]."""
        return self.bulk + 4.0 * self.shear / 3.0

    @property
    def vp(self) -> float:
        """P-wave speed [m/s]."""
        return math.sqrt(self.constrained / self.density)

    @property
    def vs(self) -> float:
        """S-wave speed [m/s]."""
        return math.sqrt(self.shear / self.density)

    def row(self) -> np.ndarray:
        """The material row of the kernels (``M_*`` columns of
        :mod:`murus.continuum.kernels`).

        Returns
        -------
        ndarray (NM,)
        """
        r = np.zeros(K.NM)
        r[K.M_K] = self.bulk
        r[K.M_G] = self.shear
        r[K.M_RHO] = self.density
        r[K.M_NPHI] = 1.0
        r[K.M_NPSI] = 1.0
        r[K.M_TENS] = math.inf
        return r


@dataclass(frozen=True)
class MohrCoulomb(Elastic):
    """Mohr-Coulomb elastic-perfectly plastic zone material with non-associated flow and a
    tension cut-off (Itasca FLAC, Constitutive Models, "Mohr-Coulomb model").

    Parameters
    ----------
    density : float
        Mass density [kg/m³].
    E, nu or K, G : float
        Elastic constants (:class:`Elastic`).
    friction_deg : float
        Friction angle phi [deg], 0 <= phi < 90.
    cohesion : float
        Cohesion c [Pa], >= 0.
    dilation_deg : float
        Dilation angle psi [deg], 0 <= psi <= phi.
    tension : float or None
        Tensile strength [Pa], >= 0; capped at ``c / tan phi`` (the apex of the shear surface);
        None: that cap (``inf`` when phi = 0).

    References
    ----------
    Itasca FLAC, Constitutive Models (Mohr-Coulomb model: yield function, tension cut-off
    ``sigma_t <= c / tan phi``, non-associated shear flow with ``N_psi``).
    """

    friction_deg: float = 30.0
    cohesion: float = 0.0
    dilation_deg: float = 0.0
    tension: float | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        phi = _finite("friction_deg", self.friction_deg, 0.0)
        if phi >= 90.0:
            raise MaterialError(f"friction_deg must be < 90, got {phi!r}", key=("friction_deg",))
        _finite("cohesion", self.cohesion, 0.0)
        psi = _finite("dilation_deg", self.dilation_deg, 0.0)
        if psi > phi:
            raise MaterialError(f"dilation_deg ({psi:g}) must not exceed friction_deg ({phi:g})",
                                key=("dilation_deg",))
        if self.tension is not None:
            _finite("tension", self.tension, 0.0)
        if phi == 0.0 and self.cohesion == 0.0:
            raise MaterialError("a Mohr-Coulomb material needs friction_deg > 0 or cohesion > 0",
                                key=("cohesion",))

    @property
    def tensile_strength(self) -> float:
        """The tension cut-off used [Pa]: ``min(tension, c / tan phi)``."""
        cap = (self.cohesion / math.tan(math.radians(self.friction_deg))
               if self.friction_deg > 0.0 else math.inf)
        return cap if self.tension is None else min(float(self.tension), cap)

    def row(self) -> np.ndarray:
        """The material row of the kernels (``M_*`` columns).

        Returns
        -------
        ndarray (NM,)
        """
        r = super().row()
        sp = math.sin(math.radians(self.friction_deg))
        ss = math.sin(math.radians(self.dilation_deg))
        r[K.M_NPHI] = (1.0 + sp) / (1.0 - sp)
        r[K.M_NPSI] = (1.0 + ss) / (1.0 - ss)
        r[K.M_CSN] = 2.0 * self.cohesion * math.sqrt(r[K.M_NPHI])
        r[K.M_TENS] = self.tensile_strength
        r[K.M_PLAS] = 1.0
        return r
