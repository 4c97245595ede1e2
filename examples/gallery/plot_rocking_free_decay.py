"""
Free rocking of a wall and Housner's coefficient of restitution
===============================================================

Block1 of EURODYN (2020), Table 1 (0.3 x 3.0 m, unit length, 21 kN/m³) released from
0.9 alpha rocks freely: at each impact the angular velocity is multiplied by Housner's
coefficient of restitution ``e = 1 - 3/2 sin² alpha`` (Housner 1963). The peaks of
``theta / alpha`` decay accordingly (VALIDATION.md, "Free rocking against the closed form").
"""

import matplotlib.pyplot as plt

from murus.rocking import RockingModel, restrained_wall_block, simulate

block = restrained_wall_block("block1")
print(f"alpha = {block.alpha:.4f} rad, p = {block.p:.3f} rad/s, "
      f"e (Housner) = {block.housner_restitution():.4f}")

res = simulate(RockingModel(block), theta0_over_alpha=0.9, duration=15.0)
print(f"{res.n_impacts} impacts, theta_max/alpha = {res.theta_max / res.alpha:.3f}")

fig, ax = plt.subplots(figsize=(7, 3))
ax.plot(res.t, res.theta / res.alpha)
ax.set_xlabel("t [s]")
ax.set_ylabel(r"$\theta / \alpha$")
ax.set_title("EURODYN (2020) block1, free rocking from 0.9 alpha")
ax.grid(True)
plt.tight_layout()
