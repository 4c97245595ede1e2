"""Named kernel data of the 2D distinct-element engine: the structures that
:mod:`murus.dem.kernels` takes, instead of long lists of bare arrays.

Each structure is a :func:`collections.namedtuple` of NumPy arrays, which numba compiles as a
typed tuple (no copy, no boxing: the kernels read ``bodies.bpos[b, 0]`` as fast as a bare
``bpos[b, 0]``). The field names are the attribute names of :class:`murus.dem.model.Model`, so
that :func:`pack` builds a structure from a model and :data:`STATE_ARRAYS` lists what a
checkpoint saves, without a third list of names.

Adding a field to the DEM state touches two places:

1. the field here, in the structure it belongs to (with its line in the structure's docstring);
2. its allocation in :meth:`murus.dem.model.Model.build` (``self.<name> = ...``).

The kernels then read it by name; :func:`pack` hands it over and :meth:`Model.save` /
:meth:`Model.load` store and restore it (``Model._ARRAYS`` is built from
:data:`STATE_ARRAYS`). Two caveats: a field that the per-pair contact body
(:func:`murus.dem.kernels.process_pair`) reads is also unpacked by name in
:func:`murus.dem.kernels._contacts_parallel` and passed to it (bare arrays keep that loop's
speed), and a checkpoint written before the field existed loads only if the field is listed in
``Model._ZERO_IF_MISSING``.

Layouts of the small float records (slot records ``F_*``, joint properties ``J_*``, parameters
``P_*``, energies ``E_*``, counters ``C_*``, statistics ``S_*``, pair records ``W_*``, partial
sums of the body blocks ``Q_*``) are declared as named constants in :mod:`murus.dem.kernels`.
"""

from __future__ import annotations

from collections import namedtuple

__all__ = ["Bodies", "Shapes", "Joints", "Contacts", "Drive", "Frame", "SubContact",
           "PairMotion", "STATE_ARRAYS", "pack"]

Bodies = namedtuple("Bodies", ["bpos", "bang", "bvel", "bomg", "bmass", "binert", "bkin",
                               "brad", "blast", "bsnap", "bpresc", "bext"])
Bodies.__doc__ = """Bodies (``nb`` rows each).

- ``bpos (nb, 2)``: centroid [m];
- ``bang (nb,)``: angle [rad, counter-clockwise];
- ``bvel (nb, 2)`` [m/s] and ``bomg (nb,)`` [rad/s]: velocities at the half step ``t - dt/2``;
- ``bmass (nb,)`` [kg], ``binert (nb,)`` [kg m²] about the centroid;
- ``bkin (nb,)`` int64: 0 dynamic, 1 fixed, 2 moved by the base motion, 3 moved at its
  prescribed velocity ``bpresc``;
- ``brad (nb,)``: bounding radius about the centroid [m];
- ``blast (nb, 3)``: position and angle at the last rebuild of the pair list;
- ``bsnap (nb, 6)``: state at the last force evaluation (x, y, angle [m, rad], mid-step
  velocities vx, vy [m/s], omega [rad/s]);
- ``bpresc (nb, 3)``: prescribed velocity (vx, vy [m/s], omega [rad/s]) of kind-3 bodies;
- ``bext (nb, 3)``: external force (Fx, Fy) [N] and moment about the centroid [N m] on each
  dynamic body.
"""

Shapes = namedtuple("Shapes", ["sbody", "skind", "svs", "svn", "srad", "sgroup", "lv", "wv"])
Shapes.__doc__ = """Shapes (``ns`` rows each, int64 unless stated) and their vertices.

- ``sbody``: owning body; ``skind``: 0 rounded polygon, 1 disc;
- ``svs``, ``svn``: first vertex and vertex count in ``lv`` / ``wv``;
- ``srad`` (float): rounding radius of a polygon, radius of a disc [m];
- ``sgroup``: joint group;
- ``lv (nv, 2)``: core vertices of a polygon relative to the body centroid at angle 0, the disc
  centre for a disc [m]; ``wv (nv, 2)``: the same in world coordinates [m].
"""

