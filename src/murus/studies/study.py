"""Study files (TOML): a rocking case, a grid of parameters and a record set.

Example (``examples/studies/restrained_block2_spectrum.toml``)::

    [study]
    name = "restrained_block2_spectrum"
    chunk_size = 256          # histories per task (one simulate_batch call)
    retries = 2               # a failing chunk is re-run this many times, then recorded failed

    [case.body]               # the rocking case tables (murus.rocking.case), inline ...
    width = 0.6
    height = 6.0
    density = 2140.7
    [case.restraint]
    motion_sides = "one"
    [case.restraint.tie]      # height: default the top of the wall
    [case.restraint.transverse_walls]
    stiffness = "eq11"        # K' from K by EURODYN (2020), eq. 11 (or a number, or "rigid")
    # ... or: case = "wall.toml" (a case file, relative to this file)

    [sweep]                   # one dimension per key, in this order
    K_over_Kd = { linspace = [0.0, 1.0, 50] }
    # "restraint.damper.fraction" = [0.0, 0.05, 0.1]; "motion.scale" = [0.5, 1.0]
    # forms: a list, {linspace = [a, b, n]}, {geomspace = [a, b, n]}, {arange = [a, b, step]}

    [records]                 # suite = "farfield" | folder = "dir" (pattern) | files = [...]
    suite = "farfield"
    select = ["farfield_01a", "farfield_12b"]   # or first = 4
    max_duration = 20.0       # s, first seconds of each record
    scale = 1.0
    # im = "PGA" | "PGV" | "Sa(T=0.5)": the meaning of the sweep parameter "im" (levels in g,
    # or m/s for PGV): each record is scaled to each level

    [output]
    folder = "restrained_block2_spectrum"   # relative to this file (the CLI's --out wins)
    figure = "spectrum.png"              # optional: plotted when the run ends

Sweep parameters: any field of the case by dotted name (``"body.width"``,
``"restraint.tie.stiffness"``, ``"restraint.damper.fraction"``, ``"restitution.value"``), and:

- ``K_over_Kd``: tie stiffness as a fraction of ``K_d`` of EURODYN (2020), eq. 12
  (:func:`murus.rocking.design.tie_design`);
- ``block``: a EURODYN (2020), Table 1 geometry, ``"block1"`` ... ``"block6"``;
- ``variant``: the names of ``[variants.NAME]`` tables, each replacing whole top-level tables of
  the case (e.g. ``[variants.tied.restraint]``);
- ``motion.scale``: a factor on every record; ``im``: records scaled to intensity levels;
- without ``[records]`` the case's ``[motion]`` (a pulse) is the input, and ``motion.*`` fields
  and ``omega_p_over_p`` (pulse frequency over p) may be swept.

Rules applied to each grid node (study defaults, on top of the case schema): a tie, damper or
spring bed without a height gets the wall's height; a tie of stiffness 0 is removed; a spring bed
``"eq11"`` follows the tie (EURODYN (2020), eq. 11) and is removed with it, the wall then rocking
two-sided: the free-standing wall of EURODYN (2020), Figures 3-4 at K = 0.
"""

from __future__ import annotations

import copy
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np
from pydantic import Field, ValidationError, model_validator

from murus.config import CaseError, Strict, fail_at, load_toml, validate
from murus.rocking.defaults import RTOL
from murus.studies.records import IntensityMeasure, RecordError, RecordSet
from murus.studies.sweep import Dim, Plan, Point, grid_points

__all__ = ["Study", "load_study", "make_study", "DERIVED", "PARAM_UNITS"]

#: Derived sweep parameters (not fields of the case).
DERIVED = ("K_over_Kd", "block", "variant", "im", "omega_p_over_p")

