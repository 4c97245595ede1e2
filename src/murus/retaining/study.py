"""The behaviour-factor study of a dry-stone retaining wall (Savalle et al. (2022), §4.2-4.4, Tables
7 and 8; issue 6 item 4) as stored, resumable tasks on the executors of :mod:`murus.studies`.

Two stages of DEM runs (:func:`murus.retaining.collapse.collapse_run`):

1. S2 (harmonic ramp) for every (frequency, vertical mode): ``t_col``, ``A_col``;
2. S1 checks at ``ratio A_col`` for every ratio of ``check_ratios`` (Savalle et al. (2022), Figure
   14: stable at 0.6, collapsed at 0.7), with the slope of the S2 run; queued as soon as their S2
   run is done (no barrier between the stages). A case whose S2 run does not collapse has no
   ``A_col``: its checks are recorded as skipped.

Each case is one task of :func:`murus.studies.sweep.run_tasks` (retries, a window of tasks in
flight, serial / process pool / Dask, progress), stored by this process as it finishes.

Study folder (``out``)::

    out/
      study.json                     the resolved study, its digest, the case files (first)
      cases/S2_5Hz_none.json         summary of one run (t_col, A_col, A_pseudo, ...) and the
      cases/S2_5Hz_none.json.sha256  SHA-256 of the other files, written last, then its own
      cases/S2_5Hz_none.csv          checksum: a case is done when all match; its d_top history
      cases/S2_5Hz_none.npz          (t, d_top, acc, acc_v, kh, kv) and the blocks at the end
      cases/S1_5Hz_none_0.6.json     of the run (snapshot data; PNGs by write_snapshots)
      ...
      failures.json                  cases that failed after their retries
      behaviour_factor.csv, .md      the table (Savalle et al. (2022), Tables 7-8 layout), when the
      run ends

Re-running the same study with the same ``out`` computes only the cases without valid files
(missing, truncated or corrupt, or of other inputs) and gives the same table, byte for byte
(the table is always assembled from the stored summaries, the run times included); a folder
holding another study is refused, as for :func:`murus.studies.sweep.run_plan`. Interrupting a
run (Ctrl-C) loses no finished case. ``murus study status OUT`` shows the cases done, missing,
damaged and failed.

Case file (TOML, ``examples/retaining/``)::

    [study]
    name = "dsrw1"
    retries = 2                  # a failing case is re-run this many times, then recorded

    [wall]
    preset = "DSRW1"             # DSRW1..DSRW4, C3s, mockup-<H/B>
    # any field of RetainingWall overrides the preset: stone_height = 0.1, base = "horizontal"

    [cases]
    frequencies = [3.0, 5.0, 10.0]          # Hz
    vertical = ["none"]                     # none | in_phase | opposition (grid with frequencies)
    extra = [{ frequency = 5.0, vertical = "opposition" }]   # cases outside the grid
    check_ratios = [0.6, 0.7]               # S1 checks at these fractions of A_col ([]: none)
    peak_ratio = 0.6                        # A_peak = peak_ratio A_col, r = A_peak / A_pseudo

    [numerics]                   # keyword arguments of collapse_run (defaults there)
    xi = 0.05
    stiffness_scale = 1e-3       # default: 1e-2 on the continuum backfill, 1e-3 otherwise
    # t_pseudo, t_max, tail, threshold, safety, update_dt, sample_dt, motion_dt,
    # thrust_scale, vertical_ratio, damping_frame; [numerics.build]: build_wall options
    # backfill = "discrete"      # a disc backfill instead of the equivalent thrust, with
    # [numerics.backfill_options] W = 5.0, boundary = "absorbing", radius, spread, seed, rolling
    # backfill = "continuum"     # Mohr-Coulomb zones, the paper's model, with
    # [numerics.backfill_options] W = 5.0, size = 0.2, boundary = "free-field" | "fixed" | "quiet"
    # subcycle = "auto"          # continuum: the zones step once every n steps of the stones

    [executor]                   # the CLI's --executor/--workers/--scheduler win
    kind = "process"             # serial | process | dask
    workers = 2
    # scheduler = "tcp://HOST:PORT" (kind = "dask"; default: a local cluster)

    [output]
    folder = "out/dsrw1"         # relative to this file (the CLI's --out wins)

Units: SI (m, s, Hz, m/s², m/s³).
"""

from __future__ import annotations

import copy
import dataclasses
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import Field, ValidationError, field_validator, model_validator

from murus.config import CaseError, Strict, error_message, fail_at, load_toml
from murus.retaining.collapse import (
    SEED_TABLE7,
    BehaviourTable,
    collapse_run,
    pseudo_static_resistance,
)
from murus.retaining.collapse import digest as _digest
from murus.retaining.collapse import wall_dict as _wall_dict
from murus.retaining.geometry import GeometryError, RetainingWall

