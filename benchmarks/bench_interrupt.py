"""Interrupts and killed parents (issue 15, item 3): how fast `murus study run` and `murus
retaining behaviour-factor` stop on Ctrl-C (SIGINT to the process group, as a terminal sends it)
and how fast the workers of a process pool and of a local Dask cluster exit when the main
process is killed (SIGKILL).

    python benchmarks/bench_interrupt.py [--out benchmarks/RESULTS_interrupt.md] [--repeat 3]

The study is 12 chunks of the small EURODYN (2020) sweep of the tests, made slow by a hook that
sleeps
0.4 s (1 s for the SIGKILL runs) at the start of each chunk, so that the run is going on when the
signal comes; the signal is sent as soon as the first chunk is stored.
"""

from __future__ import annotations

import argparse
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT / "tests" / "studies"))

# the slow study, its child command and the /proc helpers are those of the tests
from studies_inputs import SLOW_CHILD as CHILD  # noqa: E402
from studies_inputs import SLOW_STUDY as STUDY  # noqa: E402
from studies_inputs import alive, children, write_study  # noqa: E402

CLI = "from murus.cli import app; app()"
EXAMPLE = ROOT / "examples" / "retaining" / "mockup_behaviour_factor.toml"




def launch(code: str, args, cwd: Path) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src"), *sys.path]),
               NUMBA_NUM_THREADS="1")
    return subprocess.Popen([sys.executable, "-c", code, *map(str, args)], cwd=cwd, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)


def wait_file(pattern_dir: Path, glob: str, p: subprocess.Popen, timeout=600.0) -> None:
    end = time.monotonic() + timeout
    while not list(pattern_dir.glob(glob)):
        if p.poll() is not None or time.monotonic() > end:
            raise RuntimeError(f"the run ended before storing a piece: {p.communicate()}")
        time.sleep(0.01)


def sigint(code, args, cwd: Path, folder: Path, glob: str) -> tuple[float, int, str]:
    p = launch(code, args, cwd)
    wait_file(folder, glob, p)
    t0 = time.monotonic()
    os.killpg(p.pid, signal.SIGINT)
    _, err = p.communicate(timeout=120)
    return time.monotonic() - t0, p.returncode, err.strip().splitlines()[-1]


def sigkill(args, cwd: Path, out: Path) -> tuple[float, int]:
    p = launch(CHILD, [1.0, *args], cwd)
    wait_file(out / "chunks", "*.sha256", p)
    workers = children(p.pid)
    t0 = time.monotonic()
    os.kill(p.pid, signal.SIGKILL)
    p.wait()
    while any(alive(w) for w in workers):
        if time.monotonic() - t0 > 120:
            for w in workers:
                if alive(w):
                    os.kill(w, signal.SIGKILL)
            return float("inf"), len(workers)
        time.sleep(0.01)
    return time.monotonic() - t0, len(workers)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=str(HERE / "RESULTS_interrupt.md"))
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    from studies_inputs import synthetic_records

    rows, kills = [], []
    with tempfile.TemporaryDirectory() as tmp:
        tmp_name = tmp
        tmp = Path(tmp)
        write_study(tmp, synthetic_records(), STUDY)
        for label, ex in (("study run, serial", ["--serial"]),
                          ("study run, process pool (2)", ["--workers", "2"]),
                          ("study run, Dask LocalCluster (2)", ["--dask", "local", "--workers",
                                                                "2"])):
            ts, codes, last = [], set(), ""
            for k in range(a.repeat):
                out = tmp / f"o{len(rows)}{k}"
                t, rc, last = sigint(CHILD, [0.4, "study", "run", "s.toml", "--out", out, *ex],
                                     tmp, out / "chunks", "*.sha256")
                ts.append(t)
                codes.add(rc)
            rows.append((label, ts, codes, last))
            print(rows[-1], file=sys.stderr)
        for label, ex in (("behaviour-factor example, serial", []),
                          ("behaviour-factor example, process pool (2)", ["--workers", "2"])):
            ts, codes, last = [], set(), ""
            for k in range(a.repeat):
                out = tmp / f"b{len(rows)}{k}"
                t, rc, last = sigint(CLI, ["retaining", "behaviour-factor", EXAMPLE, "--out",
                                           out, *ex], tmp, out / "cases", "*.json.sha256")
                ts.append(t)
                codes.add(rc)
            rows.append((label, ts, codes, last))
            print(rows[-1], file=sys.stderr)
        for label, ex in (("process pool (2)", ["--workers", "2"]),
                          ("Dask LocalCluster (2)", ["--dask", "local", "--workers", "2"])):
            ts, n = [], 0
            for k in range(a.repeat):
                t, n = sigkill(["study", "run", "s.toml", "--out", tmp / f"k{len(kills)}{k}",
                                *ex], tmp, tmp / f"k{len(kills)}{k}")
                ts.append(t)
            kills.append((label, ts, n))
            print(kills[-1], file=sys.stderr)
    lines = ["# Interrupts and killed parents (issue 15, item 3)", "",
             f"Machine: 2 cores; command: `python benchmarks/bench_interrupt.py` "
             f"({a.repeat} runs each; load average before: {os.getloadavg()[0]:.2f}).", "",
             "Ctrl-C: SIGINT sent to the process group once the first chunk (case) is stored; "
             "time until the process has exited (goal: 2 s, exit code 130).", "",
             "| command | median [s] | max [s] | exit codes | last line on stderr |",
             "|---|---|---|---|---|"]
    for label, ts, codes, last in rows:
        last = last.replace(str(ROOT) + "/", "").replace(tmp_name, "TMP")
        lines.append(f"| {label} | {statistics.median(ts):.2f} | {max(ts):.2f} | "
                     f"{', '.join(map(str, sorted(codes)))} | {last.replace('|', '/')} |")
    lines += ["", "SIGKILL of the main process during a study: time until all its worker "
              "processes are gone (goal: 10 s; before, they ran on for more than a minute).", "",
              "| executor | processes watched | median [s] | max [s] |", "|---|---|---|---|"]
    for label, ts, n in kills:
        lines.append(f"| {label} | {n} | {statistics.median(ts):.2f} | {max(ts):.2f} |")
    lines += ["", "The Dask workers exit as fast without the parent watch that murus adds to them "
              "(distributed's\nworker processes already end with the process that holds their "
              "nanny); the pool's workers did\nnot: without it they were still running 10 s after "
              "the kill (the issue measured more than a\nminute)."]
    Path(a.out).write_text("\n".join(lines) + "\n")
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
