"""Validation of the behaviour-factor study (issue 6 item 4, issue 18; Savalle et al. (2022),
§4.2-4.4, Tables 7-8, Figure 14): the example case files
``examples/retaining/dsrw1_behaviour_factor.toml`` (DSRW1: S2 at 3, 5, 10 Hz, at 5 Hz with a
vertical component in phase and in opposition, and the S1 checks at 0.6 and 0.7 A_col of
each) and ``dsrw2..4_behaviour_factor.toml`` (5 Hz with its checks), run by
:func:`murus.retaining.study.run_behaviour_study` on the continuum backfill of the paper.

The study folders under ``validation/results/retaining_behaviour/continuum/`` are the cache: a
study resumes there and computes only its missing cases (delete a folder to recompute it). Each
folder is keyed by the engine's source as the continuum records are (``engine.json``, written
before its first case: the key of ``runcache.source_key`` over ``retaining_continuum.ENGINE``):
a study made by another engine is recomputed (and left out with ``--cached``), unless
``validation/restamp_check.py --apply`` re-keyed it with the evidence that the change of the
engine changes no run.

Usage::

    python validation/retaining_behaviour.py [--out FILE] [--workers 2] [--cached] [--cache DIR]
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CACHE = ROOT / "validation" / "results" / "retaining_behaviour" / "continuum"
EXAMPLES = ROOT / "examples" / "retaining"
DATA = ROOT / "tests" / "data" / "retaining" / "savalle2022_table8.csv"
WALLS = ("DSRW1", "DSRW2", "DSRW3", "DSRW4")
#: A study folder's engine stamp: ``{runcache.ENGINE_FIELD: key, runcache.PLATFORM_FIELD: ...}``
#: (re-keyed by ``runcache.restamp`` as a record is).
STAMP = "engine.json"


def engine_key() -> str:
    """The key of the engine whose source decides the studies' runs (the continuum
    validation's)."""
    import retaining_continuum as rc
    import runcache

    return runcache.source_key(*rc.ENGINE)


def stamp_state(folder: Path, engine: str) -> tuple[str, str | None]:
    """``("new", None)``: no folder or an empty one; ``("current", key)``: stamped by
    ``engine``; ``("stale", key)``: stamped by another engine; ``("unknown", None)``: a folder
    with content and no readable stamp."""
    import runcache

    if not folder.is_dir() or not any(folder.iterdir()):
        return "new", None
    try:
        key = json.loads((folder / STAMP).read_text()).get(runcache.ENGINE_FIELD)
    except (OSError, ValueError, AttributeError):
        return "unknown", None
    if not isinstance(key, str):
        return "unknown", None
    return ("current" if key == engine else "stale"), key


def write_stamp(folder: Path, engine: str) -> None:
    import runcache

    from murus.outputs import write_text

    folder.mkdir(parents=True, exist_ok=True)
    write_text(folder / STAMP, json.dumps({runcache.ENGINE_FIELD: engine,
                                           runcache.PLATFORM_FIELD: runcache.platform()},
                                          indent=1) + "\n")


def note_machine(folder: Path) -> None:
    """Add this machine to the stamp's ``_resumed_on`` when a study is resumed on a machine
    other than the one of its first case (the same engine gives the same numbers only on a
    machine of the same arithmetic)."""
    import runcache

    from murus.outputs import write_text

    stamp = json.loads((folder / STAMP).read_text())
    here = runcache.platform()
    seen = [stamp.get(runcache.PLATFORM_FIELD)] + stamp.get("_resumed_on", [])
    if here not in seen:
        stamp["_resumed_on"] = stamp.get("_resumed_on", []) + [here]
        write_text(folder / STAMP, json.dumps(stamp, indent=1) + "\n")


class StaleStudy(Exception):
    """A study folder this script cannot vouch for (no engine stamp)."""


def studies():
    """name -> BehaviourStudy of the example case files."""
    from murus.retaining.study import load_behaviour_study

    return {w: load_behaviour_study(EXAMPLES / f"{w.lower()}_behaviour_factor.toml")
            for w in WALLS}


