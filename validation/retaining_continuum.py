"""Validation of the continuum backfill of dry-stone retaining walls (issue 18): the model of
Savalle et al. (2022) (stones as blocks, the backfill as Mohr-Coulomb zones, free-field side,
:mod:`murus.retaining.continuum_backfill`) run by :func:`murus.retaining.collapse.collapse_run`
against the paper's Tables 3, 4, 7 and 8 and Figures 7, 10, 11 and 14.

Every A_col is the median of five runs whose time step is 100, 95, 90, 85 and 80 % of the
nominal one (:func:`murus.retaining.collapse.collapse_ensemble`), given with its range; the
first run is the one the shipped command ``murus retaining collapse ... --backfill continuum``
makes. Runs are cached as JSON under ``validation/results/retaining_continuum/``, one file per
run, stamped with the key of the engine's source (:func:`runcache.source_key` of
``murus.dem``, ``murus.continuum``, ``murus.retaining`` and the harmonic signals of
``murus.motion``, without their command lines and figures): a run made by another engine is
recomputed.

Usage::

    python validation/retaining_continuum.py [--out FILE] [--jobs 2] [--group t7 mesh ...]
    python validation/retaining_continuum.py --list
"""

from __future__ import annotations

import csv
import json
import math
import statistics
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from murus.cliutil import json_safe  # noqa: E402

ROOT = HERE.parent
FIG = ROOT / "docs" / "figures" / "retaining"
DATA = ROOT / "tests" / "data" / "retaining"
CACHE = ROOT / "validation" / "results" / "retaining_continuum"
#: Sub-packages and modules whose source keys the cache (without the command lines, figures
#: and case files: runcache.NOT_ENGINE).
ENGINE = ("__init__.py", "dem", "continuum", "retaining", "motion/core.py",
          "motion/synthetic.py")
#: Runs per ensemble (the time-step factors of murus.retaining.collapse.DT_FACTORS).
NRUNS = 5

#: The mock-ups' input slope and courses: as the equivalent-thrust validation
#: (validation/retaining_dynamic.py), where their reconstruction is explained.
A_MOCK = 2.6 / 19.9
MOCK_COURSE = 0.010
MOCK_TMAX = 45.0


def _rows(name: str) -> list[dict]:
    with open(DATA / name, newline="") as fh:
        return list(csv.DictReader(r for r in fh if not r.startswith("#")))


def table7() -> list[dict]:
    """The eight cases of Savalle et al. (2022), Tables 7 and 8 (tests/data)."""
    return _rows("savalle2022_table8.csv")


def _vert(v: str) -> str:
    return {"none": "none", "in-phase": "in_phase", "opposition": "opposition"}[v]


def runs() -> dict[str, dict]:
    """Every run: key -> spec (group, wall, frequency, collapse_run keywords, run index)."""
    out: dict[str, dict] = {}

    def ens(group, base, **spec):
        for i in range(NRUNS):
            out[f"{base}_r{i}"] = dict(spec, group=group, run=i)

    for row in table7():
        v = _vert(row["vertical"])
        ens("t7", f"t7_{row['wall']}_{float(row['frequency_Hz']):g}_{v}", wall=row["wall"],
            f=float(row["frequency_Hz"]), vertical=v, kw={})
        ens("t7_thrust", f"thrust_{row['wall']}_{float(row['frequency_Hz']):g}_{v}",
            wall=row["wall"], f=float(row["frequency_Hz"]), vertical=v,
            kw={"backfill": "thrust"})
    ens("mesh", "mesh_DSRW1_5_h24", wall="DSRW1", f=5.0, vertical="none",
        kw={"size": 2.5 / 24})
    ens("width", "width_DSRW1_5_W10", wall="DSRW1", f=5.0, vertical="none", kw={"W": 10.0})
    ens("scale", "scale_DSRW1_5_k1e-2", wall="DSRW1", f=5.0, vertical="none",
        kw={"stiffness_scale": 1e-2})
    for r in (0.6, 0.7):
        out[f"s1_DSRW1_5_{r:g}"] = dict(group="s1", wall="DSRW1", f=5.0, vertical="none",
                                        ratio=r, run=0, kw={})
    from murus.retaining.geometry import MOCKUP_SLENDERNESS

    for s in MOCKUP_SLENDERNESS:
        ens("mock", f"mock_{s:g}", wall=f"mockup-{s:g}", f=10.0, vertical="none", kw={})
    for phi in (50.0, 55.0):
        ens("mock_phi", f"mock_2.7_phi{phi:g}", wall="mockup-2.7", f=10.0, vertical="none",
            kw={}, overrides={"backfill_friction_deg": phi})
    ens("mock30", "mock_2.7_30Hz", wall="mockup-2.7", f=30.0, vertical="none", kw={})
    # the joint stiffness as printed (x 1): one run of about an hour
    out["scale_DSRW1_5_k1_r0"] = dict(group="slow", wall="DSRW1", f=5.0, vertical="none",
                                      run=0, kw={"stiffness_scale": 1.0})
    return out


