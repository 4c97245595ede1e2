"""
A shaken soil column (continuum zones)
======================================

The case ``examples/continuum/soil_column.toml``: a 20 m elastic soil column
(Vs = 200 m/s, first natural frequency Vs / 4H = 2.5 Hz) on a base driven by the harmonic
ramp ``S(t) = A t sin(2 pi f t)`` at resonance. The displacement of the top relative to the base
grows as the input and the resonance build up.
"""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from murus.continuum.case import build, load_case, run_case

case_file = Path("..") / "continuum" / "soil_column.toml"
cfg, path, text = load_case(case_file)
run = run_case(build(cfg, path, text))
t = np.asarray(run.result.t)
u = np.asarray(run.result.values["u_top"])
print(f"{run.result.steps} steps, peak top displacement {np.abs(u).max() * 1e3:.2f} mm")

fig, ax = plt.subplots(figsize=(7, 3))
ax.plot(t, u * 1e3)
ax.set_xlabel("t [s]")
ax.set_ylabel("u_top - u_base [mm]")
ax.grid(True)
plt.tight_layout()