def run_all(workers: int = 1, cached: bool = False, stale: dict | None = None) -> dict:
    """name -> BehaviourStudyResult (computing the missing cases; with ``cached`` only the
    studies whose folder holds a finished table of this engine, which computes nothing).

    A folder stamped by another engine is recomputed from scratch (its content was written by
    this script: the stamp says so); with ``cached`` it is left out and listed in ``stale``
    (name -> its engine key, or None for a folder without a stamp). A folder with content but
    no stamp is refused (:class:`StaleStudy`): nothing tells which engine made it."""
    from murus.studies.executors import fresh_pool_size

    fresh_pool_size(1)  # one numba thread, in a fresh process
    from murus.retaining.study import run_behaviour_study

    eng = engine_key()
    res = {}
    for name, st in studies().items():
        folder = CACHE / name
        state, key = stamp_state(folder, eng)
        if cached:
            if state in ("stale", "unknown") and stale is not None:
                stale[name] = key
            if state != "current" or not (folder / "behaviour_factor.csv").exists():
                continue
        elif state == "unknown":
            raise StaleStudy(f"{folder}: a study folder without a readable engine stamp "
                             f"({STAMP}): delete it to recompute it")
        elif state == "stale":
            print(f"  {name}: made by engine {key}, not {eng}: recomputed", file=sys.stderr)
            shutil.rmtree(folder)
        if not cached and state == "current":
            note_machine(folder)
        elif not cached:
            write_stamp(folder, eng)
        kind = "serial" if workers <= 1 else "process"
        res[name] = run_behaviour_study(st, kind, workers=None if workers <= 1 else workers,
                                        out=CACHE / name)
    return res


def _seed_rows() -> list[dict]:
    with open(DATA) as fh:
        return list(csv.DictReader(line for line in fh if not line.startswith("#")))


def _f(x, nd=2) -> str:
    return "—" if x is None or (isinstance(x, float) and not math.isfinite(x)) else \
        f"{x:.{nd}f}"


def _err(a, b) -> str:
    if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)):
        return "—"
    return f"{100 * (a / b - 1):+.0f} %"


def _corner_rule(row: dict) -> str:
    """The interface's corner rule the S2 case of ``row`` was run with: listed in its summary
    since session 19; before, the default of the time, "follow"."""
    name = f"S2_{float(row['frequency_Hz']):g}Hz_{row['vertical']}"
    path = CACHE / row["wall"] / "cases" / f"{name}.json"
    try:
        bo = json.loads(path.read_text())["summary"]["options"]["backfill_options"]
    except (OSError, ValueError, KeyError, TypeError):
        return "unknown"
    return bo.get("corner_share", "follow") if isinstance(bo, dict) else "unknown"


