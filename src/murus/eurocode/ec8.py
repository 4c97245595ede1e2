"""EN 1998-1:2004 (Eurocode 8, part 1) seismic action: elastic and design response spectra.

Clauses implemented (recommended values; every table can be overridden for a National Annex by
passing a :class:`SpectrumParameters`):

- §3.2.2.2 horizontal elastic response spectrum, eqs (3.2)-(3.5), Tables 3.2 (Type 1) and 3.3
  (Type 2) for ground types A-E; damping correction eta = sqrt(10 / (5 + xi)) >= 0.55, eq (3.6),
  xi in percent;
- §3.2.2.3 vertical elastic response spectrum, eqs (3.8)-(3.11), Table 3.4;
- §3.2.2.5 design spectrum for elastic analysis, eqs (3.13)-(3.16), with behaviour factor q and
  lower bound factor beta = 0.2 (recommended);
- §4.2.5 importance factors gamma_I (Table 4.3 classes I-IV: 0.8, 1.0, 1.2, 1.4, recommended);
  ag = gamma_I agR (§3.2.1(3)).

Units: periods in s, ag (design ground acceleration on type A ground) and the spectra in the unit
of ag (m/s² throughout murus). Periods beyond 4 s follow eq (3.5) (the standard defines the
spectrum up to 4 s; Annex A covers longer periods for displacement spectra).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

__all__ = [
    "SpectrumParameters", "TYPE1", "TYPE2", "VERTICAL", "IMPORTANCE_FACTORS", "parameters",
    "eta", "elastic_spectrum", "vertical_spectrum", "design_spectrum", "design_spectrum_vertical",
]


@dataclass(frozen=True)
class SpectrumParameters:
    """Soil factor S and corner periods TB, TC, TD [s] (EN 1998-1 Tables 3.2 / 3.3).

    Parameters
    ----------
    S : float
        Soil factor [-].
    TB, TC, TD : float
        Corner periods [s].
    """

    S: float
    TB: float
    TC: float
    TD: float


#: EN 1998-1 Table 3.2: Type 1 spectra (recommended values)
TYPE1 = {
    "A": SpectrumParameters(1.00, 0.15, 0.40, 2.0),
    "B": SpectrumParameters(1.20, 0.15, 0.50, 2.0),
    "C": SpectrumParameters(1.15, 0.20, 0.60, 2.0),
    "D": SpectrumParameters(1.35, 0.20, 0.80, 2.0),
    "E": SpectrumParameters(1.40, 0.15, 0.50, 2.0),
}
#: EN 1998-1 Table 3.3: Type 2 spectra (recommended values)
TYPE2 = {
    "A": SpectrumParameters(1.00, 0.05, 0.25, 1.2),
    "B": SpectrumParameters(1.35, 0.05, 0.25, 1.2),
    "C": SpectrumParameters(1.50, 0.10, 0.25, 1.2),
    "D": SpectrumParameters(1.80, 0.10, 0.30, 1.2),
    "E": SpectrumParameters(1.60, 0.05, 0.25, 1.2),
}
#: EN 1998-1 Table 3.4: vertical spectra, (avg/ag, TB, TC, TD) by spectrum type
VERTICAL = {
    1: (0.90, 0.05, 0.15, 1.0),
    2: (0.45, 0.05, 0.15, 1.0),
}
#: EN 1998-1 Table 4.3 / §4.2.5(5): recommended importance factors by class
IMPORTANCE_FACTORS = {"I": 0.8, "II": 1.0, "III": 1.2, "IV": 1.4}


def parameters(ground: str, spectrum_type: int = 1) -> SpectrumParameters:
    """S, TB, TC, TD for ground type 'A'-'E' and spectrum type 1 or 2 (Tables 3.2, 3.3).

    Parameters
    ----------
    ground : str
        Ground type ``"A"`` ... ``"E"``.
    spectrum_type : int
        1 or 2.

    Returns
    -------
    SpectrumParameters

    References
    ----------
    EN 1998-1 §3.2.2.2, Tables 3.2 and 3.3 (recommended values).
    """
    table = {1: TYPE1, 2: TYPE2}.get(int(spectrum_type))
    if table is None:
        raise ValueError(f"spectrum type must be 1 or 2, got {spectrum_type!r}")
    g = str(ground).strip().upper()
    if g not in table:
        raise ValueError(
            f"ground type must be one of A, B, C, D, E, got {ground!r} (S1, S2 need a "
            "site-specific study, EN 1998-1 §3.1.2(4))"
        )
    return table[g]


def eta(damping: float = 0.05) -> float:
    """Damping correction factor eta = sqrt(10 / (5 + xi%)) >= 0.55, EN 1998-1 eq (3.6).

    ``damping`` is the viscous damping ratio as a fraction (0.05 = 5 %).

    Parameters
    ----------
    damping : float
        Viscous damping ratio [-] (0.05 = 5 %).

    Returns
    -------
    float
        [-].
    """
    if damping < 0:
        raise ValueError("damping ratio must be >= 0")
    return max(float(np.sqrt(10.0 / (5.0 + 100.0 * damping))), 0.55)


def _importance(importance) -> float:
    if importance is None:
        return 1.0
    if isinstance(importance, str):
        try:
            return IMPORTANCE_FACTORS[importance.strip().upper()]
        except KeyError:
            raise ValueError(f"importance class must be I, II, III or IV, got {importance!r}") \
                from None
    return float(importance)


def _shape(T, ag, S, TB, TC, TD, plateau):
    """Piecewise spectrum of eqs (3.2)-(3.5) with plateau ordinate ``plateau`` (= 2.5 eta)."""
    T = np.asarray(T, dtype=float)
    if np.any(T < 0):
        raise ValueError("periods must be >= 0 s")
    out = np.where(
        T <= TB,
        ag * S * (1.0 + T / TB * (plateau - 1.0)),
        np.where(
            T <= TC,
            ag * S * plateau,
            np.where(T <= TD, ag * S * plateau * TC / np.maximum(T, 1e-12),
                     ag * S * plateau * TC * TD / np.maximum(T, 1e-12) ** 2),
        ),
    )
    return out


def elastic_spectrum(T, ag: float, ground: str = "A", spectrum_type: int = 1,
                     damping: float = 0.05, importance=None,
                     params: SpectrumParameters | None = None):
    """Horizontal elastic response spectrum Se(T), EN 1998-1 §3.2.2.2, eqs (3.2)-(3.5).

    Parameters
    ----------
    T : float or array
        Periods [s].
    ag : float
        Reference peak ground acceleration on type A ground agR [m/s²]; multiplied by the
        importance factor to give ag (§3.2.1(3)).
    ground : 'A'..'E'; spectrum_type : 1 or 2 (§3.2.2.2(2)).
    damping : viscous damping ratio (fraction) for eta, eq (3.6).
    importance : class 'I'-'IV' or a factor gamma_I (default 1.0).
    params : SpectrumParameters overriding Tables 3.2 / 3.3 (National Annex).

    Returns Se [m/s²] with the shape of ``T``.
    """
    p = params if params is not None else parameters(ground, spectrum_type)
    a = ag * _importance(importance)
    return _shape(T, a, p.S, p.TB, p.TC, p.TD, 2.5 * eta(damping))


def vertical_spectrum(T, ag: float, spectrum_type: int = 1, damping: float = 0.05,
                      importance=None, avg_ratio: float | None = None,
                      corners: tuple[float, float, float] | None = None):
    """Vertical elastic response spectrum Sve(T), EN 1998-1 §3.2.2.3, eqs (3.8)-(3.11).

    avg = avg_ratio ag (Table 3.4: 0.90 Type 1, 0.45 Type 2); corners (TB, TC, TD) default
    (0.05, 0.15, 1.0) s. No soil factor (S = 1). Sve in the unit of ag.

    Parameters
    ----------
    T : float or array_like
        Periods [s].
    ag : float
        Design ground acceleration on type A ground [m/s²] (times the importance factor).
    spectrum_type : int
        1 or 2.
    damping : float
        Viscous damping ratio [-].
    importance : str or float, optional
        Importance class ``"I"`` ... ``"IV"`` or the factor gamma_I.
    avg_ratio : float, optional
        ``avg / ag`` [-] (default Table 3.4).
    corners : tuple of float, optional
        ``(TB, TC, TD)`` [s] (default Table 3.4).

    Returns
    -------
    float or numpy.ndarray
        Sve [in the unit of ``ag``].
    """
    r, TB, TC, TD = VERTICAL[int(spectrum_type)] if int(spectrum_type) in VERTICAL else (
        None, None, None, None)
    if r is None:
        raise ValueError(f"spectrum type must be 1 or 2, got {spectrum_type!r}")
    if avg_ratio is not None:
        r = float(avg_ratio)
    if corners is not None:
        TB, TC, TD = corners
    avg = r * ag * _importance(importance)
    T = np.asarray(T, dtype=float)
    e = eta(damping)
    # eqs (3.8)-(3.11): avg [1 + T/TB (3.0 eta - 1)], 3.0 avg eta, ...
    return _shape(T, avg, 1.0, TB, TC, TD, 3.0 * e)


def design_spectrum(T, ag: float, q: float, ground: str = "A", spectrum_type: int = 1,
                    importance=None, beta: float = 0.2,
                    params: SpectrumParameters | None = None):
    """Horizontal design spectrum Sd(T) for elastic analysis, EN 1998-1 §3.2.2.5, eqs
    (3.13)-(3.16):

    0 <= T <= TB: ag S [2/3 + T/TB (2.5/q - 2/3)];  TB-TC: ag S 2.5/q;
    TC-TD: max(ag S 2.5/q TC/T, beta ag);  T >= TD: max(ag S 2.5/q TC TD/T², beta ag).
    q is the behaviour factor (>= 1 here; q = 1 still gives 2/3 ag S at T = 0 as in the code).

    Parameters
    ----------
    T : float or array_like
        Periods [s].
    ag : float
        Design ground acceleration on type A ground [m/s²] (times the importance factor).
    q : float
        Behaviour factor [-] (>= 1).
    ground : str
        Ground type ``"A"`` ... ``"E"``.
    spectrum_type : int
        1 or 2.
    importance : str or float, optional
        Importance class or factor.
    beta : float
        Lower bound factor [-].
    params : SpectrumParameters, optional
        Overrides the recommended S, TB, TC, TD.

    Returns
    -------
    float or numpy.ndarray
        Sd [in the unit of ``ag``].
    """
    if q <= 0:
        raise ValueError("behaviour factor q must be positive")
    p = params if params is not None else parameters(ground, spectrum_type)
    a = ag * _importance(importance)
    T = np.asarray(T, dtype=float)
    if np.any(T < 0):
        raise ValueError("periods must be >= 0 s")
    S, TB, TC, TD = p.S, p.TB, p.TC, p.TD
    Tsafe = np.maximum(T, 1e-12)
    return np.where(
        T <= TB,
        a * S * (2.0 / 3.0 + T / TB * (2.5 / q - 2.0 / 3.0)),
        np.where(
            T <= TC,
            a * S * 2.5 / q,
            np.where(T <= TD, np.maximum(a * S * 2.5 / q * TC / Tsafe, beta * a),
                     np.maximum(a * S * 2.5 / q * TC * TD / Tsafe**2, beta * a)),
        ),
    )


def design_spectrum_vertical(T, ag: float, q: float = 1.5, spectrum_type: int = 1,
                             importance=None, beta: float = 0.2):
    """Vertical design spectrum, EN 1998-1 §3.2.2.5(6): eqs (3.13)-(3.16) with avg in place of
    ag S (S = 1) and the corner periods of Table 3.4; q up to 1.5 for all materials.

    Parameters
    ----------
    T : float or array_like
        Periods [s].
    ag : float
        Design ground acceleration on type A ground [m/s²] (times the importance factor).
    q : float
        Behaviour factor [-] (up to 1.5).
    spectrum_type : int
        1 or 2.
    importance : str or float, optional
        Importance class or factor.
    beta : float
        Lower bound factor [-].

    Returns
    -------
    float or numpy.ndarray
        Sd,v [in the unit of ``ag``].
    """
    r, TB, TC, TD = VERTICAL[int(spectrum_type)]
    return design_spectrum(T, r * ag, q, importance=importance, beta=beta,
                           params=SpectrumParameters(1.0, TB, TC, TD))


def with_overrides(p: SpectrumParameters, **kw) -> SpectrumParameters:
    """A copy of ``p`` with some of S, TB, TC, TD replaced (National Annex values)."""
    return replace(p, **kw)
