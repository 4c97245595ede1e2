"""
Minimum thickness of a semicircular arch by limit analysis (murus.limit)
========================================================================

A semicircular arch of voussoirs on its own weight stands only if its thickness exceeds a
minimum: t/R = 0.1075 for the continuous arch (Milankovitch; Heyman's 0.106), approached from
below as the voussoirs multiply. The rigid-block limit analysis of murus (Livesley 1978, solved
with scipy's HiGHS) finds the horizontal load factor of arches of decreasing thickness; the
thickness at which it falls to zero is the minimum. The verification table of
``murus verify limit`` finds the same numbers by bisection.
"""

import matplotlib.pyplot as plt

from murus.limit.verify import case_arch

rows = case_arch(quick=True)
for r in rows:
    print(f"{r['case']}: expected {r['expected']:.4f}, murus {r['obtained']:.5f}, "
          f"tolerance {r['tolerance']:.3g}")

arches = [r for r in rows if "voussoirs" in r["case"]]
labels = [r["case"].split(",")[1].split(":")[0].strip() for r in arches]
fig, ax = plt.subplots(figsize=(6, 3))
ax.bar(labels, [r["obtained"] for r in arches], color="C0", label="murus (discrete voussoirs)")
ax.axhline(0.1075, color="k", ls="--", label="continuous arch, t/R = 0.1075")
ax.set_ylim(0.100, 0.110)
ax.set_ylabel("minimum t/R [-]")
ax.legend(fontsize=8, loc="lower right")
ax.set_title("Semicircular arch: minimum thickness")
plt.tight_layout()
