"""Distinct-element case files (TOML): schema, validation, model building, run and writers.

A DEM case is recognised by its top-level ``[dem]`` table (rocking cases have ``[body]``).
Example (every table is optional except ``[dem]``, ``[materials.*]`` and the blocks)::

    [dem]
    duration = 3.0           # s of simulated time (default for a record: its end)
    thickness = 1.0          # m, out of plane
    gravity = 9.81           # m/s2
    joint = "stone"          # material of the joints not listed in [[joints]] (default: the
                             # only material)
    dt_safety = 0.2          # safety factor of the automatic time step, or dt = ... [s]
                             # (an error above the stable step)
    settle = true            # static solution under gravity before the run
    settle_tolerance = 1e-4  # unbalanced-force ratio
    overlap_tolerance = 1e-5 # m, largest overlap of two initial blocks
    [dem.damping]
    local = 0.0              # Cundall local damping during the run
    fraction = 0.05          # mass-proportional (Rayleigh) fraction of critical ...
    frequency = 5.0          # ... at this frequency [Hz]
    frame = "base"           # velocities damped: relative to the "base" or "absolute"

    [materials.stone]        # density [kg/m3], kn, ks [Pa/m], friction_deg, cohesion,
    density = 2600.0         # tensile, cohesion_res, tensile_res [Pa], rolling [-],
                             # contact_damping [-] (0..1; 1: Housner's rocking impacts)
    kn = 1e9
    ks = 1e9
    friction_deg = 35.0

    [[joints]]               # the joint between two groups (a block's group defaults to its
    a = "wall"               # material's name)
    b = "base"
    material = "interface"

    [[blocks]]               # kind: rectangle (width, height, center, angle_deg), polygon
    kind = "rectangle"       # (vertices), disc (center, radius), clump (parts: each
    width = 3.0              # {vertices = [...]} or {center = [x, y], radius = r});
    height = 0.2             # material, group, kinematic ("fixed" | "base"), tag
    center = [0.0, -0.1]
    kinematic = "base"

    [[walls]]                # a running-bond wall of rectangles, course by course from the
    courses = 10             # bottom, left to right; odd courses shifted by stagger x width
    blocks_per_course = 5
    block_width = 0.4
    block_height = 0.2
    stagger = 0.25
    origin = [-1.0, 0.0]     # bottom-left corner of the first course

    [motion]                 # of the kinematic "base" blocks, as in rocking cases:
    type = "harmonic-ramp"   # "record" (file, units, dt, scale, format), "sine-pulse" |
    A = 3.0                  # "cosine-pulse" (amplitude or amplitude_g, frequency, cycles),
    frequency = 2.0          # "harmonic-ramp" (A [m/s3], frequency), "tilt" (rate_deg_per_s,
                             # start_deg, settle_deg: a tilting table), "none"

    [[monitors]]             # body: index, "top", "wall top", "base" or a block's tag;
    name = "d_top"           # quantity: ux, uy, rot, angle, x, y, vx, vy, omega, or tilt
    body = "top"             # (no body); relative = true: minus the same quantity of the
    quantity = "ux"          # base body
    relative = true

    [stop]                   # monitor op value (op ">", "<" or "abs>"), or
    monitor = "d_top"        # fraction_of_height (value = fraction x height of the dynamic
    fraction_of_height = 0.2 # blocks, op "abs>")

    [output]
    sample_dt = 0.01         # s between history samples
    vtk_every = 0            # samples between VTK frames (0: no VTK series)
    figure = true            # blocks.png, final blocks coloured by displacement

Body indices: the ``[[blocks]]`` entries in file order, then the ``[[walls]]`` blocks (wall by
wall, course by course from the bottom, left to right). SI units; angles in degrees in the file
(``*_deg``).

Errors are one line naming the file, the line and the key (:class:`murus.config.CaseError`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field, ValidationError, model_validator

from murus.config import (
    CaseError,
    MotionFields,
    Strict,
    error_message,
    load_toml,
)
from murus.config import fail_at as _fail_at

Pos = float
Point = tuple[float, float]

#: Largest number of time steps of a run (beyond it a run would not end in days).
MAX_STEPS = 1e9
#: Largest number of samples of an analytic base motion (an array of 8-byte floats each).
MAX_MOTION_SAMPLES = 5e7
#: Largest memory [bytes] of the histories and VTK frames kept during a run.
MAX_HISTORY_BYTES = 4e9


# ---------------------------------------------------------------------- schema
class DampingCfg(Strict):
    local: float = Field(default=0.0, ge=0.0, lt=1.0, allow_inf_nan=False)
    fraction: float = Field(default=0.0, ge=0.0, allow_inf_nan=False)
    frequency: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    frame: Literal["base", "absolute"] = "base"

    @model_validator(mode="after")
    def _freq(self):
        if self.fraction > 0 and self.frequency is None:
            raise ValueError("a mass-proportional fraction needs frequency (Hz)")
        return self


class DemCfg(Strict):
    duration: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    thickness: float = Field(default=1.0, gt=0.0, allow_inf_nan=False)
    gravity: float = Field(default=9.81, ge=0.0, allow_inf_nan=False)
    joint: str | None = None
    dt: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    dt_safety: float = Field(default=0.2, gt=0.0, le=1.0, allow_inf_nan=False)
    rounding: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    settle: bool = True
    settle_tolerance: float = Field(default=1e-4, gt=0.0, lt=1.0)
    settle_max_steps: int = Field(default=200_000, gt=0)
    overlap_tolerance: float = Field(default=1e-5, ge=0.0, allow_inf_nan=False)
    max_steps: int | None = Field(default=None, gt=0)
    damping: DampingCfg = DampingCfg()


class MaterialCfg(Strict):
    density: float = Field(default=2000.0, gt=0.0, allow_inf_nan=False)
    kn: float = Field(gt=0.0, allow_inf_nan=False)
    ks: float = Field(gt=0.0, allow_inf_nan=False)
    friction_deg: float = Field(default=30.0, ge=0.0, lt=90.0)
    cohesion: float = Field(default=0.0, ge=0.0, allow_inf_nan=False)
    tensile: float = Field(default=0.0, ge=0.0, allow_inf_nan=False)
    cohesion_res: float = Field(default=0.0, ge=0.0, allow_inf_nan=False)
    tensile_res: float = Field(default=0.0, ge=0.0, allow_inf_nan=False)
    rolling: float = Field(default=0.0, ge=0.0, allow_inf_nan=False)
    contact_damping: float = Field(default=0.0, ge=0.0, le=1.0, allow_inf_nan=False)

    def joint(self):
        from murus.dem.materials import Joint

        return Joint(kn=self.kn, ks=self.ks, friction_deg=self.friction_deg,
                     cohesion=self.cohesion, tension=self.tensile,
                     cohesion_res=self.cohesion_res, tension_res=self.tensile_res,
                     rolling=self.rolling, contact_damping=self.contact_damping)


class JointCfg(Strict):
    a: str
    b: str
    material: str


class PartCfg(Strict):
    vertices: list[Point] | None = None
    center: Point | None = None
    radius: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)

    @model_validator(mode="after")
    def _one(self):
        if (self.vertices is None) == (self.radius is None):
            raise ValueError("a clump part is {vertices = [...]} or {center = [x, y], "
                             "radius = r}")
        if self.radius is not None and self.center is None:
            raise ValueError("a disc part needs center = [x, y]")
        return self


_KIND_KEYS = {
    "rectangle": {"width", "height"},
    "polygon": {"vertices"},
    "disc": {"radius"},
    "clump": {"parts"},
}
_KIND_ALLOWED = {
    "rectangle": {"width", "height", "center", "angle_deg"},
    "polygon": {"vertices"},
    "disc": {"center", "radius"},
    "clump": {"parts"},
}


class BlockCfg(Strict):
    kind: Literal["rectangle", "polygon", "disc", "clump"]
    width: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    height: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    center: Point | None = None
    angle_deg: float | None = Field(default=None, allow_inf_nan=False)
    vertices: list[Point] | None = None
    radius: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    parts: list[PartCfg] | None = None
    material: str | None = None
    group: str | None = None
    kinematic: Literal["fixed", "base"] | None = None
    tag: str | None = None

    @model_validator(mode="after")
    def _keys(self):
        geo = {"width", "height", "center", "angle_deg", "vertices", "radius", "parts"}
        given = {k for k in geo if getattr(self, k) is not None}
        extra = sorted(given - _KIND_ALLOWED[self.kind])
        if extra:
            raise ValueError(f"kind '{self.kind}' takes no {', '.join(extra)} (it takes "
                             f"{', '.join(sorted(_KIND_ALLOWED[self.kind]))})")
        missing = sorted(_KIND_KEYS[self.kind] - given)
        if self.kind == "disc" and self.center is None:
            missing.append("center")
        if missing:
            raise ValueError(f"kind '{self.kind}' needs {', '.join(missing)}")
        return self


class WallCfg(Strict):
    courses: int = Field(gt=0)
    blocks_per_course: int = Field(gt=0)
    block_width: float = Field(gt=0.0, allow_inf_nan=False)
    block_height: float = Field(gt=0.0, allow_inf_nan=False)
    stagger: float = Field(default=0.5, ge=0.0, lt=1.0, allow_inf_nan=False)
    origin: Point = (0.0, 0.0)
    material: str | None = None
    group: str | None = None


MotionKind = Literal["none", "record", "sine-pulse", "cosine-pulse", "harmonic-ramp", "tilt"]


class MotionCfg(MotionFields):
    type: MotionKind | None = None
    A: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    rate_deg_per_s: float | None = Field(default=None, allow_inf_nan=False)
    start_deg: float = Field(default=0.0, gt=-90.0, lt=90.0)
    settle_deg: float | None = Field(default=None, gt=-90.0, lt=90.0)

    @property
    def kind(self) -> str:
        if self.type is not None:
            return self.type
        return "record" if self.file else "none"

    @model_validator(mode="after")
    def _kind(self):
        kind = self.kind
        self.check_source(kind, ("sine-pulse", "cosine-pulse"))
        if kind in ("sine-pulse", "cosine-pulse"):
            if self.frequency is None:
                raise ValueError(f"type '{kind}' needs frequency (Hz)")
        if kind == "harmonic-ramp" and (self.A is None or self.frequency is None):
            raise ValueError("type 'harmonic-ramp' needs A (m/s3) and frequency (Hz)")
        if kind == "tilt" and self.rate_deg_per_s is None:
            raise ValueError("type 'tilt' needs rate_deg_per_s (0 for a fixed inclination)")
        if kind != "tilt" and (self.rate_deg_per_s is not None or self.settle_deg is not None):
            raise ValueError("rate_deg_per_s and settle_deg go with type 'tilt'")
        return self


class MonitorCfg(Strict):
    name: str = Field(min_length=1)
    body: int | str | None = None
    quantity: Literal["ux", "uy", "rot", "angle", "x", "y", "vx", "vy", "omega", "tilt"]
    relative: bool = False

    @model_validator(mode="after")
    def _body(self):
        if self.quantity == "tilt":
            if self.body is not None or self.relative:
                raise ValueError("quantity 'tilt' takes no body and no relative")
        elif self.body is None:
            raise ValueError(f"quantity '{self.quantity}' needs body (an index, 'top', "
                             "'wall top', 'base' or a block's tag)")
        return self


class StopCfg(Strict):
    monitor: str
    op: Literal[">", "<", "abs>"] | None = None
    value: float | None = Field(default=None, allow_inf_nan=False)
    fraction_of_height: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)

    @model_validator(mode="after")
    def _value(self):
        if (self.value is None) == (self.fraction_of_height is None):
            raise ValueError("give either value or fraction_of_height")
        return self


class OutputCfg(Strict):
    sample_dt: float = Field(default=0.01, gt=0.0, allow_inf_nan=False)
    vtk_every: int = Field(default=0, ge=0)
    figure: bool = True


class DemCase(Strict):
    dem: DemCfg
    materials: dict[str, MaterialCfg] = Field(min_length=1)
    joints: list[JointCfg] = []
    blocks: list[BlockCfg] = []
    walls: list[WallCfg] = []
    motion: MotionCfg = MotionCfg()
    monitors: list[MonitorCfg] = []
    stop: StopCfg | None = None
    output: OutputCfg = OutputCfg()

    @model_validator(mode="after")
    def _has_blocks(self):
        if not self.blocks and not self.walls:
            raise ValueError("the case has no blocks: add [[blocks]] or [[walls]]")
        return self


# ---------------------------------------------------------------------- locations
def fail_at(path: Path, text: str, loc: tuple, msg: str) -> CaseError:
    """A one-line CaseError naming file, line and key (``blocks[2].material``: the third
    ``[[blocks]]`` entry, counted from 0): :func:`murus.config.fail_at` with indices."""
    return _fail_at(path, text, loc, msg, indices=True)


def _validate(data: dict, path: Path, text: str) -> DemCase:
    try:
        return DemCase.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        loc = tuple(err.get("loc", ()))
        raise fail_at(path, text, loc, error_message(err)) from None


def is_dem_case(path) -> bool:
    """True when ``path`` is a readable TOML file with a top-level ``[dem]`` table."""
    try:
        data, _ = load_toml(path)
    except CaseError:
        return False
    return "dem" in data


def load_case(path) -> tuple[DemCase, Path, str]:
    """Read and validate a DEM case file; errors are one-line :class:`CaseError`."""
    path = Path(path)
    data, text = load_toml(path)
    return _validate(data, path, text), path, text


# ---------------------------------------------------------------------- building
class Built:
    """What :func:`build` returns: the model and what the run needs."""

    def __init__(self, model, run_kwargs, monitors, stop_desc, height, names, settle,
                 settle_tilt, tilt, vtk_every, figure, base):
        self.model = model
        self.run_kwargs = run_kwargs
        self.monitors = monitors
        self.stop_desc = stop_desc
        self.height = height
        self.names = names
        self.settle = settle
        self.settle_tilt = settle_tilt
        self.tilt = tilt
        self.vtk_every = vtk_every
        self.figure = figure
        self.base = base


def _shape_list(case: DemCase):
    """Every body as (where, entry, parts, kinematic, material, group, tag, wall) with parts
    ``("poly", vertices)`` or ``("disc", center, radius)``; where is its location in the file."""
    out = []
    for i, b in enumerate(case.blocks):
        where = ("blocks", i)
        if b.kind == "rectangle":
            w, h = b.width, b.height
            v = np.array([[-w / 2, -h / 2], [w / 2, -h / 2], [w / 2, h / 2], [-w / 2, h / 2]])
            a = math.radians(b.angle_deg or 0.0)
            c, s = math.cos(a), math.sin(a)
            v = v @ np.array([[c, s], [-s, c]]) + np.asarray(b.center or (0.0, 0.0), float)
            parts = [("poly", v)]
        elif b.kind == "polygon":
            parts = [("poly", np.asarray(b.vertices, float))]
        elif b.kind == "disc":
            parts = [("disc", np.asarray(b.center, float), b.radius)]
        else:
            parts = [("poly", np.asarray(p.vertices, float)) if p.vertices is not None
                     else ("disc", np.asarray(p.center, float), p.radius) for p in b.parts]
        out.append((where, f"[[blocks]] {i}", parts, b.kinematic, b.material, b.group, b.tag,
                    False))
    for iw, w in enumerate(case.walls):
        x0, y0 = w.origin
        bw, bh = w.block_width, w.block_height
        for c in range(w.courses):
            off = w.stagger * bw if c % 2 else 0.0
            for k in range(w.blocks_per_course):
                xl = x0 + off + k * bw
                yb = y0 + c * bh
                v = np.array([[xl, yb], [xl + bw, yb], [xl + bw, yb + bh], [xl, yb + bh]])
                out.append((("walls", iw), f"[[walls]] {iw} course {c} block {k}",
                            [("poly", v)], None, w.material, w.group, None, True))
    return out


def default_joint(case, path, text) -> str:
    """The material of the joints not listed in ``[[joints]]``: ``[dem] joint``, or the only
    material; a one-line :class:`CaseError` when several are defined without it or it is
    unknown."""
    d = case.dem
    if d.joint is None and len(case.materials) > 1:
        raise fail_at(path, text, ("dem", "joint"), "several materials are defined: name the "
                      f"default joint material ({', '.join(case.materials)})")
    default = d.joint or next(iter(case.materials))
    if default not in case.materials:
        raise fail_at(path, text, ("dem", "joint"), f"unknown material '{default}' (defined: "
                      f"{', '.join(case.materials)})")
    return default


def _material(case: DemCase, name: str | None, where: tuple, path, text) -> str:
    if name is None:
        if len(case.materials) == 1:
            return next(iter(case.materials))
        raise fail_at(path, text, where + ("material",), "several materials are defined: "
                      f"name one ({', '.join(case.materials)})")
    if name not in case.materials:
        raise fail_at(path, text, where + ("material",), f"unknown material '{name}' (defined: "
                      f"{', '.join(case.materials)})")
    return name


def _bbox(parts) -> np.ndarray:
    lo = np.array([np.inf, np.inf])
    hi = -lo
    for p in parts:
        if p[0] == "poly":
            lo = np.minimum(lo, p[1].min(0))
            hi = np.maximum(hi, p[1].max(0))
        else:
            lo = np.minimum(lo, p[1] - p[2])
            hi = np.maximum(hi, p[1] + p[2])
    return np.concatenate([lo, hi])


def _poly_poly(a: np.ndarray, b: np.ndarray) -> float:
    """Penetration depth [m] of two convex polygons (separating axes; <= 0 when apart)."""
    depth = math.inf
    for P in (a, b):
        e = np.roll(P, -1, axis=0) - P
        nrm = np.column_stack([e[:, 1], -e[:, 0]])
        nrm /= np.hypot(nrm[:, 0], nrm[:, 1])[:, None]
        pa = a @ nrm.T
        pb = b @ nrm.T
        ov = np.minimum(pa.max(0) - pb.min(0), pb.max(0) - pa.min(0))
        depth = min(depth, float(ov.min()))
        if depth <= 0:
            return depth
    return depth


def _poly_disc(a: np.ndarray, c: np.ndarray, r: float) -> float:
    """Penetration depth [m] of a convex polygon and a disc."""
    e = np.roll(a, -1, axis=0) - a
    L2 = (e * e).sum(1)
    t = np.clip(((c - a) * e).sum(1) / L2, 0.0, 1.0)
    q = a + t[:, None] * e
    d = float(np.hypot(*(q - c).T).min())
    # inside when c is on the inner side of every (counter-clockwise) edge
    cr = e[:, 0] * (c[1] - a[:, 1]) - e[:, 1] * (c[0] - a[:, 0])
    return r + d if bool(np.all(cr >= 0)) else r - d


def _area(v: np.ndarray) -> float:
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float((x * np.roll(y, -1) - np.roll(x, -1) * y).sum())


def _overlap(pa, pb) -> float:
    worst = -math.inf
    for p in pa:
        for q in pb:
            if p[0] == "poly" and q[0] == "poly":
                d = _poly_poly(p[1], q[1])
            elif p[0] == "disc" and q[0] == "disc":
                d = p[2] + q[2] - float(np.hypot(*(p[1] - q[1])))
            elif p[0] == "poly":
                d = _poly_disc(p[1], q[1], q[2])
            else:
                d = _poly_disc(q[1], p[1], p[2])
            worst = max(worst, d)
    return worst


def check_overlaps(shapes, tol: float) -> tuple[int, int, float] | None:
    """First pair of bodies (i, j, depth) whose initial overlap exceeds ``tol`` [m]."""
    boxes = np.array([_bbox(s) for s in shapes])
    n = len(shapes)
    for i in range(n - 1):
        bi = boxes[i]
        bj = boxes[i + 1:]
        hit = ((bj[:, 0] < bi[2] - tol) & (bj[:, 2] > bi[0] + tol)
               & (bj[:, 1] < bi[3] - tol) & (bj[:, 3] > bi[1] + tol))
        for k in np.nonzero(hit)[0]:
            j = i + 1 + int(k)
            d = _overlap(shapes[i], shapes[j])
            if d > tol:
                return i, j, d
    return None


def _check_clump(parts, where, tol: float, path, text) -> None:
    """Refuse a clump whose parts overlap by more than ``tol`` [m] (the mass of the common
    area would be counted twice); parts may touch (share an edge or a point)."""
    for i in range(len(parts) - 1):
        for j in range(i + 1, len(parts)):
            d = _overlap([parts[i]], [parts[j]])
            if d > tol:
                raise fail_at(path, text, where + ("parts",), f"clump {where[0]}[{where[1]}]: "
                              f"parts {i} and {j} overlap by {d:.3g} m > overlap_tolerance "
                              f"{tol:g} m (their common area would be counted twice in the "
                              "mass): split the clump into parts that only touch")


def _convex_parts(parts, where, key, path, text):
    """Counter-clockwise convex polygon parts; a non-convex one is an error of its entry."""
    out = []
    for p in parts:
        if p[0] != "poly":
            out.append(p)
            continue
        v = p[1]
        if v.ndim != 2 or len(v) < 3:
            raise fail_at(path, text, where + ("vertices",), "a polygon needs at least 3 "
                          "vertices [[x, y], ...]")
        a = _area(v)
        if a == 0:
            raise fail_at(path, text, where + ("vertices",), "the polygon has zero area")
        if a < 0:
            v = v[::-1].copy()
        e = np.roll(v, -1, axis=0) - v
        cr = np.roll(e, 1, axis=0)[:, 0] * e[:, 1] - np.roll(e, 1, axis=0)[:, 1] * e[:, 0]
        scale = float(np.ptp(v, axis=0).max()) ** 2
        if np.any(cr < -1e-12 * scale):
            raise fail_at(path, text, where + (key,), "the polygon is not convex: split it "
                          "into convex parts (kind = 'clump', parts = [{vertices = ...}, ...])")
        out.append(("poly", v))
    return out


def build(case: DemCase, path: Path, text: str) -> Built:
    """The model of a validated case, with its monitors, stop condition and run options.

    Input errors (unknown material, overlapping blocks, non-convex polygon, dt above the stable
    step, unknown monitor or body) are one-line :class:`CaseError` naming file, line and key."""
    from murus.dem import engine as E
    from murus.dem.materials import JointError
    from murus.dem.model import Model, ModelError

    d = case.dem
    # materials: the default joint and the pairs
    default = default_joint(case, path, text)
    joints = {}
    for name, mat in case.materials.items():
        try:
            joints[name] = mat.joint()
        except JointError as exc:
            raise fail_at(path, text, ("materials", name), str(exc)) from None
    for i, j in enumerate(case.joints):
        if j.material not in case.materials:
            raise fail_at(path, text, ("joints", i, "material"), f"unknown material "
                          f"'{j.material}' (defined: {', '.join(case.materials)})")
    try:
        m = Model(thickness=d.thickness, gravity=d.gravity, joint=joints[default],
                  rounding=d.rounding, safety=d.dt_safety)
    except ModelError as exc:
        raise fail_at(path, text, ("dem",), str(exc)) from None

    bodies = _shape_list(case)
    shapes = []
    groups = set()
    for where, _, parts, kin, mat, grp, _, _ in bodies:
        name = _material(case, mat, where, path, text)
        clump = where[0] == "blocks" and case.blocks[where[1]].kind == "clump"
        parts = _convex_parts(parts, where, "parts" if clump else "vertices", path, text)
        if clump:
            _check_clump(parts, where, d.overlap_tolerance, path, text)
        shapes.append(parts)
        group = grp or name
        groups.add(group)
        rho = case.materials[name].density
        try:
            if len(parts) == 1 and parts[0][0] == "poly":
                m.add_polygon(parts[0][1], rho, kin, group)
            elif len(parts) == 1:
                m.add_disc(parts[0][1], parts[0][2], rho, kin, group)
            else:
                m.add_clump([p[1] if p[0] == "poly" else p for p in parts], rho, kin, group)
        except ModelError as exc:
            raise fail_at(path, text, where, str(exc)) from None
    hit = check_overlaps(shapes, d.overlap_tolerance)
    if hit is not None:
        i, j, depth = hit
        raise fail_at(path, text, bodies[j][0], f"blocks {i} ({bodies[i][1]}) and {j} "
                      f"({bodies[j][1]}) overlap by {depth:.3g} m > overlap_tolerance "
                      f"{d.overlap_tolerance:g} m")
    for i, j in enumerate(case.joints):
        for key in ("a", "b"):
            g = getattr(j, key)
            if g not in groups:
                raise fail_at(path, text, ("joints", i, key), f"unknown group '{g}' (groups: "
                              f"{', '.join(sorted(groups))})")
        m.set_joint(joints[j.material], j.a, j.b)

    # motion
    mo = case.motion
    kind = mo.kind
    base = next((k for k, b in enumerate(bodies) if b[3] == "base"), None)
    fixed = next((k for k, b in enumerate(bodies) if b[3] == "fixed"), None)
    if kind not in ("none", "tilt") and base is None:
        raise fail_at(path, text, ("motion",), f"type '{kind}' moves the kinematic = 'base' "
                      "blocks, and there is none")
    duration = d.duration
    if duration is None:
        if kind != "record":
            raise fail_at(path, text, ("dem", "duration"), "required key is missing "
                          "(simulated time, s)")
    if kind in ("sine-pulse", "cosine-pulse", "harmonic-ramp"):
        span = duration if kind == "harmonic-ramp" else mo.cycles / mo.frequency
        nmo = span / (mo.dt or 0.001)
        if not nmo <= MAX_MOTION_SAMPLES:
            key = ("motion", "dt") if mo.dt is not None else (
                ("dem", "duration") if kind == "harmonic-ramp" else ("motion", "frequency"))
            raise fail_at(path, text, key, f"the {kind} would have {nmo:.3g} samples of "
                          f"{mo.dt or 0.001:g} s (limit {MAX_MOTION_SAMPLES:.0e}): raise "
                          "[motion] dt or shorten the motion")
    from murus.motion.case import build_motion

    motion = build_motion(mo, path, text, sampled_dt=mo.dt or 0.001, duration=duration)
    if kind == "record" and duration is None:
        duration = motion.duration
    if motion is not None:
        m.set_base_motion(motion)
    tilt = (mo.rate_deg_per_s or 0.0, mo.start_deg) if kind == "tilt" else None
    settle_tilt = (mo.start_deg if mo.settle_deg is None else mo.settle_deg) if tilt else None

    # the time step
    try:
        m.build()
        if tilt is not None:
            m.set_tilt(0.0, settle_tilt)
        if not (m.bkin == 0).any():
            raise fail_at(path, text, ("blocks",), "the model has no dynamic block")
        dts = E.stable_dt(m)
    except ModelError as exc:
        raise fail_at(path, text, ("blocks",), str(exc)) from None
    if d.dt is not None and d.dt > dts * (1 + 1e-12):
        raise fail_at(path, text, ("dem", "dt"), f"dt = {d.dt:g} s exceeds the stable time step "
                      f"{dts:g} s (dt_safety {d.dt_safety:g}); lower it or leave it out")
    _check_sizes(case, path, text, duration, dts, len(bodies))

    # monitors and stop
    dyn = [k for k, b in enumerate(bodies) if b[3] is None]
    tags = {b[6]: k for k, b in enumerate(bodies) if b[6] is not None}
    ref = base if base is not None else fixed

    def top_of(cands):
        if not cands:
            return None
        y = m.bpos[cands, 1]
        sel = [c for c, yy in zip(cands, y, strict=True) if yy >= y.max() - 1e-9]
        xm = float(np.median(m.bpos[cands, 0]))
        return min(sel, key=lambda c: abs(m.bpos[c, 0] - xm))

    named = {"top": top_of(dyn), "wall top": top_of([k for k in dyn if bodies[k][7]]),
             "base": ref}
    probes = {}
    for i, mon in enumerate(case.monitors):
        if mon.name in probes:
            raise fail_at(path, text, ("monitors", i, "name"), f"monitor '{mon.name}' is "
                          "defined twice")
        if mon.quantity == "tilt":
            probes[mon.name] = E.tilt_probe()
            continue
        b = mon.body
        if isinstance(b, int):
            if not 0 <= b < len(bodies):
                raise fail_at(path, text, ("monitors", i, "body"), f"unknown body {b} (the "
                              f"model has {len(bodies)} bodies, 0 to {len(bodies) - 1})")
        else:
            k = tags.get(b, named.get(b))
            if k is None:
                known = ", ".join(["top", "wall top", "base"] + sorted(tags))
                raise fail_at(path, text, ("monitors", i, "body"), f"unknown body '{b}' "
                              f"(give an index or one of: {known})")
            b = k
        if mon.relative:
            if ref is None:
                raise fail_at(path, text, ("monitors", i, "relative"), "relative = true needs "
                              "a kinematic block (the base)")
            if mon.quantity not in ("ux", "uy", "rot"):
                raise fail_at(path, text, ("monitors", i, "quantity"), "relative monitors "
                              "measure ux, uy or rot")
            probes[mon.name] = E.relative_probe(b, ref, mon.quantity)
        else:
            probes[mon.name] = E.body_probe(b, mon.quantity)
    height = _height(m, dyn)
    stop = None
    stop_desc = None
    if case.stop is not None:
        s = case.stop
        if s.monitor not in probes:
            raise fail_at(path, text, ("stop", "monitor"), f"unknown monitor '{s.monitor}' "
                          f"(monitors: {', '.join(probes) or 'none'})")
        op = s.op or (">" if s.value is not None else "abs>")
        value = s.value if s.value is not None else s.fraction_of_height * height
        stop = E.stop_when(probes[s.monitor], op, value)
        stop_desc = f"{s.monitor} {op} {value:.6g}"
    run_kwargs = {"duration": duration, "dt": d.dt, "xi": d.damping.fraction,
                  "freq": d.damping.frequency, "local_damping": d.damping.local,
                  "damping_frame": d.damping.frame,
                  "probes": probes, "sample_dt": case.output.sample_dt, "stop": stop,
                  "max_steps": d.max_steps}
    settle = ({"tol": d.settle_tolerance, "max_steps": d.settle_max_steps, "dt": d.dt}
              if d.settle else None)
    return Built(m, run_kwargs, list(probes), stop_desc, height, bodies, settle, settle_tilt,
                 tilt, case.output.vtk_every, case.output.figure, ref)


def _check_sizes(case: DemCase, path: Path, text: str, duration: float, dts: float,
                 nbody: int) -> None:
    """Refuse, naming the key, a case whose run could not end or not fit in memory: more than
    :data:`MAX_STEPS` time steps, or histories (and VTK frames) above :data:`MAX_HISTORY_BYTES`
    (an overflowing input such as ``kn = 1e300`` or ``dt = 1e-300``, which would otherwise fail
    deep inside NumPy)."""
    d = case.dem
    dt = d.dt if d.dt is not None else dts
    steps = duration / dt if dt > 0 else math.inf
    if not 1 <= steps <= MAX_STEPS:
        if d.dt is not None:
            key, what = ("dem", "dt"), f"dt = {d.dt:g} s"
        elif dts < 1e-8 or steps < 1:
            pick = max if steps > 1 else min
            name, mat = pick(case.materials.items(), key=lambda it: max(it[1].kn, it[1].ks))
            q = "kn" if mat.kn >= mat.ks else "ks"
            key = ("materials", name, q)
            what = f"{q} = {getattr(mat, q):g} Pa/m gives a stable time step of {dts:.3g} s"
        else:
            key, what = ("dem", "duration"), f"the time step {dt:.3g} s"
        if steps < 1:
            raise fail_at(path, text, key, f"{what}, longer than the duration {duration:g} s: "
                          "the run would take no step (a contact stiffness far too low?)")
        raise fail_at(path, text, key, f"{what}: the duration {duration:g} s would take "
                      f"{steps:.3g} steps (limit {MAX_STEPS:.0e})")
    every = max(1, int(round(case.output.sample_dt / dt)))
    samples = steps / every + 2
    cols = len(case.monitors) + 13  # t, monitors and the energy terms
    need = samples * cols * 32.0  # Python floats in lists
    if case.output.vtk_every:
        need += samples / case.output.vtk_every * nbody * 400.0
    if not need <= MAX_HISTORY_BYTES:
        key = (("output", "vtk_every") if case.output.vtk_every and samples * cols * 32.0
               <= MAX_HISTORY_BYTES else ("output", "sample_dt"))
        raise fail_at(path, text, key, f"{samples:.3g} samples of the histories"
                      + (" and VTK frames" if key[1] == "vtk_every" else "")
                      + f" would need {need / 1e9:.3g} GB of memory (limit "
                      f"{MAX_HISTORY_BYTES / 1e9:g} GB): raise it")


def _height(m, dyn) -> float:
    """Height [m] of the dynamic blocks (top of the highest minus bottom of the lowest)."""
    lo, hi = math.inf, -math.inf
    polys = m.world_polygons()
    for b, v in zip(m.body_of_polygon(), polys, strict=True):
        if b in dyn:
            lo = min(lo, float(v[:, 1].min()))
            hi = max(hi, float(v[:, 1].max()))
    c, r = m.discs()
    for b, cc, rr in zip(m.body_of_disc(), c, r, strict=True):
        if b in dyn:
            lo = min(lo, cc[1] - rr)
            hi = max(hi, cc[1] + rr)
    return hi - lo if hi > lo else 0.0


# ---------------------------------------------------------------------- running
class CaseRun:
    """A finished run: the result, the settling and the frames for VTK."""

    def __init__(self, built, result, settled, frames):
        self.built = built
        self.result = result
        self.settled = settled
        self.frames = frames

    @property
    def ok(self) -> bool:
        """True when the run reached its end or its stop condition after a converged settling
        (statuses ``completed``, ``stopped``); False for ``not_settled``, ``interpenetration``,
        ``unstable``, ``max_steps``, ``interrupted``."""
        return self.result.ok and (self.settled is None or bool(self.settled.converged))

    def summary(self) -> dict:
        r = self.result
        m = self.built.model
        final = {k: float(v[-1]) for k, v in r.values.items() if k in self.built.monitors}
        peak = {k: float(np.nanmax(np.abs(v))) for k, v in r.values.items()
                if k in self.built.monitors and len(v)}
        s = {"status": r.status, "ok": self.ok, "message": r.message, "t_end": float(m.time),
             "steps": int(r.steps), "dt": float(r.dt), "wall_time_s": float(r.wall),
             "bodies": int(m.nbody), "height": float(self.built.height),
             "stop": self.built.stop_desc, "final": final, "peak_abs": peak,
             "energy_error": float(r.values.get("energy.error", [math.nan])[-1])}
        if self.settled is not None:
            s["settle"] = {"converged": bool(self.settled.converged),
                           "steps": int(self.settled.steps), "ratio": float(self.settled.ratio)}
        return s


def _frame(m, base=None) -> dict:
    """Blocks of the current state, with the displacement [m] of each body since the
    reference state, relative to the body ``base`` when given (the shaking table)."""
    u = m.body_displacement()
    if base is not None:
        u = u - u[base]
    disp = np.hypot(*u.T)
    return {"polygons": m.world_polygons(), "discs": m.discs(),
            "cell_data": {"displacement": np.concatenate([disp[m.body_of_polygon()],
                                                          disp[m.body_of_disc()]]),
                          "body": np.concatenate([m.body_of_polygon(), m.body_of_disc()])}}


def run_case(built: Built, progress=False) -> CaseRun:
    """Settle (if asked) and run the model of :func:`build`.

    A settling that does not converge (the unbalanced-force ratio stays above
    ``settle_tolerance``, or two blocks interpenetrate by more than
    :data:`murus.dem.engine.OVERLAP_LIMIT` = 10 % of the thinner one's thickness along the
    contact normal) skips
    the dynamic run: the result then has status ``"not_settled"`` and the settling's message
    (:attr:`CaseRun.ok` is False). ``progress``: False, True (a bar) or a callable
    ``progress(done, total)`` (steps), see :func:`murus.dem.engine.run`."""
    m = built.model
    settled = None
    if built.settle is not None:
        settled = m.settle(**built.settle)
        if not settled.converged:
            result = m.run(duration=0.0, probes=built.run_kwargs["probes"],
                           sample_dt=built.run_kwargs["sample_dt"], dt=built.run_kwargs["dt"])
            result.status = "not_settled"
            result.message = f"settling did not converge: {settled.message}"
            return CaseRun(built, result, settled, [])
    if built.tilt is not None:
        m.set_tilt(*built.tilt)
        # gravity turned since the reference: measure energies (and displacements) from here
        m.reset_reference()
    kw = dict(built.run_kwargs)
    frames = []
    stops = [] if kw["stop"] is None else [kw["stop"]]
    if built.vtk_every:
        count = [1]  # frame 0 is the start; then every vtk_every samples

        def record(mm):
            if count[0] % built.vtk_every == 0:
                frames.append((mm.time, _frame(mm, built.base)))
            count[0] += 1
            return False

        record.__name__ = "vtk frames"
        frames.append((m.time, _frame(m, built.base)))
        stops.insert(0, record)
    kw["stop"] = stops or None
    result = m.run(progress=progress, **kw)
    return CaseRun(built, result, settled, frames)


# ---------------------------------------------------------------------- writers
def histories_csv(result) -> str:
    """Columns: t_s, the monitors, then the energy terms ``energy.*`` [J]."""
    names = list(result.values)
    lines = [",".join(["t_s"] + names)]
    cols = [result.t] + [result.values[k] for k in names]
    for row in np.column_stack(cols):
        lines.append(",".join(f"{x:.10g}" for x in row))
    return "\n".join(lines) + "\n"


def write_files(run: CaseRun, folder: Path, figure: bool = True) -> None:
    """``summary.json``, ``histories.csv``, ``blocks.png`` (final blocks coloured by the
    displacement since the settled state) and ``vtk/series.pvd`` when frames were kept."""
    import json

    from murus.rocking.output import _clean

    folder = Path(folder)
    (folder / "summary.json").write_text(json.dumps(_clean(run.summary()), indent=2) + "\n")
    (folder / "histories.csv").write_text(histories_csv(run.result))
    m = run.built.model
    if figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from murus.dem.plots import plot_blocks

        fr = _frame(m, run.built.base)
        label = ("displacement relative to the base [m]" if run.built.base is not None
                 else "displacement [m]")
        ax = plot_blocks(fr["polygons"], fr["discs"], fr["cell_data"]["displacement"],
                         label=label)
        ax.set_title(f"t = {m.time:.3f} s")
        ax.figure.savefig(folder / "blocks.png", dpi=120)
        plt.close(ax.figure)
    if run.frames:
        from murus.dem.vtk import write_series

        write_series(folder / "vtk", run.frames, binary=True)


def output_names(figure: bool = True) -> list[str]:
    """Relative paths written by :func:`write_files` that are known before the run (the
    ``vtk/`` series is checked when it is published)."""
    return ["summary.json", "histories.csv"] + (["blocks.png"] if figure else [])


def write_outputs(run: CaseRun, out: Path, figure: bool = True) -> Path:
    """Write the outputs of one run into ``out`` with :func:`murus.outputs.write_dir`
    (nothing of the user's replaced or deleted; ``out`` unchanged on failure)."""
    from murus.rocking.output import atomic_dir

    return atomic_dir(out, lambda tmp: write_files(run, tmp, figure),
                      names=output_names(figure))


def summary_line(name: str, run: CaseRun) -> str:
    s = run.summary()
    reason, vals = summary_parts(s)
    return (f"{name}: {s['t_end']:.4g} s simulated in {s['steps']} steps, {reason}"
            + (f", {vals}" if vals else ""))


def summary_parts(s: dict) -> tuple[str, str]:
    """The status with its reason, and the final monitor values, of a run's summary (its
    ``status``, ``stop``, ``ok``, ``message`` and ``final``), for the terminal line."""
    vals = ", ".join(f"{k} = {v:.4g}" for k, v in s["final"].items())
    reason = s["status"] + (f" ({s['stop']})" if s["status"] == "stopped" else "")
    if not s["ok"] and s["message"]:
        reason += f" ({s['message']})"
    return reason, vals
