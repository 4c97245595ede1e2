"""Continuum case files (TOML): schema, validation, model building, run and writers.

A continuum case is recognised by its top-level ``[continuum]`` table (distinct-element cases
have ``[dem]``, rocking cases ``[body]``). Example (every table is optional except
``[continuum]``, ``[materials.*]`` and ``[[zones]]``)::

    [continuum]
    duration = 2.0              # s of simulated time (default for a record: its end)
    gravity = 9.81              # m/s2
    large_strain = true         # coordinates follow the gridpoints, stresses rotate
    dt_safety = 0.5             # safety factor on the zones' critical time step
    initial_stress = "gravity"  # "gravity" (settle under gravity, elastic then plastic),
                                # "k0" (geostatic stresses, then settle), "none"
    k0 = 0.5                    # for "k0" (default nu / (1 - nu) of each zone's material)
    settle_tolerance = 1e-5     # unbalanced-force ratio of the settling
    [continuum.damping]
    local = 0.0                 # Cundall local damping during the run
    fraction = 0.05             # mass-proportional (Rayleigh) fraction of critical ...
    frequency = 5.0             # ... at this frequency [Hz]
    frame = "base"              # velocities damped: relative to the "base" or "absolute"

    [materials.soil]            # model: "elastic" or "mohr-coulomb"; density [kg/m3];
    model = "mohr-coulomb"      # E [Pa] and nu [-], or bulk and shear [Pa]; Mohr-Coulomb:
    density = 1800.0            # friction_deg, cohesion [Pa], dilation_deg, tension [Pa]
    E = 5e7                     # (default and cap: cohesion / tan(friction))
    nu = 0.3
    friction_deg = 35.0

    [[zones]]                   # a polygon region meshed into quadrilateral zones
    name = "soil"               # (murus.continuum.mesh.polygon_region): vertices [m], and
    material = "soil"           # nx, ny or a target size [m]; optional corners (4 vertex
    vertices = [[0, 0], [1, 0], [1, 10], [0, 10]]   # indices), grading, side_names
    size = 0.5                  # regions that share a side are merged (conforming)

    [[boundaries]]              # kind: "fixed", "roller" (direction = the fixed one: "x" |
    kind = "base"               # "y"), "base" (moved by [motion]; direction "x", "y" or
    side = "soil.bottom"        # "both"), "quiet" (viscous dashpots; frame = "rest", the
                                # default, or "base": on the velocity relative to the
                                # base, one frame per model), "pressure" (pressure
                                # [Pa], compression positive), "free-field" (a vertical
                                # side: a 1D column beside it, attached after the static
                                # stage); where: side = "REGION.SIDE"
                                # (bottom, right, top, left), line = [[x0, y0], [x1, y1]]
                                # with tol [m], or box = [xmin, ymin, xmax, ymax]

    [motion]                    # of the "base" gridpoints, as in the other case files
    type = "harmonic-ramp"
    A = 3.0
    frequency = 5.0

    [[monitors]]                # gridpoint = [x, y] (nearest gridpoint) with quantity ux,
    name = "u_top"              # uy, vx, vy, ax, ay, x, y; or zone = [x, y] (the zone that
    gridpoint = [0.5, 10.0]     # holds the point, else the nearest centroid) with sxx, syy,
    quantity = "ux"             # sxy, szz [Pa] or state; relative = true: a gridpoint's
    relative = true             # ux/uy/vx/vy minus that of the base

    [output]
    sample_dt = 0.01            # s between history samples
    vtk_every = 0               # samples between VTK frames of the zones (0: none)
    figure = true               # zones.png: the final zones, plastic state and displacement

Later boundaries at a table's position override earlier ones at shared gridpoints (a corner
both "base" and "roller" takes the later). A free-field side is usually also a "roller"
(direction "x") for the static stage: the free field releases it. Zones against blocks are
not available yet in case files.

SI units; angles in degrees (``*_deg``). Errors are one line naming the file, the line and the
key (:class:`murus.config.CaseError`), before anything is run or written.

References
----------
Itasca FLAC, User's Guide (the order of a static then a dynamic stage, boundary conditions,
histories); Savalle et al. (2022), Tables 1 and 6 (the keys a retaining-wall backfill needs).
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field, ValidationError, field_validator, model_validator

from murus import G
from murus.config import CaseError, Strict, error_message, load_toml, locate
from murus.config import fail_at as _fail_at
from murus.dem.case import DampingCfg, MotionCfg

Point = tuple[float, float]

#: Largest number of time steps of a run (beyond it a run would not end in days).
MAX_STEPS = 1e9
#: Largest number of zones of a case (about 1 kB of state each: 10 GB).
MAX_ZONES = 10_000_000

_GP_QUANTITIES = ("ux", "uy", "vx", "vy", "ax", "ay", "x", "y")
_ZONE_QUANTITIES = ("sxx", "syy", "sxy", "szz", "state")


# ---------------------------------------------------------------------- schema
class ContinuumCfg(Strict):
    duration: float | None = Field(default=None, ge=0.0, allow_inf_nan=False)
    gravity: float = Field(default=G, ge=0.0, allow_inf_nan=False)
    large_strain: bool = True
    dt_safety: float = Field(default=0.5, gt=0.0, le=1.0, allow_inf_nan=False)
    initial_stress: Literal["gravity", "k0", "none"] = "gravity"
    k0: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    settle_tolerance: float = Field(default=1e-5, gt=0.0, lt=1.0, allow_inf_nan=False)
    settle_max_steps: int = Field(default=200_000, ge=1)
    damping: DampingCfg = DampingCfg()

    @model_validator(mode="after")
    def _k0(self):
        if self.k0 is not None and self.initial_stress != "k0":
            raise ValueError("k0 goes with initial_stress = 'k0'")
        return self


class ZoneMaterialCfg(Strict):
    model: Literal["elastic", "mohr-coulomb"]
    density: float = Field(gt=0.0, allow_inf_nan=False)
    E: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    nu: float | None = Field(default=None, allow_inf_nan=False)
    bulk: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    shear: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    friction_deg: float | None = Field(default=None, ge=0.0, lt=90.0, allow_inf_nan=False)
    cohesion: float | None = Field(default=None, ge=0.0, allow_inf_nan=False)
    dilation_deg: float | None = Field(default=None, ge=0.0, lt=90.0, allow_inf_nan=False)
    tension: float | None = Field(default=None, ge=0.0, allow_inf_nan=False)

    @field_validator("nu")
    @classmethod
    def _nu(cls, v):
        if v is not None and not (-1.0 < v < 0.5):
            raise ValueError(f"nu must be in (-1, 0.5) (0.5: incompressible, no wave speed), "
                             f"got {v!r}")
        return v

    @model_validator(mode="after")
    def _keys(self):
        if (self.E is None) != (self.nu is None) or (self.bulk is None) != (self.shear is None):
            raise ValueError("give E and nu, or bulk and shear")
        if (self.E is None) == (self.bulk is None):
            raise ValueError("give either E and nu, or bulk and shear")
        plastic = ("friction_deg", "cohesion", "dilation_deg", "tension")
        if self.model == "elastic":
            given = [k for k in plastic if getattr(self, k) is not None]
            if given:
                raise ValueError(f"{given[0]} goes with model = 'mohr-coulomb'")
        return self

    def build(self):
        """The :mod:`murus.continuum.materials` object of this table."""
        from murus.continuum.materials import Elastic, MohrCoulomb

        el = (dict(E=self.E, nu=self.nu) if self.E is not None
              else dict(K=self.bulk, G=self.shear))
        if self.model == "elastic":
            return Elastic(density=self.density, **el)
        mc = {k: v for k, v in (("friction_deg", self.friction_deg),
                                ("cohesion", self.cohesion),
                                ("dilation_deg", self.dilation_deg),
                                ("tension", self.tension)) if v is not None}
        return MohrCoulomb(density=self.density, **el, **mc)


class RegionCfg(Strict):
    name: str | None = Field(default=None, min_length=1)
    material: str = Field(min_length=1)
    vertices: list[Point] = Field(min_length=3)
    corners: list[int] | None = None
    nx: int | None = Field(default=None, ge=1)
    ny: int | None = Field(default=None, ge=1)
    size: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    grading: float | tuple[float, float] = 1.0
    side_names: list[str] | None = None

    @model_validator(mode="after")
    def _size(self):
        if self.size is None and (self.nx is None or self.ny is None):
            raise ValueError("give size (m) or both nx and ny")
        return self


class BoundaryCfg(Strict):
    kind: Literal["fixed", "roller", "base", "quiet", "pressure", "free-field"]
    side: str | None = Field(default=None, min_length=1)
    line: tuple[Point, Point] | None = None
    box: tuple[float, float, float, float] | None = None
    tol: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    direction: Literal["x", "y", "both"] | None = None
    pressure: float | None = Field(default=None, allow_inf_nan=False)
    frame: Literal["rest", "base"] | None = None

    @model_validator(mode="after")
    def _where(self):
        if sum(x is not None for x in (self.side, self.line, self.box)) != 1:
            raise ValueError("give exactly one of side, line, box")
        if self.tol is not None and self.side is not None:
            raise ValueError("tol goes with line or box")
        if self.kind == "roller" and self.direction not in ("x", "y"):
            raise ValueError("a roller needs direction = 'x' or 'y' (the fixed direction)")
        if self.kind in ("quiet", "pressure", "free-field") and self.direction is not None:
            raise ValueError(f"kind '{self.kind}' takes no direction")
        if self.frame is not None and self.kind != "quiet":
            raise ValueError("frame ('rest' or 'base') goes with kind = 'quiet'")
        if (self.kind == "pressure") != (self.pressure is not None):
            raise ValueError("pressure (Pa) goes with kind = 'pressure', and it needs one")
        return self


class MonitorCfg(Strict):
    name: str = Field(min_length=1)
    gridpoint: Point | None = None
    zone: Point | None = None
    quantity: Literal["ux", "uy", "vx", "vy", "ax", "ay", "x", "y",
                      "sxx", "syy", "sxy", "szz", "state"]
    relative: bool = False

    @model_validator(mode="after")
    def _where(self):
        if (self.gridpoint is None) == (self.zone is None):
            raise ValueError("give either gridpoint = [x, y] or zone = [x, y]")
        if self.gridpoint is not None and self.quantity not in _GP_QUANTITIES:
            raise ValueError(f"a gridpoint monitor takes {', '.join(_GP_QUANTITIES)}")
        if self.zone is not None and self.quantity not in _ZONE_QUANTITIES:
            raise ValueError(f"a zone monitor takes {', '.join(_ZONE_QUANTITIES)}")
        if self.relative and self.quantity not in ("ux", "uy", "vx", "vy"):
            raise ValueError("relative goes with ux, uy, vx, vy")
        return self


class OutputCfg(Strict):
    sample_dt: float = Field(default=0.01, gt=0.0, allow_inf_nan=False)
    vtk_every: int = Field(default=0, ge=0)
    figure: bool = True


class ContinuumCase(Strict):
    continuum: ContinuumCfg
    materials: dict[str, ZoneMaterialCfg] = Field(min_length=1)
    zones: list[RegionCfg] = Field(min_length=1)
    boundaries: list[BoundaryCfg] = []
    motion: MotionCfg = MotionCfg()
    monitors: list[MonitorCfg] = []
    output: OutputCfg = OutputCfg()

    @model_validator(mode="after")
    def _names(self):
        names = [m.name for m in self.monitors]
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise ValueError(f"monitor name {sorted(dup)[0]!r} is used twice")
        return self


# ---------------------------------------------------------------------- loading
def fail_at(path: Path, text: str, loc: tuple, msg: str) -> CaseError:
    """A one-line CaseError naming file, line and key (``zones[1].size``: the second
    ``[[zones]]`` entry, counted from 0)."""
    return _fail_at(path, text, loc, msg, indices=True)


def is_continuum_case(path) -> bool:
    """True when ``path`` is a readable TOML file with a top-level ``[continuum]`` table."""
    try:
        data, _ = load_toml(path)
    except CaseError:
        return False
    return "continuum" in data


def load_case(path) -> tuple[ContinuumCase, Path, str]:
    """Read and validate a continuum case file.

    Parameters
    ----------
    path : path-like
        The TOML file.

    Returns
    -------
    tuple
        ``(case, path, text)``: the validated :class:`ContinuumCase`, the path and its text.

    Raises
    ------
    murus.config.CaseError
        One line naming the file, line and key.
    """
    path = Path(path)
    data, text = load_toml(path)
    try:
        case = ContinuumCase.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        raise fail_at(path, text, tuple(err.get("loc", ())), error_message(err)) from None
    return case, path, text


# ---------------------------------------------------------------------- building
class Built:
    """What :func:`build` returns: the model, its mesh and what the run needs."""

    def __init__(self, case, model, mesh, motion, duration, monitors, base_gp, ff_sides):
        self.case = case
        self.model = model
        self.mesh = mesh
        self.motion = motion
        self.duration = duration
        self.monitors = monitors
        self.base_gp = base_gp
        self.ff_sides = ff_sides


def _select(mesh, b: BoundaryCfg, i: int):
    key = ("boundaries", i)
    if b.side is not None:
        return mesh.side(b.side, key=key + ("side",))
    if b.line is not None:
        return mesh.on_line(b.line[0], b.line[1], b.tol, key=key + ("line",))
    return mesh.in_box(*b.box, tol=b.tol, key=key + ("box",))


def _check_free_field_side(mesh, g, key, path, text) -> None:
    """A free-field side must be vertical and run along the boundary (checked before the run;
    the columns are built after the static stage)."""
    from murus.continuum.freefield import FreeFieldError, _side_chain

    try:
        chain = _side_chain(mesh.xy, g, 1e-9 * mesh.size)
    except FreeFieldError as exc:
        raise fail_at(path, text, key, f"kind 'free-field': {exc}") from None
    if mesh.edges_of(chain).shape[0] != chain.size - 1:
        raise fail_at(path, text, key, "kind 'free-field': the gridpoints selected are not one "
                      "run of boundary edges")


def _monitor_spec(mesh, mon: MonitorCfg, base_gp):
    from murus.continuum.engine import monitor_value

    if mon.gridpoint is not None:
        g = int(np.argmin(np.hypot(*(mesh.xy - np.asarray(mon.gridpoint)).T)))
        spec = ("gp", g, mon.quantity)
        if not mon.relative:
            return spec
        ref = ("gp", int(base_gp), mon.quantity)

        def rel(m, spec=spec, ref=ref):
            return monitor_value(m, spec) - monitor_value(m, ref)

        return rel
    p = np.asarray(mon.zone, float)
    z = _zone_at(mesh, p)
    return ("zone", z, mon.quantity)


def _zone_at(mesh, p) -> int:
    """The zone that holds the point ``p`` (its four corners turn left around it), else the
    zone of the nearest centroid."""
    q = mesh.xy[mesh.zones]  # (nz, 4, 2)
    d = np.roll(q, -1, axis=1) - q
    r = p[None, None, :] - q
    inside = np.all(d[..., 0] * r[..., 1] - d[..., 1] * r[..., 0] >= 0.0, axis=1)
    hit = np.flatnonzero(inside)
    if hit.size:
        return int(hit[0])
    return int(np.argmin(np.hypot(*(q.mean(axis=1) - p).T)))


def build(case: ContinuumCase, path: Path, text: str) -> Built:
    """The model of a validated case: mesh, materials, boundaries, motion and monitors.

    Parameters
    ----------
    case : ContinuumCase
        The validated case (:func:`load_case`).
    path : pathlib.Path
        The case file (records are read relative to it).
    text : str
        Its text (for the line of a key in messages).

    Returns
    -------
    Built

    Raises
    ------
    murus.config.CaseError
        One line naming the file, line and key: a region that does not mesh (self-intersecting,
        zero size, non-conforming sides), an unknown material, a boundary that names no
        gridpoint, a motion without a base, a run that would not end.
    """
    from murus.continuum.materials import MaterialError
    from murus.continuum.mesh import MeshError, mesh_regions
    from murus.continuum.model import ContinuumModel, ModelError

    c = case.continuum
    # materials
    mats, index = [], {}
    for name, mc in case.materials.items():
        try:
            mats.append(mc.build())
        except (MaterialError, ValueError) as exc:
            raise locate(exc, path, text, ("materials", name), indices=True) from None
        index[name] = len(mats) - 1
    for i, r in enumerate(case.zones):
        if r.material not in index:
            raise fail_at(path, text, ("zones", i, "material"),
                          f"unknown material {r.material!r}; the case has "
                          f"{', '.join(sorted(index))}")
    # mesh
    regions = []
    for i, r in enumerate(case.zones):
        spec = {k: v for k, v in r.model_dump().items()
                if v is not None and k not in ("material",)}
        if isinstance(spec.get("grading"), tuple):
            spec["grading"] = tuple(spec["grading"])
        spec.setdefault("name", f"zones{i}")
        regions.append(spec)
    try:
        mesh = mesh_regions(regions, table="zones")
    except MeshError as exc:
        raise locate(exc, path, text, (), default=("zones",), indices=True) from None
    except MemoryError:
        raise fail_at(path, text, ("zones",), "the mesh is too large for memory") from None
    if mesh.n_zones > MAX_ZONES:
        raise fail_at(path, text, ("zones",), f"{mesh.n_zones} zones: more than {MAX_ZONES}")
    zmat = np.array([index[case.zones[r].material] for r in mesh.region], np.int64)
    try:
        model = ContinuumModel(mesh.xy, mesh.zones, mats, zmat, gravity=c.gravity,
                               large_strain=c.large_strain, safety=c.dt_safety)
    except (ModelError, MaterialError) as exc:
        raise locate(exc, path, text, (), default=("zones",), indices=True) from None
    # boundaries
    base_gp = None
    ff_sides = []
    for i, b in enumerate(case.boundaries):
        try:
            g = _select(mesh, b, i)
            x = b.direction in (None, "x", "both")
            y = b.direction in (None, "y", "both")
            if b.kind == "fixed":
                model.fix(g, x, y)
            elif b.kind == "roller":
                model.fix(g, b.direction == "x", b.direction == "y")
            elif b.kind == "base":
                model.set_base(g, x, y)
                base_gp = int(g[0])
            elif b.kind == "free-field":
                _check_free_field_side(mesh, g, ("boundaries", i), path, text)
                ff_sides.append(g)
            else:
                edges = mesh.edges_of(g)
                if edges.shape[0] == 0:
                    raise fail_at(path, text, ("boundaries", i),
                                  f"kind '{b.kind}': the gridpoints selected hold no boundary "
                                  "edge of the mesh")
                if b.kind == "quiet":
                    model.add_quiet(edges, frame=b.frame or "rest")
                else:
                    model.apply_pressure(edges, b.pressure)
        except CaseError:
            raise
        except (MeshError, ModelError) as exc:
            raise locate(exc, path, text, ("boundaries", i) if not exc.key
                         or exc.key[0] != "boundaries" else (), indices=True) from None
    # motion
    mo = case.motion
    if mo.kind == "tilt":
        raise fail_at(path, text, ("motion", "type"), "a tilt of the base is a DEM motion; "
                      "a continuum case takes a record, a pulse or a harmonic ramp")
    duration = c.duration
    from murus.motion.case import build_motion

    motion = None
    if mo.kind != "none":
        if base_gp is None:
            raise fail_at(path, text, ("motion",), "a motion needs a boundary of kind 'base' "
                          "(the gridpoints it moves)")
        if mo.kind == "harmonic-ramp" and duration is None:
            raise fail_at(path, text, ("continuum", "duration"),
                          "a harmonic ramp needs [continuum] duration (s)")
        motion = build_motion(mo, path, text, sampled_dt=mo.dt or 0.001, duration=duration)
        if duration is None:
            duration = (len(motion.acc) - 1) * motion.dt
    if duration is None:
        duration = 0.0
    steps = duration / model.dt
    if steps > MAX_STEPS:
        raise fail_at(path, text, ("continuum", "duration"),
                      f"{steps:.3g} time steps of {model.dt:.3g} s: more than {MAX_STEPS:g}")
    monitors = {}
    for mon in case.monitors:
        if mon.relative and base_gp is None:
            raise fail_at(path, text, ("monitors", case.monitors.index(mon), "relative"),
                          "relative needs a boundary of kind 'base'")
        monitors[mon.name] = _monitor_spec(mesh, mon, base_gp)
    return Built(case, model, mesh, motion, float(duration), monitors, base_gp, ff_sides)


# ---------------------------------------------------------------------- running
class CaseRun:
    """A finished (or interrupted) case: the settling, the run and the VTK frames."""

    def __init__(self, built: Built, settled, result, frames):
        self.built = built
        self.settled = settled
        self.result = result
        self.frames = frames

    @property
    def ok(self) -> bool:
        """True when the settling converged (or none was asked) and the run completed."""
        settled = self.settled is None or bool(self.settled.converged)
        return settled and (self.result is None or self.result.status == "completed")

    @property
    def status(self) -> str:
        if self.settled is not None and not self.settled.converged:
            return "not_settled"
        return "completed" if self.result is None else self.result.status

    def summary(self) -> dict:
        """The content of ``summary.json``."""
        m = self.built.model
        s = {"status": self.status, "ok": self.ok, "t_end": float(m.time),
             "zones": int(m.nz), "gridpoints": int(m.ng), "dt": float(m.dt),
             "plastic_zones": int(np.count_nonzero(m.plastic_state() & 3)),
             "ever_plastic_zones": int(np.count_nonzero(m.plastic_state()))}
        from murus.continuum.engine import monitor_value

        s["final"] = {k: monitor_value(m, spec) for k, spec in self.built.monitors.items()}
        if self.settled is not None:
            s["settle"] = {"converged": bool(self.settled.converged),
                           "steps": int(self.settled.steps), "ratio": float(self.settled.ratio),
                           "message": self.settled.message}
        r = self.result
        if r is not None:
            s["message"] = r.message
            s["steps"] = int(r.steps)
            s["wall_time_s"] = float(r.wall)
            s["peak_abs"] = {k: float(np.nanmax(np.abs(v))) for k, v in r.values.items()
                             if k in self.built.monitors and len(v)}
            s["energy"] = {k[len("energy."):]: float(v[-1]) for k, v in r.values.items()
                           if k.startswith("energy.") and len(v)}
        return s


def _frame(m) -> dict:
    from murus.continuum.vtk import zone_cell_data

    return {"xy": m.gxy.copy(), "zones": m.zg,
            "cell_data": zone_cell_data(stress=m.zone_stress(), strain=m.zone_strain(),
                                        state=m.plastic_state()),
            "point_data": {"displacement": m.gdisp.copy(), "velocity": m.gvel.copy()}}


def run_case(built: Built, progress=None) -> CaseRun:
    """Initial stresses, then the dynamic run of :func:`build`, in segments (one per VTK frame,
    or about 1 % of the run), so that a Ctrl-C stops it within a segment with the histories up
    to then (status ``"interrupted"``).

    Parameters
    ----------
    built : Built
        The model (:func:`build`).
    progress : callable, optional
        ``progress(done_s, total_s)`` after each segment.

    Returns
    -------
    CaseRun
        A run whose settling did not converge skips the dynamic stage (status
        ``"not_settled"``).
    """
    from murus.continuum.engine import RunResult

    case, m = built.case, built.model
    c = case.continuum
    settled = None
    if c.initial_stress == "k0":
        m.initial_stress_k0(c.k0)
    dynamic = built.duration > 0.0
    if c.initial_stress != "none":
        # a static case keeps the displacements of the settling; a dynamic one measures its
        # displacements and energies from the settled state
        settled = m.settle(tol=c.settle_tolerance, max_steps=c.settle_max_steps,
                           reset=dynamic)
        if not settled.converged:
            return CaseRun(built, settled, None, [])
    if built.ff_sides:
        m.add_free_field(built.ff_sides)  # after the static stage, as in FLAC
    if dynamic:
        m.reset_reference()
    frames = [(m.time, _frame(m))] if case.output.vtk_every else []
    if built.duration <= 0.0:
        return CaseRun(built, settled, None, frames)
    d = c.damping
    kw = dict(motion=built.motion, xi=d.fraction, freq=d.frequency, local_damping=d.local,
              monitors=built.monitors, sample_dt=case.output.sample_dt, damping_frame=d.frame)
    seg = (case.output.vtk_every * case.output.sample_dt if case.output.vtk_every
           else max(case.output.sample_dt, built.duration / 100.0))
    t_end = m.time + built.duration
    steps = 0
    wall = 0.0
    res = None
    status, message = "completed", ""
    try:
        while m.time < t_end - 0.5 * m.dt:
            res = m.run(min(seg, t_end - m.time), **kw)
            kw["motion"] = None  # set once
            kw["monitors"] = None
            steps += res.steps
            wall += res.wall
            if res.status != "completed":
                status, message = res.status, res.message
                break
            if case.output.vtk_every:
                frames.append((m.time, _frame(m)))
            if progress is not None:
                progress(built.duration - (t_end - m.time), built.duration)
    except KeyboardInterrupt:
        status, message = "interrupted", f"interrupted at t = {m.time:.6g} s"
    h = m.history
    if not message:
        message = f"completed {steps} steps to t = {m.time:.6g} s"
    vals = {k: np.asarray(v, float) for k, v in h.items() if k != "t"}
    result = RunResult(t=np.asarray(h.get("t", [m.time]), float), values=vals, status=status,
                       message=message, steps=steps, wall=wall, dt=m.dt,
                       zone_updates=steps * m.nz)
    return CaseRun(built, settled, result, frames)


# ---------------------------------------------------------------------- writers
def output_names(figure: bool = True) -> list[str]:
    """Relative paths written by :func:`write_files` that are known before the run (the
    ``vtk/`` series is checked when it is published)."""
    return ["summary.json", "histories.csv"] + (["zones.png"] if figure else [])


def write_files(run: CaseRun, folder: Path, figure: bool = True) -> None:
    """``summary.json``, ``histories.csv`` (when there was a dynamic stage), ``zones.png``
    (plastic state and displacement of the final zones) and ``vtk/zones.pvd`` when frames were
    kept."""
    import json

    from murus.rocking.output import _clean

    folder = Path(folder)
    (folder / "summary.json").write_text(json.dumps(_clean(run.summary()), indent=2) + "\n")
    if run.result is not None:
        from murus.dem.case import histories_csv  # the same columns as the blocks'

        (folder / "histories.csv").write_text(histories_csv(run.result))
    else:
        (folder / "histories.csv").write_text("t_s\n")
    m = run.built.model
    if figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from murus.continuum.plots import plot_plastic_state, plot_zones

        fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
        base = run.built.base_gp
        d = m.gdisp - (m.gdisp[base] if base is not None else 0.0)
        uz = np.hypot(*d.T)[m.zg].mean(axis=1)
        plot_zones(m.gxy, m.zg, uz, ax=axes[0],
                   label="displacement relative to the base [m]" if base is not None
                   else "displacement [m]")
        axes[0].set_title(f"displacement, t = {m.time:.3f} s")
        plot_plastic_state(m.gxy, m.zg, m.plastic_state(), ax=axes[1])
        axes[1].set_title("plastic state")
        fig.tight_layout()
        fig.savefig(folder / "zones.png", dpi=120)
        plt.close(fig)
    if run.frames:
        from murus.continuum.vtk import write_zone_series

        write_zone_series(folder / "vtk", run.frames, binary=True)


def write_outputs(run: CaseRun, out: Path, figure: bool = True) -> Path:
    """Write the outputs of one run into ``out`` (nothing of the user's replaced or deleted;
    ``out`` unchanged on failure).

    Parameters
    ----------
    run : CaseRun
        The run.
    out : pathlib.Path
        The output folder.
    figure : bool
        Write ``zones.png``.

    Returns
    -------
    pathlib.Path
        ``out``.
    """
    from murus.rocking.output import atomic_dir

    return atomic_dir(out, lambda tmp: write_files(run, tmp, figure),
                      names=output_names(figure))


def summary_line(name: str, run: CaseRun) -> str:
    """One line for the terminal."""
    s = run.summary()
    vals = ", ".join(f"{k} = {v:.4g}" for k, v in s.get("final", {}).items())
    settle = s.get("settle")
    head = f"{name}: {s['zones']} zones"
    if settle is not None:
        head += f", settled in {settle['steps']} steps" if settle["converged"] else \
            f", NOT settled ({settle['message']})"
    if run.result is not None:
        head += f", {s['t_end']:.4g} s simulated in {s['steps']} steps, {s['status']}"
    head += f", {s['plastic_zones']} zones yielding"
    return head + (f", {vals}" if vals else "")

