"""
Compressed length of a wall section (EN 1996-1-1, Mordant et al. (SERIES), §2.2.1)
==================================================================================

The compressed length of a no-tension section of length L under an axial force N and a moment
M, with a constant stress block (the effective width of EN 1996-1-1 §6.1.2.2) and with a linear
distribution (EN 1996-1-1 §6.2), as the eccentricity e = M/N grows to L/2, where the wall
starts to rock. Here the short wall of Mordant et al. (SERIES) (L = 0.72 m, 5 t on top).
"""

import matplotlib.pyplot as plt
import numpy as np

from murus import G
from murus.eurocode import ec6

L = 0.72
N = 5000.0 * G
e = np.linspace(0.0, 0.5 * L, 61)
fig, ax = plt.subplots(figsize=(6, 3.5))
for dist in ec6.DISTRIBUTIONS:
    Lc = [ec6.compressive_length(N, N * ei, L, distribution=dist) for ei in e]
    ax.plot(e / L, np.asarray(Lc) / L, label=dist)
ax.axvline(1 / 6, color="k", lw=0.6, ls="--")
ax.set_xlabel("e / L")
ax.set_ylabel("Lc / L")
ax.legend()
ax.grid(True)
plt.tight_layout()
print(f"kern limit e = {ec6.kern_limit(L):.3f} m (L/6)")
