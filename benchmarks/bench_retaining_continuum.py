"""Speed of the dry-stone retaining walls on the continuum backfill (issue 18, item 5), on an
idle machine:

A. DSRW1 of Savalle et al. (2022) under S2 at 5 Hz to collapse (d_top = 20 % H) with the
   continuum backfill at its defaults (zones of H / 12, W = 5 m, free-field side), numba on 2
   threads: goal < 15 minutes;
B. one simulated second of the H/B = 2.7 mock-up (§3) at the mesh used for Table 3 (zones of
   H / 12, courses of about 10 mm, validation/retaining_continuum.py) at 10 Hz: goal < 5 minutes;
C. the behaviour-factor study of DSRW1 (examples/retaining/dsrw1_behaviour_factor.toml: five S2
   runs and ten S1 checks on the continuum backfill) on a process pool of 2 workers and on a
   Dask LocalCluster of 2 single-threaded workers, and its resume after Ctrl-C (SIGINT to the
   process group once the first case is stored): the resumed study gives the results of the
   uninterrupted one (every case record, its history and the table, all but the wall times);
R. the resume check of C alone, against a finished study folder (``--ref``, default the
   validation cache of DSRW1, which C's process run produced).

Peer: UDEC, the tool of Savalle et al. (2022) (commercial, not runnable here): 12 hours of
computation per simulated second of its mock-up model (§3.1), quoted as the peer point.

``python benchmarks/bench_retaining_continuum.py [--parts A,B,C|R] [--ref DIR] [--out
benchmarks/RESULTS_retaining_continuum.md]``
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
UDEC_H_PER_S = 12.0
GOALS = {"A": 900.0, "B": 300.0}
EXAMPLE = ROOT / "examples" / "retaining" / "dsrw1_behaviour_factor.toml"
REF = ROOT / "validation" / "results" / "retaining_behaviour" / "continuum" / "DSRW1"
#: The command line of this environment.
MURUS = str(Path(sys.executable).parent / "murus")


def part_a():
    from murus.retaining.collapse import collapse_run
    from murus.retaining.geometry import preset

    t0 = time.perf_counter()
    r = collapse_run(preset("DSRW1"), 5.0, backfill="continuum")
    return r, time.perf_counter() - t0


def mock_wall():
    from murus.retaining.geometry import preset

    w = preset("mockup-2.7")
    n = max(1, round(w.height / 0.010))
    return w.with_(stone_height=w.height / n)


def part_b():
    from murus.retaining.collapse import collapse_run

    t0 = time.perf_counter()
    r = collapse_run(mock_wall(), 10.0, backfill="continuum", A_rate=2.6 / 19.9, t_max=1.0)
    return r, time.perf_counter() - t0


def _study(out: Path, extra: list[str], env) -> tuple[float, subprocess.CompletedProcess]:
    t0 = time.perf_counter()
    p = subprocess.run([MURUS, "retaining", "behaviour-factor",
                        str(EXAMPLE), "--out", str(out), *extra], env=env, capture_output=True,
                       text=True)
    return time.perf_counter() - t0, p


def _interrupted(out: Path, extra: list[str], env) -> tuple[float, int]:
    """Start the study, SIGINT its process group once a case is stored; (seconds from the
    signal to the exit, exit code)."""
    p = subprocess.Popen([MURUS, "retaining", "behaviour-factor",
                          str(EXAMPLE), "--out", str(out), *extra], env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         start_new_session=True)
    cases = out / "cases"
    while p.poll() is None and not list(cases.glob("*.json.sha256")):
        time.sleep(0.5)
    t0 = time.perf_counter()
    os.killpg(p.pid, signal.SIGINT)
    p.communicate(timeout=120)
    return time.perf_counter() - t0, p.returncode


def same_results(a: Path, b: Path) -> tuple[bool, list[str]]:
    """Whether two finished study folders hold the same results: every case record (its
    summary without the wall time), every case history byte for byte, and the table without
    its wall-time column; (verdict, the files that differ)."""
    def table(folder):
        lines = (folder / "behaviour_factor.csv").read_text().splitlines()
        i = lines[0].split(",").index("wall_time_s")
        return [[x for k, x in enumerate(line.split(",")) if k != i] for line in lines]

    def record(path):
        rec = json.loads(path.read_text())
        rec["summary"].pop("wall_time", None)
        return rec

    bad = [] if table(a) == table(b) else ["behaviour_factor.csv"]
    names = sorted(p.name for p in (a / "cases").glob("*.json"))
    if names != sorted(p.name for p in (b / "cases").glob("*.json")):
        bad.append("cases/ (other case files)")
        return False, bad
    for n in names:
        if record(a / "cases" / n) != record(b / "cases" / n):
            bad.append(f"cases/{n}")
        h = n[:-5] + ".csv"
        if (a / "cases" / h).read_bytes() != (b / "cases" / h).read_bytes():
            bad.append(f"cases/{h}")
    return not bad, bad


def resume_check(ref: Path, tmp: Path, env) -> dict:
    """Interrupt the study once a case is stored, resume it, compare with ``ref``."""
    out = tmp / "resumed"
    stop, code = _interrupted(out, ["--executor", "process", "--workers", "2"], env)
    done = len(list((out / "cases").glob("*.json.sha256")))
    secs, p = _study(out, ["--executor", "process", "--workers", "2"], env)
    same, bad = same_results(ref, out) if p.returncode == 0 else (False, ["(no result)"])
    return dict(stop=stop, code=code, done=done, resume=secs, rc=p.returncode, same=same,
                bad=bad, n=len(list((out / "cases").glob("*.json"))))


def part_r(ref: Path):
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    tmp = Path(tempfile.mkdtemp(prefix="bench_bf_"))
    try:
        return resume_check(ref, tmp, env)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _resume_text(res: dict, ref: str) -> str:
    verdict = ("yes" if res["same"] else "NO (" + ", ".join(res["bad"][:6]) + ")")
    return (f"Ctrl-C once the first case was stored: the study stopped in {res['stop']:.1f} s "
            f"(exit code {res['code']}) with {res['done']} case(s) kept; the resume took "
            f"{res['resume']:.0f} s (exit {res['rc']}). Its results against {ref} (the "
            f"{res['n']} case records without their wall time, their histories byte for byte, "
            f"the table without its wall-time column): the same: {verdict}.")


def part_c():
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    tmp = Path(tempfile.mkdtemp(prefix="bench_bf_"))
    rows = {}
    try:
        for label, extra in (("process, 2 workers", ["--executor", "process", "--workers",
                                                      "2"]),
                             ("Dask LocalCluster, 2 workers", ["--executor", "dask",
                                                               "--workers", "2"])):
            out = tmp / label.split(",")[0].split()[0].lower()
            secs, p = _study(out, extra, env)
            if p.returncode != 0:
                raise RuntimeError(f"{label}: exit {p.returncode}: {p.stderr[-500:]}")
            rows[label] = (secs, out)
        ref = rows["process, 2 workers"][1]
        dask_same = same_results(ref, rows["Dask LocalCluster, 2 workers"][1])
        res = resume_check(ref, tmp, env)
        res["dask_same"] = dask_same
        return rows, res
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--parts", default="A,B,C")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--ref", default=str(REF), help="Part R: the finished study folder to "
                    "compare with.")
    ap.add_argument("--out", default=str(HERE / "RESULTS_retaining_continuum.md"))
    args = ap.parse_args(argv)
    os.environ["NUMBA_NUM_THREADS"] = str(args.threads)
    import numba

    from murus.retaining.collapse import collapse_run
    from murus.retaining.geometry import preset

    parts = [p.strip().upper() for p in args.parts.split(",") if p.strip()]
    load0 = os.getloadavg()
    # compile (numba cache) before timing
    collapse_run(preset("DSRW1"), 5.0, backfill="continuum", t_max=0.05,
                 backfill_options={"size": 0.5})
    L = ["# Dry-stone retaining walls on the continuum backfill (issue 18, item 5)", "",
         f"Machine: {os.cpu_count()} cores ({platform.machine()}), Python "
         f"{platform.python_version()}, numba {numba.__version__} (NUMBA_NUM_THREADS="
         f"{args.threads} for A and B; one thread per worker for C). Command: `python "
         f"benchmarks/bench_retaining_continuum.py --parts {','.join(parts)}`. Kernels "
         "compiled (cache) before timing.", ""]
    if "A" in parts:
        r, total = part_a()
        print(f"A: {total:.1f} s, A_col {r.A_col:.3f}", file=sys.stderr)
        L += ["## A. DSRW1, S2 at 5 Hz, to collapse", "",
              "| zones | simulated [s] | A_col [m/s²] | steps | dt [s] | setup [s] | total [s] | "
              "per simulated second [s] | goal [s] | met |",
              "|---|---|---|---|---|---|---|---|---|---|",
              f"| {r.options['backfill_options']['n_zones']} | {r.t_end:.2f} | "
              f"{r.A_col:.2f} | {r.steps} | {r.dt:.2e} | {r.setup_time:.1f} | {total:.1f} | "
              f"{(r.wall_time - r.setup_time) / r.t_end:.1f} | {GOALS['A']:.0f} | "
              f"{'yes' if total < GOALS['A'] else 'no'} |", ""]
    if "B" in parts:
        r, total = part_b()
        per = (r.wall_time - r.setup_time) / r.t_end
        print(f"B: {total:.1f} s", file=sys.stderr)
        L += ["## B. Mock-up H/B = 2.7, one simulated second at 10 Hz", "",
              "| zones | courses | steps | dt [s] | setup [s] | per simulated second [s] | "
              "goal [s] | met | UDEC (Savalle et al. (2022), §3.1) | ratio |",
              "|---|---|---|---|---|---|---|---|---|---|",
              f"| {r.options['backfill_options']['n_zones']} | "
              f"{round(r.height / mock_wall().stone_height)} | {r.steps} | {r.dt:.2e} | "
              f"{r.setup_time:.1f} | {per:.1f} | {GOALS['B']:.0f} | "
              f"{'yes' if per < GOALS['B'] else 'no'} | {UDEC_H_PER_S * 3600:.0f} s | "
              f"{UDEC_H_PER_S * 3600 / per:.0f} x faster (another machine: an order of "
              "magnitude) |", ""]
    if "C" in parts:
        rows, res = part_c()
        L += ["## C. Behaviour-factor study of DSRW1 (its example case file)", "",
              "| executor | wall time [s] |", "|---|---|"]
        L += [f"| {k} | {v[0]:.0f} |" for k, v in rows.items()]
        ds, dbad = res["dask_same"]
        L += ["", f"The Dask study against the process one (same comparison as below): "
              f"{'the same' if ds else 'NOT the same: ' + ', '.join(dbad[:6])}.", "",
              _resume_text(res, "the uninterrupted process run"), ""]
    if "R" in parts:
        ref = Path(args.ref).resolve()
        lab = ref.relative_to(ROOT) if ref.is_relative_to(ROOT) else ref
        res = part_r(ref)
        L += ["## C (resume). Behaviour-factor study of DSRW1, interrupted and resumed", "",
              _resume_text(res, f"`{lab}`"), ""]
    load1 = os.getloadavg()
    L.append(f"Load average (1, 5, 15 min) at the start {' '.join(f'{x:.2f}' for x in load0)}, "
             f"at the end {' '.join(f'{x:.2f}' for x in load1)}.")
    Path(args.out).write_text("\n".join(L) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
