"""NTC 2018 (Italian building code, D.M. 17/01/2018) horizontal elastic response spectrum.

Clauses implemented:

- §3.2.3.2.1 horizontal elastic acceleration spectrum Se(T) from the site parameters ag, F0 and
  Tc* (the hazard of the limit state, Allegato A/B of the NTC 2008, kept by the NTC 2018), the
  soil category A-E (Table 3.2.IV: S_S and C_C) and the topographic category T1-T4 (Table 3.2.V:
  S_T); S = S_S S_T (eq. 3.2.3); damping correction eta = sqrt(10 / (5 + xi)) >= 0.55 with xi in
  percent (eq. 3.2.4, numbered as cited by the Circolare 2019 §C7.2.3); TC = C_C Tc*,
  TB = TC / 3, TD = 4.0 ag / g + 1.6 s (eqs. 3.2.5-3.2.7 of the NTC 2018 numbering);
- §3.2.3.2.3 elastic displacement spectrum SDe(T) = Se(T) (T / 2 pi)^2 up to T_E (eq. 3.2.10),
  then eq. 3.2.11 from T_E to T_F (linear from F0 eta to 1 times d_g) and d_g beyond T_F, with
  d_g = 0.025 ag S TC TD (eq. 3.2.12) and T_E, T_F of Table 3.2.VII (A: 4.5, 10.0 s; B: 5.0,
  10.0 s; C, D, E: 6.0, 10.0 s).

The equation numbers other than 3.2.4 are those of the NTC 2018 text as we read it (the 2008
numbering was shifted by one: 3.2.5 S, 3.2.6 eta, 3.2.7-3.2.9 corners); the clause numbers are
certain. Units: ag and the spectra in m/s², periods in s, F0 and S dimensionless. S_T is the value
at the top of the relief (Table 3.2.V); pass ``topography`` as a number to use an interpolated
value below the top.

>>> sp = NTCSpectrum(ag=0.25 * 9.81, F0=2.5, Tc_star=0.3, soil="A")
>>> round(float(sp.Se(0.2)) / 9.81, 4)   # plateau: ag S F0
0.625
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus.errors import MurusError

__all__ = ["NTCError", "NTCSpectrum", "soil_coefficients", "TOPOGRAPHY", "DISPLACEMENT_CORNERS",
           "G_NTC", "PARAMS"]

#: gravity used to normalise ag in the formulas of Table 3.2.IV and TD [m/s²]
G_NTC = 9.81

#: NTC 2018 Table 3.2.V: topographic amplification S_T (value at the top of the relief)
TOPOGRAPHY = {"T1": 1.0, "T2": 1.2, "T3": 1.2, "T4": 1.4}

#: NTC 2018 Table 3.2.VII: (T_E, T_F) [s] of the displacement spectrum by soil category
DISPLACEMENT_CORNERS = {"A": (4.5, 10.0), "B": (5.0, 10.0), "C": (6.0, 10.0), "D": (6.0, 10.0),
                        "E": (6.0, 10.0)}

#: Declared parameters and their limits (name: (low, high, unit)); Tc* and F0 span the values of
#: the national hazard grid (Allegato B of the NTC 2008: F0 about 2.2-3.0, Tc* 0.13-0.6 s),
#: widened to keep site-specific studies usable.
PARAMS = {
    "ag": (0.0, 1.5 * G_NTC, "m/s2"),
    "F0": (1.5, 4.0, "-"),
    "Tc_star": (0.05, 1.5, "s"),
    "damping": (0.0, 0.5, "-"),
}


class NTCError(MurusError, ValueError):
    """A parameter of the NTC 2018 spectrum is outside its declared limits."""


def _check(name: str, value: float) -> float:
    lo, hi, unit = PARAMS[name]
    v = float(value)
    if not math.isfinite(v) or v < lo or v > hi:
        raise NTCError(f"{name} must be in {lo:g}..{hi:g} {unit}, got {value!r}", key=(name,))
    return v


def soil_coefficients(soil: str, ag: float, F0: float, Tc_star: float) -> tuple[float, float]:
    """S_S and C_C of the soil category, NTC 2018 Table 3.2.IV.

    Parameters
    ----------
    soil : str
        Soil category ``"A"`` ... ``"E"``.
    ag : float
        Peak ground acceleration on rock (type A) of the limit state [m/s²].
    F0 : float
        Maximum spectral amplification factor [-].
    Tc_star : float
        Period of the start of the constant-velocity branch on rock, Tc* [s].

    Returns
    -------
    tuple of float
        ``(S_S, C_C)`` [-].

    References
    ----------
    NTC 2018 §3.2.3.2.1, Table 3.2.IV: B: 1.00 <= 1.40 - 0.40 F0 ag/g <= 1.20,
    C_C = 1.10 Tc*^-0.20; C: 1.00 <= 1.70 - 0.60 F0 ag/g <= 1.50, C_C = 1.05 Tc*^-0.33;
    D: 0.90 <= 2.40 - 1.50 F0 ag/g <= 1.80, C_C = 1.25 Tc*^-0.50; E: 1.00 <= 2.00 - 1.10 F0 ag/g
    <= 1.60, C_C = 1.15 Tc*^-0.40; A: 1.00, 1.00.
    """
    s = str(soil).strip().upper()
    a = ag / G_NTC
    table = {
        "A": (1.0, 1.0, 1.0, 0.0, 1.0, 0.0),
        "B": (1.00, 1.20, 1.40, 0.40, 1.10, -0.20),
        "C": (1.00, 1.50, 1.70, 0.60, 1.05, -0.33),
        "D": (0.90, 1.80, 2.40, 1.50, 1.25, -0.50),
        "E": (1.00, 1.60, 2.00, 1.10, 1.15, -0.40),
    }
    if s not in table:
        raise NTCError(f"soil category must be one of A, B, C, D, E, got {soil!r}", key=("soil",))
    lo, hi, c0, c1, k, e = table[s]
    ss = min(max(c0 - c1 * F0 * a, lo), hi)
    cc = k * Tc_star ** e
    return float(ss), float(cc)


@dataclass(frozen=True)
class NTCSpectrum:
    """NTC 2018 horizontal elastic spectrum of one limit state (§3.2.3.2.1).

    Parameters
    ----------
    ag : float
        Peak ground acceleration on rock of the limit state [m/s²].
    F0 : float
        Maximum spectral amplification on rock [-].
    Tc_star : float
        Tc* [s].
    soil : str
        Soil category A-E (Table 3.2.IV).
    topography : str or float
        Topographic category T1-T4 (Table 3.2.V) or the factor S_T itself.

    Attributes
    ----------
    S, SS, ST, CC : float
        Soil and topography factors [-] (S = SS ST, eq. 3.2.3).
    TB, TC, TD : float
        Corner periods [s] (eqs. 3.2.5-3.2.7).

    References
    ----------
    NTC 2018 §3.2.3.2.1-§3.2.3.2.3; Circolare 2019 n. 7 §C3.2.3.
    """

    ag: float
    F0: float
    Tc_star: float
    soil: str = "A"
    topography: str | float = "T1"

    def __post_init__(self):
        _check("ag", self.ag)
        _check("F0", self.F0)
        _check("Tc_star", self.Tc_star)
        soil_coefficients(self.soil, self.ag, self.F0, self.Tc_star)
        self.ST  # noqa: B018 - validates the topography

    @property
    def ST(self) -> float:
        t = self.topography
        if isinstance(t, str):
            key = t.strip().upper()
            if key not in TOPOGRAPHY:
                raise NTCError(f"topography must be one of T1, T2, T3, T4 or a factor, got {t!r}",
                               key=("topography",))
            return TOPOGRAPHY[key]
        v = float(t)
        if not (math.isfinite(v) and 1.0 <= v <= 1.4):
            raise NTCError(f"topography factor S_T must be in 1.0..1.4, got {t!r}",
                           key=("topography",))
        return v

    @property
    def SS(self) -> float:
        return soil_coefficients(self.soil, self.ag, self.F0, self.Tc_star)[0]

    @property
    def CC(self) -> float:
        return soil_coefficients(self.soil, self.ag, self.F0, self.Tc_star)[1]

    @property
    def S(self) -> float:
        return self.SS * self.ST

    @property
    def TC(self) -> float:
        return self.CC * self.Tc_star

    @property
    def TB(self) -> float:
        return self.TC / 3.0

    @property
    def TD(self) -> float:
        return 4.0 * self.ag / G_NTC + 1.6

    @property
    def TE(self) -> float:
        """T_E [s], start of the reduced displacement spectrum (Table 3.2.VII)."""
        return DISPLACEMENT_CORNERS[str(self.soil).strip().upper()][0]

    @property
    def TF(self) -> float:
        """T_F [s], start of the constant displacement d_g (Table 3.2.VII)."""
        return DISPLACEMENT_CORNERS[str(self.soil).strip().upper()][1]

    @property
    def dg(self) -> float:
        """Peak ground displacement d_g = 0.025 ag S TC TD [m] (eq. 3.2.12)."""
        return 0.025 * self.ag * self.S * self.TC * self.TD

    @property
    def pga(self) -> float:
        """Peak ground acceleration ag S [m/s²] (Se at T = 0)."""
        return self.ag * self.S

    def Se(self, T, damping: float = 0.05):
        """Elastic acceleration spectrum Se(T) [m/s²], NTC 2018 eq. 3.2.2.

        Parameters
        ----------
        T : float or array_like
            Periods [s], >= 0.
        damping : float
            Viscous damping ratio xi [-] (0.05 = 5 %), through eta (eq. 3.2.4).

        Returns
        -------
        float or numpy.ndarray
            Se [m/s²] with the shape of ``T``.
        """
        T = np.asarray(T, dtype=float)
        if np.any(~np.isfinite(T)) or np.any(T < 0):
            raise NTCError("periods must be finite and >= 0 s", key=("T",))
        xi = _check("damping", damping)
        eta = max(math.sqrt(10.0 / (5.0 + 100.0 * xi)), 0.55)
        a, F0, TB, TC, TD = self.ag * self.S, self.F0, self.TB, self.TC, self.TD
        Tp = np.maximum(T, 1e-12)
        out = np.where(
            T < TB, a * eta * F0 * (T / TB + (1.0 - T / TB) / (eta * F0)),
            np.where(T < TC, a * eta * F0,
                     np.where(T < TD, a * eta * F0 * TC / Tp, a * eta * F0 * TC * TD / Tp ** 2)))
        return out if out.ndim else float(out)

    def SDe(self, T, damping: float = 0.05):
        """Elastic displacement spectrum SDe(T) [m], NTC 2018 §3.2.3.2.3.

        SDe = Se(T) (T / 2 pi)^2 for T <= T_E (eq. 3.2.10); for T_E < T <= T_F
        SDe = 0.025 ag S TC TD [F0 eta + (1 - F0 eta) (T - T_E) / (T_F - T_E)] and for T > T_F
        SDe = d_g (eq. 3.2.11). Just above T_E the ordinate is 0.025 / (1 / 4 pi^2) = 0.987 of
        the one just below (the code's rounding of 1 / 4 pi^2 = 0.02533 to 0.025).

        Parameters
        ----------
        T : float or array_like
            Periods [s].
        damping : float
            Viscous damping ratio [-].

        Returns
        -------
        float or numpy.ndarray
            SDe [m].
        """
        T = np.asarray(T, dtype=float)
        out = np.asarray(self.Se(T, damping)) * (T / (2.0 * math.pi)) ** 2
        TE, TF, dg = self.TE, self.TF, self.dg
        if np.any(T > TE):
            eta = max(math.sqrt(10.0 / (5.0 + 100.0 * damping)), 0.55)
            fe = self.F0 * eta
            mid = dg * (fe + (1.0 - fe) * (np.minimum(T, TF) - TE) / (TF - TE))
            out = np.where(T > TF, dg, np.where(T > TE, mid, out))
        return out if out.ndim else float(out)