def _against_nominal(res: dict) -> tuple[list[str], list[str], list[float], set[str], list]:
    """The S2 cases whose A_col equals (first list) or differs from (second) the nominal run
    of the same case and corner rule in the continuum validation's cache (cases without one
    are skipped), the relative differences of the second, the machines the compared
    records were computed on (``runcache.PLATFORM_FIELD``; "not recorded" for the records
    made before the field existed), and, for the cases whose five runs are all cached,
    ``(label, A_col of the study, lowest and highest of the five, relative distance outside
    that range (0 inside))``: the study's S2 run is the shipped command's run (the nominal
    run's arguments) on the machine of the study, so this is item 6's "the shipped command
    reproduces each number within its stated range", measured there."""
    import retaining_continuum as rc
    import runcache

    same, diff, rel, machines, ranges = [], [], [], set(), []
    cont = ROOT / "validation" / "results" / "retaining_continuum"
    for r in res.values():
        for row in r.table.rows:
            if row["collapsed"] is not True:
                continue
            tag = f"{row['wall']}_{float(row['frequency_Hz']):g}_{row['vertical']}"
            key = f"t7_{tag}_r0"
            rule = _corner_rule(row)
            if rule == rc.TWIN_RULE:
                key = rc.twin_key(key)
            path = cont / f"{key}.json"
            if not path.exists():
                continue
            rec = json.loads(path.read_text())
            a = rec["summary"].get("A_col")
            pf = rec.get(runcache.PLATFORM_FIELD)
            machines.add(_machine(pf))
            lab = f"{row['wall']} {row['frequency_Hz']:g} Hz {row['vertical']}"
            ens = [json.loads(p.read_text())["summary"].get("A_col")
                   for p in (cont / f"{key[:-1]}{i}.json" for i in range(rc.NRUNS))
                   if p.exists()]
            ens = [float(x) for x in ens if x is not None]
            if len(ens) == rc.NRUNS:
                x, lo, hi = float(row["A_col_m_s2"]), min(ens), max(ens)
                out = 0.0 if lo <= x <= hi else (x / hi - 1 if x > hi else x / lo - 1)
                ranges.append((lab, x, lo, hi, out))
            if a is not None and float(a) == float(row["A_col_m_s2"]):
                same.append(lab)
            elif a is not None:
                d = float(row["A_col_m_s2"]) / float(a) - 1.0
                rel.append(d)
                diff.append(f"{lab} ({row['A_col_m_s2']:.4f} against {float(a):.4f}, "
                            f"{100 * d:+.2f} %)")
            else:
                diff.append(f"{lab} ({row['A_col_m_s2']:.4f}; the record has no A_col)")
    return same, diff, rel, machines, ranges


def _machine(pf: dict | None) -> str:
    """A machine of ``runcache.platform()`` in words ("not recorded" for None)."""
    return f"{pf.get('cpu', '?')} ({', '.join(pf.get('isa', []))})" if pf else "not recorded"


def _study_machines(res: dict) -> set[str]:
    """The machines in the engine stamps of the studies ``res``: of their first case and of
    their resumes elsewhere ("not recorded" without a stamp)."""
    import runcache

    out = set()
    for name in res:
        try:
            stamp = json.loads((CACHE / name / STAMP).read_text())
        except (OSError, ValueError):
            stamp = {}
        out.update(_machine(pf) for pf in
                   [stamp.get(runcache.PLATFORM_FIELD)] + stamp.get("_resumed_on", []))
    return out