__all__ = ["BehaviourStudy", "BehaviourStudyResult", "CaseTask", "load_behaviour_study",
           "behaviour_study", "run_behaviour_study", "run_case", "running_cases",
           "write_snapshots",
           "STUDY_FORMAT"]

STUDY_FORMAT = 1
VERTICAL = Literal["none", "in_phase", "opposition"]
_FLOAT = dict(allow_inf_nan=False)


# ----------------------------------------------------------------------------- schema ----
class StudyMeta(Strict):
    name: str = "behaviour_factor"
    description: str = ""
    retries: int = Field(default=2, ge=0)


class WallCfg(Strict):
    """A preset of :func:`murus.retaining.geometry.preset` and overrides of its fields."""

    preset: str
    height: float | None = Field(default=None, **_FLOAT)
    base_width: float | None = Field(default=None, **_FLOAT)
    top_width: float | None = Field(default=None, **_FLOAT)
    external_batter: float | None = Field(default=None, **_FLOAT)
    internal_batter: float | None = Field(default=None, **_FLOAT)
    bed_inclination_deg: float | None = Field(default=None, **_FLOAT)
    backfill_slope_deg: float | None = Field(default=None, **_FLOAT)
    stone_height: float | None = Field(default=None, **_FLOAT)
    stone_length: float | None = Field(default=None, **_FLOAT)
    wall_unit_weight: float | None = Field(default=None, **_FLOAT)
    backfill_unit_weight: float | None = Field(default=None, **_FLOAT)
    backfill_friction_deg: float | None = Field(default=None, **_FLOAT)
    joint_friction_deg: float | None = Field(default=None, **_FLOAT)
    interface_friction_deg: float | None = Field(default=None, **_FLOAT)
    base: Literal["inclined", "horizontal"] | None = None
    backfill_profile: list[tuple[float, float]] | None = None

    def overrides(self) -> dict:
        d = self.model_dump(exclude={"preset"}, exclude_none=True)
        if "backfill_profile" in d:
            d["backfill_profile"] = tuple(tuple(p) for p in d["backfill_profile"])
        return d


class ExtraCase(Strict):
    frequency: float = Field(gt=0, **_FLOAT)
    vertical: VERTICAL = "none"


class CasesCfg(Strict):
    frequencies: list[float] = Field(min_length=1)
    vertical: list[VERTICAL] = Field(default_factory=lambda: ["none"], min_length=1)
    extra: list[ExtraCase] = Field(default_factory=list)
    check_ratios: list[float] = Field(default_factory=lambda: [0.6, 0.7])
    peak_ratio: float = Field(default=0.6, gt=0, le=1, **_FLOAT)

    @field_validator("frequencies")
    @classmethod
    def _freqs(cls, v):
        if any(not (math.isfinite(f) and f > 0) for f in v):
            raise ValueError("frequencies must be positive numbers [Hz]")
        if len({f"{f:g}" for f in v}) != len(v):
            raise ValueError("repeated frequencies")
        return v

    @field_validator("vertical")
    @classmethod
    def _modes(cls, v):
        if len(set(v)) != len(v):
            raise ValueError("repeated vertical modes")
        return v

    @field_validator("check_ratios")
    @classmethod
    def _ratios(cls, v):
        if any(not (math.isfinite(r) and 0 < r < 10) for r in v):
            raise ValueError("check ratios must be positive fractions of A_col")
        if len({f"{r:g}" for r in v}) != len(v):
            raise ValueError("repeated check ratios")
        return v


class BuildCfg(Strict):
    """Options of :func:`murus.retaining.dem_wall.build_wall` (None: its default)."""

    stone_length: float | None = Field(default=None, gt=0, **_FLOAT)
    min_piece: float | None = Field(default=None, gt=0, **_FLOAT)
    kn: float | None = Field(default=None, gt=0, **_FLOAT)
    ks: float | None = Field(default=None, gt=0, **_FLOAT)
    foundation_depth: float | None = Field(default=None, gt=0, **_FLOAT)
    foundation_front: float | None = Field(default=None, ge=0, **_FLOAT)
    rounding: float | None = Field(default=None, ge=0, **_FLOAT)
    top: Literal["front", "back"] | None = None
    backstop: bool | None = None
    headers: list[int] | None = None
    bond_phase: Literal[0, 1] | None = None


class BackfillCfg(Strict):
    """Options of :class:`murus.retaining.backfill.DiscreteBackfill` (``backfill =
    "discrete"``: W, boundary container or absorbing, radius, spread, seed, rolling) or of
    :class:`murus.retaining.continuum_backfill.ContinuumBackfill` (``backfill = "continuum"``:
    W, boundary free-field or fixed, size) (None: their defaults)."""

    W: float | None = Field(default=None, gt=0, **_FLOAT)
    boundary: Literal["container", "absorbing", "free-field", "fixed", "quiet"] | None = None
    radius: float | None = Field(default=None, gt=0, **_FLOAT)
    spread: float | None = Field(default=None, ge=0, lt=1, **_FLOAT)
    seed: int | None = Field(default=None, ge=0)
    rolling: float | None = Field(default=None, ge=0, **_FLOAT)
    size: float | None = Field(default=None, gt=0, **_FLOAT)