def _wall(spec):
    from murus.retaining.geometry import preset

    w = preset(spec["wall"], **spec.get("overrides", {}))
    if w.name.lower().startswith("mockup"):
        n = max(1, round(w.height / MOCK_COURSE))
        w = w.with_(stone_height=w.height / n)
    return w


def _median_acol(prefix: str) -> float:
    vals = []
    for i in range(NRUNS):
        rec = json.loads((CACHE / f"{prefix}_r{i}.json").read_text())
        a = rec["summary"].get("A_col")
        vals.append(math.inf if a is None else float(a))
    return float(statistics.median(vals))


def compute(key: str) -> dict:
    """Run ``key`` and write its JSON to the cache; returns the stored record."""
    from murus.retaining.collapse import DT_FACTORS, collapse_run

    spec = runs()[key]
    wall = _wall(spec)
    kw = dict(spec["kw"])
    bmode = kw.pop("backfill", "continuum")
    opts = {k: kw.pop(k) for k in ("size", "W") if k in kw}
    mock = wall.name.lower().startswith("mockup")
    if mock:
        kw.update(A_rate=A_MOCK, t_max=MOCK_TMAX)
    if spec["group"] == "s1":
        acol = _median_acol("t7_DSRW1_5_none")
        kw.update(signal="S1", a_peak=spec["ratio"] * acol)
    kw["safety"] = 0.2 * DT_FACTORS[spec["run"]]
    r = collapse_run(wall, spec["f"], spec["vertical"], backfill=bmode,
                     backfill_options=opts if bmode == "continuum" else None, **kw)
    rec = {"key": key, "spec": spec, "summary": json_safe(r.summary()), "mode": r.mode,
           "stone_height": wall.stone_height,
           "t": [round(float(x), 4) for x in r.t],
           "d_top": [round(float(x), 7) for x in r.d_top]}
    if spec["run"] == 0:  # the nominal run: the final state, for the figures
        rec.update(polygons=[np.round(np.asarray(q), 5).tolist() for q in r.polygons],
                   displacement=np.round(r.displacement, 6).tolist(),
                   zone_xy=np.round(r.zone_xy, 5).tolist(), zone_cells=r.zone_cells.tolist(),
                   zone_state=r.zone_state.tolist())
    CACHE.mkdir(parents=True, exist_ok=True)
    tmp = CACHE / f"{key}.json.tmp"
    tmp.write_text(json.dumps(rec))
    tmp.replace(CACHE / f"{key}.json")
    return rec


def ensure(keys, recompute: bool = False, jobs: int = 1) -> dict[str, dict]:
    """The cached records of ``keys`` made by this engine, computing the others."""
    import runcache

    return runcache.ensure(keys, compute, CACHE, recompute, jobs,
                           engine=runcache.source_key(*ENGINE))


def cached(keys) -> dict[str, dict]:
    """The records of ``keys`` in the cache made by this engine (no computation)."""
    import runcache

    eng = runcache.source_key(*ENGINE)
    out = {}
    for k in keys:
        p = CACHE / f"{k}.json"
        if runcache._readable(p, eng):
            out[k] = json.loads(p.read_text())
    return out


def main(argv=None) -> None:
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None, help="Markdown file (default: standard output).")
    ap.add_argument("--jobs", type=int, default=1, help="Parallel runs (processes).")
    ap.add_argument("--group", nargs="*", default=None, help="Compute the runs of these "
                    "groups only (no Markdown): t7, t7_thrust, mesh, width, scale, s1, mock, "
                    "mock_phi, mock30, slow.")
    ap.add_argument("--recompute", action="store_true", help="Run again, ignoring the cache.")
    ap.add_argument("--list", action="store_true", help="List the run keys and whether cached.")
    args = ap.parse_args(argv)
    spec = runs()
    if args.list:
        have = cached(spec)
        for k in spec:
            print(k, spec[k]["group"], "cached" if k in have else "-")
        return
    if args.group is not None:
        keys = [k for k, s in spec.items() if s["group"] in args.group]
        ensure(keys, args.recompute, args.jobs)
        return
    import runcache

    runcache.emit(section(args.recompute, args.jobs), args.out)


def section(recompute: bool = False, jobs: int = 1) -> str:  # filled in below
    raise NotImplementedError


if __name__ == "__main__":
    main()
