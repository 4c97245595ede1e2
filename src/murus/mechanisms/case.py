"""Case files (TOML) of the kinematic checks of local mechanisms: schema, validation, run.

Example (``examples/mechanisms/two_storey_facade.toml``)::

    title = "two-storey façade"
    [site]                  # the seismic hazard of each limit state
    spectrum = "ntc"        # "ntc" (NTC 2018 §3.2.3.2) or "ec8" (EN 1998-1 §3.2.2.2)
    soil = "B"              # ntc: soil category A-E; ec8: use ground = "B", spectrum_type = 1
    topography = "T1"       # ntc: T1-T4 or the factor S_T
    [site.SLV]              # required; [site.SLD] and [site.SLC] optional
    ag_g = 0.20             # or ag [m/s2]
    F0 = 2.4                # ntc only
    Tc_star = 0.30          # ntc only [s]
    [building]              # for mechanisms above the ground (floor spectra, §C7.2.3)
    T1 = 0.25               # s
    height = 6.5            # m (default: the sum of the storeys)
    storeys = 2             # (default: the number of [[storeys]])
    damping = 0.05
    [analysis]
    FC = 1.35               # confidence factor 1.00..1.35
    q = 2.0                 # behaviour factor of the linear SLV check
    mechanisms = ["overturning", "vertical-flexure"]
    ties_in_curve = false   # ties act in alpha0, not in the curve that gives d0 (§C8.7.1.2.1.6)
    slices = 1              # weights per storey (overturning): 1 = one per block, as eq. C8.7.1.1
    verdict = "code"        # SLV verdict by the nonlinear check ("all": every check governs)
    [[storeys]]             # bottom to top
    height = 3.5            # m
    thickness = 0.5         # m
    density = 1800.0        # kg/m3 (or weight [N])
    width = 1.0             # m (the strip analysed)
    openings = 0.0          # m2 of openings in the strip
    [[floors]]
    level = 1               # the floor on top of storey 1
    load = 20.0e3           # N
    x = 0.30                # m from the outer face (default: mid-thickness)
    tie = 10.0e3            # N, strength of the tie (0: none)
    thrust = 0.0            # N, outward
    [[corners]]             # optional: overturning of a corner wedge (kinematics.CornerOverturning)
    height = 6.7            # m above the hinge
    t1 = 0.45               # m, the two walls
    t2 = 0.45
    density = 2000.0
    crack_angle_deg = 30.0  # cracks from the vertical
    roof_load = 5.0e3       # N on the wedge; thrust (hip rafter), tie1, tie2 [N]; z0 [m]
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import Field, model_validator

from murus.config import Strict, fail_at, load_toml, locate, validate

__all__ = ["MechanismCase", "load_case", "build", "run_case"]

_G = 9.81

Pos = Field(gt=0, allow_inf_nan=False)


class HazardCfg(Strict):
    ag: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    ag_g: float | None = Field(default=None, ge=0, le=1.5, allow_inf_nan=False)
    F0: float | None = Field(default=None, allow_inf_nan=False)
    Tc_star: float | None = Field(default=None, allow_inf_nan=False)

    @model_validator(mode="after")
    def _one_ag(self):
        if (self.ag is None) == (self.ag_g is None):
            raise ValueError("give either ag [m/s2] or ag_g [g]")
        return self

    @property
    def ag_si(self) -> float:
        return self.ag if self.ag is not None else self.ag_g * _G


class SiteCfg(Strict):
    spectrum: Literal["ntc", "ec8"] = "ntc"
    soil: str = "A"
    topography: str | float = "T1"
    ground: str = "A"
    spectrum_type: int = 1
    importance: str | float | None = None
    SLD: HazardCfg | None = None
    SLV: HazardCfg
    SLC: HazardCfg | None = None


class BuildingCfg(Strict):
    T1: float = Pos
    height: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    storeys: int | None = Field(default=None, ge=1)
    damping: float = Field(default=0.05, gt=0, le=0.3, allow_inf_nan=False)


class AnalysisCfg(Strict):
    FC: float = Field(default=1.35, ge=1.0, le=1.35, allow_inf_nan=False)
    q: float = Field(default=2.0, ge=1.0, le=4.0, allow_inf_nan=False)
    mechanisms: list[Literal["overturning", "vertical-flexure", "corner"]] = [
        "overturning", "vertical-flexure", "corner"]
    flexure_storeys: list[int] | None = None
    points: int = Field(default=101, ge=11, le=10001)
    ties_in_curve: bool = False
    slices: int = Field(default=1, ge=1, le=1000)
    verdict: Literal["code", "all"] = "code"


class StoreyCfg(Strict):
    height: float = Pos
    thickness: float = Pos
    density: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    weight: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    width: float = Field(default=1.0, gt=0, allow_inf_nan=False)
    openings: float = Field(default=0.0, ge=0, allow_inf_nan=False)


class FloorCfg(Strict):
    level: int = Field(ge=1)
    load: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    x: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    tie: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    thrust: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    inertial: bool = True


class CornerCfg(Strict):
    height: float = Pos
    t1: float = Pos
    t2: float = Pos
    density: float = Pos
    crack_angle_deg: float = Field(default=30.0, gt=0, lt=75, allow_inf_nan=False)
    roof_load: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    roof_load_s: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    thrust: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    tie1: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    tie2: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    z0: float = Field(default=0.0, ge=0, allow_inf_nan=False)


class MechanismCase(Strict):
    """A validated case file (module docstring).

    Attributes
    ----------
    title : str
    site, building, analysis
        The tables ``[site]``, ``[building]``, ``[analysis]``.
    storeys, floors, corners : list
        The arrays of tables ``[[storeys]]``, ``[[floors]]``, ``[[corners]]``.
    """

    title: str = "façade"
    site: SiteCfg
    building: BuildingCfg | None = None
    analysis: AnalysisCfg = AnalysisCfg()
    storeys: list[StoreyCfg] = Field(min_length=1)
    floors: list[FloorCfg] = []
    corners: list[CornerCfg] = []


def load_case(path) -> tuple[MechanismCase, Path, str]:
    """Read and validate a mechanism case file; errors are one-line :class:`CaseError`.

    Parameters
    ----------
    path : path-like
        The TOML file.

    Returns
    -------
    tuple
        ``(case, path, text)``.
    """
    path = Path(path)
    data, text = load_toml(path)
    return validate(MechanismCase, data, path, text), path, text


def _spectrum(site: SiteCfg, ls: str, h: HazardCfg, path: Path, text: str):
    from murus.eurocode.ntc import NTCError, NTCSpectrum
    from murus.mechanisms.demand import EC8Spectrum

    try:
        if site.spectrum == "ntc":
            for k in ("F0", "Tc_star"):
                if getattr(h, k) is None:
                    raise fail_at(path, text, ("site", ls, k), "required key is missing for "
                                  "the NTC spectrum")
            try:
                return NTCSpectrum(h.ag_si, h.F0, h.Tc_star, site.soil, site.topography)
            except NTCError as exc:
                k = exc.key[0] if exc.key else "ag"
                loc = ("site", k) if k in ("soil", "topography") else (
                    "site", ls, "ag" if h.ag is not None else "ag_g") if k == "ag" else (
                    "site", ls, k)
                raise fail_at(path, text, loc, str(exc)) from None
        for k in ("F0", "Tc_star"):
            if getattr(h, k) is not None:
                raise fail_at(path, text, ("site", ls, k), "not a parameter of the EN 1998-1 "
                              "spectrum")
        return EC8Spectrum(h.ag_si, site.ground, site.spectrum_type, site.importance)
    except ValueError as exc:
        if getattr(exc, "source", None) is not None:
            raise
        raise fail_at(path, text, ("site",), str(exc)) from None


def _needs_building(case: MechanismCase, n: int) -> bool:
    """True when a mechanism of the case stands above the ground (floor spectra needed)."""
    a = case.analysis
    if "overturning" in a.mechanisms and n > 1:
        return True
    if "vertical-flexure" in a.mechanisms and max(a.flexure_storeys or [n]) > 1:
        return True
    return "corner" in a.mechanisms and any(c.z0 > 0 for c in case.corners)


def build(case: MechanismCase, path: Path, text: str):
    """Storeys, floors and seismic input of a validated case.

    Parameters
    ----------
    case : MechanismCase
    path : pathlib.Path
    text : str
        The TOML text (for the lines of the errors).

    Returns
    -------
    tuple
        ``(storeys, floors, seismic)``.
    """
    from murus.mechanisms.checks import Seismic
    from murus.mechanisms.demand import Building, DemandError
    from murus.mechanisms.kinematics import Floor, MechanismError, Storey

    storeys = []
    for i, s in enumerate(case.storeys):
        try:
            storeys.append(Storey(**s.model_dump()))
        except MechanismError as exc:
            raise locate(exc, path, text, ("storeys", i)) from None
    n = len(storeys)
    floors = []
    for i, f in enumerate(case.floors):
        if f.level > n:
            raise fail_at(path, text, ("floors", i, "level"),
                          f"level {f.level} is above the top storey ({n})")
        try:
            floors.append(Floor(**f.model_dump()))
        except MechanismError as exc:
            raise locate(exc, path, text, ("floors", i)) from None
    spectra = {}
    for ls in ("SLD", "SLV", "SLC"):
        h = getattr(case.site, ls)
        if h is not None:
            spectra[ls] = _spectrum(case.site, ls, h, path, text)
    bld = None
    if case.building is not None:
        b = case.building
        H = b.height if b.height is not None else sum(s.height for s in storeys)
        try:
            bld = Building(b.T1, H, b.storeys if b.storeys is not None else n, b.damping)
        except DemandError as exc:
            raise locate(exc, path, text, ("building",)) from None
        if H < sum(s.height for s in storeys) * (1 - 1e-9):
            raise fail_at(path, text, ("building", "height"), f"{H:g} m is lower than the "
                          "façade")
    elif _needs_building(case, n):
        raise fail_at(path, text, ("building",), "required for mechanisms above the ground "
                      "(T1 [s] for the floor spectra of the Circolare 2019 §C7.2.3)")
    a = case.analysis
    try:
        seismic = Seismic(spectra, bld, a.FC, a.q)
    except MechanismError as exc:
        raise locate(exc, path, text, ("analysis",)) from None
    if a.flexure_storeys is not None:
        for j, k in enumerate(a.flexure_storeys):
            if not 1 <= k <= n:
                raise fail_at(path, text, ("analysis", "flexure_storeys", j),
                              f"storey {k} is not in 1..{n}")
    return storeys, floors, seismic


def run_case(case: MechanismCase, path: Path, text: str) -> dict:
    """Run the mechanisms of a case.

    Parameters
    ----------
    case : MechanismCase
    path : pathlib.Path
    text : str

    Returns
    -------
    dict
        ``results`` (list of MechanismResult, by mechanism and hinge), ``governing``
        (MechanismResult), ``seismic``.
    """
    from murus.mechanisms.facade import flexure_of_storey, governing, overturning
    from murus.mechanisms.kinematics import MechanismError

    storeys, floors, seismic = build(case, path, text)
    a = case.analysis
    results = []
    from murus.mechanisms.kinematics import SimpleOverturning

    try:
        SimpleOverturning(storeys, floors)
    except MechanismError as exc:
        raise locate(exc, path, text) from None
    try:
        if "overturning" in a.mechanisms:
            results += overturning(storeys, floors, seismic, a.points, a.ties_in_curve,
                                   a.slices, a.verdict)
        if "vertical-flexure" in a.mechanisms:
            ks = a.flexure_storeys or list(range(1, len(storeys) + 1))
            for k in ks:
                results.append(flexure_of_storey(storeys, floors, k - 1, seismic, a.points,
                                                 a.verdict))
    except MechanismError as exc:
        raise fail_at(path, text, ("storeys",), str(exc)) from None
    if "corner" in a.mechanisms:
        from murus.mechanisms.checks import analyse
        from murus.mechanisms.kinematics import CornerOverturning

        for i, c in enumerate(case.corners):
            try:
                mech = CornerOverturning(**c.model_dump())
                res = analyse(mech, seismic, a.points, a.ties_in_curve, a.verdict)
            except MechanismError as exc:
                raise locate(exc, path, text, ("corners", i)) from None
            res.name = f"corner overturning {i + 1}"
            results.append(res)
    return {"results": results, "governing": governing(results), "seismic": seismic}
