"""Seismic demand on local mechanisms: ground spectra and the floor spectra of the Circolare 2019.

- Ground: the elastic spectrum of the site, NTC 2018 §3.2.3.2 (:class:`murus.eurocode.ntc.
  NTCSpectrum`) or EN 1998-1 §3.2.2.2 (:class:`EC8Spectrum`, a thin adapter of
  :func:`murus.eurocode.ec8.elastic_spectrum`); peak ground acceleration ag S = Se(0).
- At a height z of the building (Circolare 2019 §C7.2.3, "formulazione semplificata, a diverse
  quote, per ... eventuali meccanismi locali"), first mode only (§C8.7.1.2.1.8 says it is
  sufficient for the ultimate limit states of local mechanisms):

  - peak floor acceleration a_Z(z) = Se(T1, xi1) |gamma1 psi1(z)| sqrt(1 + 0.0004 xi1^2),
    eqs. [C7.2.7]-[C7.2.8], with psi1(z) = z / H (linear first mode normalised at the top) and
    gamma1 = 3 n / (2 n + 1) (eq. [C7.2.10], n storeys), xi1 in percent;
  - floor acceleration spectrum S_eZ(T, xi, z), eq. [C7.2.6] with a = 0.8, b = 1.1 (the values
    the Circolare gives), not below Se(T, xi) for T > T1 (eq. [C7.2.5]).

  Reading of eq. [C7.2.6]: its amplification 1.1 xi1^-0.5 is evaluated with the damping of the
  building as a fraction (4.92 at 5 %, close to the a_p = 5 of Table C7.2.II for the simplified
  formula [C7.2.11]); with xi1 in percent it would be 0.49, a de-amplification. This follows
  Degli Abbati, Cattari and Lagomarsino (2018), the source of the formulation. In eq. [C7.2.7]
  xi1 is in percent, as the Circolare states.

References
----------
Circolare 21 gennaio 2019 n. 7 C.S.LL.PP., §C7.2.3, eqs. C7.2.5-C7.2.10; NTC 2018 §3.2.3.2.
S. Degli Abbati, S. Cattari, S. Lagomarsino (2018), Theoretically-based and practice-oriented
formulations for the floor spectra evaluation, Earthquake Spectra (volume, pages and DOI not
confirmed here).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus.errors import MurusError

__all__ = ["DemandError", "Building", "EC8Spectrum", "floor_acceleration", "floor_spectrum",
           "displacement_demand", "FLOOR_A", "FLOOR_B"]

#: a, b of eq. [C7.2.6] (Circolare 2019 §C7.2.3: "possono essere assunti pari a 0,8 e 1,1")
FLOOR_A = 0.8
FLOOR_B = 1.1


class DemandError(MurusError, ValueError):
    """Bad building data for the floor spectra."""


@dataclass(frozen=True)
class Building:
    """The main structure, for the floor spectra of §C7.2.3.

    Parameters
    ----------
    T1 : float
        First period of the building in the direction of the check [s] (> 0).
    height : float
        Height H of the building above the foundation [m] (> 0).
    storeys : int
        Number of storeys n (>= 1), for gamma1 = 3 n / (2 n + 1), eq. [C7.2.10].
    damping : float
        Viscous damping ratio xi1 of the building [-] (default 0.05).
    """

    T1: float
    height: float
    storeys: int
    damping: float = 0.05

    def __post_init__(self):
        for name in ("T1", "height"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise DemandError(f"{name} must be > 0, got {v!r}", key=(name,))
        if int(self.storeys) != self.storeys or self.storeys < 1:
            raise DemandError(f"storeys must be an integer >= 1, got {self.storeys!r}",
                              key=("storeys",))
        if not 0.0 < self.damping <= 0.3:
            raise DemandError(f"damping must be in (0, 0.3], got {self.damping!r}",
                              key=("damping",))

    @property
    def gamma1(self) -> float:
        """Modal participation factor gamma1 = 3 n / (2 n + 1) [-], eq. [C7.2.10]."""
        n = self.storeys
        return 3.0 * n / (2.0 * n + 1.0)

    def psi1(self, z: float) -> float:
        """First mode shape at the height z, linear and 1 at the top [-]."""
        if z < 0 or z > self.height * (1 + 1e-9):
            raise DemandError(f"the mechanism's height {z:g} m is outside the building "
                              f"(0..{self.height:g} m)", key=("height",))
        return z / self.height


@dataclass(frozen=True)
class EC8Spectrum:
    """EN 1998-1 §3.2.2.2 elastic spectrum with the interface of
    :class:`murus.eurocode.ntc.NTCSpectrum` (``Se``, ``SDe``, ``pga``).

    Parameters
    ----------
    ag : float
        Reference peak ground acceleration agR [m/s²].
    ground : str
        Ground type A-E.
    spectrum_type : int
        1 or 2.
    importance : str or float, optional
        Importance class or factor (EN 1998-1 §4.2.5).
    """

    ag: float
    ground: str = "A"
    spectrum_type: int = 1
    importance: str | float | None = None

    def __post_init__(self):
        self.Se(0.0)

    def Se(self, T, damping: float = 0.05):
        """Se(T) [m/s²], EN 1998-1 eqs (3.2)-(3.5)."""
        from murus.eurocode.ec8 import elastic_spectrum

        out = elastic_spectrum(T, self.ag, self.ground, self.spectrum_type, damping,
                               self.importance)
        return out if np.ndim(out) else float(out)

    def SDe(self, T, damping: float = 0.05):
        """SDe(T) = Se(T) (T / 2 pi)^2 [m], EN 1998-1 eq (3.7) for T <= 4 s."""
        T = np.asarray(T, dtype=float)
        out = np.asarray(self.Se(T, damping)) * (T / (2 * math.pi)) ** 2
        return out if out.ndim else float(out)

    @property
    def pga(self) -> float:
        """ag S [m/s²] (Se at T = 0)."""
        return float(self.Se(0.0))


def _eta(damping: float) -> float:
    """eta = sqrt(10 / (5 + xi%)) >= 0.55 (NTC 2018 eq. 3.2.4, EN 1998-1 eq (3.6))."""
    return max(math.sqrt(10.0 / (5.0 + 100.0 * damping)), 0.55)


def floor_acceleration(spectrum, building: Building, z: float) -> float:
    """Peak floor acceleration a_Z(z) [m/s²] of the first mode, Circolare 2019
    eqs. [C7.2.7]-[C7.2.8].

    Parameters
    ----------
    spectrum
        Ground spectrum (``Se(T, damping)``).
    building : Building
    z : float
        Height above the foundation [m].

    Returns
    -------
    float
        a_Z [m/s²] (0 at z = 0: the ground acceleration is checked separately).
    """
    xi = 100.0 * building.damping
    se = float(spectrum.Se(building.T1, building.damping))
    return se * abs(building.gamma1 * building.psi1(z)) * math.sqrt(1.0 + 0.0004 * xi ** 2)


def floor_spectrum(spectrum, building: Building, z: float, T, damping: float):
    """Floor acceleration spectrum S_eZ(T, xi, z) [m/s²], Circolare 2019 eqs. [C7.2.5]-[C7.2.6],
    first mode; not below the ground spectrum Se(T, xi) for T > T1 (eq. [C7.2.5]).

    Parameters
    ----------
    spectrum
        Ground spectrum.
    building : Building
    z : float
        Height [m].
    T : float or array_like
        Period of the local mechanism [s].
    damping : float
        Equivalent viscous damping of the mechanism xi [-] (through eta).

    Returns
    -------
    float or numpy.ndarray
        S_eZ [m/s²].
    """
    T = np.asarray(T, dtype=float)
    aZ = floor_acceleration(spectrum, building, z)
    T1 = building.T1
    A = 1.1 * building.damping ** -0.5 * _eta(damping)
    low = A * aZ / (1.0 + (A - 1.0) * np.clip(1.0 - T / (FLOOR_A * T1), 0.0, None) ** 1.6)
    high = A * aZ / (1.0 + (A - 1.0) * np.clip(T / (FLOOR_B * T1) - 1.0, 0.0, None) ** 1.2)
    out = np.where(T < FLOOR_A * T1, low, np.where(T < FLOOR_B * T1, A * aZ, high))
    ground = np.asarray(spectrum.Se(T, damping))
    out = np.where(T > T1, np.maximum(out, ground), out)
    return out if out.ndim else float(out)


def displacement_demand(spectrum, T: float, damping: float, building: Building | None = None,
                        z: float = 0.0) -> float:
    """Displacement demand on a local mechanism of secant period T [m].

    At ground level (``z = 0`` or no building): SDe(T) of the ground spectrum (Circolare 2019
    §C8.7.1.2.1.8, NTC 2018 §3.2.3.2.3). At a height z: S_eZ(T, xi, z) T^2 / (4 pi^2), not below
    S_eZ(T1, xi, z) b^2 T1^2 / (4 pi^2) for T > b T1 (eq. [C8.7.1.12]); murus also keeps the
    ground demand SDe(T) as a lower bound (the ground check of the 2009 Circolare, C8A.4.11).

    Parameters
    ----------
    spectrum
        Ground spectrum.
    T : float
        Period [s].
    damping : float
        Damping of the mechanism [-] (0.08 SLV, 0.10 SLC, §C8.7.1.2.1.8).
    building : Building, optional
    z : float
        Height of the mechanism [m].

    Returns
    -------
    float
        Demand [m].
    """
    ground = float(spectrum.SDe(T, damping))
    if building is None or z <= 0:
        return ground
    k = 1.0 / (4.0 * math.pi ** 2)
    d = float(floor_spectrum(spectrum, building, z, T, damping)) * T ** 2 * k
    bT1 = FLOOR_B * building.T1
    if T > bT1:
        d = max(d, float(floor_spectrum(spectrum, building, z, building.T1, damping))
                * bT1 ** 2 * k)
    return max(d, ground)
