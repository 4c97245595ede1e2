"""
Kinematic checks of a façade (Circolare 2019 §C8.7.1)
=====================================================

The two-storey façade of ``examples/mechanisms/two_storey_facade.toml`` checked the way the
Italian code prescribes (``murus mechanism``): simple overturning at every hinge level, its
activation multiplier alpha0, the participating mass fraction e*, the spectral acceleration
a0* and the capacity curve of the equivalent oscillator against the displacement demand.
``examples/mechanisms/facade_code_vs_dynamics.py`` compares such checks with the rocking
dynamics of the same façade (VALIDATION.md).
"""

import matplotlib.pyplot as plt

from murus.mechanisms.case import load_case, run_case
from murus.mechanisms.facade import plot_capacity

case, path, text = load_case("../mechanisms/two_storey_facade.toml")
run = run_case(case, path, text)
for r in run["results"]:
    print(f"{r.name:40s} alpha0 = {r.alpha0:.3f}  e* = {r.e_star:.3f}  "
          f"a0* = {r.a0_star:.3f} m/s²  min capacity/demand = {r.ratio:.2f}")

fig, ax = plt.subplots(figsize=(6, 3.5))
plot_capacity(run["governing"], ax=ax, seismic=run["seismic"])
plt.tight_layout()
