"""DEM contact damping against the rocking engine (issue 19, item 5).

1. Free rocking: the restitution per impact of a free-rocking DEM block for several
   ``contact_damping`` values, and its free decay against :mod:`murus.rocking` with the same e
   (figure ``docs/figures/dem/rocking_damping.png``).
2. Real records: the same block (``contact_damping = 1``, Housner's behaviour) standing on a
   base shaken by FEMA P695 far-field records (``murus[records]``), trimmed to their strong
   part and scaled so that the rocking engine rocks it to theta_max / alpha of 0.2-0.7 without
   overturning, at a scale where the response is not chaotic (theta_max of the rocking engine
   within 6 % over the scales -4, -2, +2, +4 % around it); theta_max of the DEM against the
   rocking engine with the restitution the DEM block shows in free rocking (and Housner's).
   The DEM runs are cached in ``validation/results/dem_rocking_damping/`` (keyed by the
   engine's source: a changed engine recomputes them).

    PYTHONPATH=src python validation/dem_rocking_damping.py [--out FILE]
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
FIG = ROOT / "docs" / "figures" / "dem"
CACHE = HERE / "results" / "dem_rocking_damping"
#: the block of the comparison and its contact stiffness (kn = ks) [m, m, Pa/m]; the records
#: are also run at the free-rocking part's stiffness, KN_STIFF
B, H, KN_REC, KN_STIFF = 0.25, 1.0, 1e9, 1e10
#: records searched in this order, and the scales tried [-]
SCALES = np.round(np.arange(0.5, 2.001, 0.02), 3)
N_RECORDS = 3
#: the engine key of the cached DEM runs: the DEM and the module that builds and runs them
ENGINE = ("dem", "dem/rocking_damping.py", "motion/core.py")


def _engine() -> str:
    import runcache

    return runcache.source_key(*ENGINE)


def free_table(fig_dir: Path = FIG) -> tuple[list[str], str]:
    """Part 1: the Markdown rows and the figure's file name."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from murus.dem import rocking_damping as RD
    from murus.rocking import RigidBlock, simulate

    rows = ["| block | zeta | Housner e | DEM e, impacts 1-5 | peaks 2-6 against murus.rocking "
            "(same e): largest deviation |", "|---|---|---|---|---|"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, (b, h) in zip(axes, ((0.25, 1.0), (0.2, 1.2)), strict=True):
        alpha = math.atan(b / h)
        eh = 1 - 1.5 * math.sin(alpha) ** 2
        for z in (0.0, 0.15, 1.0):
            r = RD.free_rocking(b, h, z, n_impacts=5)
            e = float(np.mean(r.e[:5]))
            rr = simulate(RigidBlock(b, h, density=RD.DENSITY), theta0_over_alpha=0.5,
                          restitution=e, duration=r.t[-1], out_dt=1e-3)
            th = np.abs(rr.theta)
            cut = np.nonzero(np.sign(rr.theta[1:]) != np.sign(rr.theta[:-1]))[0]
            # the peak of each half-cycle of the rigid run, the last one left out: the run
            # ends with the DEM's history, inside a half-cycle whose peak it may not reach
            ref = np.array([th[a:c].max() for a, c in zip(np.r_[0, cut[:-1] + 1], cut + 1,
                                                          strict=True)])
            n = min(6, r.peaks.size, ref.size)
            dev = np.abs(r.peaks[1:n] / ref[1:n] - 1)
            es = " ".join(f"{x:.4f}" for x in r.e[:5])
            rows.append(f"| {b} x {h} | {z:g} | {eh:.4f} | {es} | {100 * dev.max():.2f} % |")
            ax.plot(r.t, r.theta / alpha, lw=1, label=f"DEM zeta = {z:g} (e = {e:.3f})")
            ax.plot(rr.t, rr.theta / alpha, "k--", lw=0.7)
        ax.set_title(f"{b} x {h} m block, Housner e = {eh:.3f}\n(dashed: murus.rocking with "
                     "the DEM's e)", fontsize=9)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("theta / alpha")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig_dir.mkdir(parents=True, exist_ok=True)
    name = "rocking_damping.png"
    fig.savefig(fig_dir / name, dpi=120)
    plt.close(fig)
    return rows, name


def _trim(g):
    """The strong part of a record: from 1 s before 5 % of its Arias intensity to 3 s after
    95 %."""
    from murus.motion.core import GroundMotion

    cum = np.cumsum(g.acc ** 2)
    i5 = int(np.searchsorted(cum, 0.05 * cum[-1]))
    i95 = int(np.searchsorted(cum, 0.95 * cum[-1]))
    a = max(0, i5 - int(round(1.0 / g.dt)))
    b = min(g.acc.size, i95 + int(round(3.0 / g.dt)))
    return GroundMotion(g.dt, np.array(g.acc[a:b]), name=g.name)


def _theta_max(blk, g, e=None) -> float:
    from murus.rocking import simulate

    r = simulate(blk, g, duration=g.dt * g.acc.size + 2.0, restitution=e)
    return float(np.abs(r.theta).max())


def pick_cases(n: int = N_RECORDS) -> list[dict]:
    """The first ``n`` far-field records (in the suite's order) with a scale at which the
    rocking engine (Housner's e) rocks the block to 0.2-0.7 alpha, stably over +-4 %."""
    from murus.motion import suite
    from murus.rocking import RigidBlock

    blk = RigidBlock(B, H, density=2000.0)
    alpha = math.atan(B / H)
    out = []
    for g in suite("farfield", components="both"):
        gt = _trim(g)
        th = np.array([_theta_max(blk, gt.scaled(float(s))) / alpha for s in SCALES])
        for i in range(2, len(SCALES) - 2):
            w = th[i - 2:i + 3]
            if 0.2 <= th[i] <= 0.7 and np.all(w < 1.0) and np.ptp(w) / th[i] < 0.06:
                out.append({"record": g.name, "scale": float(SCALES[i]),
                            "spread": float(np.ptp(w) / th[i]),
                            "pga": float(np.abs(gt.acc).max() * SCALES[i])})
                break
        if len(out) >= n:
            break
    return out


def record_runs(cases: list[dict]) -> list[dict]:
    """DEM (contact_damping 1) and rocking engine on each case; DEM runs cached."""
    from murus.dem import rocking_damping as RD
    from murus.motion import suite
    from murus.rocking import RigidBlock

    eng = _engine()
    recs = {g.name: g for g in suite("farfield", components="both")}
    blk = RigidBlock(B, H, density=2000.0)
    alpha = math.atan(B / H)
    e_dem = float(np.mean(RD.free_rocking(B, H, 1.0, n_impacts=5, kn=KN_REC).e[:5]))
    out = []
    CACHE.mkdir(parents=True, exist_ok=True)
    for c in cases:
        g = _trim(recs[c["record"]]).scaled(c["scale"])
        dem = {}
        for kn in (KN_REC, KN_STIFF):
            sfx = "" if kn == KN_REC else f"_kn{kn:g}"
            path = CACHE / f"{c['record']}_x{c['scale']:g}{sfx}.json"
            rec = json.loads(path.read_text()) if path.exists() else None
            if rec is None or rec.get("_engine_source") != eng:
                t, th = RD.record_rocking(B, H, 1.0, g, kn=kn)
                rec = {"record": c["record"], "scale": c["scale"], "kn": kn,
                       "theta_max": float(np.abs(th).max()), "t": t[::25].round(4).tolist(),
                       "theta": th[::25].round(7).tolist(), "_engine_source": eng}
                tmp = path.with_suffix(".json.tmp")
                tmp.write_text(json.dumps(rec))
                tmp.replace(path)
            dem[kn] = rec["theta_max"] / alpha
        out.append(dict(c, dem=dem[KN_REC], dem_stiff=dem[KN_STIFF],
                        rocking_e_dem=_theta_max(blk, g, e_dem) / alpha,
                        rocking_housner=_theta_max(blk, g) / alpha, e_dem=e_dem))
    return out


def untrimmed(case: dict, e_dem: float) -> dict:
    """The first case on its whole record (not trimmed), DEM at KN_STIFF (cached) against the
    rocking engine with the DEM's e."""
    from murus.dem import rocking_damping as RD
    from murus.motion import suite
    from murus.rocking import RigidBlock

    alpha = math.atan(B / H)
    g0 = next(g for g in suite("farfield", components="both") if g.name == case["record"])
    g = g0.scaled(case["scale"])
    path = CACHE / f"{case['record']}_x{case['scale']:g}_whole_kn{KN_STIFF:g}.json"
    rec = json.loads(path.read_text()) if path.exists() else None
    if rec is None or rec.get("_engine_source") != _engine():
        t, th = RD.record_rocking(B, H, 1.0, g, kn=KN_STIFF)
        rec = {"record": case["record"], "scale": case["scale"], "kn": KN_STIFF,
               "theta_max": float(np.abs(th).max()), "_engine_source": _engine()}
        CACHE.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(rec))
    cum = np.cumsum(g0.acc ** 2)
    lead = g0.dt * int(np.searchsorted(cum, 0.05 * cum[-1]))
    return {"record": case["record"], "scale": case["scale"], "lead": lead,
            "dem": rec["theta_max"] / alpha,
            "rocking": _theta_max(RigidBlock(B, H, density=2000.0), g, e_dem) / alpha}


