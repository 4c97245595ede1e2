"""
A rocking spectrum of the restrained wall (EURODYN (2020), §4.1)
================================================================

The peak rotation of block2 of EURODYN (2020) against the stiffness of its tie (``K / K_d``,
with ``K_d`` of eq. 12), free-standing and restrained, under ground motions. The paper uses
the 44 FEMA P695 far-field components (``records="farfield"``, with
``pip install murus[records]``); this short version uses a two-cycle sine pulse of 0.3 g at
three times the frequency parameter ``p`` of the wall, so that it runs in
seconds, serially. A larger study runs on a process pool or a Dask cluster by changing
``executor`` (``"process"``, ``"dask"``).
"""

import matplotlib.pyplot as plt
import numpy as np

from murus.rocking import restrained_wall_block
from murus.studies import plot_rocking_spectrum, rocking_spectrum

block = restrained_wall_block("block2")
pulse = {"type": "sine-pulse", "amplitude_g": 0.3, "cycles": 2}   # a case [motion] table
ds = rocking_spectrum(block, pulse, K_over_Kd=np.linspace(0.0, 1.0, 11), omega_p_over_p=3.0,
                      executor="serial", duration=8.0)
print(ds)

fig, ax = plt.subplots(figsize=(7, 4))
plot_rocking_spectrum(ds, ax=ax)
plt.tight_layout()