#: The options and the far-side boundaries of each backfill model (:class:`BackfillCfg`).
BACKFILL_OPTIONS = {"discrete": ({"W", "boundary", "radius", "spread", "seed", "rolling"},
                                 ("container", "absorbing")),
                    "continuum": ({"W", "boundary", "size"}, ("free-field", "fixed", "quiet"))}


class NumericsCfg(Strict):
    """Keyword arguments of :func:`murus.retaining.collapse.collapse_run` (None: its
    default)."""

    xi: float | None = Field(default=None, ge=0, lt=1, **_FLOAT)
    stiffness_scale: float | None = Field(default=None, gt=0, **_FLOAT)
    A_rate: float | None = Field(default=None, gt=0, **_FLOAT)
    t_pseudo: float | None = Field(default=None, gt=0, **_FLOAT)
    t_max: float | None = Field(default=None, gt=0, **_FLOAT)
    tail: float | None = Field(default=None, ge=0, **_FLOAT)
    threshold: float | None = Field(default=None, gt=0, lt=10, **_FLOAT)
    safety: float | None = Field(default=None, gt=0, **_FLOAT)
    update_dt: float | None = Field(default=None, gt=0, **_FLOAT)
    sample_dt: float | None = Field(default=None, gt=0, **_FLOAT)
    motion_dt: float | None = Field(default=None, gt=0, **_FLOAT)
    thrust_scale: float | None = Field(default=None, ge=0, **_FLOAT)
    vertical_ratio: float | None = Field(default=None, gt=0, **_FLOAT)
    damping_frame: Literal["base", "absolute"] | None = None
    backfill: Literal["thrust", "discrete", "continuum"] | None = None
    subcycle: Literal["auto"] | Annotated[int, Field(ge=1, strict=True)] | None = None
    build: BuildCfg = BuildCfg()
    backfill_options: BackfillCfg = BackfillCfg()

    @model_validator(mode="after")
    def _backfill_options(self):
        if self.subcycle is not None and self.backfill != "continuum":
            raise ValueError("subcycle needs backfill = 'continuum'")
        from murus.retaining.collapse import subcycle_refused

        refused = subcycle_refused(self.subcycle, self.stiffness_scale)
        if refused:
            raise ValueError(refused)
        given = self.backfill_options.model_dump(exclude_none=True)
        if not given:
            return self
        if self.backfill not in BACKFILL_OPTIONS:
            raise ValueError("[numerics.backfill_options] needs backfill = 'discrete' or "
                             "'continuum'")
        keys, bounds = BACKFILL_OPTIONS[self.backfill]
        extra = sorted(set(given) - keys)
        if extra:
            raise ValueError(f"[numerics.backfill_options] {', '.join(extra)}: not an option "
                             f"of the {self.backfill} backfill ({', '.join(sorted(keys))})")
        if given.get("boundary", bounds[0]) not in bounds:
            raise ValueError(f"[numerics.backfill_options] boundary = {given['boundary']!r}: "
                             f"the {self.backfill} backfill takes {' or '.join(bounds)}")
        return self

    def kwargs(self) -> dict:
        kw = self.model_dump(exclude={"build", "backfill_options"}, exclude_none=True)
        b = self.build.model_dump(exclude_none=True)
        if b:
            kw["build"] = b
        o = self.backfill_options.model_dump(exclude_none=True)
        if o:
            kw["backfill_options"] = o
        return kw


class ExecutorCfg(Strict):
    kind: Literal["serial", "process", "dask"] = "process"
    workers: int | None = Field(default=None, ge=1)
    scheduler: str | None = None

    @model_validator(mode="after")
    def _scheduler(self):
        if self.scheduler is not None and self.kind != "dask":
            raise ValueError("scheduler needs kind = 'dask'")
        return self


class OutputCfg(Strict):
    folder: str | None = None


class BehaviourFile(Strict):
    study: StudyMeta = StudyMeta()
    wall: WallCfg
    cases: CasesCfg
    numerics: NumericsCfg = NumericsCfg()
    executor: ExecutorCfg = ExecutorCfg()
    output: OutputCfg = OutputCfg()


# ----------------------------------------------------------------------------- study -----
@dataclass(frozen=True)
class Case:
    """One DEM run of the study: ``index`` (task number), ``name`` (file stem), ``signal``
    ("S2" or "S1"), ``frequency`` [Hz], ``vertical``; for S1, ``ratio`` and ``parent`` (the
    index of its S2 run)."""

    index: int
    name: str
    signal: str
    frequency: float
    vertical: str
    ratio: float | None = None
    parent: int | None = None


