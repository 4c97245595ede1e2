"""Run every benchmark side by side with its peer and write BENCHMARKS.md (``make bench``;
``--assemble-only`` rebuilds BENCHMARKS.md from the existing results files)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

HEADER = """# murus benchmarks

Each benchmark runs murus and the tool a user would otherwise pick in the same process, on the
same input, and reports ratios and accuracy against an exact or converged reference. Regenerate
with `make bench` (installs the peers of the `bench` extra, then runs `benchmarks/run.py`).
Timings are from a 2-core machine (the project's standard machine); numba kernels are compiled
(and cached) before timing.

"""

RUNS = [
    ("bench_rocking.py", "RESULTS_rocking.md"),
    ("bench_restrained.py", "RESULTS_restrained.md"),
    ("bench_rest_rule.py", "RESULTS_rest_rule.md"),
    ("bench_spectra.py", "RESULTS_motion.md"),
    ("bench_studies.py", "RESULTS_studies.md"),
    ("bench_dem.py", "RESULTS_dem.md"),
    ("bench_retaining.py", "RESULTS_retaining.md"),
    ("bench_threads.py", "RESULTS_threads.md"),
    ("bench_interrupt.py", "RESULTS_interrupt.md"),
    ("bench_continuum.py", "RESULTS_continuum.md"),
    ("bench_coupled.py", "RESULTS_coupled.md"),
    ("bench_retaining_continuum.py", "RESULTS_retaining_continuum.md"),
    # recorded by hand (two source trees compared; the commands are in the file)
    (None, "RESULTS_checks.md"),
    (None, "RESULTS_named_data.md"),
]


def main() -> None:
    assemble_only = "--assemble-only" in sys.argv[1:]
    parts = [HEADER]
    for script, out in RUNS:
        if script is not None and not assemble_only:
            subprocess.run([sys.executable, str(HERE / script), "--out", str(HERE / out)],
                           check=True)
        text = (HERE / out).read_text()
        # one heading level down: each results file becomes a section
        parts.append("\n".join("#" + ln if ln.startswith("#") else ln
                               for ln in text.splitlines()) + "\n")
    (ROOT / "BENCHMARKS.md").write_text("\n".join(parts))
    print(f"wrote {ROOT / 'BENCHMARKS.md'}")


if __name__ == "__main__":
    main()
