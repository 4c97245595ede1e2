"""murus: seismic assessment of masonry walls.

Rigid-body rocking (:mod:`murus.rocking`), ground motions (:mod:`murus.motion`),
Eurocode checks (:mod:`murus.eurocode`). SI units throughout: m, kg, s, N, rad, m/s².
"""

__version__ = "0.1.0"

G = 9.81
"""Acceleration of gravity used throughout murus [m/s²].

The standard gravity g_n = 9.80665 m/s² (3rd CGPM, 1901) rounded to 9.81 m/s², the value of the
Eurocodes' worked examples and of the papers murus reproduces (Mordant et al. (SERIES),
Savalle et al. (2022), EURODYN (2020)): results that compare with their tables use it. Readers
convert accelerations given in g with it (PEER and COSMOS use 9.80665 m/s² for their own
conversions: 0.03 % apart). This module imports nothing, so ``from murus import G`` is free."""