@dataclass
class BehaviourStudy:
    """A resolved behaviour-factor study (module docstring): the ``wall``, the (frequency,
    vertical) ``cases`` of stage 1, the S1 ``check_ratios``, ``peak_ratio``, the keyword
    arguments ``numerics`` of :func:`collapse_run`, ``A_pseudo`` per vertical mode [m/s²],
    retries, the executor of the case file (``executor``: kind, workers, scheduler) and the
    output folder."""

    wall: RetainingWall
    wall_spec: dict
    cases: list[tuple[float, str]]
    check_ratios: list[float]
    peak_ratio: float = 0.6
    numerics: dict = field(default_factory=dict)
    A_pseudo: dict = field(default_factory=dict)
    name: str = "behaviour_factor"
    description: str = ""
    retries: int = 2
    executor: dict = field(default_factory=lambda: {"kind": "process", "workers": None,
                                                    "scheduler": None})
    output: str | None = None

    # ------------------------------------------------------------------ layout
    def tasks(self) -> list[Case]:
        """Every run: the S2 runs (one per case, in order), then the S1 checks of each."""
        s2 = [Case(i, f"S2_{f:g}Hz_{v}", "S2", f, v) for i, (f, v) in enumerate(self.cases)]
        s1 = [Case(len(s2) + k * len(self.check_ratios) + j, f"S1_{c.frequency:g}Hz_"
                   f"{c.vertical}_{r:g}", "S1", c.frequency, c.vertical, r, c.index)
              for k, c in enumerate(s2) for j, r in enumerate(self.check_ratios)]
        return s2 + s1

    def describe(self) -> dict:
        return {"name": self.name, "description": self.description, "wall": self.wall_spec,
                "cases": [[f, v] for f, v in self.cases], "check_ratios": self.check_ratios,
                "peak_ratio": self.peak_ratio, "numerics": self.numerics,
                "A_pseudo": self.A_pseudo}

    def digest(self) -> str:
        """Digest of everything that determines the numbers (not the executor)."""
        return _digest({"v": STUDY_FORMAT, "study": self.describe(),
                        "wall": _wall_dict(self.wall)})

    # ------------------------------------------------------------------ one case
    def case_kwargs(self, case: Case, parent: dict | None = None) -> dict:
        """Keyword arguments of :func:`collapse_run` for ``case`` (``parent``: the stored
        record of its S2 run, for S1: the slope of S2 and ``a_peak = ratio A_col``)."""
        kw = copy.deepcopy(self.numerics)
        kw["A_pseudo"] = self.A_pseudo[case.vertical]
        if case.signal == "S1":
            s = parent["summary"]
            kw.update(signal="S1", A_rate=s["A_rate"], a_peak=case.ratio * s["A_col"])
        return kw

    def case_digest(self, case: Case, parent: dict | None = None) -> str:
        """Digest of the inputs of one run (``parent``: the record of its S2 run, for S1)."""
        if case.signal == "S1" and not _collapsed(parent["summary"]):
            return _digest({"skipped": parent["digest"], "ratio": case.ratio})
        return _digest({"v": STUDY_FORMAT, "wall": _wall_dict(self.wall),
                        "frequency": case.frequency, "vertical": case.vertical,
                        "kw": self.case_kwargs(case, parent)})


def _collapsed(summary: dict | None) -> bool:
    return bool(summary) and bool(summary.get("collapsed")) and summary.get("A_col") is not None


# ----------------------------------------------------------------------------- loading ---
def load_behaviour_study(path) -> BehaviourStudy:
    """Read and validate a behaviour-factor case file: errors are one-line
    :class:`~murus.config.CaseError` naming the file, line and key."""
    path = Path(path)
    data, text = load_toml(path)
    return behaviour_study(data, path, text)


