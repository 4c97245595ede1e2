"""
A block sliding on an inclined plane (distinct elements against the closed form)
================================================================================

The verification case ``examples/dem/inclined_plane.toml``: a 0.5 x 0.25 m block on a plane
inclined at 30° with 25° of friction slides with the constant acceleration
``a = g (sin 30° - cos 30° tan 25°) = 0.9434 m/s²``. The case file is run by the same functions
as ``murus run``; the slip is compared with ``a t² / 2``.
"""

import math
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from murus import G
from murus.dem.case import build, load_case, run_case

case_file = Path("..") / "dem" / "inclined_plane.toml"
cfg, path, text = load_case(case_file)
run = run_case(build(cfg, path, text))
t = np.asarray(run.result.t)
u = np.asarray(run.result.values["u"])

a = G * (math.sin(math.radians(30)) - math.cos(math.radians(30)) * math.tan(math.radians(25)))
u_exact = 0.5 * a * t**2
print(f"a = {a:.4f} m/s2; slip after {t[-1]:.2f} s: murus {abs(u[-1]):.4f} m, "
      f"closed form {u_exact[-1]:.4f} m")

fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(t, np.abs(u), label="murus.dem")
ax.plot(t, u_exact, "k--", label="a t² / 2")
ax.set_xlabel("t [s]")
ax.set_ylabel("slip [m]")
ax.legend()
ax.grid(True)
plt.tight_layout()
