"""Checkpoints of a long collapse run (``murus retaining collapse --checkpoint``): the H/B = 2.7
mock-up of Savalle et al. (2022) on the continuum backfill to ``--t-max`` seconds of model time,
run three times by the command line: uninterrupted; with a checkpoint every 2 s, interrupted by
SIGINT after ``--after`` seconds of wall time (the time to stop and the exit code measured);
the same command again (resumes). The resumed outputs are compared with the uninterrupted ones
(d_top.csv byte for byte, summary.json but the wall time), and the size of the checkpoint and
the time to write one are measured.

``python benchmarks/bench_collapse_checkpoint.py [--t-max 0.6] [--after 20]``
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-max", type=float, default=0.6)
    ap.add_argument("--after", type=float, default=20.0)
    args = ap.parse_args(argv)
    murus = [sys.executable, "-c", "from murus.cli import app; app(prog_name='murus')"]
    env = dict(os.environ, NUMBA_NUM_THREADS=os.environ.get("NUMBA_NUM_THREADS", "1"))
    with tempfile.TemporaryDirectory() as tmp:
        d = Path(tmp)
        ck = d / "run.npz"
        base = murus + ["retaining", "collapse", "--preset", "mockup-2.7", "--stone-height",
                        "0.0102", "--frequency", "10", "--t-max", f"{args.t_max:g}"]
        t0 = time.perf_counter()
        subprocess.run(base + ["--out", str(d / "ref")], env=env, check=True,
                       capture_output=True)
        t_ref = time.perf_counter() - t0
        cmd = base + ["--out", str(d / "run"), "--checkpoint", str(ck),
                      "--checkpoint-every", "2"]
        p = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
        time.sleep(args.after)
        size = ck.stat().st_size if ck.exists() else 0
        p.send_signal(signal.SIGINT)
        t1 = time.perf_counter()
        _, err = p.communicate()
        stop = time.perf_counter() - t1
        kept = ck.exists()
        wrote = (d / "run").exists()
        t2 = time.perf_counter()
        r = subprocess.run(cmd, env=env, capture_output=True, text=True)
        t_res = time.perf_counter() - t2
        same_csv = (d / "ref" / "d_top.csv").read_bytes() == (d / "run" / "d_top.csv").read_bytes()
        a, b = (json.loads((d / k / "summary.json").read_text()) for k in ("ref", "run"))
        a.pop("wall_time"), b.pop("wall_time")
        # the time to write one checkpoint: the model of a short run, saved ten times
        sys.path.insert(0, str(ROOT / "validation"))
        write_ms = _write_time(d)
    print(f"uninterrupted: {t_ref:.1f} s; interrupted after {args.after:g} s: stopped in "
          f"{stop:.2f} s, exit code {p.returncode}, checkpoint kept: {kept} ({size / 1e6:.2f} "
          f"MB), outputs written: {wrote}; last line: {err.strip().splitlines()[-1]}")
    print(f"resumed: exit code {r.returncode} in {t_res:.1f} s; d_top.csv byte for byte: "
          f"{same_csv}; summary.json but the wall time: {a == b}; checkpoint removed: "
          f"{not ck.exists()}; one checkpoint written in {write_ms:.1f} ms")
    ok = (p.returncode == 130 and kept and not wrote and r.returncode == 0 and same_csv
          and a == b and not ck.exists())
    return 0 if ok else 1


def _write_time(d: Path) -> float:
    import murus.retaining.collapse as C
    from murus.continuum import coupled as CP

    times = []
    step = CP.CoupledModel.step

    def spy(self, n, drive):
        if self.dem.time > 0.05 and not times:
            for i in range(10):
                t0 = time.perf_counter()
                C._save_checkpoint(self.dem, d / f"w{i}.npz", "x", {"left": 0})
                times.append(time.perf_counter() - t0)
        return step(self, n, drive)

    from retaining_dynamic import _mock_wall

    CP.CoupledModel.step = spy
    try:
        C.collapse_run(_mock_wall(2.7), 10.0, backfill="continuum", A_rate=0.5, t_max=0.06)
    finally:
        CP.CoupledModel.step = step
    return 1e3 * sorted(times)[len(times) // 2]


if __name__ == "__main__":
    sys.exit(main())
