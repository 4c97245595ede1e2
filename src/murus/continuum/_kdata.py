"""Named kernel data of the continuum (zones) engine: the structures that
:mod:`murus.continuum.kernels` takes, in the manner of :mod:`murus.dem._kdata`.

Each structure is a :func:`collections.namedtuple` of NumPy arrays that numba compiles as a
typed tuple. The field names are the attribute names of
:class:`murus.continuum.model.ContinuumModel`, so that :func:`pack` builds a structure from a
model and :data:`STATE_ARRAYS` lists what a checkpoint saves.

The step inputs (base velocity at t and t + dt/2, gravity) are the distinct-element engine's own
:class:`murus.dem._kdata.Drive`, so that zones and blocks read the same base motion.

Layouts of the small float records (material columns ``M_*``, parameters ``P_*``, energies
``E_*``, counters ``C_*``, statistics ``S_*``, partial sums ``Q_*``) are declared as named
constants in :mod:`murus.continuum.kernels`.
"""

from __future__ import annotations

from collections import namedtuple

from murus.dem._kdata import pack  # the same: a named tuple of the arrays of a holder

__all__ = ["Grid", "Zones", "STATE_ARRAYS", "pack", "IG_GXY", "IG_GVEL", "IG_GDISP",
           "IG_GACC", "IZ_ZSIG", "IZ_ZSTATE", "IZ_ZWORK", "IZ_ZF"]

Grid = namedtuple("Grid", ["gxy", "gvel", "gacc", "gdisp", "gmass", "gfix", "gext", "gdash",
                           "gff", "gsp", "gzc"])
Grid.__doc__ = """Gridpoints (``ng`` rows each).

- ``gxy (ng, 2)``: coordinates [m] (updated each step in large-strain mode, fixed in
  small-strain mode);
- ``gvel (ng, 2)``: velocity at the half step ``t - dt/2`` [m/s];
- ``gacc (ng, 2)``: acceleration of the last step [m/s²] (velocity change over dt);
- ``gdisp (ng, 2)``: displacement since the reference state [m];
- ``gmass (ng,)``: lumped mass [kg] (per out-of-plane thickness);
- ``gfix (ng, 2)`` int64: per direction x, y: 0 free, 1 fixed (zero velocity), 2 moved by the
  base motion (velocity of the base in that direction);
- ``gext (ng, 2)``: applied force [N] (point loads and boundary pressures);
- ``gdash (ng, 3)``: quiet-boundary dashpot matrix ``(cxx, cxy, cyy)`` [N s/m] of the gridpoint,
  the sum over its quiet edges of ``L/2 (rho Cp n n^T + rho Cs t t^T)`` (zero elsewhere);
- ``gff (ng, 4)``: the free field's action on the gridpoints of a free-field side
  (:mod:`murus.continuum.freefield`), written each step: force ``L sigma_ff . n`` (x, y) [N]
  and the velocity ``v_ff`` (x, y) [m/s] that the side's dashpots act against (zero elsewhere:
  a quiet boundary's dashpots act against rest);
- ``gsp (ng + 1,)``, ``gzc (nzc,)`` int64: CSR incidence, the zone corners ``4 z + c`` of each
  gridpoint (ascending), by which the gridpoint loop gathers the corner forces.
"""

Zones = namedtuple("Zones", ["zg", "zmat", "zsig", "zstate", "zwork", "zf"])
Zones.__doc__ = """Zones (``nz`` rows each).

- ``zg (nz, 4)`` int64: gridpoints, counter-clockwise;
- ``zmat (nz,)`` int64: material row of ``mprops``;
- ``zsig (nz, 4, 4)``: stresses (sxx, syy, sxy, szz) [Pa, tension positive] of the four
  triangles: overlay A (diagonal 0-2) triangles (0, 1, 2) and (0, 2, 3), overlay B (diagonal
  1-3) triangles (0, 1, 3) and (1, 2, 3);
- ``zstate (nz,)`` int64: plastic state bits ``ST_*`` of :mod:`murus.continuum.kernels`;
- ``zwork (nz, 2)``: work in the zone [J] (per out-of-plane thickness) since the reference
  state: column 0 dissipated by plastic flow (``sigma : de_p``), column 1 the stress work
  ``(sigma_old + sigma_new) / 2 : de`` of the strain increments (stored elastic energy plus
  plastic work);
- ``zf (4 nz, 2)``: force of zone z on its corner c, row ``4 z + c`` [N] (internal stresses
  only, written by the zone loop, gathered by the gridpoint loop).
"""

#: State arrays of a model that the kernels read or write (a checkpoint saves them).
STATE_ARRAYS = Grid._fields + Zones._fields


# Positions of the fields written inside parallel loops (numba drops a write through a
# named-tuple attribute in a prange body: numba issues #5872, #7135; see murus.dem._kdata).
IG_GXY = Grid._fields.index("gxy")
IG_GVEL = Grid._fields.index("gvel")
IG_GACC = Grid._fields.index("gacc")
IG_GDISP = Grid._fields.index("gdisp")
IZ_ZSIG = Zones._fields.index("zsig")
IZ_ZSTATE = Zones._fields.index("zstate")
IZ_ZWORK = Zones._fields.index("zwork")
IZ_ZF = Zones._fields.index("zf")