PARAM_UNITS = {
    "K_over_Kd": ("1", "tie stiffness over K_d (EURODYN (2020), eq. 12)"),
    "block": ("", "EURODYN (2020), Table 1 geometry"),
    "variant": ("", "case variant"),
    "omega_p_over_p": ("1", "pulse circular frequency over p"),
    "motion.scale": ("1", "factor on the records"),
    "body.width": ("m", "wall thickness b"),
    "body.height": ("m", "wall height h"),
    "body.density": ("kg/m3", "density"),
    "body.top_mass": ("kg", "top mass"),
    "restraint.tie.stiffness": ("N/m", "tie stiffness K"),
    "restraint.tie.height": ("m", "tie height"),
    "restraint.tie.pretension": ("N", "tie pretension"),
    "restraint.tie.yield_force": ("N", "tie yield force"),
    "restraint.damper.coefficient": ("N s/m", "damper coefficient c"),
    "restraint.damper.fraction": ("1", "damper coefficient over c_d (EURODYN (2020), eq. 13)"),
    "restraint.damper.delta_t": ("s", "characteristic time of eq. 13"),
    "restraint.transverse_walls.stiffness": ("N/m/m", "spring bed stiffness K'"),
    "restitution.value": ("1", "coefficient of restitution"),
    "motion.frequency": ("Hz", "pulse frequency"),
    "motion.amplitude": ("m/s2", "pulse amplitude"),
    "motion.amplitude_g": ("g", "pulse amplitude"),
}


# ----------------------------------------------------------------------------- schema ----
class StudyMeta(Strict):
    name: str = "study"
    description: str = ""
    chunk_size: int = Field(default=256, ge=1)
    retries: int = Field(default=2, ge=0)


