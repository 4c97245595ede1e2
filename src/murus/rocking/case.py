"""Rocking case files (TOML): schema, validation and conversion into model objects.

Example (every key documented in the README)::

    [body]
    width = 0.6          # m, b (in the plane of rocking)
    height = 6.0         # m, h
    thickness = 1.0      # m
    density = 2140.7     # kg/m3, uniform rectangle (omit for a massless wall)
    top_mass = 0.0       # kg at mid-top
    [restitution]
    law = "housner"      # or "constant" with value = 0.9
    [motion]
    file = "record.csv"  # two columns time [s], acceleration (or one column with dt)
    units = "g"
    scale = 1.0
    # or: type = "sine-pulse" | "cosine-pulse" (amplitude m/s2 or amplitude_g, frequency Hz,
    #     cycles), "rectangular-pulse" (amplitude, duration), "free" (theta0_over_alpha)
    [solver]
    method = "event"     # or "newmark" with dt
    duration = 20.0      # s (default: end of the motion plus 5 s of free motion)
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Literal

from pydantic import Field, model_validator

from murus import G
from murus.config import CaseError, Strict, fail_at, load_toml, validate


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


class RestitutionCfg(Strict):
    law: Literal["housner", "constant"] = "housner"
    value: float | None = Field(default=None, ge=0.0, le=1.0, allow_inf_nan=False)

    @model_validator(mode="after")
    def _value(self):
        if self.law == "constant" and self.value is None:
            raise ValueError("law 'constant' needs value (between 0 and 1)")
        if self.law == "housner" and self.value is not None:
            raise ValueError("law 'housner' takes no value (use law = 'constant')")
        return self


MotionType = Literal["record", "sine-pulse", "cosine-pulse", "rectangular-pulse", "free"]


class MotionCfg(Strict):
    type: MotionType | None = None
    file: str | None = None
    units: Literal["g", "m/s2", "cm/s2"] | None = None
    dt: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    scale: float = Field(default=1.0, allow_inf_nan=False)
    format: Literal["at2", "esm", "cosmos", "csv"] | None = None
    amplitude: float | None = Field(default=None, allow_inf_nan=False)
    amplitude_g: float | None = Field(default=None, allow_inf_nan=False)
    frequency: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    cycles: float = Field(default=1.0, gt=0, allow_inf_nan=False)
    duration: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    theta0_over_alpha: float | None = Field(default=None, gt=-1, lt=1, allow_inf_nan=False)
    omega0: float = Field(default=0.0, allow_inf_nan=False)

    @model_validator(mode="after")
    def _kind(self):
        kind = self.kind
        if kind == "record" and not self.file:
            raise ValueError("a record needs file = '...'")
        if kind != "record" and self.file:
            raise ValueError(f"type '{kind}' takes no file")
        if kind in ("sine-pulse", "cosine-pulse", "rectangular-pulse"):
            if (self.amplitude is None) == (self.amplitude_g is None):
                raise ValueError(f"type '{kind}' needs exactly one of amplitude, amplitude_g")
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
        if self.amplitude is not None:
            return self.amplitude * self.scale
        return (self.amplitude_g or 0.0) * G * self.scale


class SolverCfg(Strict):
    method: Literal["event", "newmark"] = "event"
    dt: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    duration: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    rtol: float = Field(default=1e-9, gt=0, lt=1e-2)
    out_dt: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    linearised: bool = False

    @model_validator(mode="after")
    def _dt(self):
        if self.method == "newmark" and self.dt is None:
            raise ValueError("method 'newmark' needs dt (s)")
        return self


class RockingCase(Strict):
    body: BodyCfg
    restitution: RestitutionCfg = RestitutionCfg()
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
    from murus.rocking.body import BodyError, RigidBlock
    from murus.rocking.excitation import (
        cosine_pulse,
        free_vibration,
        rectangular_pulse,
        sine_pulse,
    )
    from murus.rocking.model import RockingModel
    from murus.rocking.restitution import Constant, Housner

    b = case.body
    try:
        body = RigidBlock(b.width, b.height, b.thickness, b.density, b.top_mass, name=b.name)
    except BodyError as exc:
        raise fail_at(path, text, ("body",), str(exc)) from None
    law = Housner() if case.restitution.law == "housner" else Constant(case.restitution.value)
    model = RockingModel(body, law, linearised=case.solver.linearised)
    m = case.motion
    kind = m.kind
    if kind == "record":
        motion = _read_record(m, path, text)
    elif kind == "sine-pulse":
        motion = sine_pulse(m.amplitude_si, m.frequency, m.cycles)
    elif kind == "cosine-pulse":
        motion = cosine_pulse(m.amplitude_si, m.frequency, m.cycles)
    elif kind == "rectangular-pulse":
        motion = rectangular_pulse(m.amplitude_si, m.duration)
    else:
        motion = free_vibration()
    kwargs = {
        "method": case.solver.method,
        "duration": case.solver.duration,
        "rtol": case.solver.rtol,
        "dt": case.solver.dt,
        "out_dt": case.solver.out_dt,
        "omega0": m.omega0,
    }
    if m.theta0_over_alpha is not None:
        kwargs["theta0_over_alpha"] = m.theta0_over_alpha
    if kwargs["duration"] is None and kind == "free":
        kwargs["duration"] = 20.0
    if case.solver.method == "newmark" and kwargs["duration"] is None:
        kwargs["duration"] = motion.end_time + 5.0
    if case.solver.duration is not None and not math.isfinite(case.solver.duration):
        raise fail_at(path, text, ("solver", "duration"), "must be finite")
    return model, motion, kwargs


def _read_record(m: MotionCfg, path: Path, text: str):
    from murus.motion import MotionFormatError, read

    f = Path(m.file)
    if not f.is_absolute():
        f = path.parent / f
    if not f.exists():
        raise fail_at(path, text, ("motion", "file"), f"motion file '{m.file}' not found")
    try:
        gm = read(f, units=m.units, dt=m.dt, scale=m.scale, format=m.format)
    except MotionFormatError as exc:
        raise CaseError(str(exc)) from None
    except ValueError as exc:
        raise CaseError(f"{f.name}: {exc}") from None
    if gm.npts < 2:
        raise CaseError(f"{f.name}: the record has fewer than two samples")
    return gm
