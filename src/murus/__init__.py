"""murus: seismic assessment of masonry walls.

Rigid-body rocking (:mod:`murus.rocking`), ground motions (:mod:`murus.motion`),
Eurocode checks (:mod:`murus.eurocode`). SI units throughout: m, kg, s, N, rad, m/s².
"""

__version__ = "0.1.0"

G = 9.81  #: standard gravity used throughout murus [m/s²]
