"""
The harmonic ramp of the collapse runs (Savalle et al. (2022), eq. 5)
=====================================================================

The input S2 of the collapse protocol of Savalle et al. (2022), §4.2: ``S(t) = A t sin(2 pi f
t)``, whose envelope ``A t`` reaches the pseudo-static resistance of the wall at 2.5 s. Here
for DSRW1 (``A_pseudo`` from the limit equilibrium of Table 8) at 5 Hz, with the velocity and
displacement of the base.
"""

import matplotlib.pyplot as plt
import numpy as np

from murus.motion import synthetic
from murus.retaining import critical_acceleration, preset

A_pseudo = critical_acceleration(preset("DSRW1")).A_pseudo
A = A_pseudo / 2.5                      # m/s3
f = 5.0
ramp = synthetic.harmonic_ramp(A, f, duration=4.0, dt=0.001)
t = np.arange(ramp.acc.size) * ramp.dt
print(f"A_pseudo = {A_pseudo:.3f} m/s2, A = {A:.3f} m/s3")

fig, axes = plt.subplots(3, 1, figsize=(7, 5), sharex=True)
axes[0].plot(t, ramp.acc, lw=0.6)
axes[0].plot(t, A * t, "k--", lw=1, label="envelope A t")
axes[0].axhline(A_pseudo, color="r", lw=0.8, label="A_pseudo")
axes[0].set_ylabel("a [m/s²]")
axes[0].legend(loc="upper left")
axes[1].plot(t, synthetic.ramp_velocity(A, f, t), lw=0.8)
axes[1].set_ylabel("v [m/s]")
axes[2].plot(t, synthetic.ramp_displacement(A, f, t) * 1e3, lw=0.8)
axes[2].set_ylabel("d [mm]")
axes[2].set_xlabel("t [s]")
plt.tight_layout()