Joints = namedtuple("Joints", ["jprops", "jtab"])
Joints.__doc__ = """Joint laws: ``jprops (nj, NJ)`` property rows (``J_*`` columns of
:mod:`murus.dem.kernels`) and ``jtab (ng, ng)`` int64, the joint of each pair of groups."""

Contacts = namedtuple("Contacts", ["pairs", "pj", "pbond", "sid", "sf", "sbr"])
Contacts.__doc__ = """Candidate pairs (shape a < shape b) and their two sub-contact slots.

- ``pairs (np, 2)`` int64: the shapes a < b, sorted by ``a * ns + b``;
- ``pj (np,)`` int64: joint of the pair; ``pbond (np,)`` int8: 1 when new sub-contacts of the
  pair start bonded;
- ``sid (np, 2)`` int64: key of each slot (a global vertex index; -1 empty);
- ``sf (np, 2, NSF)``: float record of each slot (``F_*`` fields);
- ``sbr (np, 2)`` int8: 1 when the slot is broken (residual cohesion and tension).
"""

Drive = namedtuple("Drive", ["vfull", "vhalf", "grav", "gdot"])
Drive.__doc__ = """Step inputs of a chunk of ``n`` steps (rows i = 0 .. n-1, each ``(n, 2)``).

- ``vfull``: base-motion velocity at t_i [m/s]; ``vhalf``: at t_i + dt/2 [m/s];
- ``grav``: gravity vector at t_i [m/s²]; ``gdot``: its rate [m/s³].
"""

Frame = namedtuple("Frame", ["vx", "vy", "vhx", "vhy", "gx", "gy", "gdx", "gdy"])
Frame.__doc__ = """Row i of a :class:`Drive`, as scalars read by name in the body update:
base velocity at t_i (``vx, vy``) and t_i + dt/2 (``vhx, vhy``) [m/s], gravity (``gx, gy``)
[m/s²] and its rate (``gdx, gdy``) [m/s³]."""

SubContact = namedtuple("SubContact", ["px", "py", "nx", "ny", "gap", "trib"])
SubContact.__doc__ = """A sub-contact found by the narrow phase: contact point (px, py) [m], unit
normal (nx, ny) from shape a to shape b, gap between the rounded surfaces [m] (negative in
penetration), tributary length [m]."""

PairMotion = namedtuple("PairMotion", ["vax", "vay", "wa", "xa", "ya", "vbx", "vby", "wb", "xb",
                                       "yb"])
PairMotion.__doc__ = """Velocities [m/s, rad/s] and centroids [m] of the bodies a and b of a
pair."""

#: State arrays of a model that the kernels read or write (a checkpoint saves them).
STATE_ARRAYS = Bodies._fields + Shapes._fields + Joints._fields + Contacts._fields


def pack(cls, obj):
    """The structure ``cls`` (:class:`Bodies`, :class:`Shapes`, :class:`Joints` or
    :class:`Contacts`) of the arrays of ``obj`` (a :class:`murus.dem.model.Model`) of the same
    names.

    Parameters
    ----------
    cls : type
        A named tuple class of this module.
    obj : object
        Holder of the arrays as attributes.

    Returns
    -------
    cls
        The named tuple of the arrays (no copy).
    """
    return cls(*[getattr(obj, f) for f in cls._fields])


# Positions of the fields that the kernels write inside a parallel (``prange``) loop. numba
# drops a write through a named-tuple attribute there (``c.sf[k] = x`` inside the loop body
# has no effect: numba issues #5872 and #7135, still open in numba 0.68), while a write through
# the field's position (``bodies[IB_BPOS][b, 0] = x``) is kept; reads by attribute are
# unaffected. (The contact loop takes bare arrays for another reason: kernels.process_pair.)
IB_BPOS = Bodies._fields.index("bpos")
IB_BANG = Bodies._fields.index("bang")
IB_BVEL = Bodies._fields.index("bvel")
IB_BOMG = Bodies._fields.index("bomg")
IB_BSNAP = Bodies._fields.index("bsnap")
IS_WV = Shapes._fields.index("wv")