def section(workers: int = 1, cached: bool = False) -> str:
    stale: dict = {}
    res = run_all(workers, cached, stale)
    seed = {(r["wall"], float(r["frequency_Hz"]), r["vertical"].replace("-", "_")): r
            for r in _seed_rows()}
    L = ["## Dry-stone retaining walls: behaviour factor (Savalle et al. (2022), Tables 7-8, "
         "Figure 14)", ""]
    L.append("The behaviour-factor study of `murus.retaining.study` on the example case files "
             "`examples/retaining/dsrw1_behaviour_factor.toml` (DSRW1) and "
             "`dsrw2..4_behaviour_factor.toml` (5 Hz), on the continuum backfill of the paper "
             "with the numerics of the section *on the continuum backfill* below (one run per "
             "case, the nominal one: the medians of five runs are there): S2 until d_top = 20 "
             "% H gives A_col, A_peak = 0.6 A_col, r = A_peak / A_pseudo with the murus "
             "A_pseudo (limit equilibrium, same vertical component). Produced by `python "
             "validation/retaining_behaviour.py` (the study folders in "
             "`validation/results/retaining_behaviour/continuum/` are its cache); the same table "
             "comes from `murus retaining behaviour-factor examples/retaining/"
             "dsrw1_behaviour_factor.toml`.")
    missing = [w for w in WALLS if w not in res and w not in stale]
    if stale:
        L.append("")
        L.append("Made by another engine, so left out (`python validation/retaining_behaviour.py "
                 "--workers 2` recomputes them; `validation/restamp_check.py --apply` re-keys "
                 "them where the change of the engine is shown to change no run): "
                 + ", ".join(f"{w} ({k or 'no stamp'})" for w, k in stale.items()) + ".")
    if missing:
        L.append("")
        one = len(missing) == 1
        L.append(f"Not computed yet: {', '.join(missing)} (`python "
                 f"validation/retaining_behaviour.py --workers 2` computes "
                 f"{'it' if one else 'them'}; {'its' if one else 'their'} S2 "
                 f"run{'' if one else 's'} {'is' if one else 'are'} the nominal "
                 f"run{'' if one else 's'} of the continuum section below).")
    L.append("")
    L.append("| wall | f [Hz] | vertical | seed A_col [m/s²] | murus A_col [m/s²] (error) | "
             "seed A_pseudo | murus A_pseudo | seed r | murus r | S1 at 0.6 / 0.7 A_col "
             "(seed: stable / collapsed) |")
    L.append("|---|---|---|---|---|---|---|---|---|---|")
    rs, a5, checks = [], {}, []
    for r in res.values():
        for row in r.table.rows:
            key = (row["wall"], float(row["frequency_Hz"]), row["vertical"])
            s = seed.get(key, {})
            sa = float(s["A_col_m_s2"]) if s.get("A_col_m_s2") else None
            sp = float(s["A_pseudo_m_s2"]) if s.get("A_pseudo_m_s2") else None
            sr = float(s["r"]) if s.get("r") else None
            ok = row["collapsed"] is True  # or False, or "missing" / "failed"
            a = row["A_col_m_s2"] if ok else None
            chk = r.checks.get((row["frequency_Hz"], row["vertical"]), {})
            c = " / ".join(chk.get(x, "—") for x in r.check_ratios) if r.check_ratios else "—"
            checks.append((row["wall"], row["frequency_Hz"], row["vertical"], c))
            if ok and math.isfinite(row["r"]):
                rs.append((row["wall"], row["r"]))
            if ok and sa is not None and key[1:] == (5.0, "none"):
                a5[row["wall"]] = (sa, a)
            a_txt = f"{_f(a)} ({_err(a, sa)})" if ok else \
                "no collapse to 15 s" if row["collapsed"] is False else str(row["collapsed"])
            L.append(f"| {row['wall']} | {row['frequency_Hz']:g} | {row['vertical']} | "
                     f"{_f(sa)} | {a_txt} | {_f(sp)} | {_f(row['A_pseudo_m_s2'])} | {_f(sr)} | "
                     f"{_f(row['r']) if ok else '—'} | {c} |")
    L.append("")
    import retaining_continuum as rc

    rules = sorted({_corner_rule(row) for r in res.values() for row in r.table.rows})
    if rules and rules != [rc.default_rule()]:
        L.append(f"- **The cached cases were run with the corner rule {', '.join(rules)}** (the "
                 "interface's `corner_share`; the default before session 19 was 'follow', "
                 f"since then '{rc.default_rule()}': VALIDATION.md, *The corner rule*). They "
                 "stand for that "
                 "rule until the studies are run again (delete the study folders and run "
                 "`python validation/retaining_behaviour.py --workers 2`, about 1.5 "
                 "core-hours); the continuum section below gives both rules.")
    same, diff, rel, machines, ranges = _against_nominal(res)
    if same or diff:
        L.append(f"- The study's S2 runs against the nominal runs of the continuum section "
                 f"below (the same numerics, computed separately): {len(same)} of "
                 f"{len(same) + len(diff)} equal bit for bit"
                 + ("" if not diff else "; differing: " + ", ".join(diff)) + ".")
        if rel:
            L.append(f"- Where they differ (largest {100 * max(map(abs, rel)):.1f} %): equality "
                     "bit for bit holds only for one engine on one machine, and a collapse run "
                     "amplifies differences in the last digits of the arithmetic, which is why "
                     "the continuum section gives each A_col as the median of five runs with "
                     "its range. The machine of the nominal records: "
                     + "; ".join(sorted(machines)) + "; the study folders': "
                     + "; ".join(sorted(_study_machines(res))) + ".")
    if ranges:
        outside = [f"{lab} ({x:.4f} against [{lo:.4f}-{hi:.4f}], {100 * o:+.2f} % beyond it)"
                   for lab, x, lo, hi, o in ranges if o != 0.0]
        L.append(f"- The study's S2 runs are the shipped command's runs (the nominal run's "
                 f"arguments: `murus retaining collapse --preset DSRW1 --frequency 5` and so "
                 f"on) on the study's machine; against the range of the five runs of the "
                 f"continuum section (item 6 of issue 18: the shipped command within the "
                 f"stated range): {len(ranges) - len(outside)} of {len(ranges)} within it"
                 + ("." if not outside else "; outside: " + ", ".join(outside) + "."))
    r1 = [r for w, r in rs if w == "DSRW1"]
    above = ("above it in every case" if rs and min(r for _, r in rs) > 1.5
             else "below it in some cases")
    rm = sum(r for _, r in rs) / len(rs) if rs else math.nan
    if r1:
        L.append(f"- murus r of DSRW1 over its collapsed cases: mean {sum(r1) / len(r1):.2f}, "
                 f"minimum {min(r1):.2f} ({len(r1)} cases); Savalle et al. (2022) (DSRW1, Table "
                 f"8): mean 2.08, minimum 1.83; over all the walls murus gives mean "
                 f"{rm:.2f} ({len(rs)} cases of 8; {100 * (rm / 2.08 - 1):+.1f} % against the "
                 f"paper's mean 2.08, goal within 10 %: "
                 f"{'met' if abs(rm / 2.08 - 1) <= 0.10 else 'missed'}), minimum "
                 f"{min(r for _, r in rs):.2f}. The seed proposes r = 1.5 for design; the murus "
                 f"r is {above}.")
    L.append("- S1 checks (seed Figure 14: stable at 0.6 A_col, collapsed at 0.7): the last "
             "column gives the murus outcome; 'skipped': the S2 run did not collapse (no A_col "
             "to check).")
    other = [f"{w} at {f:g} Hz ({v}): {c}" for w, f, v, c in checks
             if c != "stable / collapsed"]
    L.append("- The paper makes the S1 checks for DSRW1 in one case (Figure 14) and assumes "
             "the ratio 0.6 independent of the wall, the frequency and the ramp (§4.3); murus "
             "makes them for every case. " + (
                 "Every case gives the paper's outcome." if not other else
                 "Cases with another outcome (where S1 at 0.6 A_col collapses, A_peak = 0.6 "
                 "A_col overestimates the capacity under S1): " + "; ".join(other) + "."))
    if len(a5) < 2:
        L.append("")
        return "\n".join(L)
    order_s = sorted(a5, key=lambda w: -a5[w][0])
    order_m = sorted(a5, key=lambda w: -a5[w][1])
    L.append(f"- The walls at 5 Hz ranked by A_col: seed {' > '.join(order_s)}, murus "
             f"{' > '.join(order_m)} ({'the same order' if order_s == order_m else 'another order'}"
             "); DSRW2, the only one with a sloped backfill, is by far the weakest in both.")
    L.append("")
    return "\n".join(L)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--cached", action="store_true", help="The finished studies only (no "
                    "computation; a wall not computed is listed as such).")
    ap.add_argument("--cache", default=None, help="The studies' folder (default "
                    "validation/results/retaining_behaviour/continuum): e.g. a scratch folder "
                    "that replaces it once every study in it is complete.")
    args = ap.parse_args(argv)
    import runcache

    if args.cache is not None:
        global CACHE
        CACHE = Path(args.cache).resolve()

    try:
        text = section(args.workers, args.cached)
    except StaleStudy as exc:
        print(f"error: {exc}", file=sys.stderr)
        raise SystemExit(2) from None
    runcache.emit(text, args.out)


if __name__ == "__main__":
    main()
