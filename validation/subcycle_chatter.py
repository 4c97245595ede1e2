"""Subcycling at the printed joint stiffness: the sliding mock-up H/B = 1.7 (the validation's
run ``mock_1.7_k1_r0``: joints and interface as printed, 10 Hz, the S2 ramp) to t = 9.5 s with
one step for all and subcycled (``subcycle="auto"``), recording d_top and, after every chunk of
steps, the wall-backfill interface's normal force. Subcycled, the interface starts to chatter
at t = 7.74 s (its normal force jumps between 0 and about 100 N within a millisecond, against
6-15 N before) and the wall creeps 1.1 mm at an input of about 1 m/s², far below its
pseudo-static resistance (3.88 m/s²); with one step for all it does not, but only by chance:
continued from the same state at 7.5 s with a shorter step or a 1e-12 m shift of the stones,
one step for all creeps as well, on energy the interface's contacts gain
(``results/retaining_continuum_x1_perturbation.json``; VALIDATION.md, *Subcycling*). About
15 minutes subcycled and 50 minutes with one step for all on one idle core.

The runs use the interface's corner rule of the time, ``corner_share="follow"``, whose corners
fed the chatter (the default "shrink" mends it, and with it subcycling is allowed at x 1):
``collapse_run`` refuses subcycling above x 1e-1 with "follow", so this script lifts the
refusal for its own runs, the evidence of why it stands.

Usage::

    python validation/subcycle_chatter.py [--out FILE.json] [--mended]
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
OUT = HERE / "results" / "retaining_continuum_subcycle_x1.json"
T_MAX = 9.5
SAMPLES = (6.0, 7.0, 7.5, 7.7, 7.8, 8.0, 8.5, 9.0, 9.4)


def run(subcycle: str | None) -> dict:
    """One variant: d_top at :data:`SAMPLES` and the interface's normal force per window."""
    import numpy as np
    import retaining_continuum as rc

    from murus.retaining import continuum_backfill as cb
    from murus.retaining.collapse import collapse_run

    hold, rows = {}, []
    orig = cb.ContinuumBackfill.settle

    def settle(self, dw, external=None, built=None):
        hold["bf"] = self
        return orig(self, dw, external=external, built=built)

    def prog(t, t_end, info):
        if info == "run" and "bf" in hold:
            rows.append((float(t), hold["bf"].interface.normal_force()))

    cb.ContinuumBackfill.settle = settle
    import murus.retaining.collapse as col

    limit = col.SUBCYCLE_MAX_SCALE
    col.SUBCYCLE_MAX_SCALE = float("inf")  # the evidence of why it is refused (module doc)
    try:
        wall = rc._wall(rc.runs()["mock_1.7_k1_r0"])  # (its subcycled twin is withdrawn)
        kw = dict(stiffness_scale=1.0, A_rate=rc.A_MOCK, t_max=T_MAX, safety=0.2,
                  backfill="continuum", backfill_options={"corner_share": "follow"},
                  progress=prog)
        if subcycle is not None:
            kw["subcycle"] = subcycle
        t0 = time.time()
        r = collapse_run(wall, 10.0, "none", **kw)
    finally:
        cb.ContinuumBackfill.settle = orig
        col.SUBCYCLE_MAX_SCALE = limit
    t, d = np.asarray(r.t), np.asarray(r.d_top)
    f = np.asarray(rows)

    def window(a, b):
        sel = f[(f[:, 0] >= a) & (f[:, 0] < b), 1]
        return [float(sel.min()), float(sel.max())] if sel.size else None

    return {"subcycle": subcycle, "wall_time_s": time.time() - t0,
            "d_top_mm": {f"{s:g}": float(np.interp(s, t, d)) * 1e3 for s in SAMPLES},
            "interface_normal_N": {"7.0-7.7": window(7.0, 7.7), "7.74-8.0": window(7.74, 8.0)}}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(OUT))
    ap.add_argument("--mended", action="store_true",
                    help="only the subcycled run, with the fast partition of the interface "
                         "(session 15's scheme), added to --out as 'mended' beside the "
                         "earlier runs")
    args = ap.parse_args(argv)
    if args.mended:
        res = json.loads(Path(args.out).read_text())
        res["mended"] = run("auto")
    else:
        res = {"case": "sub_1.7_k1_r0 to t = 9.5 s", "runs": [run(None), run("auto")]}
    Path(args.out).write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps(res, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
