"""
Tie design of the restrained wall (EURODYN (2020), eq. 12)
==========================================================

The six walls of EURODYN (2020), Table 1, restrained by a steel tie at their top: the design
force and stiffness of the tie by equilibrium about the pivot (eq. 12), and the resonance
frequencies of the one-sided system with that tie (eq. 8).
"""

import matplotlib.pyplot as plt

from murus.rocking import restrained_wall_block
from murus.rocking.design import resonance_frequencies, tie_design

rows = []
for i in range(1, 7):
    block = restrained_wall_block(f"block{i}")
    td = tie_design(block)
    res = resonance_frequencies(block, K=td.K_d)
    rows.append((f"block{i}", block.width, block.height, td.T_d, td.phi_d * 1e3, td.K_d,
                 res.omega_plus))

print(f"{'wall':8s} {'b [m]':>6s} {'h [m]':>6s} {'T_d [N]':>9s} {'phi_d [mm]':>10s} "
      f"{'K_d [N/m]':>10s} {'omega+ [rad/s]':>14s}")
for name, b, h, T, phi, K, w in rows:
    print(f"{name:8s} {b:6.2f} {h:6.2f} {T:9.1f} {phi:10.2f} {K:10.3g} {w:14.2f}")

fig, ax = plt.subplots(figsize=(6, 3))
ax.bar([r[0] for r in rows], [r[5] for r in rows])
ax.set_ylabel(r"$K_d$ [N/m]")
ax.set_yscale("log")
ax.set_title("Tie stiffness by eq. 12, EURODYN (2020)")
plt.tight_layout()
