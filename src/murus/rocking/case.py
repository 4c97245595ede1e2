"""Rocking case files (TOML): schema, validation and conversion into model objects.

Example (every key documented in the README)::

    [body]
    width = 0.6          # m, b (in the plane of rocking)
    height = 6.0         # m, h
    thickness = 1.0      # m
    density = 2140.7     # kg/m3, uniform rectangle (omit for a massless wall)
    top_mass = 0.0       # kg at mid-top
    [restitution]
    law = "housner"      # or "constant" (value = 0.9), "coefficient" (k = 1.5: e = 1 - k sin2
                         # alpha, Mordant et al. (SERIES), eqs. 14-15), "amplitude-dependent" (k0,
                         # k1, k0_free, k1_free, A0, variant = "causal" | "iterated": eqs. 16-18)
    [pivot]              # Mordant et al. (SERIES), §3.3.1
    law = "corner"       # or "compressive-length" with reading = "effective-width" | "kern" |
                         # "neutral-axis", factor = 1.0, min_lever_fraction = 0.05
    [restraint]          # EURODYN (2020)
    motion_sides = "two" # or "one": inward rotations against the transverse walls
    [restraint.tie]
    stiffness = 7.0e4    # N/m; height (m), x (m, body coordinate), tension_only = true,
    height = 6.0         # pretension (N), yield_force (N)
    [restraint.damper]
    coefficient = 1.0e3  # N s/m, or fraction (of c_d) with delta_t (s), EURODYN (2020), eq. 13
    height = 6.0
    [restraint.transverse_walls]
    stiffness = 4.5e8    # N/m per m of height, or "rigid"; effective_height (m), z1 (m), x (m)
    effective_height = 6.0
    [base]               # the support: "rigid" (default) or an elastic layer, e.g. rubber
    model = "winkler"    # stiffness (N/m3) or modulus (Pa) with layer_thickness (m);
    stiffness = 1.0e9    # damping (N s/m3) or damping_ratio; kinematics = "corner" | "centre"
    [motion]
    file = "record.csv"  # two columns time [s], acceleration (or one column with dt)
    units = "g"
    scale = 1.0
    # or: type = "sine-pulse" | "cosine-pulse" (amplitude m/s2 or amplitude_g, frequency Hz,
    #     cycles), "rectangular-pulse" (amplitude, duration), "free" (theta0_over_alpha)
    [solver]
    method = "event"     # or "newmark" with dt
    duration = 20.0      # s (default: end of the motion plus 5 s of free motion)
    rest_tol = 1e-3      # cascades of impacts summed below rest_tol * p * alpha (0: never)
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Literal

from pydantic import Field, field_validator, model_validator

from murus.config import MotionFields, Strict, fail_at, load_toml, locate, validate


class BodyCfg(Strict):
    width: float = Field(gt=0, allow_inf_nan=False)
    height: float = Field(gt=0, allow_inf_nan=False)
    thickness: float = Field(default=1.0, gt=0, allow_inf_nan=False)
    density: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    top_mass: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    name: str = "wall"

    @model_validator(mode="after")
    def _has_mass(self):
        if self.density == 0.0 and self.top_mass == 0.0:
            raise ValueError("the body has no mass: give density and/or top_mass")
        return self


Coef = float | None


class RestitutionCfg(Strict):
    law: Literal["housner", "constant", "coefficient", "amplitude-dependent"] = "housner"
    value: float | None = Field(default=None, ge=0.0, le=1.0, allow_inf_nan=False)
    k: Coef = Field(default=None, ge=0.0, allow_inf_nan=False)
    k0: Coef = Field(default=None, ge=0.0, allow_inf_nan=False)
    k1: Coef = Field(default=None, ge=0.0, allow_inf_nan=False)
    k0_free: Coef = Field(default=None, ge=0.0, allow_inf_nan=False)
    k1_free: Coef = Field(default=None, ge=0.0, allow_inf_nan=False)
    A0: Coef = Field(default=None, gt=0.0, allow_inf_nan=False)
    variant: Literal["causal", "iterated"] | None = None

    @model_validator(mode="after")
    def _value(self):
        given = {k for k in ("value", "k", "k0", "k1", "k0_free", "k1_free", "A0", "variant")
                 if getattr(self, k) is not None}
        allowed = {
            "housner": set(),
            "constant": {"value"},
            "coefficient": {"k", "k0_free", "A0"},
            "amplitude-dependent": {"k0", "k1", "k0_free", "k1_free", "A0", "variant"},
        }[self.law]
        extra = sorted(given - allowed)
        if extra:
            raise ValueError(f"law '{self.law}' takes no {', '.join(extra)}"
                             + (f" (it takes {', '.join(sorted(allowed))})" if allowed else ""))
        if self.law == "constant" and self.value is None:
            raise ValueError("law 'constant' needs value (between 0 and 1)")
        return self

    def build(self):
        from murus.rocking.restitution import AmplitudeDependent, Constant, Housner

        if self.law == "housner":
            return Housner()
        if self.law == "constant":
            return Constant(self.value)
        common = {"k0_free": self.k0_free, "A0": self.A0}
        if self.law == "coefficient":
            return AmplitudeDependent.coefficient(1.5 if self.k is None else self.k, **common)
        return AmplitudeDependent(
            1.0 if self.k0 is None else self.k0, 1.0 if self.k1 is None else self.k1,
            k1_free=self.k1_free, variant=self.variant or "causal", **common)


class PivotCfg(Strict):
    law: Literal["corner", "compressive-length"] = "corner"
    reading: Literal["effective-width", "kern", "neutral-axis", "corner"] = "effective-width"
    factor: float = Field(default=1.0, gt=0.0, allow_inf_nan=False)
    min_lever_fraction: float = Field(default=0.05, gt=0.0, le=1.0, allow_inf_nan=False)


class TieCfg(Strict):
    stiffness: float = Field(gt=0, allow_inf_nan=False)
    height: float = Field(gt=0, allow_inf_nan=False)
    x: float = Field(default=0.0, allow_inf_nan=False)
    tension_only: bool = True
    pretension: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    yield_force: float | None = Field(default=None, gt=0, allow_inf_nan=False)


class DamperCfg(Strict):
    coefficient: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    fraction: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    delta_t: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    height: float = Field(gt=0, allow_inf_nan=False)
    x: float = Field(default=0.0, allow_inf_nan=False)

    @model_validator(mode="after")
    def _c(self):
        if (self.coefficient is None) == (self.fraction is None):
            raise ValueError("give either coefficient (N s/m) or fraction (of c_d) with delta_t")
        if self.fraction is not None and self.delta_t is None:
            raise ValueError("fraction (of c_d, EURODYN (2020), eq. 13) needs delta_t (s)")
        if self.coefficient is not None and self.delta_t is not None:
            raise ValueError("delta_t goes with fraction, not with coefficient")
        return self


class WallsCfg(Strict):
    stiffness: float | Literal["rigid"]
    effective_height: float = Field(gt=0, allow_inf_nan=False)
    z1: float = Field(default=0.0, ge=0, allow_inf_nan=False)
    x: float | None = Field(default=None, allow_inf_nan=False)

    @field_validator("stiffness")
    @classmethod
    def _stiffness(cls, v):
        # a number > 0 (N/m per m of height) or "rigid"; a Field(gt=0) on the union would be
        # applied to the string too and raise a TypeError instead of a validation error
        if isinstance(v, str):
            return v
        if math.isnan(v) or v <= 0:  # inf is accepted as "rigid"
            raise ValueError(f"stiffness must be > 0 (N/m per m) or 'rigid', got {v}")
        return v


class RestraintCfg(Strict):
    motion_sides: Literal["one", "two"] = "two"
    tie: TieCfg | None = None
    damper: DamperCfg | None = None
    transverse_walls: WallsCfg | None = None


MotionType = Literal["record", "sine-pulse", "cosine-pulse", "rectangular-pulse", "free"]


class MotionCfg(MotionFields):
    type: MotionType | None = None
    duration: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    theta0_over_alpha: float | None = Field(default=None, gt=-1, lt=1, allow_inf_nan=False)
    omega0: float = Field(default=0.0, allow_inf_nan=False)

    @model_validator(mode="after")
    def _kind(self):
        kind = self.kind
        self.check_source(kind, ("sine-pulse", "cosine-pulse", "rectangular-pulse"))
        if kind in ("sine-pulse", "cosine-pulse") and self.frequency is None:
            raise ValueError(f"type '{kind}' needs frequency (Hz)")
        if kind == "rectangular-pulse" and self.duration is None:
            raise ValueError("type 'rectangular-pulse' needs duration (s)")
        if kind == "free" and self.theta0_over_alpha is None and self.omega0 == 0.0:
            raise ValueError("type 'free' needs theta0_over_alpha and/or omega0")
        return self

    @property
    def kind(self) -> str:
        if self.type is not None:
            return self.type
        return "record" if self.file else "free"

    @property
    def amplitude_si(self) -> float:
        """The pulse amplitude [m/s²], scale included (:func:`murus.motion.case.amplitude_si`)."""
        from murus.motion.case import amplitude_si

        return amplitude_si(self)


class SolverCfg(Strict):
    method: Literal["event", "newmark"] = "event"
    dt: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    duration: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    rtol: float | None = Field(default=None, gt=0, lt=1e-2)  # None: the engine's default
    rest_tol: float = Field(default=1e-3, ge=0, lt=1, allow_inf_nan=False)
    out_dt: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    linearised: bool = False

    @model_validator(mode="after")
    def _dt(self):
        if self.method == "newmark" and self.dt is None:
            raise ValueError("method 'newmark' needs dt (s)")
        return self


class BaseCfg(Strict):
    model: Literal["rigid", "winkler"] = "rigid"
    stiffness: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    modulus: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    layer_thickness: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    damping: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    damping_ratio: float | None = Field(default=None, ge=0, allow_inf_nan=False)
    kinematics: Literal["corner", "centre"] = "corner"

    @model_validator(mode="after")
    def _layer(self):
        given = [k for k in ("stiffness", "modulus", "layer_thickness", "damping",
                             "damping_ratio") if getattr(self, k) is not None]
        if self.model == "rigid":
            if given:
                raise ValueError(f"a rigid base takes no {', '.join(given)} "
                                 "(set model = 'winkler')")
            return self
        if (self.stiffness is None) == (self.modulus is None):
            raise ValueError("a Winkler base needs stiffness (N/m3) or modulus (Pa) with "
                             "layer_thickness (m)")
        if self.modulus is not None and self.layer_thickness is None:
            raise ValueError("modulus needs layer_thickness (m): stiffness = modulus / thickness")
        if self.damping is not None and self.damping_ratio is not None:
            raise ValueError("give damping or damping_ratio, not both")
        return self

    def build(self):
        from murus.rocking.winkler import WinklerBase

        k = self.stiffness if self.stiffness is not None else self.modulus / self.layer_thickness
        return WinklerBase(k, thickness=self.layer_thickness, damping=self.damping or 0.0,
                           damping_ratio=self.damping_ratio or 0.0, kinematics=self.kinematics)


class RockingCase(Strict):
    body: BodyCfg
    base: BaseCfg = BaseCfg()
    restitution: RestitutionCfg = RestitutionCfg()
    pivot: PivotCfg = PivotCfg()
    restraint: RestraintCfg = RestraintCfg()
    motion: MotionCfg
    solver: SolverCfg = SolverCfg()


def load_case(path) -> tuple[RockingCase, Path, str]:
    """Read and validate a rocking case file; errors are one-line :class:`CaseError`."""
    path = Path(path)
    data, text = load_toml(path)
    case = validate(RockingCase, data, path, text)
    return case, path, text


def build(case: RockingCase, path: Path, text: str):
    """Model, excitation and solver options of a validated case.

    Returns ``(model, motion, kwargs)`` for :func:`murus.rocking.simulate`."""
    from murus.motion.case import build_motion
    from murus.rocking.body import BodyError, RigidBlock

    b = case.body
    try:
        body = RigidBlock(b.width, b.height, b.thickness, b.density, b.top_mass, name=b.name)
    except BodyError as exc:
        raise fail_at(path, text, ("body",), str(exc)) from None
    if case.base.model == "winkler":
        model = _winkler(case, body, path, text)
    else:
        model = build_model(case, body, path, text)
    m = case.motion
    kind = m.kind
    motion = build_motion(m, path, text)
    kwargs = {
        "method": case.solver.method,
        "duration": case.solver.duration,
        "dt": case.solver.dt,
        "out_dt": case.solver.out_dt,
        "omega0": m.omega0,
    }
    if case.solver.rtol is not None:
        kwargs["rtol"] = case.solver.rtol
    if m.theta0_over_alpha is not None:
        kwargs["theta0_over_alpha"] = m.theta0_over_alpha
    if kwargs["duration"] is None and kind == "free":  # the default of simulate() too
        from murus.rocking.summary import FREE_VIBRATION_DURATION

        kwargs["duration"] = FREE_VIBRATION_DURATION
    if case.solver.method == "newmark" and kwargs["duration"] is None:
        kwargs["duration"] = motion.end_time + 5.0
    if case.solver.duration is not None and not math.isfinite(case.solver.duration):
        raise fail_at(path, text, ("solver", "duration"), "must be finite")
    _check_sizes(case, motion, kwargs, path, text)
    return model, motion, kwargs


#: Largest number of output samples (or Newmark steps) of a rocking run: each sample holds
#: about 64 bytes of arrays, so 5e7 samples take 3.2 GB.
MAX_SAMPLES = 5e7


def _check_sizes(case: RockingCase, motion, kwargs: dict, path: Path, text: str) -> None:
    """Refuse, naming the key, a run whose output arrays (or Newmark steps) would exceed
    :data:`MAX_SAMPLES` (``dt = 1e-300``, ``out_dt = 1e-300``, ``duration = 1e300`` or a pulse
    frequency of 1e300 Hz, which would otherwise fail deep inside NumPy)."""
    from murus.rocking.engine import FREE_TAIL
    from murus.rocking.excitation import as_excitation

    exc = as_excitation(motion)
    dur = kwargs.get("duration")
    t_end = float(dur) if dur is not None else exc.end_time + FREE_TAIL
    sv, m = case.solver, case.motion
    if sv.method == "newmark":
        step, key, what = sv.dt, ("solver", "dt"), f"dt = {sv.dt:g} s"
    elif sv.out_dt is not None:
        step, key, what = sv.out_dt, ("solver", "out_dt"), f"out_dt = {sv.out_dt:g} s"
    else:
        step = exc.default_output_step()
        key = (("motion", "frequency") if m.kind in ("sine-pulse", "cosine-pulse")
               else ("motion", "duration") if m.kind == "rectangular-pulse"
               else ("motion", "dt") if m.kind == "record" and m.dt is not None
               else ("motion", "file") if m.kind == "record" else ("solver", "out_dt"))
        what = f"the default output step {step:.3g} s of the motion (set [solver] out_dt)"
    n = t_end / step if step > 0 else math.inf
    if not n <= MAX_SAMPLES:
        if dur is not None and dur > MAX_SAMPLES * 1e-3:  # too long even at 1 ms
            key, what = ("solver", "duration"), f"duration = {dur:g} s"
        raise fail_at(path, text, key, f"{what}: {t_end:.3g} s of response would take "
                      f"{n:.3g} samples (limit {MAX_SAMPLES:.0e})")


def _winkler(case: RockingCase, body, path: Path, text: str):
    """A body on an elastic layer: contact, pivot and energy loss follow from the layer, so the
    restitution, pivot and restraint tables do not apply."""
    from murus.rocking.winkler import WinklerError

    data = case.model_dump(exclude_unset=True)
    for key in ("restitution", "pivot", "restraint"):
        if key in data:
            raise fail_at(path, text, (key,), f"[{key}] does not apply to a Winkler base: the "
                          "layer's deformation gives the contact, the pivot and the energy loss")
    if case.solver.method != "event" or case.solver.linearised:
        raise fail_at(path, text, ("solver",), "a Winkler base runs with method = 'event' and "
                      "the full equations only")
    if "rest_tol" in case.solver.model_fields_set:
        raise fail_at(path, text, ("solver", "rest_tol"), "a Winkler base has no rest rule: "
                      "the layer keeps the wall in continuous contact")
    try:
        from murus.rocking.winkler import WinklerModel

        return WinklerModel(body, case.base.build())
    except WinklerError as exc:
        raise fail_at(path, text, ("base",), str(exc)) from None


def run_case(model, motion, kwargs):
    """Run what :func:`build` returned through :func:`murus.rocking.simulate`, which dispatches
    on the model: a :class:`~murus.rocking.winkler.WinklerModel` (``[base] model = "winkler"``)
    takes only the options of the elastic layer, with ``rtol`` at least 1e-10."""
    from murus.rocking.engine import simulate
    from murus.rocking.winkler import WinklerModel

    if isinstance(model, WinklerModel):
        kwargs = {k: v for k, v in kwargs.items() if k in ("duration", "out_dt", "omega0",
                                                            "theta0_over_alpha", "rtol")}
        if kwargs.get("rtol") is not None:
            kwargs["rtol"] = max(kwargs["rtol"], 1e-10)  # the Winkler layer's floor
    return simulate(model, motion, **kwargs)


def build_model(case: RockingCase, body, path: Path, text: str):
    """The rocking model of a case; a bad combination names the table it comes from."""
    from math import inf

    from murus.rocking.model import ModelError, RockingModel
    from murus.rocking.restitution import RestitutionError
    from murus.rocking.restraints import Damper, Pivot, RestraintError, SpringBed, Tie

    r = case.restraint
    where = ("restraint",)
    try:
        where = ("restitution",)
        law = case.restitution.build()
        where = ("pivot",)
        pv = case.pivot
        pivot = Pivot(pv.law, pv.reading, pv.factor, pv.min_lever_fraction)
        tie = damper = walls = None
        if r.tie is not None:
            where = ("restraint", "tie")
            t = r.tie
            tie = Tie(t.stiffness, t.height, t.x, t.tension_only, t.pretension,
                      inf if t.yield_force is None else t.yield_force)
        if r.damper is not None:
            where = ("restraint", "damper")
            d = r.damper
            c = d.coefficient
            if c is None:
                from murus.rocking.design import reference_damping

                c = d.fraction * reference_damping(body, d.delta_t)
            damper = Damper(c, d.height, d.x)
        if r.transverse_walls is not None:
            where = ("restraint", "transverse_walls")
            w = r.transverse_walls
            k = math.inf if w.stiffness == "rigid" else w.stiffness
            walls = SpringBed(k, w.effective_height, w.z1, w.x)
        where = ("restraint",)
        return RockingModel(body, law, linearised=case.solver.linearised, tie=tie,
                            transverse_walls=walls, damper=damper, motion_sides=r.motion_sides,
                            pivot=pivot, rest_tol=case.solver.rest_tol)
    except (ModelError, RestitutionError, RestraintError) as exc:
        # a RockingModel error names its argument (tie, damper, transverse_walls,
        # motion_sides): a key of [restraint]; the others are the table being built
        raise locate(exc, path, text, ("restraint",) if exc.key else (), where) from None

