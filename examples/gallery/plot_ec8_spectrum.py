"""
Elastic response spectra of EN 1998-1
=====================================

The horizontal elastic spectra of EN 1998-1 §3.2.2.2 (eqs 3.2-3.5, Type 1, recommended values)
for the five ground types, for a design ground acceleration of 0.25 g, and the damping
correction eta of eq. 3.6.
"""

import matplotlib.pyplot as plt
import numpy as np

from murus import G
from murus.eurocode import ec8

T = np.linspace(0.0, 4.0, 401)
ag = 0.25 * G
fig, ax = plt.subplots(figsize=(7, 4))
for ground in "ABCDE":
    ax.plot(T, ec8.elastic_spectrum(T, ag, ground=ground) / G, label=f"ground {ground}")
ax.set_xlabel("T [s]")
ax.set_ylabel("Se / g")
ax.set_title("EN 1998-1 Type 1, ag = 0.25 g, 5 % damping")
ax.legend()
ax.grid(True)
plt.tight_layout()

for xi in (0.02, 0.05, 0.10, 0.20):
    print(f"damping {xi:.0%}: eta = {ec8.eta(xi):.3f}")