def section(fig_dir: Path | None = None) -> str:
    fig_dir = FIG if fig_dir is None else fig_dir
    rel = fig_dir.relative_to(ROOT) if fig_dir.is_relative_to(ROOT) else fig_dir
    rows, fig = free_table(fig_dir)
    lines = ["## A DEM block that rocks like the rocking engine (issue 19, item 5)", "",
             "The joint's contact damping (`contact_damping = zeta` of a material, "
             "`murus.dem.materials.Joint`): a normal dashpot `c = 2 zeta sqrt(kn A m_eff)` on "
             "each sub-contact, acting only while the surfaces overlap and close (it damps the "
             "approach of an impact, never the separation, and never pulls), in the manner of "
             "the impact-only viscous damping of Vlachakis et al. (2021), J. Eng. Mech. 147(11), "
             "doi:10.1061/(ASCE)EM.1943-7889.0001985. Free rocking of a block released from "
             "alpha / 2 on a fixed base (kn = ks = 1e10 Pa/m, friction 40 deg, rounding 0.2 mm, "
             "`murus.dem.rocking_damping.free_rocking`): the restitution per impact (the ratio "
             "of the rigid rocking velocities at theta = 0 after and before each impact) and "
             "the peaks against `murus.rocking` run with the DEM's mean e.", "", *rows, "",
             f"![free rocking, DEM against murus.rocking]({rel}/{fig})", "",
             "`contact_damping = 1` gives Housner's restitution within 0.6 % (0.25 x 1.0 m) "
             "and 0.2 % (0.2 x 1.2 m), and the free decay of the rocking engine within 2 % "
             "peak by peak: this is Housner's behaviour in the DEM (docs, *Rocking blocks in "
             "the DEM*). Without it the block keeps 0.97-0.99 per impact (it loses energy only "
             "by slip). A restitution between Housner's and the undamped one is reached by "
             "`murus.dem.rocking_damping.calibrate`; **one below Housner's is out of reach**: "
             "the dashpot makes the impact on the new corner at most plastic, which is "
             "Housner's own assumption (a lower e needs a loss the rigid-block theory does not "
             "have, e.g. crushing at the corner).", ""]
    cases = pick_cases()
    res = record_runs(cases)
    alpha = math.atan(B / H)
    lines += ["### Under real records", "",
              f"The {B} x {H} m block (kn = ks = {KN_REC:g} Pa/m, `contact_damping = 1`; its "
              f"free-rocking e = {res[0]['e_dem']:.4f}, Housner's "
              f"{1 - 1.5 * math.sin(alpha) ** 2:.4f}) on a base shaken by FEMA P695 far-field "
              "records trimmed to their strong part (from 1 s before 5 % of the Arias "
              "intensity to 3 s after 95 %), scaled so that the rocking engine rocks it "
              "without overturning and stably (theta_max within 6 % over -4, -2, +2, +4 % of "
              "the scale: not chaotic there; the first such records of the suite). theta_max "
              "/ alpha:", "",
              f"| record | scale | PGA [m/s²] | spread of the rocking engine over +-4 % | "
              f"rocking engine, DEM's e | rocking engine, Housner's e | DEM, kn {KN_REC:g} "
              f"(against the DEM's e) | DEM, kn {KN_STIFF:g} (against the DEM's e) |",
              "|---|---|---|---|---|---|---|---|"]
    for r in res:
        d1 = 100 * (r["dem"] / r["rocking_e_dem"] - 1)
        d2 = 100 * (r["dem_stiff"] / r["rocking_e_dem"] - 1)
        lines.append(f"| {r['record']} | {r['scale']:g} | {r['pga']:.2f} | "
                     f"{100 * r['spread']:.1f} % | {r['rocking_e_dem']:.3f} | "
                     f"{r['rocking_housner']:.3f} | {r['dem']:.3f} ({d1:+.1f} %) | "
                     f"{r['dem_stiff']:.3f} ({d2:+.1f} %) |")
    un = untrimmed(cases[0], res[0]["e_dem"])
    within = sum(abs(r["dem"] / r["rocking_e_dem"] - 1) <= 0.10 for r in res)
    within2 = sum(abs(r["dem_stiff"] / r["rocking_e_dem"] - 1) <= 0.10 for r in res)
    lines += ["", f"Within 10 % of the rocking engine with the same e: {within} of {len(res)} "
              f"at kn = {KN_REC:g}, {within2} of {len(res)} at kn = {KN_STIFF:g} (goal: theta_max "
              "within 10 % under three records where the response is not chaotic; the two "
              "contact stiffnesses are a perturbation of the model of the size a DEM user makes, "
              "and the difference between them measures how sensitive the response still is).",
              "",
              f"The trimming matters: on the whole record {un['record']} x {un['scale']:g} "
              f"(with its {un['lead']:.0f} s of weak motion before the strong part) the DEM at "
              f"kn = {KN_STIFF:g} gives {un['dem']:.3f} against the rocking engine's "
              f"{un['rocking']:.3f} ({100 * (un['dem'] / un['rocking'] - 1):+.1f} %): below the "
              "uplift threshold the rigid block does not move at all, the DEM block on elastic "
              "contacts does (the source of the difference is not isolated further here).", "",
              "Regenerate: `PYTHONPATH=src python validation/dem_rocking_damping.py` (the "
              "free-rocking part about 3 minutes on one core; each DEM record run several "
              "minutes, cached).", ""]
    return "\n".join(lines)


def main(argv=None) -> None:
    import runcache

    runcache.section_main(section, __doc__, argv)


if __name__ == "__main__":
    main()
