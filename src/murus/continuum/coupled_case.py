"""Case files of blocks and zones together (TOML): a distinct-element case (:mod:`murus.dem.case`)
with continuum regions (:mod:`murus.continuum.case`) and the interfaces between them, run in one
time loop by :class:`murus.continuum.coupled.CoupledModel`.

A coupled case is a DEM case (``[dem]``, its materials, ``[[joints]]``, ``[[blocks]]``,
``[[walls]]``, ``[motion]``, ``[[monitors]]``, ``[stop]``, ``[output]``, with their meaning and
defaults) that also has ``[[zones]]``; the continuum tables keep the syntax of a continuum
case, and one table is new, ``[[interfaces]]``::

    [dem]                       # the run: duration, gravity, time step, settling, damping
    duration = 2.0              # (of blocks and zones alike: one time loop)
    joint = "stone"
    [dem.damping]
    fraction = 0.05
    frequency = 5.0

    [continuum]                 # optional: what concerns the zones only
    initial_stress = "k0"       # "gravity" (default: the settling of blocks and zones from
                                # zero stress) or "k0" (geostatic stresses first); "none"
                                # only with [dem] settle = false
    k0 = 0.5                    # default nu / (1 - nu)
    dt_safety = 0.5             # on the zones' critical time step
    gravity = 9.81              # if given, the same as [dem] gravity

    [materials.stone]           # a joint material (kn, ks, friction_deg, ...: the DEM keys)
    kn = 1e9
    ks = 1e9
    [materials.soil]            # a zone material: it has "model" (the continuum keys)
    model = "mohr-coulomb"
    density = 1520.0
    E = 9.27e7
    nu = 0.22
    friction_deg = 37.7
    [materials.contact]         # the interface's joint law: kn, ks [Pa/m], friction_deg,
    kn = 2.9e8                  # cohesion, tensile [Pa] (density is not used)
    ks = 2.9e8
    friction_deg = 25.0

    [[zones]]                   # regions, as in a continuum case
    name = "backfill"
    material = "soil"
    vertices = [[0.6, 0.0], [6.0, 0.0], [6.0, 2.0], [0.6, 2.0]]
    size = 0.25

    [[boundaries]]              # of the zones, as in a continuum case ("base" gridpoints
    kind = "base"               # follow [motion] with the "base" blocks)
    side = "backfill.bottom"

    [[interfaces]]              # zone boundary gridpoints and edges against the blocks:
    side = "backfill.left"      # side = "REGION.SIDE", line = [[x0, y0], [x1, y1]] (tol),
    material = "contact"        # or box = [xmin, ymin, xmax, ymax]; material: a joint
                                # material (default: [dem] joint)

    [[monitors]]                # a block's (body = ...) or a gridpoint's / zone's
    name = "u_soil"             # (gridpoint = [x, y] / zone = [x, y]), in one history;
    gridpoint = [3.0, 2.0]      # [stop] may name any of them
    quantity = "ux"

``[motion]`` moves the ``kinematic = "base"`` blocks and the zones' ``"base"`` gridpoints
together (one base); with no base block, the zones' base alone. The DEM keys have their DEM
meaning (the settling: ``[dem] settle``, ``settle_tolerance``;
the damping ``[dem.damping]`` acts on blocks and zones alike); ``[continuum]`` takes neither
duration, settling nor damping (they are the run's, given once in ``[dem]``). Several
``[[interfaces]]`` entries are merged into one interface, so they name the same material.
The zones are in large-strain mode (the interface follows the gridpoints as they move).
The settling of blocks and zones (:func:`murus.dem.engine.settle`) is plastic from its first
step (a continuum case settles elastically first): a cohesionless backfill is best started
from geostatic stresses (``initial_stress = "k0"``). Free-field sides are attached after the
settling, as in a continuum case.

Errors are one line naming the file, the line and the key (:class:`murus.config.CaseError`),
before anything is run or written: besides those of the two case kinds, an interface that names
no zone boundary edge, zones that overlap blocks by more than ``[dem] overlap_tolerance``, a
``[continuum]`` gravity other than ``[dem]``'s, small-strain zones.

Outputs (:func:`write_outputs`): ``summary.json``, ``histories.csv`` (the monitors of blocks,
gridpoints and zones, then the energy terms of blocks, zones and interface), ``model.png``
(blocks and zones coloured by their displacement relative to the base, and the zones' plastic
state) and, with ``[output] vtk_every``, ``vtk/series.pvd`` (blocks) beside ``vtk/zones.pvd``
(zones) for ParaView.

References
----------
Itasca UDEC, Theory and Background (a model of blocks and zones: one static stage, then the
dynamic stage); Savalle et al. (2022), §2 and Tables 1 and 6 (a dry-stone wall of blocks and a
Mohr-Coulomb backfill continuum with its interface).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from pydantic import Field, ValidationError, model_validator

from murus.config import CaseError, Strict, error_message, load_toml, locate
from murus.config import fail_at as _fail_at

Point = tuple[float, float]

#: Top-level tables of a coupled case besides those of a DEM case.
CONTINUUM_TABLES = ("continuum", "zones", "boundaries", "interfaces")
#: Keys that make a ``[materials.*]`` table a zone material (a joint material has none).
ZONE_MATERIAL_KEYS = frozenset({"model", "E", "nu", "bulk", "shear", "dilation_deg"})
#: ``[continuum]`` keys that belong to the run, given in ``[dem]`` in a coupled case.
RUN_KEYS = {"duration": "duration", "settle_tolerance": "settle_tolerance",
            "settle_max_steps": "settle_max_steps", "damping": "damping"}


class InterfaceCfg(Strict):
    side: str | None = Field(default=None, min_length=1)
    line: tuple[Point, Point] | None = None
    box: tuple[float, float, float, float] | None = None
    tol: float | None = Field(default=None, gt=0.0, allow_inf_nan=False)
    material: str | None = Field(default=None, min_length=1)

    @model_validator(mode="after")
    def _where(self):
        if sum(x is not None for x in (self.side, self.line, self.box)) != 1:
            raise ValueError("give exactly one of side, line, box")
        if self.tol is not None and self.side is not None:
            raise ValueError("tol goes with line or box")
        return self


def fail_at(path: Path, text: str, loc: tuple, msg: str) -> CaseError:
    """A one-line CaseError naming file, line and key (entries of arrays of tables by index)."""
    return _fail_at(path, text, loc, msg, indices=True)


def is_coupled_case(path) -> bool:
    """True when ``path`` is a readable TOML file with ``[[zones]]`` and blocks (``[dem]``,
    ``[[blocks]]`` or ``[[walls]]``)."""
    try:
        data, _ = load_toml(path)
    except CaseError:
        return False
    return "zones" in data and any(k in data for k in ("dem", "blocks", "walls"))


def _is_zone_material(table) -> bool:
    return isinstance(table, dict) and bool(ZONE_MATERIAL_KEYS & set(table))


def _is_zone_monitor(table) -> bool:
    return isinstance(table, dict) and ("gridpoint" in table or "zone" in table)


class CoupledCase:
    """A validated coupled case: its DEM part, its continuum part and the interfaces.

    Attributes
    ----------
    dem : murus.dem.case.DemCase
        Blocks, joint materials, motion, block monitors, output (no stop: :attr:`stop`).
    continuum : murus.continuum.case.ContinuumCase
        Zones, zone materials, boundaries, gridpoint and zone monitors (no motion: the
        blocks' model carries it).
    interfaces : list of InterfaceCfg
    joint_materials : dict
        Every joint material (:class:`murus.dem.case.MaterialCfg`), those of the interfaces
        included.
    stop : murus.dem.case.StopCfg or None
    monitor_order : list of str
        The monitor names in file order.
    dem_index, zone_index : list of int
        The file index of each DEM and continuum monitor (for the location of an error).
    initial_stress : str
    k0 : float or None
    """

    def __init__(self, **kw):
        self.__dict__.update(kw)


def _remap(loc: tuple, index: list[int]) -> tuple:
    """A key path of a sub-list of ``[[monitors]]`` as a key path of the file."""
    loc = tuple(loc)
    if len(loc) >= 2 and loc[0] == "monitors" and isinstance(loc[1], int) \
            and 0 <= loc[1] < len(index):
        return ("monitors", index[loc[1]]) + loc[2:]
    return loc


def _validate(model, data, path, text, index):
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        raise fail_at(path, text, _remap(err.get("loc", ()), index),
                      error_message(err)) from None


def _validate_at(model, data, path, text, prefix: tuple):
    """Validate one table at the key path ``prefix``."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        err = exc.errors()[0]
        raise fail_at(path, text, prefix + tuple(err.get("loc", ())),
                      error_message(err)) from None


def _relocated(exc: CaseError, path, text, index) -> CaseError:
    """A CaseError of a sub-case builder, with its ``[[monitors]]`` index that of the file."""
    key = _remap(exc.key, index)
    if key == tuple(exc.key):
        return exc
    return fail_at(path, text, key, exc.reason)


def load_case(path) -> tuple[CoupledCase, Path, str]:
    """Read and validate a coupled case file (module doc).

    Parameters
    ----------
    path : path-like
        The TOML file.

    Returns
    -------
    tuple
        ``(case, path, text)``: the validated :class:`CoupledCase`, the path and its text.

    Raises
    ------
    murus.config.CaseError
        One line naming the file, line and key.
    """
    from murus.continuum.case import ContinuumCase, ContinuumCfg
    from murus.dem.case import DemCase, MaterialCfg, StopCfg

    path = Path(path)
    data, text = load_toml(path)
    known = set(DemCase.model_fields) | set(CONTINUUM_TABLES)
    for k in data:
        if k not in known:
            raise fail_at(path, text, (k,), f"unknown table or key {k!r} (a case of blocks and "
                          f"zones has {', '.join(sorted(known))})")
    if "dem" not in data:
        raise fail_at(path, text, (), "a case of blocks and zones needs a [dem] table (the "
                      "run: duration, gravity, time step, damping)")
    mats = data.get("materials", {})
    if not isinstance(mats, dict):
        raise fail_at(path, text, ("materials",), "[materials.NAME] tables are expected")
    mons = data.get("monitors", [])
    if not isinstance(mons, list):
        raise fail_at(path, text, ("monitors",), "[[monitors]] tables are expected")
    dem_index = [i for i, m in enumerate(mons) if not _is_zone_monitor(m)]
    zone_index = [i for i, m in enumerate(mons) if _is_zone_monitor(m)]
    names = [m.get("name") for m in mons if isinstance(m, dict)]
    for i, n in enumerate(names):
        if n is not None and names.index(n) != i:
            raise fail_at(path, text, ("monitors", i, "name"), f"monitor name {n!r} is used "
                          "twice")
    # the DEM part (the stop is checked here, built with all monitors)
    ddata = {k: v for k, v in data.items() if k in DemCase.model_fields and k != "stop"}
    jmats = {k: v for k, v in mats.items() if not _is_zone_material(v)}
    # a joint material named by [[interfaces]] only is not the blocks' (so that the blocks'
    # single material stays their default)
    raw_if = data.get("interfaces", [])
    if not isinstance(raw_if, list) or not raw_if:
        raise fail_at(path, text, ("interfaces",), "blocks and zones need [[interfaces]] "
                      "(side = 'REGION.SIDE' of the zones against the blocks, material)")
    named = {t.get("material") for t in raw_if if isinstance(t, dict)}
    for i, t in enumerate(raw_if):
        name = t.get("material") if isinstance(t, dict) else None
        if isinstance(name, str) and name not in jmats:
            what = "a zone material" if name in mats else "unknown"
            raise fail_at(path, text, ("interfaces", i, "material"), f"{name!r}: {what}; an "
                          "interface takes a joint material (kn, ks, friction_deg, ...): "
                          f"{', '.join(jmats)}")
    used = {(data.get("dem") or {}).get("joint")} if isinstance(data.get("dem"), dict) else set()
    for tab in ("blocks", "walls", "joints"):
        for t in data.get(tab, []) if isinstance(data.get(tab), list) else []:
            if isinstance(t, dict):
                used.add(t.get("material"))
    ddata["materials"] = {k: v for k, v in jmats.items() if k not in named or k in used}
    ddata["monitors"] = [mons[i] for i in dem_index]
    if not ddata["materials"]:
        raise fail_at(path, text, ("materials",), "no joint material (kn, ks, ...) for the "
                      "blocks")
    dem = _validate(DemCase, ddata, path, text, dem_index)
    joint_materials = dict(dem.materials)
    for k, v in jmats.items():
        if k not in joint_materials:
            joint_materials[k] = _validate_at(MaterialCfg, v, path, text, ("materials", k))
    stop = _validate_at(StopCfg, data["stop"], path, text, ("stop",)) if "stop" in data \
        else None
    # [continuum]: the zones' own keys; the run's are [dem]'s
    craw = data.get("continuum", {})
    if not isinstance(craw, dict):
        raise fail_at(path, text, ("continuum",), "a [continuum] table is expected")
    for k in RUN_KEYS:
        if k in craw:
            raise fail_at(path, text, ("continuum", k), f"blocks and zones share one time "
                          f"loop: give {k} in [dem]")
    cc = _validate(ContinuumCfg, craw, path, text, [])
    if "gravity" in craw and not math.isclose(cc.gravity, dem.dem.gravity, rel_tol=1e-12,
                                              abs_tol=0.0):
        raise fail_at(path, text, ("continuum", "gravity"), f"gravity {cc.gravity:g} m/s2 "
                      f"differs from [dem] gravity {dem.dem.gravity:g} m/s2 (blocks and zones "
                      "fall under one gravity: give it once, in [dem])")
    if not cc.large_strain:
        raise fail_at(path, text, ("continuum", "large_strain"), "zones against blocks must "
                      "be in large-strain mode (the interface follows the gridpoints as they "
                      "move)")
    if cc.initial_stress == "none" and dem.dem.settle:
        raise fail_at(path, text, ("continuum", "initial_stress"), "blocks and zones settle "
                      "together: 'none' goes with [dem] settle = false")
    cdict = {k: v for k, v in craw.items() if k in ("dt_safety",)}
    cdict["gravity"] = dem.dem.gravity
    cdict["initial_stress"] = "none"  # the settling is the coupled model's
    cdata = {"continuum": cdict,
             "materials": {k: v for k, v in mats.items() if _is_zone_material(v)},
             "zones": data.get("zones", []),
             "boundaries": data.get("boundaries", []),
             "monitors": [mons[i] for i in zone_index]}
    if "output" in data:
        cdata["output"] = data["output"]
    if not cdata["materials"]:
        raise fail_at(path, text, ("materials",), "no zone material (a [materials.NAME] table "
                      "with model = 'elastic' or 'mohr-coulomb') for the zones")
    cont = _validate(ContinuumCase, cdata, path, text, zone_index)
    ifs = [_validate_at(InterfaceCfg, t, path, text, ("interfaces", i))
           for i, t in enumerate(raw_if)]
    order = [m.get("name") for m in mons]
    return (CoupledCase(dem=dem, continuum=cont, interfaces=ifs, stop=stop,
                        joint_materials=joint_materials,
                        monitor_order=order, dem_index=dem_index, zone_index=zone_index,
                        initial_stress=cc.initial_stress, k0=cc.k0), path, text)


# ---------------------------------------------------------------------- building
class Built:
    """What :func:`build` returns: the coupled model and what the run needs.

    Attributes
    ----------
    cm : murus.continuum.coupled.CoupledModel
    blocks : murus.dem.case.Built
        The blocks' part (model, settling, tilt, base body, height).
    zones : murus.continuum.case.Built
        The zones' part (model, mesh, base gridpoint, free-field sides).
    run_kwargs : dict
        Arguments of :func:`murus.dem.engine.run` (probes of blocks, gridpoints and zones).
    monitors : list of str
    stop_desc : str or None
    """

    def __init__(self, **kw):
        self.__dict__.update(kw)


def _zone_probe(zones, spec):
    """A gridpoint or zone monitor of the continuum builder as a probe of the blocks' model."""
    from murus.dem.engine import Probe

    if isinstance(spec, tuple):
        return Probe(spec)

    def probe(m, f=spec):
        return float(f(zones))

    return probe


def _check_zone_overlaps(bm, mesh, tol, case, path, text) -> None:
    """Refuse zones that overlap a block by more than ``tol`` [m] (separating axes on each
    zone quadrilateral and each block part; touching is allowed)."""
    from murus.dem.case import check_overlaps

    q = mesh.xy[mesh.zones]  # (nz, 4, 2)
    lo, hi = q.min(axis=1), q.max(axis=1)
    parts = [(b, ("poly", v)) for b, v in zip(bm.body_of_polygon(), bm.world_polygons(),
                                               strict=True)]
    c, r = bm.discs()
    parts += [(b, ("disc", cc, rr)) for b, cc, rr in zip(bm.body_of_disc(), c, r, strict=True)]
    for b, p in parts:
        blo = p[1].min(0) if p[0] == "poly" else p[1] - p[2]
        bhi = p[1].max(0) if p[0] == "poly" else p[1] + p[2]
        hit = np.flatnonzero((lo[:, 0] < bhi[0] - tol) & (hi[:, 0] > blo[0] + tol)
                             & (lo[:, 1] < bhi[1] - tol) & (hi[:, 1] > blo[1] + tol))
        for z in hit:
            res = check_overlaps([[p], [("poly", q[z])]], tol)
            if res is not None:
                reg = int(mesh.region[z])
                name = case.continuum.zones[reg].name or f"zones{reg}"
                raise fail_at(path, text, ("zones", reg), f"zone {int(z)} of region {name!r} "
                              f"overlaps block {int(b)} by {res[2]:.3g} m > [dem] "
                              f"overlap_tolerance {tol:g} m: the zones must lie beside the "
                              "blocks (touching them along the interface)")


def _interface(case, zb, bm, path, text):
    from murus.continuum.case import _select
    from murus.continuum.interface import Interface, InterfaceError
    from murus.continuum.mesh import MeshError

    mesh, zm = zb.mesh, zb.model
    dmats = case.joint_materials
    default = case.dem.dem.joint or next(iter(case.dem.materials))
    edges, mat = [], None
    ff = (np.unique(np.concatenate([np.asarray(g) for g in zb.ff_sides]))
          if zb.ff_sides else np.zeros(0, np.int64))
    for i, f in enumerate(case.interfaces):
        name = f.material or default
        if name not in dmats:
            raise fail_at(path, text, ("interfaces", i, "material"), f"unknown joint material "
                          f"{name!r} (joint materials: {', '.join(dmats)})")
        if mat is not None and name != mat:
            raise fail_at(path, text, ("interfaces", i, "material"), f"material {name!r}: the "
                          f"interfaces of a case share one joint law (the first is {mat!r})")
        mat = name
        sel = type("Sel", (), {"side": f.side, "line": f.line, "box": f.box, "tol": f.tol})
        try:
            g = _select(mesh, sel, i)
        except MeshError as exc:
            key = tuple(exc.key) if exc.key else ("interfaces", i)
            if key and key[0] == "boundaries":
                key = ("interfaces",) + key[1:]
            raise fail_at(path, text, key, str(exc)) from None
        e = mesh.edges_of(g)
        if e.shape[0] == 0:
            raise fail_at(path, text, ("interfaces", i), "the gridpoints selected hold no "
                          "boundary edge of the zones")
        if np.intersect1d(np.unique(e), ff).size:
            raise fail_at(path, text, ("interfaces", i), "a gridpoint of the interface is on a "
                          "free-field side (the free field takes the side's gridpoints)")
        edges.append(e)
    e = np.unique(np.concatenate(edges), axis=0)
    try:
        return Interface(zm, e, bm, dmats[mat].joint()), mat
    except InterfaceError as exc:
        raise locate(exc, path, text, ("interfaces", 0), indices=True) from None


def _zones_only_motion(case: CoupledCase, path: Path, text: str):
    """The DEM part for its builder and, when ``[motion]`` moves only the zones' base
    gridpoints (no block is ``kinematic = "base"``), the motion, built here: the blocks'
    builder would refuse a motion without a base block."""
    from murus.dem import case as DC
    from murus.motion.case import build_motion

    mo = case.dem.motion
    kind = mo.kind
    if kind in ("none", "tilt") or any(b.kinematic == "base" for b in case.dem.blocks):
        return case.dem, None
    d = case.dem.dem
    if d.duration is None and kind != "record":
        raise fail_at(path, text, ("dem", "duration"), "required key is missing (simulated "
                      "time, s)")
    if kind != "record":
        span = d.duration if kind == "harmonic-ramp" else mo.cycles / mo.frequency
        if not span / (mo.dt or 0.001) <= DC.MAX_MOTION_SAMPLES:
            raise fail_at(path, text, ("motion", "dt") if mo.dt else ("motion",),
                          f"the {kind} would have more than {DC.MAX_MOTION_SAMPLES:.0e} "
                          f"samples of {mo.dt or 0.001:g} s: raise [motion] dt")
    motion = build_motion(mo, path, text, sampled_dt=mo.dt or 0.001, duration=d.duration)
    dur = d.duration if d.duration is not None else motion.duration
    dcase = case.dem.model_copy(update={"motion": DC.MotionCfg(),
                                        "dem": d.model_copy(update={"duration": dur})})
    return dcase, motion


def build(case: CoupledCase, path: Path, text: str) -> Built:
    """The coupled model of a validated case: the blocks by :func:`murus.dem.case.build`, the
    zones by :func:`murus.continuum.case.build`, then the interfaces, the coupling, the
    monitors of both in one history and the stop condition.

    Parameters
    ----------
    case : CoupledCase
        The validated case (:func:`load_case`).
    path : pathlib.Path
        The case file.
    text : str
        Its text.

    Returns
    -------
    Built

    Raises
    ------
    murus.config.CaseError
        One line naming the file, line and key (module doc).
    """
    from murus.continuum import case as CC
    from murus.continuum.coupled import CoupledError, CoupledModel
    from murus.dem import case as DC
    from murus.dem import engine as E

    dcase, zmotion = _zones_only_motion(case, path, text)
    try:
        db = DC.build(dcase, path, text)
    except CaseError as exc:
        raise _relocated(exc, path, text, case.dem_index) from None
    try:
        zb = CC.build(case.continuum, path, text)
    except CaseError as exc:
        raise _relocated(exc, path, text, case.zone_index) from None
    bm, zm = db.model, zb.model
    if zmotion is not None:
        if zb.base_gp is None:
            raise fail_at(path, text, ("motion",), f"type '{case.dem.motion.kind}' moves the "
                          "kinematic = 'base' blocks and the 'base' gridpoints of the zones, "
                          "and there is none")
        bm.set_base_motion(zmotion)  # the blocks' model drives the zones' base gridpoints
    _check_zone_overlaps(bm, zb.mesh, case.dem.dem.overlap_tolerance, case, path, text)
    iface, _ = _interface(case, zb, bm, path, text)
    try:
        cm = CoupledModel(bm, zm, iface)
        if db.run_kwargs["dt"] is not None:
            cm.set_dt(db.run_kwargs["dt"])
    except CoupledError as exc:
        where = {"interface": ("interfaces", 0), "gravity": ("continuum", "gravity"),
                 "dt": ("dem", "dt")}
        key = where.get(exc.key[0] if exc.key else "", ("zones",))
        raise fail_at(path, text, key, str(exc)) from None
    duration = float(db.run_kwargs["duration"])
    steps = duration / cm.dt
    if steps > DC.MAX_STEPS:
        raise fail_at(path, text, ("dem", "duration"), f"{steps:.3g} time steps of "
                      f"{cm.dt:.3g} s (the zones' or the interface's stable step): more than "
                      f"{DC.MAX_STEPS:.0e}")
    probes = dict(db.run_kwargs["probes"])
    for name, spec in zb.monitors.items():
        probes[name] = _zone_probe(zm, spec)
    probes = {n: probes[n] for n in case.monitor_order}
    stop, stop_desc = None, None
    if case.stop is not None:
        s = case.stop
        if s.monitor not in probes:
            raise fail_at(path, text, ("stop", "monitor"), f"unknown monitor '{s.monitor}' "
                          f"(monitors: {', '.join(probes) or 'none'})")
        op = s.op or (">" if s.value is not None else "abs>")
        value = s.value if s.value is not None else s.fraction_of_height * db.height
        stop = E.stop_when(probes[s.monitor], op, value)
        stop_desc = f"{s.monitor} {op} {value:.6g}"
    kw = dict(db.run_kwargs, probes=probes, stop=stop)
    return Built(case=case, cm=cm, blocks=db, zones=zb, run_kwargs=kw, monitors=list(probes),
                 stop_desc=stop_desc, vtk_every=case.dem.output.vtk_every,
                 figure=case.dem.output.figure)


# ---------------------------------------------------------------------- running
class CaseRun:
    """A finished (or interrupted) coupled run: the settling, the result and the VTK frames
    (pairs of block and zone frames)."""

    def __init__(self, built, result, settled, frames):
        self.built = built
        self.result = result
        self.settled = settled
        self.frames = frames

    @property
    def ok(self) -> bool:
        """True when the run reached its end or its stop condition after a converged
        settling."""
        return self.result.ok and (self.settled is None or bool(self.settled.converged))

    def summary(self) -> dict:
        """The content of ``summary.json``."""
        b = self.built
        r, m, z = self.result, b.cm.dem, b.cm.zones
        final = {k: float(v[-1]) for k, v in r.values.items() if k in b.monitors and len(v)}
        peak = {k: float(np.nanmax(np.abs(v))) for k, v in r.values.items()
                if k in b.monitors and len(v) and np.isfinite(v).any()}
        s = {"status": r.status, "ok": self.ok, "message": r.message, "t_end": float(m.time),
             "steps": int(r.steps), "dt": float(r.dt), "wall_time_s": float(r.wall),
             "bodies": int(m.nbody), "zones": int(z.nz), "gridpoints": int(z.ng),
             "height": float(b.blocks.height), "stop": b.stop_desc, "final": final,
             "peak_abs": peak,
             "energy_error": float(r.values.get("energy.error", [math.nan])[-1]),
             "plastic_zones": int(np.count_nonzero(z.plastic_state() & 3)),
             "ever_plastic_zones": int(np.count_nonzero(z.plastic_state())),
             "interface": {"normal_force": float(b.cm.iface.normal_force()),
                           "shear_force": float(b.cm.iface.shear_force())}}
        if self.settled is not None:
            s["settle"] = {"converged": bool(self.settled.converged),
                           "steps": int(self.settled.steps), "ratio": float(self.settled.ratio),
                           "message": self.settled.message}
        return s


def _block_frame(m, base):
    """The blocks now, coloured by their displacement [m] since the reference state
    (relative to the body ``base`` when given)."""
    u = m.body_displacement()
    if base is not None:
        u = u - u[base]
    d = np.hypot(*u.T)
    return {"polygons": m.world_polygons(), "discs": m.discs(),
            "cell_data": {"displacement": np.concatenate([d[m.body_of_polygon()],
                                                          d[m.body_of_disc()]]),
                          "body": np.concatenate([m.body_of_polygon(), m.body_of_disc()])}}


def _frames(b):
    from murus.continuum.case import _frame

    cm = b.cm
    return (cm.dem.time, _block_frame(cm.dem, b.blocks.base), _frame(cm.zones))


def run_case(built: Built, progress=False) -> CaseRun:
    """Initial stresses (K0 if asked), the settling of blocks and zones together under gravity,
    the free-field sides, then the dynamic run (:func:`murus.dem.engine.run`: progress, stop
    conditions, Ctrl-C between chunks of steps with status ``"interrupted"``).

    Parameters
    ----------
    built : Built
        The model (:func:`build`).
    progress : bool or callable
        As for :func:`murus.dem.engine.run` (``progress(done, total)`` in steps).

    Returns
    -------
    CaseRun
        A settling that did not converge skips the dynamic run (status ``"not_settled"``).
    """
    cm, db, zb = built.cm, built.blocks, built.zones
    m = cm.dem
    case = built.case
    if case.initial_stress == "k0":
        cm.zones.initial_stress_k0(case.k0)
    settled = None
    kw = dict(built.run_kwargs)
    if db.settle is not None:
        settled = m.settle(**db.settle)
        if not settled.converged:
            result = m.run(duration=0.0, probes=kw["probes"], sample_dt=kw["sample_dt"],
                           dt=kw["dt"])
            result.status = "not_settled"
            result.message = f"settling did not converge: {settled.message}"
            return CaseRun(built, result, settled, [])
    changed = False
    if db.tilt is not None:
        m.set_tilt(*db.tilt)
        changed = True
    if zb.ff_sides:
        cm.zones.add_free_field(zb.ff_sides)  # after the static stage, as in FLAC
        cm.set_dt(kw["dt"] if kw["dt"] is not None else min(cm.dt, cm.stable_dt()))
        changed = True
    if changed:
        m.reset_reference()
    frames = []
    stops = [] if kw["stop"] is None else [kw["stop"]]
    if built.vtk_every:
        count = [1]

        def record(mm):
            if count[0] % built.vtk_every == 0:
                frames.append(_frames(built))
            count[0] += 1
            return False

        record.__name__ = "vtk frames"
        frames.append(_frames(built))
        stops.insert(0, record)
    kw["stop"] = stops or None
    kw["dt"] = None  # set on the coupled model (build)
    result = m.run(progress=progress, **kw)
    return CaseRun(built, result, settled, frames)


# ---------------------------------------------------------------------- writers
FIGURE = "model.png"


def output_names(figure: bool = True) -> list[str]:
    """Relative paths written by :func:`write_files` known before the run (the ``vtk/``
    series is checked when it is published)."""
    return ["summary.json", "histories.csv"] + ([FIGURE] if figure else [])


def plot_model(run: CaseRun):
    """Blocks and zones at the end of the run: their displacement relative to the base on one
    colour scale, and the zones' plastic state beside the blocks.

    Parameters
    ----------
    run : CaseRun

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    from murus.continuum.plots import plot_plastic_state, plot_zones
    from murus.dem.plots import plot_blocks

    b = run.built
    m, z = b.cm.dem, b.cm.zones
    fr = _block_frame(m, b.blocks.base)
    ub = fr["cell_data"]["displacement"]
    if b.blocks.base is not None:
        ref = m.body_displacement()[b.blocks.base]
        label = "displacement relative to the base [m]"
    else:
        ref = np.zeros(2)
        label = "displacement [m]"
    uz = np.hypot(*(z.gdisp - ref).T)[z.zg].mean(axis=1)
    pts = np.vstack([z.gxy] + [np.asarray(v) for v in fr["polygons"]])
    span = np.ptp(pts, axis=0)
    wide = span[0] > 2.5 * span[1]  # a long backfill: the two panels one above the other
    fig, axes = plt.subplots(2 if wide else 1, 1 if wide else 2,
                             figsize=(11, 7) if wide else (13, 4.5))
    plot_zones(z.gxy, z.zg, uz, ax=axes[0], label=label)
    zc = axes[0].collections[-1]
    zc.colorbar.remove()
    plot_blocks(fr["polygons"], fr["discs"], ub, ax=axes[0], label=label)
    allv = np.concatenate([ub, uz])
    allv = allv[np.isfinite(allv)]
    lo, hi = (float(allv.min()), float(allv.max())) if allv.size else (0.0, 1.0)
    for col in axes[0].collections:
        if col.get_array() is not None:
            col.set_clim(lo, hi)
    axes[0].set_title(f"displacement, t = {m.time:.3f} s")
    plot_plastic_state(z.gxy, z.zg, z.plastic_state(), ax=axes[1], blocks=fr["polygons"])
    axes[1].set_title("plastic state")
    fig.tight_layout()
    return fig


def write_files(run: CaseRun, folder: Path, figure: bool = True) -> None:
    """``summary.json``, ``histories.csv``, ``model.png`` and, when frames were kept,
    ``vtk/series.pvd`` (blocks) and ``vtk/zones.pvd`` (zones)."""
    import json

    from murus.dem.case import histories_csv
    from murus.rocking.output import _clean

    folder = Path(folder)
    (folder / "summary.json").write_text(json.dumps(_clean(run.summary()), indent=2) + "\n")
    (folder / "histories.csv").write_text(histories_csv(run.result))
    if figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig = plot_model(run)
        fig.savefig(folder / FIGURE, dpi=120)
        plt.close(fig)
    if run.frames:
        from murus.continuum.vtk import write_zone_series
        from murus.dem.vtk import write_series

        write_series(folder / "vtk", [(t, fb) for t, fb, _ in run.frames], binary=True)
        write_zone_series(folder / "vtk", [(t, fz) for t, _, fz in run.frames], binary=True)


def write_outputs(run: CaseRun, out: Path, figure: bool = True) -> Path:
    """Write the outputs of one run into ``out`` (nothing of the user's replaced or deleted;
    ``out`` unchanged on failure).

    Parameters
    ----------
    run : CaseRun
    out : pathlib.Path
        The output folder.
    figure : bool
        Write ``model.png``.

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
    from murus.dem.case import summary_parts

    s = run.summary()
    reason, vals = summary_parts(s)
    return (f"{name}: {s['bodies']} bodies and {s['zones']} zones, {s['t_end']:.4g} s simulated "
            f"in {s['steps']} steps, {reason}, {s['plastic_zones']} zones yielding"
            + (f", {vals}" if vals else ""))
