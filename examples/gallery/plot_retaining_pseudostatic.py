"""
Pseudo-static resistance of dry-stone retaining walls (Savalle et al. (2022), Table 8)
======================================================================================

The limit equilibrium of the four full-scale walls DSRW1-4 of Savalle et al. (2022), joint by
joint, under a horizontal action and with a vertical component of half the horizontal one,
against the paper's Table 8; then the active thrust of the trial-wedge (Coulomb) search on a
6 m wall as the seismic coefficient grows.
"""

import math

import matplotlib.pyplot as plt
import numpy as np

from murus.retaining import critical_acceleration, preset, trial_wedge

print(f"{'wall':6s} {'A_pseudo [m/s2]':>16s} {'with kv = kh/2':>16s}")
for name in ("DSRW1", "DSRW2", "DSRW3", "DSRW4"):
    wall = preset(name)
    a0 = critical_acceleration(wall).A_pseudo
    a1 = critical_acceleration(wall, kv_ratio=0.5).A_pseudo
    print(f"{name:6s} {a0:16.3f} {a1:16.3f}")

kh = np.linspace(0.0, 0.3, 16)
thrust = [trial_wedge(6.0, math.radians(35.0), delta=math.radians(20.0), gamma=18e3,
                      kh=k).thrust / 1e3 for k in kh]
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(kh, thrust, "o-")
ax.set_xlabel("kh")
ax.set_ylabel("thrust [kN/m]")
ax.set_title("Trial wedge, H = 6 m, phi = 35°, delta = 20°")
ax.grid(True)
plt.tight_layout()
