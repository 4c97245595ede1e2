"""Mordant et al. (SERIES), §2 on a virtual wall: write a shaking-table test sequence in the murus format
(white-noise tests between seismic tests of increasing PGA), then identify the frequency and
damping along it (Figures 3-4), classify the seismic tests (§2.3) and tabulate the compressive
length against Eurocode 6 (Table 2).

    python examples/identify/virtual_sequence.py OUT_DIR

The same processing works on laboratory files in the documented format
(``murus.identify.testdata``); with the command group registered it is
``murus lab synthesize OUT_DIR/seq`` then ``murus lab sequence OUT_DIR/seq --out OUT_DIR/report``.
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

from murus.identify.classify import classify_sequence  # noqa: E402
from murus.identify.compressive import compressive_table  # noqa: E402
from murus.identify.modal import (  # noqa: E402
    evolution,
    plot_damping_evolution,
    plot_frequency_evolution,
)
from murus.identify.synth import synthesize_sequence  # noqa: E402
from murus.identify.testdata import read_sequence  # noqa: E402


def main(out: Path) -> None:
    folder = out / "seq"
    if not folder.exists():
        synthesize_sequence(folder, seed=0)
    seq = read_sequence(folder)
    evo = evolution(seq)
    print(evo.table(), end="\n\n")
    for c in classify_sequence(seq):
        print(f"{c.name}: {c.label} (ratio {c.ratio:.2f})")
    print()
    print(compressive_table(seq).to_markdown())
    for stem, fn in (("frequency", plot_frequency_evolution), ("damping", plot_damping_evolution)):
        ax = fn(evo)
        ax.figure.savefig(out / f"{stem}.png", dpi=120)


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "identify_example"))
