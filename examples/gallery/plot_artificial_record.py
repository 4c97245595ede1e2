"""
An artificial record compatible with EN 1998-1
==============================================

Artificial accelerograms whose mean 5 % spectrum matches the EN 1998-1 elastic spectrum
(§3.2.3.1.2): a stationary part of 10 s under a trapezoidal envelope, iterated in the frequency
domain. Here three records for ground B, ag = 0.25 g, and the checks of the standard.
"""

import matplotlib.pyplot as plt
import numpy as np

from murus import G
from murus.eurocode import ec8
from murus.motion import artificial, spectra

ag = 0.25 * G
records = artificial.generate_ec8(ag, ground="B", n=3, seed=1)
report = artificial.check_ec8(records, ag, ground="B", T1=0.5)   # a wall of T1 = 0.5 s
print(report.to_text())
print("all criteria passed:", report.passed)

periods = np.geomspace(0.05, 4.0, 60)
fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.5))
rec = records[0]
ax1.plot(np.arange(rec.acc.size) * rec.dt, rec.acc / G, lw=0.6)
ax1.set_xlabel("t [s]")
ax1.set_ylabel("a / g")
ax1.set_title(rec.name)
for r in records:
    ax2.plot(periods, spectra.pseudo_spectrum(r, periods) / G, lw=0.8)
ax2.plot(periods, ec8.elastic_spectrum(periods, ag, ground="B") / G, "k", lw=2, label="EC8")
ax2.set_xscale("log")
ax2.set_xlabel("T [s]")
ax2.set_ylabel("PSA / g")
ax2.legend()
plt.tight_layout()