def behaviour_study(data: dict, path: Path | None = None, text: str = "") -> BehaviourStudy:
    """A :class:`BehaviourStudy` from the tables of a case file (``data``, a dict); ``path``
    and ``text`` locate errors (without them the message names the key only)."""

    def fail(loc, msg):
        if path is None:
            return CaseError(f"[{'.'.join(str(x) for x in loc if not isinstance(x, int))}] "
                             f"{msg}", key=tuple(loc), reason=msg)
        return fail_at(path, text, tuple(loc), msg)

    try:
        cfg = BehaviourFile.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        loc = tuple(err.get("loc", ()))
        loc = tuple(x for x in loc if not (isinstance(x, str) and x.startswith(
            ("literal[", "function-", "tuple["))))
        raise fail(loc, error_message(err)) from None
    from murus.retaining.geometry import preset

    ov = cfg.wall.overrides()
    try:
        wall = preset(cfg.wall.preset, **ov)
    except (GeometryError, TypeError, ValueError) as exc:
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        # a GeometryError names the parameter (its key path); an override is a [wall] key
        key = getattr(exc, "key", ())
        raise fail(("wall", key[0] if key and key[0] in ov else "preset"), msg) from None
    cases: list[tuple[float, str]] = [(float(f), v) for v in cfg.cases.vertical
                                      for f in cfg.cases.frequencies]
    for i, e in enumerate(cfg.cases.extra):
        c = (float(e.frequency), e.vertical)
        if any(f"{f:g}" == f"{c[0]:g}" and v == c[1] for f, v in cases):
            raise fail(("cases", "extra"), f"case {i + 1} ({c[0]:g} Hz, {c[1]}) is "
                       "already in the grid of frequencies and vertical modes")
        cases.append(c)
    numerics = cfg.numerics.kwargs()
    vr = numerics.get("vertical_ratio", 0.5)
    aps = {}
    for v in dict.fromkeys(v for _, v in cases):
        try:
            aps[v] = float(pseudo_static_resistance(wall, v, None, vr))
        except (ValueError, ArithmeticError) as exc:
            raise fail(("wall", "preset"), f"pseudo-static resistance ({v}): "
                       f"{str(exc).splitlines()[0]}") from None
    _check_dem_wall(wall, numerics, fail)
    out = cfg.output.folder
    if out is not None and path is not None and not Path(out).is_absolute():
        out = str(path.parent / out)
    return BehaviourStudy(
        wall=wall, wall_spec={"preset": cfg.wall.preset, **ov}, cases=cases,
        check_ratios=[float(r) for r in cfg.cases.check_ratios],
        peak_ratio=cfg.cases.peak_ratio, numerics=numerics, A_pseudo=aps,
        name=cfg.study.name, description=cfg.study.description, retries=cfg.study.retries,
        executor=cfg.executor.model_dump(), output=out)


def _check_dem_wall(wall: RetainingWall, numerics: dict, fail) -> None:
    """Build the DEM wall once, so that bad input is an error before anything runs (the runs
    build it again in the workers)."""
    from murus.dem.materials import JointError
    from murus.dem.model import ModelError
    from murus.retaining.dem_wall import DemWallError, build_wall

    kw = {k: numerics[k] for k in ("stiffness_scale", "safety") if k in numerics}
    try:
        build_wall(wall, **kw, **numerics.get("build", {}))
    except (DemWallError, ModelError, JointError, ValueError) as exc:
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        # a DemWallError with a key names a parameter of the wall, else the numerics
        key = exc.key if isinstance(exc, DemWallError) else ()
        raise fail(("wall",) + key if key else ("numerics",), msg) from None


# ----------------------------------------------------------------------------- tasks -----
@dataclass(frozen=True)
class CaseTask:
    """What a worker needs for one run (pickled to it): ``skip`` (a reason) for an S1 check
    that has nothing to check (its S2 run did not collapse)."""

    index: int
    wall: RetainingWall
    frequency: float
    vertical: str
    kwargs: dict
    skip: str | None = None
    progress_file: str | None = None


def run_case(task: CaseTask):
    """Run one case in a worker: the :class:`~murus.retaining.collapse.CollapseResult` (or
    ``None`` for a skipped check). With ``progress_file``, the progress of the run (the
    :func:`murus.progress.progress` blocks it opens, e.g. its DEM run) is written there while
    it runs (read by :func:`running_cases`), and the file removed at the end."""
    if task.skip is not None:
        return None
    if task.progress_file is None:
        return collapse_run(task.wall, task.frequency, task.vertical, **task.kwargs)
    from murus.progress import set_reporter

    rep = _FileReporter(Path(task.progress_file))
    rep("starting", 0.0, None, "")
    set_reporter(rep)
    try:
        return collapse_run(task.wall, task.frequency, task.vertical, **task.kwargs)
    finally:
        set_reporter(None)
        Path(task.progress_file).unlink(missing_ok=True)


class _FileReporter:
    """A :func:`murus.progress.set_reporter` callback writing the latest update to a small
    JSON file (atomically, at most once a second)."""

    def __init__(self, path: Path):
        self.path = path
        self.t0 = self.last = 0.0

    def __call__(self, desc, done, total, info) -> None:
        import time

        now = time.monotonic()
        if self.t0 == 0.0:
            self.t0 = now
        elif now - self.last < 1.0 and not (total and done >= total):
            return
        self.last = now
        data = json.dumps({"desc": desc, "done": done, "total": total, "info": info,
                           "elapsed": now - self.t0})
        try:
            _atomic(self.path, lambda p: Path(p).write_text(data), fsync=False)
        except OSError:
            pass


