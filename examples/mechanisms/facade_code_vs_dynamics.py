"""A façade with a tie, checked by the code and by the dynamics.

The two-storey façade of VALIDATION.md ("The code's kinematic checks against the rocking
dynamics"): 3.5 + 3.2 m high, 0.5 m thick, 2000 kg/m³, floors of 6 and 4.5 kN per metre of wall
on its centreline, a tie of 6 kN/m at the first floor.

1. The Circolare 2019 checks of simple overturning about its base (murus.mechanisms): the
   reference ground acceleration agR at which the linear (q = 2) and nonlinear checks fail,
   FC = 1, EN 1998-1 type 1 spectrum on ground B.
2. The rocking engine (murus.rocking): the same façade as a rigid body on its outer toe, the
   tie an elastic-perfectly plastic 10 m S275 rod yielding at 6 kN, one-sided against the
   transverse walls, under seven artificial records of that spectrum scaled in steps of agR:
   the step at which each record overturns it.

Run: ``python examples/mechanisms/facade_code_vs_dynamics.py`` (a few seconds).
"""

import numpy as np

from murus import G
from murus.mechanisms import Floor, Seismic, Storey, overturning
from murus.mechanisms.demand import Building, EC8Spectrum
from murus.motion.artificial import generate_ec8
from murus.rocking import RockingModel, SpringBed, Tie, simulate_batch
from murus.rocking.body import RigidBlock
from murus.rocking.design import S275_FU, STEEL_E

h1, h2, s, rho = 3.5, 3.2, 0.5, 2000.0          # m, m, m, kg/m³
loads, tie = (6000.0, 4500.0), 6000.0           # N per metre of wall

# -- 1. the code: the ratios are capacity / demand at agR = 1 m/s², and the demands scale
#       with agR, so the agR of each limit is its ratio
storeys = [Storey(height=h1, thickness=s, density=rho), Storey(height=h2, thickness=s,
                                                               density=rho)]
floors = [Floor(level=1, load=loads[0], x=s / 2, tie=tie), Floor(level=2, load=loads[1],
                                                                  x=s / 2)]
# (the building only serves the hinge at the first floor, above the ground)
seismic = Seismic(spectra={"SLV": EC8Spectrum(1.0, "B", 1)}, FC=1.0, q=2.0,
                  building=Building(T1=0.25, height=h1 + h2, storeys=2))
base = overturning(storeys, floors, seismic)[0]      # the hinge at the foundation
limits = {c.method: c.ratio / G for c in base.checks if c.limit_state == "SLV"}
print(f"code: alpha0 = {base.alpha0:.3f}, e* = {base.e_star:.3f}, "
      f"a0* = {base.a0_star:.3f} m/s²; SLV fails at agR = {limits['linear']:.3f} g (linear), "
      f"{limits['nonlinear']:.3f} g (nonlinear)")

# -- 2. the dynamics
body = RigidBlock(width=s, height=h1 + h2, density=rho,
                  masses=((loads[0] / G, h1), (loads[1] / G, h1 + h2)))
area = tie / (0.7 * S275_FU / 1.05)             # the S275 rod whose design force is the tie's
model = RockingModel(body, tie=Tie(STEEL_E * area / 10.0, h1, yield_force=tie),
                     transverse_walls=SpringBed(4.5e8, body.height), motion_sides="one")
records = generate_ec8(1.0, "B", 1, n=7, seed=1)  # compatible with agR = 1 m/s²
levels = np.round(np.arange(0.025, 1.0001, 0.025), 4)  # agR [g]
res = simulate_batch([model], [r.scaled(a * G) for a in levels for r in records])
over = res.overturned[0].reshape(levels.size, len(records))
first = [levels[np.argmax(over[:, j])] for j in range(len(records)) if over[:, j].any()]
print("dynamics: agR [g] at which each record overturns the façade:",
      ", ".join(f"{a:.3g}" for a in first))
print(f"          four of seven overturn it at agR = {levels[np.argmax(over.mean(1) > 0.5)]:.3g} g")