class RecordsCfg(Strict):
    suite: str | None = None
    components: Literal["both", "a", "b"] = "both"
    folder: str | None = None
    pattern: str = "*"
    files: list[str] | None = None
    select: list[str] | None = None
    first: int | None = Field(default=None, ge=1)
    units: Literal["g", "m/s2", "cm/s2"] | None = None
    dt: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    format: Literal["at2", "esm", "cosmos", "csv"] | None = None
    scale: float = Field(default=1.0, gt=0, allow_inf_nan=False)
    max_duration: float | None = Field(default=None, gt=0, allow_inf_nan=False)
    im: str | None = None

    @model_validator(mode="after")
    def _one_source(self):
        given = [k for k in ("suite", "folder", "files") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError("give exactly one of suite, folder, files")
        if self.select is not None and self.first is not None:
            raise ValueError("give select or first, not both")
        if self.im is not None:
            IntensityMeasure.parse(self.im)
        return self


class OutputCfg(Strict):
    folder: str | None = None
    figure: str | None = None


class StudyFile(Strict):
    study: StudyMeta = StudyMeta()
    case: dict | str
    sweep: dict = Field(default_factory=dict)
    records: RecordsCfg | None = None
    output: OutputCfg = OutputCfg()
    variants: dict[str, dict] = Field(default_factory=dict)


# ----------------------------------------------------------------------------- study -----
@dataclass
class Study:
    """A study: a rocking case, a grid of swept parameters and a record set (module docstring).

    Made by :func:`load_study` (a study file) or :func:`make_study` (Python objects);
    :meth:`plan` resolves it into a :class:`~murus.studies.sweep.Plan`, :func:`run_study`
    runs it.

    Attributes
    ----------
    case : dict
        The tables of a rocking case file (:mod:`murus.rocking.case`), SI units.
    sweep : dict of str to list
        The values of each swept parameter, in the order of the dimensions; a parameter's
        units are those of the case field it names (``body.width`` [m], ``K_over_Kd`` [-],
        ``motion.scale`` [-], ``im`` [g, or m/s for PGV] ...).
    records : RecordSet or None
        The ground motions; ``None``: the case's ``[motion]`` (a pulse).
    name : str
        Name of the study.
    description : str
        Free text.
    variants : dict
        ``{name: tables}``: the case variants of the sweep parameter ``variant``, each
        replacing whole top-level tables of the case.
    im : IntensityMeasure or None
        The measure of the ``im`` levels (``PGA``, ``PGV``, ``Sa(T=...)``).
    chunk_size : int
        Histories per task (one ``simulate_batch`` call).
    retries : int
        A failing chunk is re-run this many times, then recorded as failed.
    output : str or None
        The study folder of the study file (relative paths resolved against the file).
    figure : str or None
        File name of a figure plotted when the run ends.
    path, text : pathlib.Path or None, str
        The study file and its text, to locate errors (file, line, key).
    case_path, case_text : pathlib.Path or None, str
        Those of a separate case file.

    References
    ----------
    EURODYN (2020), eqs. 11-12 and Table 1 (``K_over_Kd``, ``block``, ``"eq11"``).
    """

    case: dict
    sweep: dict[str, list]
    records: RecordSet | None = None
    name: str = "study"
    description: str = ""
    variants: dict = field(default_factory=dict)
    im: IntensityMeasure | None = None
    chunk_size: int = 256
    retries: int = 2
    output: str | None = None
    figure: str | None = None
    path: Path | None = None
    text: str = ""
    case_path: Path | None = None
    case_text: str = ""

    # -------------------------------------------------------------- error locations
    def _fail(self, loc: tuple, msg: str, node: dict | None = None) -> CaseError:
        at = "" if not node else " (at " + ", ".join(f"{k} = {_fmt(v)}" for k, v in
                                                     node.items()) + ")"
        dotted = ".".join(str(x) for x in loc)
        if node and dotted in node:  # the swept value is the culprit
            loc = ("sweep", dotted)
        elif loc and loc[0] not in ("sweep", "records", "study", "output", "variants", "case"):
            if self.case_path is not None:
                return fail_at(self.case_path, self.case_text, loc, msg + at)
            loc = ("case",) + tuple(loc)
        if self.path is None:
            return CaseError(f"[{'.'.join(str(x) for x in loc)}] {msg}{at}", key=loc,
                             reason=msg + at)
        return fail_at(self.path, self.text, loc, msg + at)

    # -------------------------------------------------------------- plan
    def dims(self) -> list[Dim]:
        out = []
        for name, values in self.sweep.items():
            units, long = PARAM_UNITS.get(name, ("", name))
            if name == "im" and self.im is not None:
                units, long = self.im.units, f"intensity measure {self.im.label}"
            out.append(Dim(name, tuple(values), {"units": units, "long_name": long}))
        return out

    def describe(self) -> dict:
        return {
            "name": self.name, "description": self.description, "case": self.case,
            "sweep": {k: [_jsonable(v) for v in vs] for k, vs in self.sweep.items()},
            "variants": self.variants,
            "records": None if self.records is None else self.records.describe(),
            "im": None if self.im is None else self.im.label,
            "chunk_size": self.chunk_size,
        }

    def plan(self) -> Plan:
        """Resolve every grid node into a model (and scales or an excitation); bad values raise a
        one-line :class:`CaseError` naming the file, line and key and the node."""
        self._check_names()
        dims = self.dims()
        records = self.records
        case_motion_records = None
        if records is None:
            records = case_motion_records = self._case_record()
        im_values = None
        if "im" in self.sweep:
            if records is None or self.im is None:
                raise self._fail(("sweep", "im"), "sweeping 'im' needs [records] with im = "
                                 "'PGA' | 'PGV' | 'Sa(T=...)'")
            try:
                im_values = self.im.of(records.load())
            except (RecordError, ValueError) as exc:
                raise self._fail(("records",), str(exc)) from None
            if np.any(~np.isfinite(im_values)) or np.any(im_values <= 0):
                raise self._fail(("records", "im"), "a record has a zero intensity measure")
        elif records is not None:
            try:
                records.load()
            except RecordError as exc:
                raise self._fail(("records",) if case_motion_records is None else
                                 ("motion", "file"), str(exc)) from None
        points = []
        duration = rtol = None
        for node in grid_points(dims):
            cfg, body = self._node_case(node)
            model = self._node_model(cfg, body, node)
            if duration is None:
                duration, rtol = cfg.solver.duration, cfg.solver.rtol
            scale: float | tuple = 1.0
            exc = None
            if records is not None:
                if "motion.scale" in node:
                    scale = float(node["motion.scale"])
                if im_values is not None:
                    scale = tuple(float(x) for x in float(node["im"]) / im_values
                                  * np.broadcast_to(scale, im_values.shape))
            else:
                exc = self._pulse(cfg, body, node)
            points.append(Point(model, scale, exc))
        return Plan(self.name, dims, points, records=records, spec=self.describe(),
                    duration=duration, rtol=rtol if rtol is not None else RTOL,
                    chunk_size=self.chunk_size)

    def _check_names(self) -> None:
        for name, values in self.sweep.items():
            if not values:
                raise self._fail(("sweep", name), "no values")
            if name in DERIVED:
                continue
            parts = name.split(".")
            if parts[0] == "motion":
                recs = self.records is not None or _motion_kind(self.case) == "record"
                if recs and name != "motion.scale":
                    raise self._fail(("sweep", name), "with [records] only motion.scale (or im) "
                                     "can be swept among the motion fields")
                continue
            if parts[0] not in ("body", "restitution", "pivot", "restraint"):
                raise self._fail(("sweep", name), "unknown sweep parameter: use a case field "
                                 "(body.*, restitution.*, pivot.*, restraint.*, motion.*) or "
                                 f"one of {', '.join(DERIVED)}")
        if "variant" in self.sweep:
            for v in self.sweep["variant"]:
                if v not in self.variants:
                    raise self._fail(("sweep", "variant"), f"no [variants.{v}] table")
        if "block" in self.sweep:
            bad = [b for b in self.sweep["block"] if b not in
                   [f"block{i}" for i in range(1, 7)]]
            if bad:
                raise self._fail(("sweep", "block"), f"unknown EURODYN (2020) block {bad[0]!r} "
                                 "(block1 ... block6)")
        if "omega_p_over_p" in self.sweep and self.records is not None:
            raise self._fail(("sweep", "omega_p_over_p"), "omega_p_over_p sweeps the frequency "
                             "of the case's pulse: remove [records]")

    def _case_record(self) -> RecordSet | None:
        m = self.case.get("motion") or {}
        kind = m.get("type") or ("record" if m.get("file") else None)
        if kind != "record":
            return None
        f = Path(m["file"])
        base = (self.case_path or self.path or Path.cwd() / "x").parent
        if not f.is_absolute():
            f = base / f
        return RecordSet(kind="files", files=(str(f.resolve()),), units=m.get("units"),
                         dt=m.get("dt"), format=m.get("format"), scale=m.get("scale", 1.0))

    def _node_case(self, node: dict):
        """The validated case of a grid node and its body."""

        data = copy.deepcopy(self.case)
        if "variant" in node:
            for key, table in self.variants[node["variant"]].items():
                data[key] = copy.deepcopy(table)
        if "block" in node:
            from murus.rocking.body import restrained_wall_block

            b = restrained_wall_block(node["block"])
            body = dict(data.get("body") or {})
            body.update(width=b.width, height=b.height, thickness=b.thickness,
                        density=b.density, top_mass=0.0, name=b.name)
            data["body"] = body
        for name, value in node.items():
            if name in DERIVED or name == "motion.scale" and self.records is not None:
                continue
            _set(data, name.split("."), _jsonable(value))
        if self.records is not None or _motion_kind(data) == "record":
            data["motion"] = {"type": "free", "theta0_over_alpha": 0.5}  # placeholder
        restraint = data.setdefault("restraint", {})
        walls = restraint.get("transverse_walls")
        eq11 = isinstance(walls, dict) and walls.get("stiffness") == "eq11"
        if eq11:
            walls = dict(walls)
            walls["stiffness"] = 1.0  # placeholder, resolved below
            restraint["transverse_walls"] = walls
        elif isinstance(walls, dict) and isinstance(walls.get("stiffness"), str) \
                and walls.get("stiffness") != "rigid":
            raise self._fail(("restraint", "transverse_walls", "stiffness"), "must be a number "
                             f"(N/m/m), 'rigid' or 'eq11' (got {walls['stiffness']!r})", node)
        elif isinstance(walls, dict) and walls.get("stiffness") == "rigid":
            # rigid walls as an infinite stiffness (the case schema's "rigid" literal trips
            # pydantic's gt constraint of the float branch)
            restraint["transverse_walls"] = {**walls, "stiffness": math.inf}
        h = (data.get("body") or {}).get("height")
        for key, hk in (("tie", "height"), ("damper", "height"),
                        ("transverse_walls", "effective_height")):
            t = restraint.get(key)
            if isinstance(t, dict) and hk not in t and h is not None:
                restraint[key] = {**t, hk: h}
        if "K_over_Kd" in node:
            restraint["tie"] = {**(restraint.get("tie") or {"height": h}), "stiffness": 1.0}
        if isinstance(restraint.get("tie"), dict) and restraint["tie"].get("stiffness") == 0:
            restraint["tie"] = {**restraint["tie"], "stiffness": 1.0}
            k_zero = True
        else:
            k_zero = False
        cfg = self._validate(data, node)
        from murus.rocking.body import BodyError, RigidBlock

        b = cfg.body
        try:
            body = RigidBlock(b.width, b.height, b.thickness, b.density, b.top_mass, name=b.name)
        except BodyError as exc:
            raise self._fail(("body",), str(exc), node) from None
        # derived stiffnesses
        r = dict(cfg.restraint.model_dump(exclude_unset=False))
        tie = r.get("tie")
        if "K_over_Kd" in node:
            from murus.rocking.design import DesignError, tie_design

            try:
                Kd = tie_design(body, tie["height"]).K_d
            except DesignError as exc:
                raise self._fail(("restraint", "tie"), str(exc), node) from None
            if Kd <= 0.0:
                raise self._fail(("sweep", "K_over_Kd"), "K_d = 0: the wall needs no tie by eq. "
                                 "12 (mu <= tan alpha); sweep restraint.tie.stiffness", node)
            ratio = float(node["K_over_Kd"])
            if not ratio >= 0.0:
                raise self._fail(("sweep", "K_over_Kd"), f"must be >= 0, got {ratio:g}", node)
            tie["stiffness"] = ratio * Kd
        elif k_zero:
            tie["stiffness"] = 0.0
        if tie is not None and tie["stiffness"] == 0.0:
            r["tie"] = tie = None
        if eq11:
            if tie is None:
                r["transverse_walls"] = None
                r["motion_sides"] = "two"
            else:
                from murus.rocking.design import bed_stiffness_equal

                r["transverse_walls"]["stiffness"] = bed_stiffness_equal(
                    body, tie["stiffness"], tie["height"], tie["x"])
        if "K_over_Kd" in node or eq11 or k_zero:
            from murus.rocking.case import RestraintCfg

            r = {k: v for k, v in r.items() if v is not None}
            try:
                cfg = cfg.model_copy(update={"restraint": RestraintCfg.model_validate(r)})
            except ValidationError as exc:
                err = exc.errors()[0]
                loc = ("restraint",) + tuple(x for x in err.get("loc", ())
                                             if not isinstance(x, int))
                raise self._fail(loc, err.get("msg", "invalid value").removeprefix(
                    "Value error, "), node) from None
        return cfg, body

    def _validate(self, data: dict, node: dict):
        from murus.config import error_message
        from murus.rocking.case import RockingCase

        try:
            return RockingCase.model_validate(data)
        except ValidationError as exc:
            errs = exc.errors()

            def swept(e):  # an error on a swept key names the culprit best
                return ".".join(str(x) for x in e.get("loc", ()) if not isinstance(x, int)) \
                    in node

            err = next((e for e in errs if swept(e)), errs[0])
            loc = tuple(x for x in err.get("loc", ()) if not isinstance(x, int)
                        and not _UNION_TAG.match(str(x)))
            raise self._fail(loc, error_message(err), node) from None

    def _node_model(self, cfg, body, node):
        from murus.rocking.case import build_model

        if cfg.base.model != "rigid":
            raise self._fail(("base",), "studies run the rigid-base engine (simulate_batch): "
                             "a Winkler base is not supported")
        if cfg.solver.method != "event":
            raise self._fail(("solver", "method"), "studies run the event-driven kernel "
                             "(simulate_batch): method must be 'event'")
        if cfg.solver.rest_tol == 0.0:
            raise self._fail(("solver", "rest_tol"), "rest_tol = 0 never ends a cascade of "
                             "impacts and every history would stop early: give a positive value "
                             "(default 1e-3)")
        path, text = (self.case_path, self.case_text) if self.case_path else (self.path,
                                                                               self.text)
        try:
            return build_model(cfg, body, path or Path("study"), text)
        except CaseError as exc:
            # the key path of the case's table; in a study file the case is its [case] table
            loc = exc.key if self.case_path is not None or self.path is None else \
                ("case",) + exc.key
            at = ", ".join(f"{k} = {_fmt(v)}" for k, v in node.items())
            raise fail_at(path or Path("study"), text, loc,
                          f"{exc.reason} (at {at})" if at else exc.reason) from None

    def _pulse(self, cfg, body, node):
        from murus.motion.case import build_motion

        m = cfg.motion
        kind = m.kind
        if kind not in ("sine-pulse", "cosine-pulse", "rectangular-pulse"):
            raise self._fail(("motion",), "without [records] the case's motion must be a pulse "
                             "(sine-pulse, cosine-pulse, rectangular-pulse) or a record file")
        freq = None
        if "omega_p_over_p" in node and kind != "rectangular-pulse":
            freq = float(node["omega_p_over_p"]) * body.p / (2.0 * math.pi)
        return build_motion(m, None, kind=kind, frequency=freq)


_UNION_TAG = re.compile(r"^(float|int|str|bool|literal\[.*\]|function-.*)$")


def _motion_kind(data: dict) -> str | None:
    m = data.get("motion") or {}
    return m.get("type") or ("record" if m.get("file") else None)


def _set(data: dict, parts: list[str], value) -> None:
    d = data
    for p in parts[:-1]:
        nxt = d.get(p)
        if not isinstance(nxt, dict):
            nxt = {}
            d[p] = nxt
        d = nxt
    d[parts[-1]] = value


def _fmt(v) -> str:
    return f"{v:g}" if isinstance(v, float) else str(v)


def _jsonable(v):
    if isinstance(v, np.generic):
        return v.item()
    return v


# ----------------------------------------------------------------------------- loading ---
_SPACES = ("linspace", "geomspace", "arange", "values")


def _values(name: str, spec, fail):
    if isinstance(spec, list):
        vals = spec
    elif isinstance(spec, dict) and len(spec) == 1 and next(iter(spec)) in _SPACES:
        kind, args = next(iter(spec.items()))
        if kind == "values":
            vals = args
        else:
            if not (isinstance(args, list) and len(args) == 3
                    and all(isinstance(x, int | float) for x in args)):
                raise fail(f"{kind} needs three numbers [start, stop, {'step' if kind == 'arange' else 'n'}]")  # noqa: E501
            a, b, n = args
            if kind == "arange":
                if n <= 0:
                    raise fail("arange step must be positive")
                vals = np.arange(a, b + 0.5 * n, n).tolist()
            else:
                if int(n) != n or n < 1:
                    raise fail(f"{kind} needs an integer count, got {n!r}")
                if kind == "geomspace" and (a <= 0 or b <= 0):
                    raise fail("geomspace bounds must be positive")
                vals = getattr(np, kind)(a, b, int(n)).tolist()
    else:
        raise fail("give a list of values or {linspace = [start, stop, n]}, "
                   "{geomspace = [start, stop, n]}, {arange = [start, stop, step]}")
    if not isinstance(vals, list) or not vals:
        raise fail("no values")
    if not (all(isinstance(v, str) for v in vals)
            or all(isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
                   for v in vals)):
        raise fail("values must be all numbers (finite) or all strings")
    if len(set(vals)) != len(vals):
        raise fail("repeated values")
    return [float(v) if not isinstance(v, str) else v for v in vals]


def _flatten_sweep(d: dict, prefix: str = "") -> dict:
    out = {}
    for k, v in d.items():
        name = f"{prefix}{k}"
        if isinstance(v, dict) and not (len(v) == 1 and next(iter(v)) in _SPACES):
            out.update(_flatten_sweep(v, name + "."))
        else:
            out[name] = v
    return out


def load_study(path) -> Study:
    """Read and validate a study file (TOML; module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The study file; a separate case file, a records folder or files and the output folder
        are relative to its folder.

    Returns
    -------
    Study
        The validated study, its sweep values expanded (``linspace``, ``geomspace``,
        ``arange`` forms) and its records selected.

    Raises
    ------
    CaseError
        One line naming the file, line and key: unreadable or invalid TOML, an unknown key,
        a case file, records folder or record file not found, an unknown suite or record, or
        bad sweep values.
    """
    path = Path(path)
    data, text = load_toml(path)
    cfg = validate(StudyFile, data, path, text)
    case_path = None
    case_text = ""
    if isinstance(cfg.case, str):
        case_path = Path(cfg.case)
        if not case_path.is_absolute():
            case_path = path.parent / case_path
        if not case_path.exists():
            raise fail_at(path, text, ("case",), f"case file '{cfg.case}' not found")
        case, case_text = load_toml(case_path)
    else:
        case = copy.deepcopy(cfg.case)
    sweep = {}
    for name, spec in _flatten_sweep(cfg.sweep).items():
        def fail(msg, name=name):
            return fail_at(path, text, ("sweep", name), msg)

        sweep[name] = _values(name, spec, fail)
    rec = cfg.records
    records = None
    im = None
    if rec is not None:
        try:
            records = _record_set(rec, path)
        except RecordError as exc:
            raise fail_at(path, text, ("records",), str(exc)) from None
        if rec.im is not None:
            im = IntensityMeasure.parse(rec.im)
    out = cfg.output.folder
    if out is not None and not Path(out).is_absolute():
        out = str(path.parent / out)
    return Study(case=case, sweep=sweep, records=records, name=cfg.study.name,
                 description=cfg.study.description, variants=dict(cfg.variants), im=im,
                 chunk_size=cfg.study.chunk_size, retries=cfg.study.retries, output=out,
                 figure=cfg.output.figure, path=path, text=text, case_path=case_path,
                 case_text=case_text)


def _record_set(rec: RecordsCfg, path: Path) -> RecordSet:
    common = {"scale": rec.scale, "max_duration": rec.max_duration}
    if rec.suite is not None:
        from murus.motion.records import SUITES

        if rec.suite not in SUITES:
            raise RecordError(f"unknown suite {rec.suite!r}: use one of {', '.join(SUITES)}")
        rs = RecordSet(kind="suite", suite=rec.suite, components=rec.components, **common)
    else:
        if rec.folder is not None:
            folder = Path(rec.folder)
            if not folder.is_absolute():
                folder = path.parent / folder
            if not folder.is_dir():
                raise RecordError(f"records folder '{rec.folder}' not found")
            files = sorted(str(f.resolve()) for f in folder.glob(rec.pattern)
                           if f.is_file() and not f.name.startswith("."))
            if not files:
                raise RecordError(f"no files matching '{rec.pattern}' in '{rec.folder}'")
        else:
            files = []
            for f in rec.files:
                p = Path(f)
                if not p.is_absolute():
                    p = path.parent / p
                if not p.exists():
                    raise RecordError(f"record file '{f}' not found")
                files.append(str(p.resolve()))
        rs = RecordSet(kind="files", files=tuple(files), units=rec.units, dt=rec.dt,
                       format=rec.format, **common)
    if rec.first is not None or rec.select is not None:
        names = [m.name for m in rs.load()]
        sel = names[: rec.first] if rec.first is not None else rec.select
        missing = [s for s in sel if s not in names]
        if missing:
            raise RecordError(f"records not in the set: {', '.join(missing[:5])}")
        import dataclasses

        rs = dataclasses.replace(rs, select=tuple(sel))
    return rs


def make_study(case: dict, sweep: dict, records=None, *, name: str = "study",
               variants: dict | None = None, im=None, chunk_size: int = 256,
               retries: int = 2) -> Study:
    """A :class:`Study` from Python objects.

    Parameters
    ----------
    case : dict
        The tables of a rocking case file as a dict (SI units, :mod:`murus.rocking.case`).
    sweep : dict
        ``{name: values}``, in the order of the dimensions; a single number or string is one
        value. Units: those of the case field each name stands for (module docstring).
    records : optional
        Anything :meth:`RecordSet.coerce` takes (a suite name, files, ground motions), or
        ``None`` for the case's pulse.
    name : str
        Name of the study.
    variants : dict, optional
        ``{name: tables}`` of the sweep parameter ``variant``.
    im : str, optional
        The measure of the ``im`` levels: ``"PGA"``, ``"PGV"`` or ``"Sa(T=...)"``.
    chunk_size : int
        Histories per task.
    retries : int
        Re-runs of a failing chunk before it is recorded as failed.

    Returns
    -------
    Study
        Errors are located by key (``[sweep.NAME]``), there being no file.

    Raises
    ------
    CaseError
        If the values of a sweep parameter are invalid.
    """
    sw = {}
    for k, v in sweep.items():
        vals = [v] if isinstance(v, str | int | float) else list(np.asarray(v).tolist())

        def fail(msg, k=k):
            return CaseError(f"[sweep.{k}] {msg}", key=("sweep", k), reason=msg)

        sw[k] = _values(k, vals, fail)
    return Study(case=copy.deepcopy(case), sweep=sw,
                 records=None if records is None else RecordSet.coerce(records), name=name,
                 variants=dict(variants or {}),
                 im=None if im is None else IntensityMeasure.parse(im), chunk_size=chunk_size,
                 retries=retries)


def run_study(study: Study, executor="process", *, workers=None, scheduler=None, out=None,
              progress=None, hook=None):
    """Plan and run a study (see :func:`murus.studies.sweep.run_plan`).

    Parameters
    ----------
    study : Study
        The study.
    executor : str or ExecutorHandle
        ``"serial"``, ``"process"``, ``"dask"`` or an open executor handle.
    workers : int, optional
        Number of workers of the executor.
    scheduler : str, optional
        Address of a Dask scheduler.
    out : str or pathlib.Path, optional
        Study folder; default the study's ``output`` (none: nothing is written).
    progress : callable, optional
        ``progress(done, total, failed)``, counts of chunks.
    hook : callable, optional
        A picklable ``hook(chunk_index)`` run in the worker before each chunk.

    Returns
    -------
    xarray.Dataset
        The summaries of every history over the dimensions of the sweep and ``record``
        (:func:`~murus.studies.sweep.run_plan`).

    Raises
    ------
    CaseError
        If a grid node does not resolve into a model (one line naming the file, line, key and
        node).
    StudyError
        If the options are invalid or ``out`` holds another study.
    """
    from murus.studies.sweep import run_plan

    out = out if out is not None else study.output
    return run_plan(study.plan(), executor, workers=workers, scheduler=scheduler, out=out,
                    retries=study.retries, progress=progress, hook=hook)