def running_cases(out) -> str:
    """What the cases running in the study folder ``out`` are doing (from their progress
    files): ``"S2_5Hz_none: DEM run 1.2/2 s (40 %)"`` (``"...: running for 3.1s"`` until the
    run reports), joined by ``"; "`` ("" if none)."""
    from murus.progress import format_seconds

    parts = []
    for f in sorted((Path(out) / "cases").glob(".*.progress")):
        try:
            d = json.loads(f.read_text())
        except (OSError, ValueError):
            continue
        name = f.name[1:].removesuffix(".progress")
        done, total = d.get("done") or 0, d.get("total")
        what = d.get("desc") or "running"
        if total:
            what += f" {done:.3g}/{total:.3g} ({100 * min(1.0, done / total):.0f} %)"
        if d.get("info"):
            what += f", {d['info']}"
        parts.append(f"{name}: running for {format_seconds(time_since(f))}"
                     if what == "starting" else f"{name}: {what}")
    return "; ".join(parts)


def time_since(path: Path) -> float:
    """Seconds since ``path`` was last written."""
    import time

    try:
        return max(0.0, time.time() - path.stat().st_mtime)
    except OSError:
        return float("nan")


# ----------------------------------------------------------------------------- storage ---
def _json_round(obj):
    """``obj`` as it reads back from its JSON file (NaN -> None; floats round-trip exactly),
    so that a fresh run and a resumed one see the same numbers."""
    from murus.cliutil import json_safe

    return json.loads(json.dumps(json_safe(obj), sort_keys=True))


def _case_record(study: BehaviourStudy, case: Case, digest: str, res) -> dict:
    rec = {"format": STUDY_FORMAT, "task": case.index, "name": case.name,
           "signal": case.signal, "frequency": case.frequency, "vertical": case.vertical,
           "ratio": case.ratio, "digest": digest}
    if res is None:
        rec["skipped"] = "the S2 run did not collapse: no A_col to check"
    else:
        rec["summary"] = res.summary()
        rec["history"] = f"{case.name}.csv"
        rec["snapshot"] = f"{case.name}.npz"
    return _json_round(rec)


def _atomic(path: Path, write, fsync: bool = True) -> None:
    """Write a piece of the study atomically and durably, under the temporary name of the
    pieces of studies (:func:`murus.outputs.atomic_write`, :mod:`murus.studies.sweep`)."""
    from murus.outputs import atomic_write, process_tmp_name

    atomic_write(path, write, tmp_name=process_tmp_name(path), fsync=fsync)


def _save_case(folder: Path, rec: dict, res) -> None:
    """The history CSV and the snapshot data first, the JSON last (it marks the case done),
    listing the SHA-256 of the other two, then the checksum of the JSON (``NAME.json.sha256``):
    a truncated or corrupt file of the case is found and the case recomputed."""
    from murus.studies.sweep import file_sha256, write_checksum, write_json

    (folder / f"{rec['name']}.json.sha256").unlink(missing_ok=True)
    if res is not None:
        _atomic(folder / rec["history"], res.history_csv)
        polys = [np.asarray(p, float) for p in res.polygons]
        counts = np.array([len(p) for p in polys], dtype=np.int64)
        verts = np.concatenate(polys) if polys else np.zeros((0, 2))

        def npz(p):
            with open(p, "wb") as fh:
                np.savez(fh, vertices=verts, counts=counts,
                         displacement=np.asarray(res.displacement, float),
                         disc_centres=np.asarray(res.disc_centres, float),
                         disc_radii=np.asarray(res.disc_radii, float),
                         disc_displacement=np.asarray(res.disc_displacement, float),
                         t_col=np.float64(res.t_col), t_end=np.float64(res.t_end))

        _atomic(folder / rec["snapshot"], npz)
        rec["sha256"] = {rec[k]: file_sha256(folder / rec[k]) for k in ("history", "snapshot")}
    path = folder / f"{rec['name']}.json"
    write_json(path, rec)
    write_checksum(path)


