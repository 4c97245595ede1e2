"""Speed of the rigid-block limit analysis on a running-bond wall of 500 blocks.

A DEM case with a ``[[walls]]`` table (25 courses of 20 blocks, 0.4 x 0.2 m, half-bond) on a
fixed base is written to a temporary file and analysed by :func:`murus.limit.analyse` with
associative and non-associative friction; the script prints the number of blocks and
interfaces, the load factors, the LP solutions of the non-associative scheme and the wall
times (interface search and LP assembly included). No peer is timed here (no Python
rigid-block limit analysis package is installed to compare with).

``python benchmarks/bench_limit.py [--courses 25] [--per-course 20] [--friction-deg 30]``
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

CASE = """[dem]
duration = 1.0

[materials.stone]
density = 2000.0
kn = 1e9
ks = 1e9
friction_deg = {phi}

[[blocks]]
kind = "rectangle"
width = {base_w}
height = 0.2
center = [{base_x}, -0.1]
kinematic = "fixed"

[[walls]]
courses = {courses}
blocks_per_course = {per}
block_width = 0.4
block_height = 0.2
stagger = 0.5
origin = [0.0, 0.0]
"""


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--courses", type=int, default=25)
    p.add_argument("--per-course", type=int, default=20)
    p.add_argument("--friction-deg", type=float, default=30.0)
    a = p.parse_args()
    from murus.limit import analyse, find_interfaces, from_case

    width = 0.4 * (a.per_course + 1)
    text = CASE.format(phi=a.friction_deg, base_w=width + 1.0, base_x=width / 2,
                       courses=a.courses, per=a.per_course)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "wall.toml"
        path.write_text(text)
        t0 = time.perf_counter()
        asm = from_case(path)
        itf = find_interfaces(asm)
        t1 = time.perf_counter()
        print(f"{asm.nblock - 1} blocks, {len(itf)} interfaces: read and interface search "
              f"{t1 - t0:.3f} s")
        for friction in ("associative", "non-associative"):
            t0 = time.perf_counter()
            r = analyse(asm, friction=friction)
            dt = time.perf_counter() - t0
            print(f"{friction:>16}: load factor {r.load_factor:.6f}, {r.iterations} LP "
                  f"solution(s), converged {r.converged}, {dt:.3f} s")


if __name__ == "__main__":
    main()
