"""Small shared inputs for the tests of murus.studies: short synthetic records (no data
files), a plan of a few dozen histories."""

import numpy as np

from murus.motion import GroundMotion
from murus.rocking import restrained_wall_block
from murus.studies.spectrum import spectrum_case
from murus.studies.study import make_study


def synthetic_records(n: int = 4, seconds: float = 6.0, seed: int = 11):
    """Band-limited noise records of a few seconds, PGA 2.5-5 m/s² (enough to rock block1)."""
    rng = np.random.default_rng(seed)
    dt = 0.01
    out = []
    m = int(seconds / dt)
    t = np.arange(m) * dt
    env = np.minimum(1.0, t / 1.0) * np.exp(-np.maximum(t - 3.0, 0.0))
    for i in range(n):
        a = np.convolve(rng.standard_normal(m + 40), np.ones(12) / 12, mode="same")[:m] * env
        a *= (2.5 + 2.5 * i / max(n - 1, 1)) / np.abs(a).max()
        out.append(GroundMotion(dt, a, name=f"syn{i}", meta={"event": f"synthetic {i}"}))
    return out


def small_study(records, n_k: int = 6, chunk_size: int = 8):
    """block1 of EURODYN (2020), K/K_d in [0, 1] (eq. 11 walls), x 2 scale factors x the records."""
    case = spectrum_case(restrained_wall_block("block1"))
    return make_study(case, {"K_over_Kd": np.linspace(0.0, 1.0, n_k),
                             "motion.scale": [0.6, 1.0]}, records, name="small",
                      chunk_size=chunk_size)