def _load_case(folder: Path, case: Case, digest: str) -> dict | None:
    """The stored record of ``case`` if its files are intact and of these inputs, else None
    (the case is recomputed)."""
    from murus.studies.sweep import task_file_state

    p = folder / f"{case.name}.json"
    if task_file_state(p) is not None:
        return None  # missing, truncated or corrupt
    try:
        rec = json.loads(p.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(rec, dict) or rec.get("digest") != digest:
        return None
    if "skipped" not in rec and not (folder / str(rec.get("history"))).exists():
        return None
    return rec


# ----------------------------------------------------------------------------- runner ----
@dataclass
class BehaviourStudyResult:
    """The outcome of a study: ``table`` (Savalle et al. (2022), Tables 7-8 layout, one row per S2
    case), ``checks`` ``{(frequency, vertical): {ratio: "stable" | "collapsed" | "skipped" |
    "failed" | "missing"}}``, ``records`` (the stored record of every task, None if missing),
    ``failures`` ``{task index: {"error", "attempts", "case"}}``, ``digest``, ``out``."""

    table: BehaviourTable
    checks: dict
    check_ratios: list
    records: list
    failures: dict
    digest: str
    out: Path | None = None

    def check_columns(self) -> list[str]:
        return [f"S1_{r:g}_A_col" for r in self.check_ratios]

    def to_csv(self, path) -> None:
        """The table of :meth:`BehaviourTable.to_csv` with a column per S1 check."""
        import csv
        import io

        path = Path(path)

        def write(tmp):
            self.table.to_csv(tmp)
            rows = list(csv.reader(io.StringIO(Path(tmp).read_text())))
            rows[0] += self.check_columns()
            for row, trow in zip(rows[1:], self.table.rows, strict=True):
                c = self.checks.get((trow["frequency_Hz"], trow["vertical"]), {})
                row += [c.get(r, "") for r in self.check_ratios]
            with open(tmp, "w", newline="") as fh:
                csv.writer(fh).writerows(rows)

        _atomic(path, write)

    def to_markdown(self) -> str:
        """Tables 7 and 8 in one (a column per case) and a line per S1 check."""
        md = self.table.to_markdown()
        lines = [f"| S1 at {r:g} A_col | " + " | ".join(
            self.checks.get((row["frequency_Hz"], row["vertical"]), {}).get(r, "-")
            for row in self.table.rows) + " |" for r in self.check_ratios]
        return md + ("\n".join(lines) + "\n" if lines else "")

    @property
    def n_failed(self) -> int:
        return len(self.failures)


def run_behaviour_study(study: BehaviourStudy, executor=None, *, workers: int | None = None,
                        scheduler: str | None = None, out=None, retries: int | None = None,
                        progress=None, hook=None, window: int | None = None
                        ) -> BehaviourStudyResult:
    """Run (or resume) a study and return its table.

    executor:
        ``"serial"``, ``"process"``, ``"dask"`` or an open
        :class:`~murus.studies.executors.ExecutorHandle`; default the ``[executor]`` of the
        case file (with its ``workers`` and ``scheduler`` unless given here).
    out:
        Study folder (module docstring): each case is stored as it finishes and a re-run
        computes only the missing ones; the table is written to
        ``out/behaviour_factor.csv`` and ``.md`` when the run ends. Default
        ``study.output``; ``None`` for neither: the run is kept in memory.
    retries, progress, hook, window:
        As for :func:`murus.studies.sweep.run_tasks` (``progress(done, total, failed)`` counts
        cases; default retries those of the study).
    """
    from murus.studies.sweep import prepare_folder, run_tasks, write_json

    if executor is None:
        ex = study.executor
        executor = ex.get("kind", "process")
        workers = workers if workers is not None else ex.get("workers")
        scheduler = scheduler if scheduler is not None else ex.get("scheduler")
    retries = study.retries if retries is None else retries
    out = Path(out) if out is not None else (Path(study.output) if study.output else None)
    digest = study.digest()
    cases = study.tasks()
    folder = out / "cases" if out is not None else None
    if out is not None:
        prepare_folder(out, digest, {
            "name": study.name, "kind": "retaining.behaviour_factor", "spec": study.describe(),
            "unit": "cases", "result_file": "behaviour_factor.csv",
            "task_files": [f"cases/{c.name}.json" for c in cases],
            "tasks": [dataclasses.asdict(c) for c in cases]})
        folder.mkdir(exist_ok=True)
    records: list[dict | None] = [None] * len(cases)
    children: dict[int, list[Case]] = {}
    for c in cases:
        if c.parent is not None:
            children.setdefault(c.parent, []).append(c)

    def task_of(c: Case) -> tuple[int, CaseTask] | None:
        """The task of ``c``, or None when its stored record is valid (then loaded) or when
        its S2 run is not done (it is queued when that run finishes)."""
        parent = records[c.parent] if c.parent is not None else None
        if c.parent is not None and parent is None:
            return None
        d = study.case_digest(c, parent)
        if folder is not None:
            rec = _load_case(folder, c, d)
            if rec is not None:
                records[c.index] = rec
                return None
        if c.signal == "S1" and not _collapsed(parent["summary"]):
            return c.index, CaseTask(c.index, study.wall, c.frequency, c.vertical, {},
                                     "no collapse")
        pf = None if folder is None else str(folder / f".{c.name}.progress")
        return c.index, CaseTask(c.index, study.wall, c.frequency, c.vertical,
                                 study.case_kwargs(c, parent), None, pf)

    todo = [t for t in map(task_of, cases) if t is not None]  # S2 runs first, then S1
    done = sum(r is not None for r in records)

    def on_result(i, res):
        c = cases[i]
        parent = records[c.parent] if c.parent is not None else None
        rec = _case_record(study, c, study.case_digest(c, parent), res)
        if folder is not None:
            _save_case(folder, rec, res)
        records[i] = rec
        return [t for t in map(task_of, children.get(i, [])) if t is not None]

    try:
        failures = run_tasks(run_case, todo, executor, workers=workers, scheduler=scheduler,
                             retries=retries, on_result=on_result, progress=progress,
                             total=len(cases), done=done, hook=hook, window=window)
    finally:
        if folder is not None:  # those of abandoned runs
            for f in folder.glob(".*.progress"):
                f.unlink(missing_ok=True)
    for i, f in failures.items():
        f["case"] = cases[i].name
    result = _assemble(study, cases, records, failures, digest, out)
    if out is not None:
        if failures:
            write_json(out / "failures.json", {str(k): v for k, v in failures.items()})
        elif (out / "failures.json").exists():
            (out / "failures.json").unlink()
        result.to_csv(out / "behaviour_factor.csv")
        md = result.to_markdown()
        _atomic(out / "behaviour_factor.md", lambda p: Path(p).write_text(md, encoding="utf-8"))
    return result


def _assemble(study: BehaviourStudy, cases: list[Case], records, failures, digest,
              out) -> BehaviourStudyResult:
    rows = []
    checks: dict = {}
    for c in cases:
        if c.signal == "S2":
            rec = records[c.index]
            s = (rec or {}).get("summary") or {}
            rows.append(_row(study, c, s, "failed" if c.index in failures else
                             "missing" if rec is None else None))
            checks[(c.frequency, c.vertical)] = {}
        else:
            rec = records[c.index]
            if rec is None:
                state = "failed" if c.index in failures else "missing"
            elif "skipped" in rec:
                state = "skipped"
            else:
                state = "collapsed" if rec["summary"].get("collapsed") else "stable"
            checks[(c.frequency, c.vertical)][c.ratio] = state
    table = BehaviourTable(rows, [], study.peak_ratio)
    return BehaviourStudyResult(table, checks, list(study.check_ratios), list(records),
                                dict(failures), digest, out)


def _num(v) -> float:
    return math.nan if v is None else float(v)


def _row(study: BehaviourStudy, c: Case, s: dict, state: str | None) -> dict:
    """One row of Savalle et al. (2022), Tables 7-8 (the row of :func:`murus.retaining.collapse.
    behaviour_factor`) from a stored summary."""
    collapsed = bool(s.get("collapsed"))
    A_col = _num(s.get("A_col"))
    A_pseudo = _num(s.get("A_pseudo", study.A_pseudo.get(c.vertical)))
    A_peak = study.peak_ratio * A_col if collapsed else math.nan
    seed = SEED_TABLE7.get((c.frequency, c.vertical)) if study.wall.name == "DSRW1" else None
    return {"wall": study.wall.name, "frequency_Hz": c.frequency, "vertical": c.vertical,
            "t_col_s": _num(s.get("t_col")), "A_col_m_s2": A_col, "A_peak_m_s2": A_peak,
            "A_pseudo_m_s2": A_pseudo, "r": A_peak / A_pseudo,
            "collapsed": state if state is not None else collapsed,
            "wall_time_s": _num(s.get("wall_time")),
            "seed_A_col_m_s2": seed[1] if seed else math.nan,
            "seed_r": seed[3] if seed else math.nan}


# ----------------------------------------------------------------------------- figures ---
def write_snapshots(out, dpi: int = 110) -> list[Path]:
    """``cases/NAME.png`` for every stored run of the study folder ``out``: the blocks at the
    end of the run (the collapse instant when it collapsed), coloured by their displacement
    relative to the base. Only the figures missing or older than their data are drawn."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    from murus.retaining.collapse import plot_collapse

    folder = Path(out) / "cases"
    written = []
    for data in sorted(folder.glob("*.npz")):
        png = data.with_suffix(".png")
        meta = data.with_suffix(".json")
        if not meta.exists() or (png.exists() and png.stat().st_mtime >= data.stat().st_mtime):
            continue
        rec = json.loads(meta.read_text())
        s = rec.get("summary") or {}
        with np.load(data) as z:
            verts, counts, disp = z["vertices"], z["counts"], z["displacement"]
            discs = ((z["disc_centres"], z["disc_radii"]) if "disc_radii" in z.files
                     else None)  # studies stored before the discs were
            ddisc = z["disc_displacement"] if discs is not None else None
        polys = np.split(verts, np.cumsum(counts)[:-1]) if counts.size else []
        state = (f"collapse at t = {s['t_col']:.2f} s" if s.get("collapsed") and
                 s.get("t_col") is not None else f"no collapse up to {_num(s.get('t_end')):.2f} s")
        extra = f", peak {rec['ratio']:g} A_col" if rec.get("ratio") is not None else ""
        ax = plot_collapse(polys, disp, discs, ddisc,
                           f"{s.get('wall', '')} {rec['signal']}{extra}, {rec['frequency']:g} "
                           f"Hz, vertical {rec['vertical']}: {state}")
        _atomic(png, lambda p, fig=ax.figure: fig.savefig(p, dpi=dpi, format="png"))
        plt.close(ax.figure)
        written.append(png)
    return written
