"""Linear and nonlinear kinematic checks of local mechanisms, Circolare 2019 §C8.7.1.2.1.

For a mechanism (:mod:`murus.mechanisms.kinematics`):

Equivalent oscillator (§C8.7.1.2.1.3):
    alpha0 by virtual work, eq. [C8.7.1.1]; e* eq. [C8.7.1.5]; M* = e* sum W / g;
    capacity curve a(d): a = alpha(d_C) g / (e* FC), eq. [C8.7.1.3];
    d = d_C sum W dx^2 / (dx_C sum W dx), eq. [C8.7.1.4]; d0 where a vanishes.

Linear check (§C8.7.1.2.1.5 and §C8.7.1.2.1.7):
    activation acceleration a0* = alpha0 g / (e* FC), eq. [C8.7.1.8] (2009: C8A.4.4).
    SLD: a0* >= a_Z,SLD(z), the peak acceleration at the height z of the mechanism (ground:
    ag S; at height eqs. [C7.2.7]-[C7.2.8], never below ag S);
    SLV: ag,SLV = q ag,SLD >= ag (q = 2 unless better known); murus writes it as
    a0* >= a_Z,SLV(z) / q, with a_Z proportional to ag (the spectral shape of the SLV hazard
    kept fixed), so that capacity / demand = ag,SLV / ag. At ground level this is the
    a0* >= ag S / q of the 2009 Circolare (eq. C8A.4.9).

Nonlinear check (§C8.7.1.2.1.6 and §C8.7.1.2.1.8):
    d_SLV = 0.4 d0, d_SLC = 0.6 d0 (§C8.7.1.2.1.6, on the curve with the actions present up to
    collapse); secant periods T_SLV = 1.68 pi sqrt(d_SLV / a(d_SLV)), eq. [C8.7.1.10],
    T_SLC = 1.56 pi sqrt(d_SLC / a(d_SLC)), eq. [C8.7.1.11]; demand SDe(T) at ground or
    S_eZ(T, xi, z) T^2 / 4 pi^2 at height, eq. [C8.7.1.12], with xi = 8 % (SLV), 10 % (SLC);
    capacity / demand = d / demand (= ag,SLV / ag for a demand proportional to ag); when it is
    lower than the activation ratio of the SLD check (with the SLV hazard) the latter is taken
    (§C8.7.1.2.1.8: "si assume quest'ultima anche per lo SLV").

The 2009 Circolare (C8A.4) used d_u* = 0.4 d0*, T_s = 2 pi sqrt(d_s*/a_s*) with d_s* = 0.4 d_u*;
murus follows the 2019 text (found in the transcription of the Circolare by
claudiopagani/structural-codes, corpus/units/circ2019/c8.7.1.2.1.*).

References
----------
Circolare 21 gennaio 2019 n. 7 C.S.LL.PP., §C8.7.1.2.1 and §C7.2.3; Circolare 2 febbraio 2009
n. 617, §C8A.4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from murus.mechanisms.demand import Building, displacement_demand, floor_acceleration
from murus.mechanisms.kinematics import (
    GRAVITY,
    Mechanism,
    MechanismError,
    alpha,
    control_x,
    participation,
)

__all__ = ["PARAMS", "LIMIT_STATES", "Seismic", "Check", "MechanismResult", "analyse",
           "capacity_curve"]

#: Declared parameters: name -> (low, high, default, unit, source)
PARAMS = {
    "FC": (1.0, 1.35, 1.35, "-", "Circolare 2019 §C8.5.4, Table C8.5.IV (LC1-LC3)"),
    "q": (1.0, 4.0, 2.0, "-", "Circolare 2019 §C8.7.1.2.1.7 (q = 2 without better evaluation)"),
}

#: The limit states of the checks: fraction of d0, period coefficient (x pi), damping
LIMIT_STATES = {
    "SLD": {"linear": True},
    "SLV": {"d0_fraction": 0.4, "period": 1.68, "damping": 0.08,
            "eq": "[C8.7.1.10], [C8.7.1.12]"},
    "SLC": {"d0_fraction": 0.6, "period": 1.56, "damping": 0.10, "eq": "[C8.7.1.11]"},
}


def _param(name, value):
    lo, hi, _, unit, src = PARAMS[name]
    v = float(value)
    if not (math.isfinite(v) and lo <= v <= hi):
        raise MechanismError(f"{name} must be in {lo:g}..{hi:g} ({src}), got {value!r}",
                             key=(name,))
    return v


@dataclass(frozen=True)
class Seismic:
    """The seismic input of the checks.

    Parameters
    ----------
    spectra : dict
        Ground spectra by limit state ``"SLD"``, ``"SLV"``, ``"SLC"`` (``SLV`` required); each
        with ``Se(T, damping)``, ``SDe(T, damping)`` and ``pga`` (ag S) [m/s²].
    building : Building, optional
        The main structure, for mechanisms above the ground (floor spectra of §C7.2.3).
    FC : float
        Confidence factor (1.00..1.35).
    q : float
        Behaviour factor of the linear SLV check (default 2.0).
    """

    spectra: dict
    building: Building | None = None
    FC: float = 1.35
    q: float = 2.0

    def __post_init__(self):
        _param("FC", self.FC)
        _param("q", self.q)
        if "SLV" not in self.spectra:
            raise MechanismError("the SLV spectrum is required", key=("SLV",))
        bad = set(self.spectra) - set(LIMIT_STATES)
        if bad:
            raise MechanismError(f"unknown limit state {sorted(bad)[0]!r} (SLD, SLV, SLC)",
                                 key=(sorted(bad)[0],))


@dataclass(frozen=True)
class Check:
    """One check: capacity >= demand (ratio = capacity / demand >= 1 passes).

    Attributes
    ----------
    limit_state : str
        ``"SLD"``, ``"SLV"`` or ``"SLC"``.
    method : str
        ``"linear"`` (accelerations) or ``"nonlinear"`` (displacements).
    quantity : str
        The checked quantity (``"a0*"``, ``"d_SLV"``, ...).
    capacity, demand : float
        In ``unit`` (m/s2 or m).
    unit : str
    ratio : float
        capacity / demand as defined by the check (module docstring).
    equation : str
        The equations of the Circolare used.
    details : dict
        Intermediate values (period, damping, floor acceleration, ...).
    governs : bool
        The check enters the verdict of the mechanism (False: the simplified linear SLV check
        when the nonlinear one was made, shown for information; :func:`analyse`).
    """

    limit_state: str
    method: str
    quantity: str
    capacity: float
    demand: float
    unit: str
    ratio: float
    equation: str
    details: dict = field(default_factory=dict)
    governs: bool = True

    @property
    def passed(self) -> bool:
        return bool(self.ratio >= 1.0)

    def as_dict(self) -> dict:
        return {"limit_state": self.limit_state, "method": self.method, "governs": self.governs,
                "quantity": self.quantity, "capacity": self.capacity, "demand": self.demand,
                "unit": self.unit, "ratio": self.ratio, "passed": self.passed,
                "equation": self.equation, **self.details}


@dataclass
class MechanismResult:
    """Result of the kinematic checks of one mechanism (SI units).

    Attributes
    ----------
    name : str
    z : float
        Height of the base of the mechanism [m].
    alpha0 : float
        Activation multiplier [-].
    e_star, M_star : float
        Participating mass fraction [-] and mass [kg].
    a0_star : float
        Spectral activation acceleration [m/s²].
    d0_star : float
        Displacement of the equivalent oscillator where a* vanishes [m].
    curve : dict
        ``theta`` [rad], ``alpha`` [-], ``d_star`` [m], ``a_star`` [m/s²] (capacity curve).
    checks : list of Check
    """

    name: str
    z: float
    alpha0: float
    e_star: float
    M_star: float
    a0_star: float
    d0_star: float
    FC: float
    curve: dict
    checks: list
    info: dict = field(default_factory=dict)

    @property
    def ratio(self) -> float:
        """The smallest capacity / demand ratio of the checks that govern."""
        return min(c.ratio for c in self.checks if c.governs)

    @property
    def passed(self) -> bool:
        return all(c.passed for c in self.checks if c.governs)

    def summary(self) -> dict:
        return {"name": self.name, "z": self.z, "alpha0": self.alpha0, "e_star": self.e_star,
                "M_star": self.M_star, "a0_star": self.a0_star, "d0_star": self.d0_star,
                "FC": self.FC, "ratio": self.ratio, "passed": self.passed, **self.info,
                "checks": [c.as_dict() for c in self.checks],
                "capacity_curve": {"d_star": [float(x) for x in self.curve["d_star"]],
                                   "a_star": [float(x) for x in self.curve["a_star"]]}}


def _collapse_rotation(mech: Mechanism) -> float:
    """Rotation theta0 where alpha vanishes [rad] (bisection after a scan)."""
    a0 = alpha(mech, 0.0)
    if a0 <= 0:
        raise MechanismError(f"{mech.name}: alpha0 = {a0:.3g} <= 0: the wall is unstable "
                             "under its own loads")
    top = mech.theta_max * 0.999
    grid = np.linspace(0.0, top, 400)
    prev = 0.0
    for th in grid[1:]:
        try:
            a = alpha(mech, float(th))
        except MechanismError:
            a = -1.0
        if not math.isfinite(a) or a <= 0:
            lo, hi = prev, float(th)
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                try:
                    am = alpha(mech, mid)
                except MechanismError:
                    am = -1.0
                if math.isfinite(am) and am > 0:
                    lo = mid
                else:
                    hi = mid
            return 0.5 * (lo + hi)
        prev = float(th)
    raise MechanismError(f"{mech.name}: alpha stays positive up to theta = {top:.3g} rad: "
                         "no collapse displacement d0 (ties too strong for a rigid-block "
                         "curve)")


def capacity_curve(mech: Mechanism, FC: float = 1.0, n: int = 101) -> dict:
    """Capacity curve of the equivalent oscillator, Circolare 2019 eqs. [C8.7.1.3]-[C8.7.1.4].

    Parameters
    ----------
    mech : Mechanism
    FC : float
        Confidence factor.
    n : int
        Number of points from theta = 0 to the collapse rotation.

    Returns
    -------
    dict
        ``theta`` [rad], ``alpha`` [-], ``d_star`` [m], ``a_star`` [m/s²], ``theta0`` [rad],
        ``d0_star`` [m] and the participation of :func:`participation`.
    """
    part = participation(mech)
    th0 = _collapse_rotation(mech)
    theta = np.linspace(0.0, th0, n)
    al = np.array([alpha(mech, float(t)) for t in theta])
    al[-1] = 0.0
    x0 = control_x(mech, 0.0)
    dC = np.array([control_x(mech, float(t)) - x0 for t in theta])
    d = dC * part["factor"]
    a = al * GRAVITY / (part["e_star"] * FC)
    return {"theta": theta, "alpha": al, "d_star": d, "a_star": a, "theta0": th0,
            "d0_star": float(d[-1]), **part}


class _WithoutTies:
    """``mech`` with its ties removed (the capacity curve without the ties, :func:`analyse`)."""

    def __init__(self, mech):
        self.mech = mech
        self.name = mech.name
        self.theta_max = mech.theta_max

    def state(self, theta):
        from dataclasses import replace

        s = self.mech.state(theta)
        return replace(s, T=np.zeros_like(s.T))


def analyse(mech: Mechanism, seismic: Seismic, n: int = 101,
            ties_in_curve: bool = False, verdict: str = "code") -> MechanismResult:
    """Linear and nonlinear kinematic checks of ``mech`` (module docstring).

    Parameters
    ----------
    mech : Mechanism
    seismic : Seismic
    n : int
        Points of the capacity curve.
    ties_in_curve : bool
        Keep the ties in the capacity curve of the nonlinear checks. The curve that gives d0
        holds "only the actions whose presence is verified up to collapse" (§C8.7.1.2.1.6): a tie
        at its strength up to rotations of tens of degrees rarely is, so by default the ties act
        in alpha0 (linear checks, and the activation ratio that bounds the nonlinear ones from
        below) and not in the curve.
    verdict : str
        ``"code"``: the SLV verdict is the nonlinear check, the linear one (with q) being the
        simplified method for when no capacity curve is computed (§C8.7.1.2.1.7); it is kept
        for information. ``"all"``: every check governs (the more conservative reading).

    Returns
    -------
    MechanismResult
    """
    if verdict not in ("code", "all"):
        raise MechanismError(f"verdict must be 'code' or 'all', got {verdict!r}",
                             key=("verdict",))
    FC, q = seismic.FC, seismic.q
    al0 = alpha(mech, 0.0)
    has_ties = bool(mech.state(0.0).T.size)
    cur = capacity_curve(mech if ties_in_curve or not has_ties else _WithoutTies(mech), FC, n)
    e = cur["e_star"]
    a0s = al0 * GRAVITY / (e * FC)
    z = mech.z
    bld = seismic.building
    if z > 0 and bld is None:
        raise MechanismError(f"{mech.name}: the mechanism is at z = {z:g} m: give the building "
                             "(T1, height, storeys) for the floor spectra", key=("building",))

    def peak(sp) -> tuple[float, float]:
        ground = float(sp.pga)
        floor = floor_acceleration(sp, bld, z) if z > 0 else 0.0
        return max(ground, floor), floor

    checks = []
    if "SLD" in seismic.spectra:
        dem, floor = peak(seismic.spectra["SLD"])
        checks.append(Check("SLD", "linear", "a0*", a0s, dem, "m/s2", a0s / dem,
                            "[C8.7.1.8], [C7.2.8]", {"a_ground": float(
                                seismic.spectra["SLD"].pga), "a_floor": floor}))
    sp = seismic.spectra["SLV"]
    dem, floor = peak(sp)
    act = a0s / dem
    checks.append(Check("SLV", "linear", "a0*", a0s, dem / q, "m/s2", a0s * q / dem,
                        "[C8.7.1.8], [C7.2.8], q (C8.7.1.2.1.7)",
                        {"q": q, "a_ground": float(sp.pga), "a_floor": floor},
                        governs=verdict == "all"))
    d, a = cur["d_star"], cur["a_star"]
    for ls in ("SLV", "SLC"):
        if ls not in seismic.spectra:
            continue
        spec = LIMIT_STATES[ls]
        sp = seismic.spectra[ls]
        du = spec["d0_fraction"] * cur["d0_star"]
        au = float(np.interp(du, d, a))
        if au <= 0:
            raise MechanismError(f"{mech.name}: a(d_{ls}) <= 0")
        T = spec["period"] * math.pi * math.sqrt(du / au)
        demand = displacement_demand(sp, T, spec["damping"], bld, z)
        ratio = du / demand
        act_ls = a0s / peak(sp)[0]
        details = {"T": T, "a_at_d": au, "damping": spec["damping"],
                   "displacement_ratio": ratio, "activation_ratio": act_ls}
        checks.append(Check(ls, "nonlinear", f"d_{ls}", du, demand, "m", max(ratio, act_ls),
                            spec["eq"], details))
    info = {"activation_ratio_SLV": act, "ties_in_curve": bool(ties_in_curve and has_ties)}
    return MechanismResult(mech.name, z, al0, e, cur["M_star"], a0s, cur["d0_star"], FC,
                           {k: cur[k] for k in ("theta", "alpha", "d_star", "a_star")},
                           checks, info)
